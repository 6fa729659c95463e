#include "io/obj.h"
#include "io/scene_file.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>

namespace atelier::io {
namespace {

const std::filesystem::path SCENES = std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/scenes";

/// A small valid scene; `extraTop` is spliced into the top-level object and `extraCloth`
/// into the cloth.
std::string sceneText(const std::string& extraTop = "", const std::string& extraCloth = "",
                      const std::string& material = R"("cotton")") {
    return R"({
  "format": "atelier-scene",
  "version": 1,
  "cloths": [{
    "name": "sheet",
    "mesh": {"type": "rectangle", "width": 1, "height": 0.5, "cells": [4, 2]},
    "material": )" +
           material + extraCloth + R"(
  }],
  "pins": [{"cloth": "sheet", "corner": "top-left"}])" +
           extraTop + R"(
})";
}

Result<sim::SceneSpec> sceneFrom(const std::string& text, const std::filesystem::path& dir = ".",
                                 bool validate = true) {
    SceneLoadOptions options;
    options.validate = validate;
    return parseScene(text, "scene.json", dir, options);
}

void expectSceneError(const Result<sim::SceneSpec>& result, const std::string& where,
                      const std::string& fragment) {
    ASSERT_FALSE(result.ok()) << "expected an error at " << where;
    EXPECT_EQ(result.error().file, "scene.json");
    EXPECT_EQ(result.error().where, where) << result.error().toString();
    EXPECT_NE(result.error().message.find(fragment), std::string::npos)
        << result.error().toString();
}

TEST(SceneFile, EveryBundledSceneLoads) {
    int count = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(SCENES)) {
        if (entry.path().extension() != ".json") {
            continue;
        }
        SCOPED_TRACE(entry.path().string());
        const auto scene = loadScene(entry.path());
        ASSERT_TRUE(scene.ok()) << scene.error().toString();
        EXPECT_FALSE(scene.value().cloths.empty());
        EXPECT_GT(scene.value().duration, 0);
        int vertices = 0;
        for (const auto& cloth : scene.value().cloths) {
            vertices += cloth.mesh.vertexCount();
            EXPECT_EQ(cloth.position.rows(), cloth.mesh.vertexCount());
            EXPECT_TRUE(cloth.position.allFinite());
        }
        EXPECT_LE(vertices, 1200) << "bundled scenes stay small (CI runs them all)";
        ++count;
    }
    EXPECT_GE(count, 15);
}

TEST(SceneFile, HangingSheetContents) {
    const auto loaded = loadScene(SCENES / "hanging-sheet.json");
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::SceneSpec& scene = loaded.value();
    ASSERT_EQ(scene.cloths.size(), 1U);
    const sim::ClothSpec& cloth = scene.cloths[0];
    EXPECT_EQ(cloth.mesh.vertexCount(), 21 * 21);
    EXPECT_EQ(cloth.material.name, "cotton");
    EXPECT_EQ(cloth.model, sim::StretchModel::Fem);
    EXPECT_EQ(scene.integrator.kind, sim::IntegratorKind::Rk45);
    // Top corners (max warp y): (0, 20) and (20, 20) of the 21 × 21 grid.
    EXPECT_EQ(scene.pins, (std::vector<int>{20 * 21, 20 * 21 + 20}));
    // Placement: origin + x·u + y·v with v = -z.
    EXPECT_TRUE(cloth.position.row(20 * 21 + 20).isApprox(Eigen::RowVector3d(0.5, 1.5, 0.0)));
}

