#pragma once
/// Writing a file so that readers see either the old or the new content, never a partial one.

#include "io/result.h"

#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>

namespace atelier::io {

/// Writes `contents` to `path` atomically: into a temporary file in the same directory
/// (`.NAME.tmp-PID-XXXXXX`), which is flushed, fsync'ed and then renamed over `path` (the
/// directory is fsync'ed too). On failure the temporary file is removed and `path` keeps its
/// old content. A process killed while writing cannot remove its temporary file: the next
/// write of the same `path` removes those left by processes that no longer run.
Result<void> writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

/// Reads a whole file into a string. The path must name a regular file (a symbolic link to one
/// is fine): a directory, FIFO, device or socket is refused without reading or blocking, and so
/// is a file larger than `maxBytes` (checked before reading, and again while reading).
Result<std::string> readFile(const std::filesystem::path& path,
                             std::uint64_t maxBytes = std::numeric_limits<std::uint64_t>::max());

} // namespace atelier::io
