#include "io/scene_file.h"
#include "io/temp_dir.h"

#include "sim/collision/obstacle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

namespace atelier::io {
namespace {

/// A small valid scene with `obstacles` (the JSON array's content) and `extraTop` spliced into
/// the top-level object and `extraCloth` into the cloth.
std::string obstacleSceneText(const std::string& obstacles, const std::string& extraTop = "",
                              const std::string& extraCloth = "") {
    return R"({
  "format": "atelier-scene",
  "version": 1,
  "cloths": [{
    "name": "sheet",
    "mesh": {"type": "rectangle", "width": 0.2, "height": 0.2, "cells": [2, 2]},
    "placement": {"origin": [-0.1, 0.5, 0.1], "u_axis": [1, 0, 0], "v_axis": [0, 0, -1]},
    "material": "cotton")" +
           extraCloth + R"(
  }],
  "obstacles": [)" +
           obstacles + "]" + extraTop + R"(
})";
}

Result<sim::SceneSpec> parseObstacleScene(const std::string& text,
                                          const std::filesystem::path& dir = ".") {
    return parseScene(text, "scene.json", dir);
}

/// The parse fails at exactly `where`, and the message names the file and that
/// pointer.
void expectObstacleError(const Result<sim::SceneSpec>& result, const std::string& where,
                         const std::string& fragment) {
    ASSERT_FALSE(result.ok()) << "expected an error at " << where;
    EXPECT_EQ(result.error().file, "scene.json");
    EXPECT_EQ(result.error().where, where) << result.error().toString();
    EXPECT_NE(result.error().toString().find("scene.json: " + where + ": "), std::string::npos)
        << result.error().toString();
    EXPECT_NE(result.error().message.find(fragment), std::string::npos)
        << result.error().toString();
}

/// A unit tetrahedron, faces counter-clockwise seen from outside (closed, outward).
const std::string TETRAHEDRON = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/// The tetrahedron with every vertex moved by `dy` along y.
std::string movedTetrahedron(double dy) {
    const std::string y = std::to_string(dy);
    const std::string y1 = std::to_string(1 + dy);
    return "v 0 " + y + " 0\nv 1 " + y + " 0\nv 0 " + y1 + " 0\nv 0 " + y + " 1\n" +
           "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
}

const sim::ObstacleSpec& onlyObstacle(const Result<sim::SceneSpec>& loaded) {
    EXPECT_EQ(loaded.value().obstacles.size(), 1U);
    return loaded.value().obstacles.at(0);
}

TEST(SceneFileObstacles, NoObstaclesByDefault) {
    const auto loaded = parseObstacleScene(obstacleSceneText(""));
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    EXPECT_TRUE(loaded.value().obstacles.empty());
    const sim::ClothSpec& cloth = loaded.value().cloths[0];
    EXPECT_EQ(cloth.thickness, 0.002);
    EXPECT_FALSE(cloth.selfCollision);
    const sim::CollisionOptions defaults;
    EXPECT_EQ(loaded.value().collision.continuous, defaults.continuous);
    EXPECT_EQ(loaded.value().collision.iterations, defaults.iterations);
}