TEST(SceneFile, PlacementPinsDrivesAndSettings) {
    const auto loaded =
        sceneFrom(sceneText(R"(,
  "drives": [{"cloth": 0, "corner": "bottom-right", "relative": true,
              "keys": [[0, 0, 0, 0], [1, 0, 2, 0]], "release_time": 1.5},
             {"cloth": "sheet", "edge": "top", "relative": true, "keys": [[0, 1, 0, 0]]}],
  "seams": [{"cloth_a": "sheet", "vertex_a": 0, "cloth_b": "sheet", "corner_b": "top-right"}],
  "gravity": [0, 0, -1],
  "air": {"drag": 0.2, "wind": [1, 0, 0]},
  "integrator": {"type": "implicit-euler", "dt": 0.01, "max_dt": 0.02},
  "duration": 2.5,
  "frame_rate": 24)",
                            R"(,
    "placement": {"origin": [1, 2, 3], "u_axis": [0, 0, 2], "v_axis": [0, 1, 0]},
    "model": "springs", "cross_springs": true)"),
                  ".", /*validate=*/false); // the loader only, not the engine's checks
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::SceneSpec& scene = loaded.value();
    const sim::ClothSpec& cloth = scene.cloths[0];
    // Vertex (i, j) = j·5 + i at rest (i·0.25, j·0.25); u = +z (normalized), v = +y.
    EXPECT_TRUE(cloth.position.row(4).isApprox(Eigen::RowVector3d(1, 2, 4)));
    EXPECT_TRUE(cloth.position.row(2 * 5).isApprox(Eigen::RowVector3d(1, 2.5, 3)));
    EXPECT_EQ(cloth.model, sim::StretchModel::Springs);
    EXPECT_TRUE(cloth.crossSprings);
    ASSERT_EQ(scene.drives.size(), 1U + 5U);
    EXPECT_EQ(scene.drives[0].vertex, 4);
    EXPECT_TRUE(scene.drives[0].positions[1].isApprox(sim::Vec3(1, 4, 4)));
    EXPECT_EQ(scene.drives[0].releaseTime, 1.5);
    EXPECT_EQ(scene.drives[1].vertex, 10);
    ASSERT_EQ(scene.seams.size(), 1U);
    EXPECT_EQ(scene.seams[0].b, 14);
    EXPECT_TRUE(scene.gravity);
    EXPECT_EQ(scene.gravityVector, sim::Vec3(0, 0, -1));
    EXPECT_TRUE(scene.air.enabled);
    EXPECT_EQ(scene.integrator.kind, sim::IntegratorKind::ImplicitEuler);
    EXPECT_EQ(scene.duration, 2.5);
    EXPECT_EQ(scene.frameRate, 24);
}

