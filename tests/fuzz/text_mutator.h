#pragma once
/// Byte-level mutations of any text (truncated, bytes flipped, inserted, deleted, repeated) and
/// line-level mutations of OBJ meshes (face indices out of range, NaN coordinates, huge
/// polygons and counts) and of DXF files (hostile values, groups dropped, repeated or out of
/// order, entities opened and never closed).

#include "rng.h"

#include <string>
#include <vector>

namespace atelier::fuzz {

/// `text` with one byte-level mutation; appends what it did to `notes`.
std::string mutateBytes(std::string text, Rng& rng, std::vector<std::string>& notes);

/// OBJ `text` with one line-level mutation; appends what it did to `notes`.
std::string mutateObj(const std::string& text, Rng& rng, std::vector<std::string>& notes);

/// DXF `text` with one group-level mutation; appends what it did to `notes`.
std::string mutateDxf(const std::string& text, Rng& rng, std::vector<std::string>& notes);

} // namespace atelier::fuzz