TEST(SceneFileObstacles, GeneratedShapes) {
    struct Case {
        std::string shape;
        bool closed;
        long triangles; ///< expected count, or 0 = only > 0
    };
    const Case cases[] = {
        {R"({"type": "plane"})", false, 2},
        {R"({"type": "plane", "size": 3, "cells": 4})", false, 32},
        {R"({"type": "sphere", "radius": 0.3})", true, 20 * 256},
        {R"({"type": "sphere", "radius": 0.3, "subdivisions": 2})", true, 20 * 16},
        {R"({"type": "box", "size": [1, 0.5, 0.25]})", true, 12},
        {R"({"type": "box", "size": [1, 0.5, 0.25], "cells": 2})", true, 48},
        {R"({"type": "capsule", "radius": 0.1, "length": 0.5})", true, 0},
        {R"({"type": "capsule", "radius": 0.1, "length": 0.5, "segments": 8})", true, 0},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.shape);
        const auto loaded = parseObstacleScene(obstacleSceneText(R"({"shape": )" + c.shape + "}"));
        ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
        const sim::ObstacleSpec& o = onlyObstacle(loaded);
        EXPECT_EQ(o.name, "obstacle0");
        EXPECT_GT(o.vertices.rows(), 0);
        EXPECT_GT(o.triangles.rows(), 0);
        if (c.triangles > 0) {
            EXPECT_EQ(o.triangles.rows(), c.triangles);
        }
        EXPECT_EQ(o.closed, c.closed);
        EXPECT_EQ(sim::isClosedOriented(o.triangles, static_cast<int>(o.vertices.rows())),
                  c.closed);
        // Static at the origin: one key at t = 0.
        ASSERT_EQ(o.keys.size(), 1U);
        EXPECT_EQ(o.keys[0].time, 0);
        EXPECT_EQ(o.keys[0].translation, sim::Vec3::Zero());
        EXPECT_EQ(o.keys[0].rotation, sim::Vec3::Zero());
        EXPECT_TRUE(o.frames.empty());
        EXPECT_EQ(o.thickness, 0.002);
        EXPECT_EQ(o.staticFriction, 0.4);
        EXPECT_EQ(o.kineticFriction, 0.3);
    }

    // Generated shapes are centred at the origin: the plane in XZ, the capsule along Y.
    const auto plane =
        parseObstacleScene(obstacleSceneText(R"({"shape": {"type": "plane", "size": 3}})"));
    ASSERT_TRUE(plane.ok()) << plane.error().toString();
    EXPECT_NEAR(onlyObstacle(plane).vertices.col(1).cwiseAbs().maxCoeff(), 0, 1e-15);
    EXPECT_NEAR(onlyObstacle(plane).vertices.col(0).maxCoeff(), 1.5, 1e-12);
    const auto capsule = parseObstacleScene(
        obstacleSceneText(R"({"shape": {"type": "capsule", "radius": 0.1, "length": 0.5}})"));
    ASSERT_TRUE(capsule.ok()) << capsule.error().toString();
    EXPECT_NEAR(onlyObstacle(capsule).vertices.col(1).maxCoeff(), 0.35, 1e-12);
    EXPECT_NEAR(onlyObstacle(capsule).vertices.col(0).maxCoeff(), 0.1, 1e-12);

    // A sphere may be declared two-sided.
    const auto open = parseObstacleScene(
        obstacleSceneText(R"({"shape": {"type": "sphere", "radius": 0.3}, "closed": false})"));
    ASSERT_TRUE(open.ok()) << open.error().toString();
    EXPECT_FALSE(onlyObstacle(open).closed);
}

TEST(SceneFileObstacles, StaticPoseAndSurface) {
    const auto loaded = parseObstacleScene(obstacleSceneText(R"({
        "name": "ball", "description": "a ball",
        "shape": {"type": "sphere", "radius": 0.3, "subdivisions": 1},
        "position": [0, 0.3, 0], "rotation_deg": [0, 90, 0],
        "thickness": 0.003, "static_friction": 0.6, "kinetic_friction": 0.5})"));
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::ObstacleSpec& o = onlyObstacle(loaded);
    EXPECT_EQ(o.name, "ball");
    EXPECT_EQ(o.thickness, 0.003);
    EXPECT_EQ(o.staticFriction, 0.6);
    EXPECT_EQ(o.kineticFriction, 0.5);
    ASSERT_EQ(o.keys.size(), 1U);
    EXPECT_EQ(o.keys[0].time, 0);
    EXPECT_EQ(o.keys[0].translation, sim::Vec3(0, 0.3, 0));
    EXPECT_NEAR((o.keys[0].rotation - sim::Vec3(0, std::numbers::pi / 2, 0)).norm(), 0, 1e-15);
    // The mesh stays in the obstacle's own frame; the key places it.
    EXPECT_NEAR(o.vertices.rowwise().norm().maxCoeff(), 0.3, 1e-12);
    sim::MatX3 world;
    sim::obstaclePositionsAt(o, 1.0, world);
    EXPECT_NEAR((world.colwise().mean() - Eigen::RowVector3d(0, 0.3, 0)).norm(), 0, 1e-12);
}