TEST(SceneFile, FoldsSetRestAnglesOfInteriorEdges) {
    const auto loaded = sceneFrom(sceneText("", R"(,
    "folds": [{"vertices": [6, 1], "angle_deg": 90}])"));
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::ClothSpec& cloth = loaded.value().cloths[0];
    ASSERT_EQ(cloth.restAngles.size(), cloth.mesh.hinges.rows());
    int folded = 0;
    for (int h = 0; h < cloth.mesh.hinges.rows(); ++h) {
        const bool isFold = (cloth.mesh.hinges(h, 0) == 1 && cloth.mesh.hinges(h, 1) == 6) ||
                            (cloth.mesh.hinges(h, 0) == 6 && cloth.mesh.hinges(h, 1) == 1);
        EXPECT_DOUBLE_EQ(cloth.restAngles[h], isFold ? std::acos(-1.0) / 2 : 0.0);
        folded += isFold ? 1 : 0;
    }
    EXPECT_EQ(folded, 1);
    // A border edge has no fold angle.
    expectSceneError(sceneFrom(sceneText("", R"(,
    "folds": [{"vertices": [0, 1], "angle_deg": 30}])")),
                     "/cloths/0/folds/0/vertices", "not an interior edge");
    expectSceneError(sceneFrom(sceneText("", R"(,
    "folds": [{"vertices": [6, 1], "angle_deg": 180}])")),
                     "/cloths/0/folds/0/angle_deg", "between");
}

TEST(SceneFile, MaterialOverridesAndRandomStart) {
    const auto loaded = sceneFrom(sceneText("", R"(,
    "initial": {"type": "random", "amplitude": 0.1, "seed": 3})",
                                            R"({"preset": "denim", "bending_n_m": 2e-4})"));
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::ClothSpec& cloth = loaded.value().cloths[0];
    EXPECT_EQ(cloth.material.name, "denim");
    EXPECT_EQ(cloth.material.bending, 2e-4);
    EXPECT_EQ(cloth.material.density, builtinMaterialPresets().at("denim").density);
    // Every free vertex moved, by at most the amplitude per coordinate; pinned vertices hold
    // the placement (else the crumpling would stretch the cloth between pins for good).
    const auto& pins = loaded.value().pins;
    for (int i = 0; i < cloth.mesh.vertexCount(); ++i) {
        const Eigen::RowVector3d rest(cloth.mesh.rest(i, 0), cloth.mesh.rest(i, 1), 0);
        const Eigen::RowVector3d d = cloth.position.row(i) - rest;
        EXPECT_LE(d.cwiseAbs().maxCoeff(), 0.1);
        if (std::find(pins.begin(), pins.end(), i) == pins.end()) {
            EXPECT_GT(d.norm(), 0);
        } else {
            EXPECT_EQ(d.norm(), 0);
        }
    }
    // Deterministic.
    const auto again = sceneFrom(sceneText("", R"(,
    "initial": {"type": "random", "amplitude": 0.1, "seed": 3})",
                                           R"({"preset": "denim", "bending_n_m": 2e-4})"));
    ASSERT_TRUE(again.ok());
    EXPECT_EQ(again.value().cloths[0].position, cloth.position);
}

TEST(SceneFile, ErrorsNameTheJsonPath) {
    expectSceneError(sceneFrom(sceneText(R"(, "duraton": 2)")), "/duraton", "unknown key");
    expectSceneError(sceneFrom(sceneText("", R"(, "bendng": true)")), "/cloths/0/bendng",
                     "unknown key");
    expectSceneError(sceneFrom(sceneText(R"(, "duration": "long")")), "/duration",
                     "expected a number");
    expectSceneError(sceneFrom(sceneText(R"(, "duration": 0)")), "/duration", "positive");
    expectSceneError(sceneFrom(sceneText("", "", R"("demin")")), "/cloths/0/material",
                     "unknown material");
    expectSceneError(
        sceneFrom(sceneText("", "", R"({"preset": "cotton", "density_kg_per_m2": -1})")),
        "/cloths/0/material/density_kg_per_m2", "positive");
    expectSceneError(sceneFrom(sceneText("", "", "42")), "/cloths/0/material",
                     "expected a preset name");
    expectSceneError(sceneFrom(sceneText("", R"(, "model": "mass-spring")")), "/cloths/0/model",
                     "unknown model");
    expectSceneError(sceneFrom(sceneText(R"(, "integrator": {"type": "rk5"})")), "/integrator/type",
                     "unknown integrator");
    expectSceneError(sceneFrom(sceneText(R"(, "integrator": {"dt": -1})")), "/integrator/dt",
                     "positive");
    expectSceneError(sceneFrom(sceneText(R"(, "seams": [{"cloth_a": "sheet", "vertex_a": 0,
        "cloth_b": "sheet", "vertex_b": 15}])")),
                     "/seams/0/vertex_b", "out of range");
    expectSceneError(
        sceneFrom(sceneText(R"(, "drives": [{"cloth": "sheet", "vertex": -1, "keys": []}])")),
        "/drives/0/vertex", "out of range");
    expectSceneError(
        sceneFrom(sceneText(R"(, "drives": [{"cloth": "shet", "vertex": 1, "keys": []}])")),
        "/drives/0/cloth", "no cloth named");
    expectSceneError(sceneFrom(sceneText(R"(, "drives": [{"cloth": 0, "vertex": 1,
        "keys": [[0, 0, 0, 0], [0, 1, 1, 1]]}])")),
                     "/drives/0/keys/1/0", "increase");
    expectSceneError(sceneFrom(sceneText(R"(, "gravity": [0, -9.8])")), "/gravity", "3 numbers");
    expectSceneError(
        sceneFrom(sceneText("", R"(, "placement": {"u_axis": [1, 0, 0], "v_axis": [2, 0, 0]})")),
        "/cloths/0/placement/v_axis", "parallel");
    expectSceneError(sceneFrom(R"({"format": "atelier-scene", "version": 2, "cloths": []})"),
                     "/version", "unsupported version");
    expectSceneError(sceneFrom(R"({"format": "atelier-scene", "version": 1, "cloths": []})"),
                     "/cloths", "at least one cloth");

    // Pins: a corner of a rectangle, an unknown edge name.
    const std::string pinsReplaced = std::regex_replace(
        sceneText(), std::regex(R"("corner": "top-left")"), R"("corner": "top-middle")");
    expectSceneError(sceneFrom(pinsReplaced), "/pins/0/corner", "unknown corner");

    // JSON syntax errors give the line.
    const auto syntax = sceneFrom("{\n  \"format\": \"atelier-scene\",\n  \"version\": 1,,\n}");
    ASSERT_FALSE(syntax.ok());
    EXPECT_EQ(syntax.error().where.substr(0, 7), "line 3,") << syntax.error().toString();
}

