#include "io/scene_obstacles.h"

#include "io/body_file.h"
#include "io/obj.h"

#include "sim/collision/obstacle.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace atelier::io::detail {

namespace {

using nlohmann::json;

/// Limits of generated obstacle shapes (typos like `"cells": 20000` are refused early).
constexpr long long MAX_SHAPE_CELLS = 500;
constexpr long long MAX_SPHERE_SUBDIVISIONS = 7;
constexpr long long MIN_CAPSULE_SEGMENTS = 6;
constexpr long long MAX_CAPSULE_SEGMENTS = 1024;

constexpr double RAD_PER_DEG = 3.14159265358979323846 / 180.0;

/// An integer `key` in [lo, hi], or `fallback` when absent.
int boundedInteger(ObjectReader& r, std::string_view key, long long fallback, long long lo,
                   long long hi) {
    const long long n = r.integer(key, fallback);
    if (n < lo || n > hi) {
        r.fail(key, "must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                        "] (found " + std::to_string(n) + ")");
    }
    return static_cast<int>(n);
}

/// An OBJ as an obstacle mesh: one vertex per `v` line that a face uses, in file order (UV
/// seams welded back, unused `v` lines dropped), scaled by `scale`.
void weldObj(const ObjMesh& mesh, double scale, sim::MatX3& vertices, sim::MatX3i& triangles) {
    int sources = 0;
    for (const int s : mesh.sourceVertex) {
        sources = std::max(sources, s + 1);
    }
    std::vector<int> index(static_cast<std::size_t>(sources), -1);
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
        for (int c = 0; c < 3; ++c) {
            index[static_cast<std::size_t>(
                mesh.sourceVertex[static_cast<std::size_t>(mesh.triangles(t, c))])] = 0;
        }
    }
    int next = 0;
    for (int& i : index) {
        if (i == 0) {
            i = next++;
        }
    }
    vertices.resize(next, 3);
    for (std::size_t v = 0; v < mesh.sourceVertex.size(); ++v) {
        const int i = index[static_cast<std::size_t>(mesh.sourceVertex[v])];
        if (i >= 0) {
            vertices.row(i) = scale * mesh.positions.row(static_cast<Eigen::Index>(v));
        }
    }
    triangles.resize(mesh.triangles.rows(), 3);
    for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
        for (int c = 0; c < 3; ++c) {
            triangles(t, c) = index[static_cast<std::size_t>(
                mesh.sourceVertex[static_cast<std::size_t>(mesh.triangles(t, c))])];
        }
    }
}

/// Six times the signed volume enclosed by a closed mesh: positive when its faces are
/// counter-clockwise seen from outside.
double signedVolume6(const sim::MatX3& vertices, const sim::MatX3i& triangles) {
    double sum = 0;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        const sim::Vec3 a = vertices.row(triangles(t, 0));
        const sim::Vec3 b = vertices.row(triangles(t, 1));
        const sim::Vec3 c = vertices.row(triangles(t, 2));
        sum += a.dot(b.cross(c));
    }
    return sum;
}

/// The rotation matrix of a rotation vector (axis × angle) [rad].
sim::Mat3 rotationMatrix(const sim::Vec3& rotation) {
    const double angle = rotation.norm();
    if (angle < 1e-300) {
        return sim::Mat3::Identity();
    }
    return Eigen::AngleAxisd(angle, rotation / angle).toRotationMatrix();
}

class ObstacleReader {
  public:
    ObstacleReader(const std::filesystem::path& baseDir, const Limits& limits, SceneSize& size,
                   std::vector<sim::ObstacleSpec>& obstacles)
        : m_baseDir(baseDir), m_limits(limits), m_size(size), m_obstacles(obstacles) {}