TEST(SceneFileObstacles, MotionKeys) {
    const auto loaded = parseObstacleScene(obstacleSceneText(R"({
        "name": "spinner", "shape": {"type": "box", "size": [0.2, 0.2, 0.2]},
        "position": [0, 0.3, 0],
        "motion": {"keys": [{"time": 0},
                            {"time": 2, "position": [1, 0.3, 0], "rotation_deg": [0, 1440, 0]},
                            {"time": 3, "rotation_deg": [0, 1440, 0]}]}})"));
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::ObstacleSpec& o = onlyObstacle(loaded);
    ASSERT_EQ(o.keys.size(), 3U);
    EXPECT_EQ(o.keys[0].time, 0);
    EXPECT_EQ(o.keys[0].translation, sim::Vec3(0, 0.3, 0)); // the static pose
    EXPECT_EQ(o.keys[0].rotation, sim::Vec3::Zero());
    EXPECT_EQ(o.keys[1].time, 2);
    EXPECT_EQ(o.keys[1].translation, sim::Vec3(1, 0.3, 0));
    EXPECT_NEAR(o.keys[1].rotation.y(), 8 * std::numbers::pi, 1e-12); // four turns, not reduced
    EXPECT_EQ(o.keys[2].translation, sim::Vec3(0, 0.3, 0));
    EXPECT_TRUE(sim::obstacleMoves(o));
}

TEST(SceneFileObstacles, ObjObstacles) {
    test::TempDir dir;
    dir.write("tet.obj", TETRAHEDRON);
    const auto loaded = parseObstacleScene(obstacleSceneText(R"({"name": "tet",
        "shape": {"type": "obj", "path": "tet.obj", "scale": 2}})"),
                                           dir.path());
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::ObstacleSpec& o = onlyObstacle(loaded);
    EXPECT_EQ(o.vertices.rows(), 4);
    EXPECT_EQ(o.triangles.rows(), 4);
    EXPECT_TRUE(o.closed);                                     // detected
    EXPECT_EQ(o.vertices.row(2), Eigen::RowVector3d(0, 2, 0)); // scaled
    ASSERT_EQ(o.keys.size(), 1U);

    // UV seams are welded back: a tetrahedron with one texture coordinate per face corner
    // is still closed, with 4 vertices.
    dir.write("tet-uv.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                            "vt 0 0\nvt 1 0\nvt 0 1\n"
                            "f 1/1 3/2 2/3\nf 1/1 2/2 4/3\nf 1/3 4/2 3/1\nf 2/1 3/2 4/3\n");
    const auto welded = parseObstacleScene(
        obstacleSceneText(R"({"shape": {"type": "obj", "path": "tet-uv.obj"}})"), dir.path());
    ASSERT_TRUE(welded.ok()) << welded.error().toString();
    EXPECT_EQ(onlyObstacle(welded).vertices.rows(), 4);
    EXPECT_TRUE(onlyObstacle(welded).closed);

    // An open mesh (one triangle) is detected as two-sided.
    dir.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 0 -1\nf 1 2 3\n");
    const auto open = parseObstacleScene(
        obstacleSceneText(R"({"shape": {"type": "obj", "path": "open.obj"}})"), dir.path());
    ASSERT_TRUE(open.ok()) << open.error().toString();
    EXPECT_FALSE(onlyObstacle(open).closed);
}