TEST(SceneFile, ObjMeshes) {
    test::TempDir dir;
    // A unit square in UV, two triangles; the 3D positions differ from the UVs.
    dir.write("square.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                            "vt 0 0\nvt 2 0\nvt 2 2\nvt 0 2\n"
                            "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
    const std::string obj = R"({"type": "obj", "path": "square.obj", "uv_scale": 0.5})";
    const std::string text =
        std::regex_replace(sceneText(), std::regex(R"(\{"type": "rectangle"[^}]*\})"), obj);
    const std::string withPin =
        std::regex_replace(text, std::regex(R"("corner": "top-left")"), R"("vertex": 2)");
    const auto loaded = sceneFrom(withPin, dir.path());
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    const sim::ClothSpec& cloth = loaded.value().cloths[0];
    EXPECT_EQ(cloth.mesh.vertexCount(), 4);
    EXPECT_EQ(cloth.mesh.rest.row(2), Eigen::RowVector2d(1, 1));   // UV × uv_scale
    EXPECT_EQ(cloth.position.row(2), Eigen::RowVector3d(1, 1, 0)); // the OBJ's own positions

    // Corners are only for rectangles.
    expectSceneError(sceneFrom(text, dir.path()), "/pins/0/corner", "only for rectangle");

    // A zero-area triangle in the rest shape (collinear UVs).
    dir.write("square.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                            "vt 0 0\nvt 1 0\nvt 2 0\nvt 0 1\n"
                            "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
    expectSceneError(sceneFrom(withPin, dir.path()), "/cloths/0/mesh", "zero area");

    // No UVs: no rest shape.
    dir.write("square.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n");
    expectSceneError(sceneFrom(withPin, dir.path()), "/cloths/0/mesh/path", "texture coordinates");

    // A malformed OBJ: the error names the JSON path, the OBJ file and its line.
    dir.write("square.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 7\n");
    const auto broken = sceneFrom(withPin, dir.path());
    expectSceneError(broken, "/cloths/0/mesh/path", "line 4");
    EXPECT_NE(broken.error().message.find("square.obj"), std::string::npos);

    // A missing OBJ file.
    std::filesystem::remove(dir / "square.obj");
    expectSceneError(sceneFrom(withPin, dir.path()), "/cloths/0/mesh/path", "square.obj");
}

TEST(SceneFile, RectangleCorners) {
    EXPECT_EQ(rectangleCorner("bottom-left", 4, 2), 0);
    EXPECT_EQ(rectangleCorner("bottom-right", 4, 2), 4);
    EXPECT_EQ(rectangleCorner("top-left", 4, 2), 10);
    EXPECT_EQ(rectangleCorner("top-right", 4, 2), 14);
    EXPECT_EQ(rectangleCorner("middle", 4, 2), -1);
}

} // namespace
} // namespace atelier::io
