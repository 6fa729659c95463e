// Hostile input found by fuzzing: each case is the tiny input that crashed, hung or ran away
// with memory, now an error naming the place.
#include "io/atomic_file.h"
#include "io/body_file.h"
#include "io/json_reader.h"
#include "io/materials.h"
#include "io/obj.h"
#include "io/project_file.h"
#include "io/scene_file.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <string>

namespace atelier::io {
namespace {

const std::string GRID = R"({"type": "rectangle", "width": 0.2, "height": 0.2, "cells": [2, 2]})";

/// A valid scene with `top` spliced into the top-level object, the cloth's `mesh` and
/// `moreCloths` after it.
std::string hostileSceneText(const std::string& top = "", const std::string& mesh = GRID,
                             const std::string& moreCloths = "") {
    return R"({"format": "atelier-scene", "version": 1,
  "cloths": [{"name": "sheet", "material": "cotton",
    "mesh": )" +
           mesh + "}" + moreCloths + "]" + top + "}";
}

/// The error as `file: where: message`.
template <class T> std::string errorOf(const Result<T>& result) {
    return result.ok() ? std::string("(no error)") : result.error().toString();
}

// ---------------------------------------------------------------------------------------------
// JSON nesting and duplicate keys (every JSON file goes through detail::parseJson)

TEST(HostileJson, DeepNestingIsAnErrorNotAStackOverflow) {
    const std::string deep = std::string(200'000, '[') + R"(, "format": 1})";
    EXPECT_EQ(errorOf(parseScene(deep, "s.json", ".")),
              "s.json: line 1, column 257: nested deeper than 256 arrays and objects");
    EXPECT_EQ(errorOf(parseProject("{\"a\":\n" + deep, "p.atelier")),
              "p.atelier: line 2, column 256: nested deeper than 256 arrays and objects");
    EXPECT_FALSE(parseMaterialPresets(deep, "f.json").ok());
    // Up to the limit the structure passes; the parser then reads it.
    const std::string ok = std::string(256, '[') + std::string(256, ']');
    EXPECT_TRUE(detail::parseJson(ok, "x.json").ok());
    EXPECT_FALSE(detail::parseJson("[" + ok + "]", "x.json").ok());
}

TEST(HostileJson, DuplicateKeysNameBothPlacesAndTheObject) {
    EXPECT_EQ(errorOf(parseScene(R"({"format": "atelier-scene",
 "version": 1, "format": "x"})",
                                 "s.json", ".")),
              "s.json: line 2, column 16: duplicate key \"format\" in the object at / (first at "
              "line 1, column 2)");
    EXPECT_EQ(errorOf(parseScene(hostileSceneText("", R"({"type": "rectangle", "type": "obj"})"),
                                 "s.json", ".")),
              "s.json: line 3, column 35: duplicate key \"type\" in the object at "
              "/cloths/0/mesh (first at line 3, column 14)");
    // Escapes are decoded before keys are compared; keys of other objects and strings that
    // are values are not keys of this object.
    EXPECT_NE(errorOf(detail::parseJson(R"({"a": 1, "\u0061": 2})", "x.json"))
                  .find("duplicate key \"a\""),
              std::string::npos);
    EXPECT_TRUE(
        detail::parseJson(R"({"a": "a", "b": {"a": ["a", {"a": 1}]}, "c": "\"a"})", "x.json").ok());
    // Pointers name array elements and escape '/' and '~'.
    EXPECT_NE(errorOf(detail::parseJson(R"({"x/y": [0, {"k": 1, "k": 2}]})", "x.json"))
                  .find("in the object at /x~1y/1 "),
              std::string::npos);
}

TEST(HostileJson, ProjectsAndPresetFilesRefuseDuplicateKeys) {
    EXPECT_NE(errorOf(parseProject(R"({"format": "atelier-project", "version": 2,
                                       "version": 2})",
                                   "p.atelier"))
                  .find("duplicate key \"version\""),
              std::string::npos);
    EXPECT_NE(errorOf(parseMaterialPresets(R"({"format": "atelier-fabrics", "version": 1,
        "presets": {"a": {}, "a": {}}})",
                                           "f.json"))
                  .find("duplicate key \"a\" in the object at /presets"),
              std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Scene limits

TEST(HostileScene, HugeCellCountsAreRefusedWithTheirSize) {
    // (n + 1)² overflowed 64 bits and passed as a tiny grid.
    EXPECT_EQ(
        errorOf(parseScene(
            hostileSceneText("", R"({"type": "rectangle", "cells": [3037000499, 3037000499]})"),
            "s.json", ".")),
        "s.json: /cloths/0/mesh/cells: a grid of 3037000499 × 3037000499 cells has "
        "9.22337203700025e+18 vertices, more than the limit of 4000000");
}

TEST(HostileScene, FrameRateFramesAndStepsAreBounded) {
    EXPECT_EQ(errorOf(parseScene(hostileSceneText(R"(, "frame_rate": 1e300)"), "s.json", ".")),
              "s.json: /frame_rate: must be at most 1000.0 frames per second (found 1e+300)");
    EXPECT_EQ(errorOf(parseScene(hostileSceneText(R"(, "duration": 1e6)"), "s.json", ".")),
              "s.json: /duration: duration × frame_rate is 30000000.0 frames, more than the "
              "limit of 100000");
    EXPECT_EQ(errorOf(parseScene(hostileSceneText(R"(, "duration": 3000, "integrator": {"dt": 1e-9,
            "min_dt": 1e-10})"),
                                 "s.json", ".")),
              "s.json: /duration: duration / integrator dt is 3000000000000.0 steps, more than the "
              "limit of 1000000000");
}