TEST(SceneFileObstacles, ObjFrames) {
    test::TempDir dir;
    dir.write("tet.obj", TETRAHEDRON);
    dir.write("tet_000.obj", movedTetrahedron(0));
    dir.write("tet_001.obj", movedTetrahedron(0.5));
    const auto loaded =
        parseObstacleScene(obstacleSceneText(R"({"shape": {"type": "obj", "path": "tet.obj",
        "scale": 2}, "position": [0, 1, 0],
        "frames": {"times": [0, 0.5], "paths": ["tet_000.obj", "tet_001.obj"]}})"),
                           dir.path());
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::ObstacleSpec& o = onlyObstacle(loaded);
    ASSERT_EQ(o.frames.size(), 2U);
    ASSERT_EQ(o.frameTimes.size(), 2U);
    EXPECT_EQ(o.frameTimes[1], 0.5);
    EXPECT_TRUE(o.keys.empty()); // frames replace the rigid pose
    // Scaled, then placed by the static pose.
    EXPECT_NEAR((o.frames[0].row(2) - Eigen::RowVector3d(0, 3, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((o.frames[1].row(2) - Eigen::RowVector3d(0, 4, 0)).norm(), 0, 1e-12);
    EXPECT_TRUE(sim::obstacleMoves(o));
}

TEST(SceneFileObstacles, ClothCollisionFieldsAndOptions) {
    const auto loaded = parseObstacleScene(obstacleSceneText(
        R"({"shape": {"type": "plane"}})",
        R"(, "collision": {"continuous": false, "iterations": 7, "proximity_factor": 0.25,
             "extraction_speed": 2.5, "solve_contacts": false, "contact_stiffness": 40,
             "contact_layer": 0.5, "friction_slip_speed": 0.002, "solve_self_contacts": false})",
        R"(, "thickness": 0.004, "self_collision": true)"));
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::SceneSpec& scene = loaded.value();
    EXPECT_EQ(scene.cloths[0].thickness, 0.004);
    EXPECT_TRUE(scene.cloths[0].selfCollision);
    EXPECT_FALSE(scene.collision.continuous);
    EXPECT_EQ(scene.collision.iterations, 7);
    EXPECT_EQ(scene.collision.proximityFactor, 0.25);
    EXPECT_EQ(scene.collision.extractionSpeed, 2.5);
    EXPECT_FALSE(scene.collision.solveContacts);
    EXPECT_EQ(scene.collision.solve.stiffness, 40.0);
    EXPECT_EQ(scene.collision.solve.margin, 0.5);
    EXPECT_EQ(scene.collision.solve.slipSpeed, 0.002);
    EXPECT_FALSE(scene.collision.solve.selfContacts); // the default is true
}

