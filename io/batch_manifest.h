#pragma once
/// Batch manifests (`atelier-batch`, version 1): the jobs of `atelier-cli batch`, each a project
/// to drape with its own body, fabric and settings, and the pictures and meshes to write.
/// docs/batch.md describes the format; errors name the manifest and the JSON pointer.

#include "io/limits.h"
#include "io/result.h"

#include "patterns/project.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::io {

/// One job: a project and what is changed in it before it is draped.
struct BatchJob {
    /// Unique within the manifest: letters, digits, `.`, `_`, `-` (it names the job's folder).
    std::string name;
    std::filesystem::path project; ///< the `.atelier` file, resolved against the manifest
    /// Replaces the project's body (a mesh path resolved against the manifest), or none.
    std::optional<patterns::BodySource> body;
    std::string bodyLabel; ///< the body's name in the manifest (`M`, `male-L`), or empty
    /// A built-in fabric preset given to every material of the project, or empty.
    std::string fabric;
    std::optional<double> particleDistance; ///< [m], replaces the project's
    std::optional<double> timeLimit;        ///< [s], replaces the project's
    std::vector<std::string> views;         ///< pictures to draw (render view names)
    int width = 512;                        ///< picture size [pixels]
    int height = 512;
    int threads = 1; ///< engine threads of the job's drape
    /// Garment mesh formats besides the OBJ every job writes (its pictures are drawn from it):
    /// "glb", "fbx", "ply" (and "obj", which changes nothing).
    std::vector<std::string> exports = {"obj"};
    std::string pointer; ///< where the job is in the manifest (`/jobs/3`, `/matrix`)
};

struct BatchManifest {
    std::vector<BatchJob> jobs; ///< `jobs` in file order, then the `matrix`'s combinations
};

/// Reads a manifest:
/// `{"format": "atelier-batch", "version": 1, "defaults": {...}, "jobs": [...], "matrix": {...}}`.
/// Checks what can be checked without draping: keys, types, ranges, unique job names, fabric
/// presets and that each project file exists. View names are checked by the caller (the
/// renderer knows them), against `pointer`.
Result<BatchManifest> loadBatchManifest(const std::filesystem::path& path,
                                        const Limits& limits = {});
Result<BatchManifest> parseBatchManifest(std::string_view text, const std::string& file,
                                         const std::filesystem::path& baseDir,
                                         const Limits& limits = {});

/// The jobs a worker takes with `--shard index/count`: every count-th job starting at index
/// (0-based), so that `count` workers share one manifest with no coordinator.
std::vector<std::size_t> shardJobs(std::size_t jobCount, int index, int count);

/// 64-bit FNV-1a of `text`: a job's fingerprint (its project text and options), so that a
/// re-run redoes a job whose manifest entry changed.
std::uint64_t fingerprint(std::string_view text);

} // namespace atelier::io
