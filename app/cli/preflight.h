#pragma once
/// What a command checks before any work starts, so that a long run does not end in an error
/// it could have given at once: output paths (folders exist and are writable, no output
/// overwrites an input or another output) and mesh size limits.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace atelier::app {

/// A path given on the command line, with the flag (or argument name) that gave it.
struct NamedPath {
    std::string flag; ///< e.g. "--out", "project"
    std::filesystem::path path;
};

/// Checks the outputs before any work: each output's folder exists and is writable, no output
/// is an existing folder, and no output is the same file as an input or another output
/// (compared as weakly canonical paths). Empty paths are skipped. Returns the message of the
/// first problem, naming the flag and the path (`--out: /a/b.obj: is the input project`), or
/// nullopt.
std::optional<std::string> checkOutputs(const std::vector<NamedPath>& inputs,
                                        const std::vector<NamedPath>& outputs);

/// Checks `--frames-dir`-like folder outputs: an existing path must be a folder, and it must
/// not be one of the files. Returns the message or nullopt.
std::optional<std::string> checkOutputFolder(const NamedPath& folder,
                                             const std::vector<NamedPath>& files);

/// The default of `--max-vertices`: meshes estimated larger are refused before meshing.
inline constexpr long DEFAULT_MAX_VERTICES = 200000;

/// The message refusing a mesh of `estimate` vertices above `limit` (what it is, the estimate,
/// and the flag that raises the limit), or nullopt when it fits.
std::optional<std::string> checkVertexLimit(const std::string& what, long estimate, long limit);

} // namespace atelier::app