TEST(HostileScene, ContactThicknessIsBounded) {
    // Metres of contact layer made every primitive a contact candidate of every other: found by
    // the fuzzer as a hang (cloth) and bad_alloc (obstacle).
    EXPECT_EQ(
        errorOf(parseScene(hostileSceneText("", GRID + R"(, "thickness": 1e9)"), "s.json", ".")),
        "s.json: /cloths/0/thickness: must be at most 0.05 (the limit thickness-m; found "
        "1000000000.0)");
    EXPECT_EQ(errorOf(parseScene(hostileSceneText(R"(, "obstacles": [{"name": "floor",
            "shape": {"type": "plane", "size": 4}, "thickness": 1.003}])"),
                                 "s.json", ".")),
              "s.json: /obstacles/0/thickness: must be at most 0.05 (the limit thickness-m; found "
              "1.003)");
    EXPECT_TRUE(
        parseScene(hostileSceneText("", GRID + R"(, "thickness": 0.05)"), "s.json", ".").ok());
    SceneLoadOptions raised;
    raised.limits.maxThickness = 2.0;
    EXPECT_TRUE(
        parseScene(hostileSceneText("", GRID + R"(, "thickness": 1.5)"), "s.json", ".", raised)
            .ok());
}

TEST(HostileScene, ClothCountAndSceneSizeAreBounded) {
    std::string cloths;
    for (int i = 0; i < 400; ++i) {
        cloths += std::string(i == 0 ? "" : ", ") + R"({"name": "c)" + std::to_string(i) +
                  R"(", "material": "cotton", "mesh": {"type": "rectangle"}})";
    }
    const std::string many =
        R"({"format": "atelier-scene", "version": 1, "cloths": [)" + cloths + "]}";
    EXPECT_EQ(errorOf(parseScene(many, "s.json", ".")),
              "s.json: /cloths: 400 cloths, more than the limit of 256");
    // Each cloth under the per-cloth size, together over the scene's (a lowered limit).
    SceneLoadOptions options;
    options.limits.maxSceneVertices = 50;
    const std::string two = hostileSceneText("", GRID, R"(, {"name": "b", "material": "cotton",
          "mesh": {"type": "rectangle", "cells": [6, 6]}})");
    EXPECT_EQ(errorOf(parseScene(two, "s.json", ".", options)),
              "s.json: /cloths/1/mesh: the scene reaches 58 vertices here, more than the limit "
              "of 50");
}

