#pragma once
/// Internal to io/: the obstacles of a scene file (assets/scenes/README.md): generated shapes,
/// OBJ meshes, static poses, rigid motion and per-vertex frames.

#include "io/json_reader.h"
#include "io/limits.h"

#include "sim/scene.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace atelier::io::detail {

/// Vertices and triangles of a scene read so far (cloths, obstacles and each obstacle frame),
/// held to Limits::maxSceneVertices and maxSceneTriangles as they are read.
struct SceneSize {
    long long vertices = 0;
    long long triangles = 0;
    /// Adds one mesh; throws JsonError at `pointer` when the scene goes over a limit.
    void add(long long meshVertices, long long meshTriangles, const Limits& limits,
             const std::string& pointer);
};

/// Throws JsonError at `pointer` when a coordinate of `x` is farther than
/// Limits::maxSceneCoordinate from the origin (`what` names the values: "positions").
void checkCoordinates(const sim::MatX3& x, const Limits& limits, const std::string& pointer,
                      const std::string& what);

/// Reads the scene's `obstacles` array at `pointer` into `out`; OBJ paths resolve against
/// `baseDir` and count towards `size`. Throws JsonError.
void readObstacles(const nlohmann::json& value, const std::string& pointer,
                   const std::filesystem::path& baseDir, const Limits& limits, SceneSize& size,
                   std::vector<sim::ObstacleSpec>& out);

} // namespace atelier::io::detail
