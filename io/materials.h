#pragma once
/// Fabric presets: named sim::Material values from a JSON file (assets/materials/fabrics.json).

#include "io/limits.h"
#include "io/result.h"

#include "sim/material.h"

#include <filesystem>
#include <map>
#include <string>
#include <string_view>

namespace atelier::io {

/// Preset name → material (its `name` set to the preset name).
using MaterialPresets = std::map<std::string, sim::Material>;

/// Reads a fabric preset file:
/// `{"format": "atelier-fabrics", "version": 1, "presets": {"cotton": {...}, ...}}`, each preset
/// with every field of `readMaterial` below plus a `"source"` string citing where the values
/// come from. Errors name the JSON pointer (`fabrics.json: /presets/denim/density_kg_per_m2: ...`).
/// The file must be a regular file within `limits` (size, nesting).
Result<MaterialPresets> loadMaterialPresets(const std::filesystem::path& path,
                                            const Limits& limits = {});

/// Same as `loadMaterialPresets` for JSON text; `file` is used in error messages.
Result<MaterialPresets> parseMaterialPresets(std::string_view text, const std::string& file,
                                             const Limits& limits = {});

/// The presets of assets/materials/fabrics.json as built into the library (no file access).
const MaterialPresets& builtinMaterialPresets();

/// The preset names, comma-separated, for a message listing what there is.
std::string presetNames(const MaterialPresets& presets);

/// The text of a fabric preset file (what loadMaterialPresets reads) holding `material` as the
/// preset `name`, with its `description` and `source` (where the values come from).
std::string formatMaterialPreset(const std::string& name, const sim::Material& material,
                                 const std::string& description, const std::string& source);

} // namespace atelier::io