TEST(HostileScene, CoordinatesAndBodyMeshesAreBounded) {
    EXPECT_EQ(errorOf(parseScene(hostileSceneText(R"(, "obstacles": [{"shape": {"type": "sphere",
                                    "radius": 1e300}}])"),
                                 "s.json", ".")),
              "s.json: /obstacles/0/shape: the shape's vertices reach 1e+300 m from the origin, "
              "more than the 100.0 m a scene spans");
    const test::TempDir dir;
    dir.write("big.obj", "v 0 0 0\nv 5 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"
                         "f 2 3 4\n");
    EXPECT_EQ(errorOf(parseScene(hostileSceneText(R"(, "obstacles": [{"shape": {"type": "obj",
                                    "path": "big.obj"}}])"),
                                 "s.json", dir.path())),
              "s.json: /obstacles/0/shape/path: big.obj: the mesh is 5.0 m along x, more than "
              "the 3.0 m a body may measure (a body mesh is in metres, Y up)");
    patterns::BodySource body;
    body.meshPath = "big.obj";
    EXPECT_EQ(errorOf(loadBody(body, dir.path(), dir / "p.atelier")),
              (dir / "big.obj").string() +
                  ": the mesh is 5.0 m along x, more than the 3.0 m a body may measure (a body "
                  "mesh is in metres, Y up)");
}

// ---------------------------------------------------------------------------------------------
// Paths: special files, size limits

TEST(HostilePaths, SpecialFilesAreRefusedWithoutReading) {
    const std::string zero = hostileSceneText("", R"({"type": "obj", "path": "/dev/zero"})");
    EXPECT_EQ(errorOf(parseScene(zero, "s.json", ".")),
              "s.json: /cloths/0/mesh/path: /dev/zero: not a regular file (a character device)");
    const test::TempDir dir;
    const std::filesystem::path fifo = dir / "fifo.obj";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    // Opening a FIFO used to wait for a writer for ever.
    EXPECT_EQ(errorOf(readObj(fifo)), fifo.string() + ": not a regular file (a FIFO)");
    EXPECT_EQ(errorOf(loadScene(dir.path())), dir.path().string() + ": not a regular file (a "
                                                                    "directory)");
    dir.write("p.atelier", R"({"format": "atelier-project", "version": 2,
                               "body": {"mesh": "fifo.obj"}})");
    EXPECT_EQ(errorOf(loadProject(dir / "p.atelier")),
              (dir / "p.atelier").string() +
                  ": /body/mesh: body mesh is not a regular file: " + fifo.string());
}

TEST(HostilePaths, SymlinksToRegularFilesAndAbsolutePathsAreRead) {
    const test::TempDir dir;
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
    std::filesystem::create_symlink(dir / "tri.obj", dir / "link.obj");
    EXPECT_TRUE(readObj(dir / "link.obj").ok());
    const std::string absolute =
        hostileSceneText("", R"({"type": "obj", "path": ")" + (dir / "link.obj").string() + "\"}");
    EXPECT_TRUE(parseScene(absolute, "s.json", "/nonexistent").ok())
        << errorOf(parseScene(absolute, "s.json", "/nonexistent"));
}

TEST(HostilePaths, FilesOverTheSizeLimitAreRefusedBeforeReading) {
    const test::TempDir dir;
    dir.write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_EQ(errorOf(readObj(dir / "tri.obj", 10)),
              (dir / "tri.obj").string() + ": file too large: 32 bytes (the limit is 10 bytes)");
    dir.write("s.json", hostileSceneText());
    SceneLoadOptions options;
    options.limits.maxJsonBytes = 100;
    EXPECT_NE(errorOf(loadScene(dir / "s.json", options)).find("file too large"),
              std::string::npos);
    EXPECT_TRUE(loadScene(dir / "s.json").ok());
}

// ---------------------------------------------------------------------------------------------
// Names written into files

TEST(HostileNames, InvalidUtf8IsRefusedOnLoadAndReplacedOnWrite) {
    // Reading: a name that is not UTF-8 is invalid JSON, at its line and column.
    const auto loaded =
        parseProject("{\"format\": \"atelier-project\",\n\"name\": \"a\xff\"}", "p.atelier");
    ASSERT_FALSE(loaded.ok());
    EXPECT_EQ(loaded.error().where.rfind("line 2, column ", 0), 0U) << errorOf(loaded);
    EXPECT_NE(loaded.error().message.find("invalid JSON"), std::string::npos);
    // Writing a name made in code (an editor, a path): replaced, never thrown.
    patterns::Project project;
    project.name = "a\xff";
    EXPECT_NE(formatProject(project).find("\"name\": \"a\xEF\xBF\xBD\""), std::string::npos);
    EXPECT_EQ(detail::inQuotes("a\xff"), "\"a\xEF\xBF\xBD\"");
}

} // namespace
} // namespace atelier::io