    void readObstacle(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        r.allow({"description"});
        r.optionalString("description");
        sim::ObstacleSpec obstacle;
        obstacle.name = r.string("name", "obstacle" + std::to_string(m_obstacles.size()));
        for (const sim::ObstacleSpec& other : m_obstacles) {
            if (other.name == obstacle.name) {
                r.fail("name", "another obstacle is already named " + inQuotes(obstacle.name));
            }
        }

        // Shape: the mesh in the obstacle's own frame.
        bool closedDefault = true;
        bool isObj = false;
        double scale = 1.0;
        {
            ObjectReader sh(r.require("shape"), r.pointerOf("shape"));
            const std::string type = sh.string("type");
            if (type == "plane") {
                const double size = sh.positive("size", 2.0);
                const int cells = boundedInteger(sh, "cells", 1, 1, MAX_SHAPE_CELLS);
                sim::makePlaneMesh(size, cells, obstacle.vertices, obstacle.triangles);
                closedDefault = false;
            } else if (type == "sphere") {
                const double radius = sh.positive("radius");
                const int subdivisions =
                    boundedInteger(sh, "subdivisions", 4, 0, MAX_SPHERE_SUBDIVISIONS);
                sim::makeSphereMesh(radius, subdivisions, obstacle.vertices, obstacle.triangles);
            } else if (type == "box") {
                const sim::Vec3 size = sh.vec3("size");
                if (!(size.minCoeff() > 0)) {
                    sh.fail("size", "every extent must be positive");
                }
                const int cells = boundedInteger(sh, "cells", 1, 1, MAX_SHAPE_CELLS);
                sim::makeBoxMesh(size, cells, obstacle.vertices, obstacle.triangles);
            } else if (type == "capsule") {
                const double radius = sh.positive("radius");
                const double length = sh.positive("length");
                const int segments =
                    boundedInteger(sh, "segments", 32, MIN_CAPSULE_SEGMENTS, MAX_CAPSULE_SEGMENTS);
                // The cylinder is cut into rows about as tall as the ring's edges are long.
                const double rows = length / (2 * M_PI * radius / segments);
                if (!(rows * segments <= static_cast<double>(m_limits.maxSceneVertices))) {
                    sh.fail("radius",
                            "a capsule this thin for its length (" + json(length / radius).dump() +
                                " radii) would have about " + json(rows * segments).dump() +
                                " vertices, more than the limit of " +
                                std::to_string(m_limits.maxSceneVertices));
                }
                sim::makeCapsuleMesh(radius, length, segments, obstacle.vertices,
                                     obstacle.triangles);
            } else if (type == "obj") {
                const std::string path = sh.string("path");
                scale = sh.positive("scale", 1.0);
                auto obj = readObj(m_baseDir / path, m_limits.maxMeshBytes);
                if (!obj.ok()) {
                    failWith(sh.pointerOf("path"), obj.error());
                }
                if (obj.value().triangles.rows() == 0) {
                    sh.fail("path", path + ": has no faces");
                }
                weldObj(obj.value(), scale, obstacle.vertices, obstacle.triangles);
                if (auto problem = checkBodyExtent(obstacle.vertices, m_limits.maxBodyExtent)) {
                    sh.fail("path", path + ": " + *problem);
                }
                isObj = true;
            } else {
                sh.fail("type", "unknown shape type " + inQuotes(type) +
                                    " (expected \"plane\", \"sphere\", \"box\", \"capsule\" "
                                    "or \"obj\")");
            }
            sh.finish();
        }
        const bool closedOriented =
            sim::isClosedOriented(obstacle.triangles, static_cast<int>(obstacle.vertices.rows()));
        if (isObj) {
            closedDefault = closedOriented;
        }
        obstacle.closed = r.boolean("closed", closedDefault);
        if (obstacle.closed && !closedOriented) {
            r.fail("closed", "the mesh is not closed: a closed obstacle needs every edge shared "
                             "by exactly two triangles that traverse it in opposite directions "
                             "(leave \"closed\" out or set it to false for a two-sided surface)");
        }
        if (obstacle.closed && isObj &&
            !(signedVolume6(obstacle.vertices, obstacle.triangles) > 0)) {
            r.fail("shape", "the faces of the closed mesh point inward (negative enclosed "
                            "volume); reverse their vertex order so that they are "
                            "counter-clockwise seen from outside");
        }

        obstacle.thickness = r.nonNegativeAtMost("thickness", obstacle.thickness,
                                                 m_limits.maxThickness, THICKNESS_LIMIT);
        obstacle.staticFriction = r.nonNegative("static_friction", obstacle.staticFriction);
        obstacle.kineticFriction = r.nonNegative("kinetic_friction", obstacle.kineticFriction);

        // Pose and motion: a static pose (one key), rigid keys, or per-vertex frames.
        sim::ObstacleKey pose;
        pose.translation = r.vec3("position", sim::Vec3::Zero());
        pose.rotation = r.vec3("rotation_deg", sim::Vec3::Zero()) * RAD_PER_DEG;
        const json* motion = r.find("motion");
        const json* frames = r.find("frames");
        if (motion != nullptr && frames != nullptr) {
            r.fail("frames", "give either \"motion\" (rigid keys) or \"frames\" (per-vertex "
                             "animation), not both");
        }
        if (motion != nullptr) {
            readObstacleMotion(ObjectReader(*motion, r.pointerOf("motion")), pose, obstacle);
        } else if (frames != nullptr) {
            if (!isObj) {
                r.fail("frames", "per-vertex frames need an \"obj\" shape");
            }
            readObstacleFrames(ObjectReader(*frames, r.pointerOf("frames")), pose, scale, obstacle);
        } else {
            obstacle.keys.push_back(pose);
        }
        r.finish();
        checkPlacement(obstacle, ptr);
        m_obstacles.push_back(std::move(obstacle));
    }