TEST(SceneFileObstacles, ErrorsNameTheJsonPointer) {
    test::TempDir dir;
    dir.write("tet.obj", TETRAHEDRON);
    dir.write("tet_000.obj", movedTetrahedron(0));
    dir.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 0 -1\nf 1 2 3\n");
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 0 -1\nf 1 2 3\n");
    // Inside out: every face of the tetrahedron reversed.
    dir.write("inverted.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                              "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n");
    const auto at = [&](const std::string& obstacle) {
        return parseObstacleScene(obstacleSceneText(obstacle), dir.path());
    };

    expectObstacleError(at(R"({"shape": {"type": "cone"}})"), "/obstacles/0/shape/type",
                        "unknown shape type");
    expectObstacleError(at(R"({"shape": {"type": "plane"}, "thickness": -0.001})"),
                        "/obstacles/0/thickness", "must not be negative");
    expectObstacleError(at(R"({"shape": {"type": "plane"}, "kinetic_friction": -1})"),
                        "/obstacles/0/kinetic_friction", "must not be negative");
    expectObstacleError(at(R"({"shape": {"type": "obj", "path": "open.obj"}, "closed": true})"),
                        "/obstacles/0/closed", "not closed");
    expectObstacleError(at(R"({"shape": {"type": "plane"}, "closed": true})"),
                        "/obstacles/0/closed", "not closed");
    expectObstacleError(at(R"({"shape": {"type": "obj", "path": "inverted.obj"}})"),
                        "/obstacles/0/shape", "inward");
    expectObstacleError(at(R"({"shape": {"type": "plane"},
        "motion": {"keys": [{"time": 0}, {"time": 1}, {"time": 1}]}})"),
                        "/obstacles/0/motion/keys/2/time", "increase");
    expectObstacleError(at(R"({"shape": {"type": "plane"}, "motion": {"keys": []}})"),
                        "/obstacles/0/motion/keys", "at least one key");
    expectObstacleError(at(R"({"shape": {"type": "obj", "path": "tet.obj"},
        "frames": {"times": [0, 1], "paths": ["tet_000.obj", "tri.obj"]}})"),
                        "/obstacles/0/frames/paths/1", "3 vertices");
    expectObstacleError(at(R"({"shape": {"type": "obj", "path": "tet.obj"},
        "frames": {"times": [0, 1], "paths": ["tet_000.obj"]}})"),
                        "/obstacles/0/frames/paths", "one per time");
    expectObstacleError(at(R"({"shape": {"type": "obj", "path": "tet.obj"},
        "frames": {"times": [1, 0], "paths": ["tet_000.obj", "tet_000.obj"]}})"),
                        "/obstacles/0/frames/times/1", "increase");
    expectObstacleError(at(R"({"shape": {"type": "sphere", "radius": 1},
        "frames": {"times": [0], "paths": ["tet_000.obj"]}})"),
                        "/obstacles/0/frames", "obj");
    expectObstacleError(at(R"({"shape": {"type": "obj", "path": "tet.obj"},
        "motion": {"keys": [{"time": 0}]}, "frames": {"times": [0], "paths": ["tet.obj"]}})"),
                        "/obstacles/0/frames", "not both");
    expectObstacleError(at(R"({"shape": {"type": "plane"}, "colour": "red"})"),
                        "/obstacles/0/colour", "unknown key");
    expectObstacleError(at(R"({"shape": {"type": "sphere", "radius": 1, "size": 2}})"),
                        "/obstacles/0/shape/size", "unknown key");
    expectObstacleError(
        at(R"({"shape": {"type": "plane"}, "motion": {"keys": [{"time": 0, "pos": [0, 0, 0]}]}})"),
        "/obstacles/0/motion/keys/0/pos", "unknown key");
    expectObstacleError(at(R"({"shape": {"type": "sphere", "radius": 1, "subdivisions": 8}})"),
                        "/obstacles/0/shape/subdivisions", "[0, 7]");
    expectObstacleError(at(R"({"shape": {"type": "sphere"}})"), "/obstacles/0/shape",
                        "missing required key \"radius\"");
    expectObstacleError(at(R"({"shape": {"type": "box", "size": [1, 0, 1]}})"),
                        "/obstacles/0/shape/size", "positive");
    expectObstacleError(at(R"({"shape": {"type": "obj", "path": "missing.obj"}})"),
                        "/obstacles/0/shape/path", "missing.obj");
    expectObstacleError(
        at(R"({"shape": {"type": "plane"}}, {"name": "obstacle0", "shape": {"type": "plane"}})"),
        "/obstacles/1/name", "already named");
    expectObstacleError(parseObstacleScene(obstacleSceneText("", "", R"(, "thickness": -1)")),
                        "/cloths/0/thickness", "must not be negative");
    expectObstacleError(parseObstacleScene(obstacleSceneText("", "", R"(, "self_collision": 1)")),
                        "/cloths/0/self_collision", "true or false");
    const struct {
        const char* top; ///< appended to the scene's top level
        const char* where;
        const char* message;
    } collisionCases[] = {
        {R"(, "collision": {"iterations": 0})", "/collision/iterations", "an integer in [1, 1000]"},
        {R"(, "collision": {"iterations": 1.5})", "/collision/iterations", "integer"},
        {R"(, "collision": {"extraction_speed": 0})", "/collision/extraction_speed", "positive"},
        {R"(, "collision": {"contact_layer": 0})", "/collision/contact_layer", "positive"},
        {R"(, "collision": {"proximity_factor": -0.5})", "/collision/proximity_factor",
         "must not be negative"},
        {R"(, "collision": {"continous": true})", "/collision/continous", "unknown key"},
    };
    for (const auto& c : collisionCases) {
        expectObstacleError(parseObstacleScene(obstacleSceneText("", c.top)), c.where, c.message);
    }
}

} // namespace
} // namespace atelier::io
