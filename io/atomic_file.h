#pragma once
/// Writing a file so that readers see either the old or the new content, never a partial one.

#include "io/result.h"

#include <filesystem>
#include <string_view>

namespace atelier::io {

/// Writes `contents` to `path` atomically: into a temporary file in the same directory
/// (`.NAME.tmp-PID-XXXXXX`), which is flushed, fsync'ed and then renamed over `path` (the
/// directory is fsync'ed too). On failure the temporary file is removed and `path` keeps its
/// old content. A process killed while writing cannot remove its temporary file: the next
/// write of the same `path` removes those left by processes that no longer run.
Result<void> writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

/// Reads a whole file into a string.
Result<std::string> readFile(const std::filesystem::path& path);

} // namespace atelier::io