    /// `motion`: rigid keys; positions and rotations a key leaves out are the static pose's.
    static void readObstacleMotion(ObjectReader r, const sim::ObstacleKey& pose,
                                   sim::ObstacleSpec& obstacle) {
        const std::string kp = r.pointerOf("keys");
        const json& keys = arrayAt(r.require("keys"), kp);
        if (keys.empty()) {
            r.fail("keys", "a motion needs at least one key");
        }
        for (std::size_t i = 0; i < keys.size(); ++i) {
            ObjectReader k(keys[i], childPointer(kp, i));
            sim::ObstacleKey key;
            key.time = k.number("time");
            if (!obstacle.keys.empty() && !(key.time > obstacle.keys.back().time)) {
                k.fail("time", "key times must increase (the previous key is at " +
                                   json(obstacle.keys.back().time).dump() + " s)");
            }
            key.translation = k.vec3("position", pose.translation);
            key.rotation = pose.rotation;
            if (const json* rotation = k.find("rotation_deg")) {
                key.rotation = vec3At(*rotation, k.pointerOf("rotation_deg")) * RAD_PER_DEG;
            }
            k.finish();
            obstacle.keys.push_back(key);
        }
        r.finish();
    }

    /// `frames`: per-vertex animation from OBJ files of the same mesh; each frame is scaled
    /// and placed by the static pose like the shape.
    void readObstacleFrames(ObjectReader r, const sim::ObstacleKey& pose, double scale,
                            sim::ObstacleSpec& obstacle) const {
        const std::string tp = r.pointerOf("times");
        const std::string pp = r.pointerOf("paths");
        const json& times = arrayAt(r.require("times"), tp);
        const json& paths = arrayAt(r.require("paths"), pp);
        if (times.empty()) {
            r.fail("times", "frames need at least one time");
        }
        if (paths.size() != times.size()) {
            r.fail("paths", "expected " + std::to_string(times.size()) +
                                " paths, one per time, found " + std::to_string(paths.size()));
        }
        const sim::Mat3 rotation = rotationMatrix(pose.rotation);
        const Eigen::Index nv = obstacle.vertices.rows();
        for (std::size_t i = 0; i < times.size(); ++i) {
            const std::string timePtr = childPointer(tp, i);
            const double t = numberAt(times[i], timePtr);
            if (!obstacle.frameTimes.empty() && !(t > obstacle.frameTimes.back())) {
                throw JsonError{timePtr, "frame times must increase"};
            }
            const std::string pathPtr = childPointer(pp, i);
            if (!paths[i].is_string()) {
                throw JsonError{pathPtr, "expected a string, found " + typeName(paths[i])};
            }
            const std::string path = paths[i].get<std::string>();
            auto obj = readObj(m_baseDir / path, m_limits.maxMeshBytes);
            if (!obj.ok()) {
                failWith(pathPtr, obj.error());
            }
            sim::MatX3 positions;
            sim::MatX3i triangles;
            weldObj(obj.value(), scale, positions, triangles);
            m_size.add(positions.rows(), 0, m_limits, pathPtr);
            if (positions.rows() != nv) {
                throw JsonError{pathPtr, path + ": has " + std::to_string(positions.rows()) +
                                             " vertices (used by faces); the shape's mesh has " +
                                             std::to_string(nv) +
                                             " (every frame is the same mesh, moved)"};
            }
            for (Eigen::Index v = 0; v < nv; ++v) {
                positions.row(v) =
                    (rotation * positions.row(v).transpose() + pose.translation).transpose();
            }
            checkCoordinates(positions, m_limits, pathPtr, "the frame's vertices");
            obstacle.frameTimes.push_back(t);
            obstacle.frames.push_back(std::move(positions));
        }
        r.finish();
    }

