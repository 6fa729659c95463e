#include "io/obj.h"
#include "io/temp_dir.h"

#include "sim/mesh/cloth_mesh.h"

#include <gtest/gtest.h>

namespace atelier::io {
namespace {

/// One triangle in the z = 0 plane.
void oneTriangle(sim::MatX3& positions, sim::MatX3i& triangles) {
    positions.resize(3, 3);
    positions << 0, 0, 0, 1, 0, 0, 0, 1, 0;
    triangles.resize(1, 3);
    triangles << 0, 1, 2;
}

Result<ObjMesh> readText(const test::TempDir& dir, const std::string& text) {
    return readObj(dir.write("mesh.obj", text));
}

void expectErrorAtLine(const Result<ObjMesh>& result, int line, const std::string& fragment) {
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.error().where, "line " + std::to_string(line)) << result.error().toString();
    EXPECT_NE(result.error().message.find(fragment), std::string::npos)
        << result.error().toString();
    EXPECT_NE(result.error().file.find("mesh.obj"), std::string::npos);
}

TEST(Obj, RoundTripWithUvsAndGroups) {
    test::TempDir dir;
    sim::MatX2 rest;
    sim::MatX3i triangles;
    sim::RectangleOptions rect;
    rect.width = 0.7;
    rect.height = 0.3;
    rect.cellsX = 5;
    rect.cellsY = 3;
    rect.triangulation = sim::Triangulation::Irregular;
    sim::makeRectangle(rect, rest, triangles);
    sim::MatX3 positions(rest.rows(), 3);
    for (Eigen::Index i = 0; i < rest.rows(); ++i) {
        positions.row(i) << rest(i, 0) + 0.1, 1.0 / 3.0, -rest(i, 1) * 1e-7;
    }
    ObjWriteOptions options;
    options.uvs = rest;
    const int half = static_cast<int>(triangles.rows() / 2);
    options.groups = {{"front", 0, half},
                      {"back", half, static_cast<int>(triangles.rows()) - half}};
    options.comment = "test\nsecond line";
    const auto path = dir / "sheet.obj";
    const auto written = writeObj(path, positions, triangles, options);
    ASSERT_TRUE(written.ok()) << written.error().toString();

    const auto read = readObj(path);
    ASSERT_TRUE(read.ok()) << read.error().toString();
    const ObjMesh& mesh = read.value();
    // Exact: numbers are written in the shortest form that reads back identically.
    EXPECT_EQ(mesh.positions, positions);
    EXPECT_EQ(mesh.uvs, rest);
    EXPECT_EQ(mesh.triangles, triangles);
    ASSERT_EQ(mesh.groups.size(), 2U);
    EXPECT_EQ(mesh.groups[0].name, "front");
    EXPECT_EQ(mesh.groups[0].triangleCount, half);
    EXPECT_EQ(mesh.groups[1].name, "back");
    EXPECT_EQ(mesh.groups[1].firstTriangle, half);
}

TEST(Obj, GroupNamesAndCommentsCannotInjectStatements) {
    // A cloth or panel name with a newline used to write `v` and `f` lines of its own.
    sim::MatX3 positions;
    sim::MatX3i triangles;
    oneTriangle(positions, triangles);
    ObjWriteOptions options;
    options.normals = false;
    options.groups.push_back({"front\nv 9 9 9\nf 1 2 4 #x", 0, 1});
    options.comment = "a\rv 1 1 1\nb";
    const auto text = formatObj(positions, triangles, options);
    ASSERT_TRUE(text.ok());
    EXPECT_EQ(text.value(), "# a v 1 1 1\n# b\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                            "g front_v_9_9_9_f_1_2_4__x\nf 1 2 3\n");
}

TEST(Obj, RoundTripWithoutUvsOrNormals) {
    test::TempDir dir;
    sim::MatX3 positions;
    sim::MatX3i triangles;
    oneTriangle(positions, triangles);
    ObjWriteOptions options;
    options.normals = false;
    ASSERT_TRUE(writeObj(dir / "t.obj", positions, triangles, options).ok());
    const auto read = readObj(dir / "t.obj");
    ASSERT_TRUE(read.ok());
    EXPECT_EQ(read.value().positions, positions);
    EXPECT_EQ(read.value().uvs.rows(), 0);
    EXPECT_TRUE(read.value().groups.empty());
}

TEST(Obj, AllIndexFormsNegativeIndicesAndFans) {
    test::TempDir dir;
    const auto read = readText(dir, "# a quad and a triangle\n"
                                    "mtllib x.mtl\n"
                                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                    "vn 0 0 1\n"
                                    "o quad\n"
                                    "f 1 2 3 4\n"
                                    "g tri\n"
                                    "usemtl cloth\ns off\n"
                                    "f -4//-1 -3//1 -1//1\n");
    ASSERT_TRUE(read.ok()) << read.error().toString();
    const ObjMesh& mesh = read.value();
    ASSERT_EQ(mesh.triangles.rows(), 3);
    EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
    EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
    EXPECT_EQ(mesh.triangles.row(2), Eigen::RowVector3i(0, 1, 3));
    ASSERT_EQ(mesh.groups.size(), 2U);
    EXPECT_EQ(mesh.groups[0].name, "quad");
    EXPECT_EQ(mesh.groups[0].triangleCount, 2);
    EXPECT_EQ(mesh.groups[1].name, "tri");
}

TEST(Obj, UvSeamsSplitVertices) {
    test::TempDir dir;
    // Two triangles sharing the edge 1-3 in 3D but with different UVs on one side.
    const auto read = readText(dir, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 5 5\n"
                                    "f 1/1 2/2 3/3\n"
                                    "f 1/5/ 3/3 4/4\n");
    ASSERT_FALSE(read.ok()) << "'1/5/' has an empty normal index";
    const auto ok = readText(dir, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                  "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 5 5\n"
                                  "f 1/1 2/2 3/3\n"
                                  "f 1/5 3/3 4/4\n");
    ASSERT_TRUE(ok.ok()) << ok.error().toString();
    const ObjMesh& mesh = ok.value();
    EXPECT_EQ(mesh.positions.rows(), 5); // v1 appears with vt1 and vt5
    EXPECT_EQ(mesh.uvs.rows(), 5);
    for (int f = 0; f < 2; ++f) {
        for (int k = 0; k < 3; ++k) {
            const int v = mesh.triangles(f, k);
            EXPECT_EQ(mesh.positions.row(v),
                      mesh.positions.row(v)); // finite
            EXPECT_GE(mesh.sourceVertex[static_cast<std::size_t>(v)], 0);
        }
    }
    // Vertex 0 (v1, vt1) and vertex 1 (v1, vt5): same position, different UVs.
    EXPECT_EQ(mesh.sourceVertex[0], 0);
    EXPECT_EQ(mesh.sourceVertex[1], 0);
    EXPECT_EQ(mesh.uvs.row(1), Eigen::RowVector2d(5, 5));
}

TEST(Obj, MalformedFilesNameTheLine) {
    test::TempDir dir;
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 0\n"), 2, "expected 3");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 x 0\n"), 2, "not a number");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n"), 5, "out of range");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n"), 4, "index 0");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n"), 4, "out of range");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 0 0\nf 1 2\n"), 3, "at least 3");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2 3\n"), 4,
                      "texture coordinate");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 1 2 3\n"),
                      6, "texture coordinates");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/a 2 3\n"), 4, "not an index");
    expectErrorAtLine(readText(dir, "v 0 0 0\nv 1 inf 0\n"), 2, "not finite");
}

TEST(Obj, MissingFile) {
    test::TempDir dir;
    const auto read = readObj(dir / "nope.obj");
    ASSERT_FALSE(read.ok());
    EXPECT_NE(read.error().toString().find("nope.obj"), std::string::npos);
}

TEST(Obj, WriterRefusesBadInput) {
    sim::MatX3 positions(3, 3);
    positions.setZero();
    sim::MatX3i triangles(1, 3);
    triangles << 0, 1, 3;
    EXPECT_FALSE(formatObj(positions, triangles).ok());
    triangles << 0, 1, 2;
    ObjWriteOptions options;
    options.uvs = sim::MatX2::Zero(2, 2);
    EXPECT_FALSE(formatObj(positions, triangles, options).ok());
}

} // namespace
} // namespace atelier::io