  private:
    /// The shape's size and every pose within the limits.
    void checkPlacement(const sim::ObstacleSpec& obstacle, const std::string& ptr) const {
        m_size.add(obstacle.vertices.rows(), obstacle.triangles.rows(), m_limits,
                   childPointer(ptr, "shape"));
        checkCoordinates(obstacle.vertices, m_limits, childPointer(ptr, "shape"),
                         "the shape's vertices");
        sim::MatX3 translations(static_cast<Eigen::Index>(obstacle.keys.size()), 3);
        for (std::size_t k = 0; k < obstacle.keys.size(); ++k) {
            translations.row(static_cast<Eigen::Index>(k)) = obstacle.keys[k].translation;
        }
        checkCoordinates(translations, m_limits, ptr, "positions");
    }

    const std::filesystem::path& m_baseDir;
    const Limits& m_limits;
    SceneSize& m_size;
    std::vector<sim::ObstacleSpec>& m_obstacles;
};

} // namespace

void SceneSize::add(long long meshVertices, long long meshTriangles, const Limits& limits,
                    const std::string& pointer) {
    vertices += meshVertices;
    triangles += meshTriangles;
    if (vertices > limits.maxSceneVertices) {
        throw JsonError{pointer, "the scene reaches " + std::to_string(vertices) +
                                     " vertices here, more than the limit of " +
                                     std::to_string(limits.maxSceneVertices)};
    }
    if (triangles > limits.maxSceneTriangles) {
        throw JsonError{pointer, "the scene reaches " + std::to_string(triangles) +
                                     " triangles here, more than the limit of " +
                                     std::to_string(limits.maxSceneTriangles)};
    }
}

void checkCoordinates(const sim::MatX3& x, const Limits& limits, const std::string& pointer,
                      const std::string& what) {
    if (x.size() == 0) {
        return;
    }
    const double largest = x.cwiseAbs().maxCoeff();
    if (!(largest <= limits.maxSceneCoordinate)) {
        throw JsonError{pointer, what + " reach " + json(largest).dump() +
                                     " m from the origin, more than the " +
                                     json(limits.maxSceneCoordinate).dump() + " m a scene spans"};
    }
}

void readObstacles(const json& value, const std::string& pointer,
                   const std::filesystem::path& baseDir, const Limits& limits, SceneSize& size,
                   std::vector<sim::ObstacleSpec>& out) {
    const json& list = arrayAt(value, pointer);
    if (list.size() > static_cast<std::size_t>(limits.maxObstacles)) {
        throw JsonError{pointer, std::to_string(list.size()) +
                                     " obstacles, more than the limit of " +
                                     std::to_string(limits.maxObstacles)};
    }
    ObstacleReader reader(baseDir, limits, size, out);
    for (std::size_t i = 0; i < list.size(); ++i) {
        reader.readObstacle(value[i], childPointer(pointer, i));
    }
}

} // namespace atelier::io::detail
