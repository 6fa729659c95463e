#include "io/body_file.h"
#include "io/mesh_export.h"
#include "io/mesh_import.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace atelier {
namespace {

using io::LengthUnit;
using io::UpAxis;

/// A closed box standing body-like: x ∈ [−0.2, 0.2], y ∈ [0, 1.7], z ∈ [0, 0.25] [m], Y up,
/// 12 outward triangles. `perFace`: each face has its own 4 vertices (24, as STL or split
/// normals give).
io::RawMesh boxBody(bool perFace = false) {
    const double lo[3] = {-0.2, 0.0, 0.0};
    const double hi[3] = {0.2, 1.7, 0.25};
    sim::MatX3 corners(8, 3);
    for (int i = 0; i < 8; ++i) {
        corners.row(i) = sim::Vec3((i & 1) != 0 ? hi[0] : lo[0], (i & 2) != 0 ? hi[1] : lo[1],
                                   (i & 4) != 0 ? hi[2] : lo[2]);
    }
    // Quads (outward, counter-clockwise) over the corner bits x=1, y=2, z=4.
    const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    io::RawMesh raw;
    raw.format = "test";
    raw.triangles.resize(12, 3);
    if (perFace) {
        raw.positions.resize(24, 3);
    } else {
        raw.positions = corners;
    }
    for (int q = 0; q < 6; ++q) {
        int v[4];
        for (int k = 0; k < 4; ++k) {
            v[k] = perFace ? 4 * q + k : quads[q][k];
            if (perFace) {
                raw.positions.row(v[k]) = corners.row(quads[q][k]);
            }
        }
        raw.triangles.row(2 * q) << v[0], v[1], v[2];
        raw.triangles.row(2 * q + 1) << v[0], v[2], v[3];
    }
    return raw;
}

/// The box as a Z-up file would hold it: Y up → Z up, (x, y, z) → (x, −z, y) (front −y).
io::RawMesh zUp(io::RawMesh raw) {
    for (Eigen::Index i = 0; i < raw.positions.rows(); ++i) {
        const sim::Vec3 p = raw.positions.row(i);
        raw.positions.row(i) = sim::Vec3(p.x(), -p.z(), p.y());
    }
    return raw;
}

io::RawMesh scaled(io::RawMesh raw, double factor) {
    raw.positions *= factor;
    return raw;
}

/// Checks the normalised box: metres, Y up, on y = 0, facing +z, within `tol` [m].
void expectBox(const io::ImportedBody& body, double tol) {
    const sim::Vec3 lo = body.vertices.colwise().minCoeff();
    const sim::Vec3 hi = body.vertices.colwise().maxCoeff();
    EXPECT_NEAR(lo.x(), -0.2, tol);
    EXPECT_NEAR(hi.x(), 0.2, tol);
    EXPECT_NEAR(lo.y(), 0.0, tol);
    EXPECT_NEAR(hi.y(), 1.7, tol);
    EXPECT_NEAR(lo.z(), 0.0, tol);
    EXPECT_NEAR(hi.z(), 0.25, tol);
    EXPECT_NEAR(body.report.height, 1.7, tol);
    EXPECT_EQ(body.report.vertices, 8);
    EXPECT_EQ(body.report.triangles, 12);
    EXPECT_EQ(body.report.holes, 0);
    EXPECT_EQ(body.report.nonManifoldEdges, 0);
    EXPECT_TRUE(body.report.warnings.empty()) << body.report.warnings.front();
}

std::string errorOf(const Result<io::ImportedBody>& r) {
    return r.ok() ? std::string("no error") : r.error().toString();
}

TEST(BodyImport, UnitsComeFromTheHeight) {
    for (const auto& [factor, unit] :
         {std::pair{1000.0, LengthUnit::Millimetre}, std::pair{100.0, LengthUnit::Centimetre},
          std::pair{1.0, LengthUnit::Metre}}) {
        auto body = io::normaliseBody(scaled(boxBody(), factor), "box");
        ASSERT_TRUE(body.ok()) << body.error().toString();
        EXPECT_EQ(body.value().report.units, unit) << factor;
        EXPECT_EQ(body.value().report.unitsFrom, "the height");
        EXPECT_NEAR(body.value().report.fileHeight, 1.7 * factor, 1e-9 * factor);
        expectBox(body.value(), 1e-12);
    }
}

TEST(BodyImport, ZUpIsTurnedYUpFacingPlusZ) {
    auto body = io::normaliseBody(scaled(zUp(boxBody()), 100.0), "box");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    EXPECT_EQ(body.value().report.up, UpAxis::Z);
    EXPECT_EQ(body.value().report.upFrom, "the bounding box");
    EXPECT_EQ(body.value().report.units, LengthUnit::Centimetre);
    expectBox(body.value(), 1e-12);
}

TEST(BodyImport, GivenUnitsAndAxisOverrideDetection) {
    io::BodyImportOptions options;
    options.units = LengthUnit::Centimetre;
    auto body = io::normaliseBody(boxBody(), "box", options);
    ASSERT_TRUE(body.ok()) << body.error().toString();
    EXPECT_EQ(body.value().report.unitsFrom, "given");
    EXPECT_NEAR(body.value().report.height, 0.017, 1e-12);

    options = {};
    options.up = UpAxis::Y;
    // Taken Y up, the box is 0.25 tall: no unit makes that a body.
    EXPECT_EQ(errorOf(io::normaliseBody(zUp(boxBody()), "box", options)),
              "box: the mesh is 0.25 file units tall: in no unit (mm, cm, m) is that a body 0.5 "
              "to 2.5 m tall (give the unit if it is one)");
    options.units = LengthUnit::Metre;
    body = io::normaliseBody(zUp(boxBody()), "box", options);
    ASSERT_TRUE(body.ok()) << body.error().toString();
    EXPECT_EQ(body.value().report.up, UpAxis::Y);
    EXPECT_EQ(body.value().report.upFrom, "given");
    // Taken Y up, the box is as tall as it was deep.
    EXPECT_NEAR(body.value().report.fileHeight, 0.25, 1e-12);
}

TEST(BodyImport, MetadataDecidesOnlyWhenTheBoxDoesNotContradictIt) {
    io::RawMesh raw = zUp(boxBody());
    raw.metadataUp = UpAxis::Y;
    auto body = io::normaliseBody(raw, "box");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    EXPECT_EQ(body.value().report.up, UpAxis::Z);
    ASSERT_EQ(body.value().report.warnings.size(), 1u);
    EXPECT_EQ(body.value().report.warnings[0],
              "the file declares y up but the body is tallest along z: using z (give the up "
              "axis if wrong)");
    raw = boxBody();
    raw.metadataUp = UpAxis::Y;
    body = io::normaliseBody(raw, "box");
    ASSERT_TRUE(body.ok());
    EXPECT_EQ(body.value().report.upFrom, "the file's metadata");
}

TEST(BodyImport, SplitVerticesAreWelded) {
    auto body = io::normaliseBody(boxBody(true), "box");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    EXPECT_EQ(body.value().report.sourceVertices, 24);
    expectBox(body.value(), 1e-12);
}

TEST(BodyImport, HolesAndNonManifoldEdgesAreCountedAndWarned) {
    io::RawMesh open = boxBody();
    open.triangles.conservativeResize(11, 3); // one triangle of the top face missing
    auto body = io::normaliseBody(open, "open.ply");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    EXPECT_EQ(body.value().report.holes, 1);
    EXPECT_EQ(body.value().report.boundaryEdges, 3);
    ASSERT_EQ(body.value().report.warnings.size(), 1u);
    EXPECT_EQ(body.value().report.warnings[0], "the surface is open: 1 hole (3 boundary edges)");

    io::RawMesh fin = boxBody();
    fin.positions.conservativeResize(9, 3);
    fin.positions.row(8) = sim::Vec3(0.0, 0.85, 0.6);
    fin.triangles.conservativeResize(13, 3);
    fin.triangles.row(12) << 4, 5, 8; // on the edge (4, 5) of the front face and the bottom
    body = io::normaliseBody(fin, "fin.ply");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    EXPECT_EQ(body.value().report.nonManifoldEdges, 1);
    EXPECT_EQ(body.value().report.holes, 1); // the fin's two free edges form one loop
    EXPECT_NE(std::find(body.value().report.warnings.begin(), body.value().report.warnings.end(),
                        "1 non-manifold edges (shared by three or more triangles)"),
              body.value().report.warnings.end());
}

TEST(BodyImport, WhatCannotBeABodyIsRefused) {
    io::RawMesh empty;
    empty.positions.resize(0, 3);
    empty.triangles.resize(0, 3);
    EXPECT_EQ(errorOf(io::normaliseBody(empty, "e.stl")),
              "e.stl: the file holds no triangles: it cannot be a body");
    io::RawMesh one = boxBody();
    one.triangles.conservativeResize(1, 3);
    EXPECT_EQ(errorOf(io::normaliseBody(one, "t.stl")),
              "t.stl: 1 triangle cannot be a body (a body is a surface around a volume: at "
              "least 4)");
    EXPECT_EQ(errorOf(io::normaliseBody(scaled(boxBody(), 10000.0 / 1.7), "tall.ply")),
              "tall.ply: the mesh is 1e+04 file units tall: in no unit (mm, cm, m) is that a "
              "body 0.5 to 2.5 m tall (give the unit if it is one)");
    io::BodyImportOptions metres;
    metres.units = LengthUnit::Metre;
    EXPECT_EQ(errorOf(io::normaliseBody(scaled(boxBody(), 10000.0 / 1.7), "tall.ply", metres)),
              "tall.ply: the mesh is 10000.0 m along y, more than the 3.0 m a body may measure "
              "(a body mesh is in metres, Y up)");
    io::RawMesh nan = boxBody();
    nan.positions(3, 1) = std::nan("");
    EXPECT_EQ(errorOf(io::normaliseBody(nan, "n.ply")), "n.ply: vertex 3 is not finite");
    io::RawMesh flat = boxBody();
    flat.positions.col(2).setZero();
    EXPECT_EQ(errorOf(io::normaliseBody(flat, "f.ply")),
              "f.ply: the mesh is flat (0.4 × 1.7 × 0 file units): it cannot be a body");
}

// ---------------------------------------------------------------------------------------------
// Files

std::string asciiStl(const io::RawMesh& raw) {
    std::string out = "solid body\n";
    for (Eigen::Index f = 0; f < raw.triangles.rows(); ++f) {
        out += "facet normal 0 0 0\nouter loop\n";
        for (int k = 0; k < 3; ++k) {
            const sim::Vec3 p = raw.positions.row(raw.triangles(f, k));
            out += "vertex " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " +
                   std::to_string(p.z()) + "\n";
        }
        out += "endloop\nendfacet\n";
    }
    return out + "endsolid body\n";
}

std::string asciiPly(const io::RawMesh& raw) {
    std::string out = "ply\nformat ascii 1.0\nelement vertex " +
                      std::to_string(raw.positions.rows()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                      std::to_string(raw.triangles.rows()) +
                      "\nproperty list uchar int vertex_indices\nend_header\n";
    for (Eigen::Index i = 0; i < raw.positions.rows(); ++i) {
        out += std::to_string(raw.positions(i, 0)) + " " + std::to_string(raw.positions(i, 1)) +
               " " + std::to_string(raw.positions(i, 2)) + "\n";
    }
    for (Eigen::Index f = 0; f < raw.triangles.rows(); ++f) {
        out += "3 " + std::to_string(raw.triangles(f, 0)) + " " +
               std::to_string(raw.triangles(f, 1)) + " " + std::to_string(raw.triangles(f, 2)) +
               "\n";
    }
    return out;
}

std::string objText(const io::RawMesh& raw) {
    std::string out;
    for (Eigen::Index i = 0; i < raw.positions.rows(); ++i) {
        out += "v " + std::to_string(raw.positions(i, 0)) + " " +
               std::to_string(raw.positions(i, 1)) + " " + std::to_string(raw.positions(i, 2)) +
               "\n";
    }
    for (Eigen::Index f = 0; f < raw.triangles.rows(); ++f) {
        out += "f " + std::to_string(raw.triangles(f, 0) + 1) + " " +
               std::to_string(raw.triangles(f, 1) + 1) + " " +
               std::to_string(raw.triangles(f, 2) + 1) + "\n";
    }
    return out;
}

/// The raw mesh written with io's exporter (glTF, FBX), one group.
void exportRaw(const std::filesystem::path& path, const io::RawMesh& raw, io::MeshFormat format) {
    io::SurfaceMesh surface;
    surface.positions = raw.positions;
    surface.triangles = raw.triangles;
    surface.groups.push_back(io::ObjGroup{"body", 0, static_cast<int>(raw.triangles.rows())});
    auto written = io::exportMesh(path, surface, format);
    ASSERT_TRUE(written.ok()) << written.error().toString();
}

TEST(BodyImportFiles, EachFormatInEachUnitAndAxisIsNormalised) {
    const test::TempDir dir;
    struct Case {
        std::string name;
        LengthUnit unit;
        UpAxis up;
    };
    std::vector<Case> cases;
    // Text formats written here; the exporter's formats (single precision) through io.
    const io::RawMesh mmZ = scaled(zUp(boxBody(true)), 1000.0);
    dir.write("mm-zup.stl", asciiStl(mmZ));
    cases.push_back({"mm-zup.stl", LengthUnit::Millimetre, UpAxis::Z});
    dir.write("cm.ply", asciiPly(scaled(boxBody(), 100.0)));
    cases.push_back({"cm.ply", LengthUnit::Centimetre, UpAxis::Y});
    dir.write("mm.obj", objText(scaled(boxBody(), 1000.0)));
    cases.push_back({"mm.obj", LengthUnit::Millimetre, UpAxis::Y});
    exportRaw(dir / "m-zup.glb", zUp(boxBody()), io::MeshFormat::Glb);
    cases.push_back({"m-zup.glb", LengthUnit::Metre, UpAxis::Z});
    exportRaw(dir / "cm.fbx", scaled(boxBody(true), 100.0), io::MeshFormat::FbxAscii);
    cases.push_back({"cm.fbx", LengthUnit::Centimetre, UpAxis::Y});
    exportRaw(dir / "mm.glb", scaled(boxBody(), 1000.0), io::MeshFormat::Glb);
    cases.push_back({"mm.glb", LengthUnit::Millimetre, UpAxis::Y});
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        auto body = io::importBody(dir / c.name);
        ASSERT_TRUE(body.ok()) << body.error().toString();
        EXPECT_EQ(body.value().report.units, c.unit);
        EXPECT_EQ(body.value().report.up, c.up);
        const io::BodyImportReport& r = body.value().report;
        // A glTF file is Y up by its specification: a Z-up one overrules it, saying so.
        const bool overruled = c.name == "m-zup.glb";
        EXPECT_EQ(r.warnings.size(), overruled ? 1u : 0u);
        EXPECT_NEAR(r.height, 1.7, 1e-5);
        io::ImportedBody quiet = body.value();
        quiet.report.warnings.clear();
        expectBox(quiet, 1e-5);
    }
}

/// The box as COLLADA, Z up in centimetres: assimp applies `up_axis` and `unit` itself.
std::string colladaZUpCm() {
    const io::RawMesh raw = scaled(zUp(boxBody()), 100.0);
    std::string positions;
    for (Eigen::Index i = 0; i < raw.positions.rows(); ++i) {
        for (int k = 0; k < 3; ++k) {
            positions += std::to_string(raw.positions(i, k)) + " ";
        }
    }
    std::string indices;
    for (Eigen::Index f = 0; f < raw.triangles.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            indices += std::to_string(raw.triangles(f, k)) + " ";
        }
    }
    return R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="centimeter" meter="0.01"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="box" name="box"><mesh>
    <source id="box-pos"><float_array id="box-pos-array" count="24">)" +
           positions + R"(</float_array>
      <technique_common><accessor source="#box-pos-array" count="8" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="box-vtx"><input semantic="POSITION" source="#box-pos"/></vertices>
    <triangles count="12"><input semantic="VERTEX" source="#box-vtx" offset="0"/><p>)" +
           indices + R"(</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene"><node id="n">
    <instance_geometry url="#box"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
)";
}

TEST(BodyImportFiles, ColladaUpAxisAndUnitAreApplied) {
    const test::TempDir dir;
    auto body = io::importBody(dir.write("box.dae", colladaZUpCm()));
    ASSERT_TRUE(body.ok()) << body.error().toString();
    EXPECT_EQ(body.value().report.format, "COLLADA");
    expectBox(body.value(), 1e-5);
}

TEST(BodyImportFiles, BrokenAndUnsupportedFilesGiveErrors) {
    const test::TempDir dir;
    EXPECT_EQ(errorOf(io::importBody(dir.write("body.xyz", "1 2 3\n"))),
              (dir / "body.xyz").string() +
                  ": unsupported mesh format \".xyz\" (supported: .obj, .fbx, .gltf, .glb, "
                  ".dae, .ply, .stl)");
    const std::string garbage = "\x01\x02garbage\xff\xfe not a mesh at all\n";
    for (const char* name : {"g.fbx", "g.glb", "g.gltf", "g.dae", "g.ply", "g.stl", "g.obj"}) {
        SCOPED_TRACE(name);
        const auto r = io::importBody(dir.write(name, garbage));
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().file, (dir / name).string());
    }
    // A glTF binary cut short, and one with its header only.
    exportRaw(dir / "whole.glb", boxBody(), io::MeshFormat::Glb);
    const std::string whole = test::readText(dir / "whole.glb");
    for (const std::size_t keep : {whole.size() / 2, std::size_t{12}, std::size_t{0}}) {
        const auto r = io::importBody(dir.write("cut.glb", whole.substr(0, keep)));
        EXPECT_FALSE(r.ok()) << keep;
    }
    // An STL of one triangle.
    io::RawMesh one = boxBody();
    one.triangles.conservativeResize(1, 3);
    EXPECT_EQ(errorOf(io::importBody(dir.write("one.stl", asciiStl(one)))),
              (dir / "one.stl").string() +
                  ": 1 triangle cannot be a body (a body is a surface around a volume: at "
                  "least 4)");
    std::error_code ec;
    std::filesystem::create_directory(dir / "folder.glb", ec);
    EXPECT_FALSE(io::importBody(dir / "folder.glb").ok());
}

TEST(BodyImportFiles, AProjectBodyMayBeAnyFormatWithItsUnitAndAxis) {
    const test::TempDir dir;
    dir.write("body.stl", asciiStl(scaled(zUp(boxBody()), 100.0)));
    patterns::BodySource source;
    source.meshPath = "body.stl";
    // Detected (cm, Z up) it would load; given in metres it is 170 m tall, and given Y up as
    // well it is 170 m long along z.
    source.meshUnits = "m";
    const std::string prefix = (dir / "body.stl").string() + ": the mesh is 170.0 m along ";
    const std::string suffix =
        ", more than the 3.0 m a body may measure (a body mesh is in metres, Y up)";
    const auto given = io::loadBody(source, dir.path(), dir / "p.atelier");
    ASSERT_FALSE(given.ok());
    EXPECT_EQ(given.error().toString(), prefix + "y" + suffix);
    source.meshUp = "y";
    const auto both = io::loadBody(source, dir.path(), dir / "p.atelier");
    ASSERT_FALSE(both.ok());
    EXPECT_EQ(both.error().toString(), prefix + "z" + suffix);
}

std::filesystem::path sharedData(const std::string& relative) {
    return std::filesystem::path(ATELIER_SOURCE_DIR) / ".." / "shared" / "data" / relative;
}

TEST(BodyImportFiles, TheMakeHumanBodyLoads) {
    const auto path = sharedData("bodies/makehuman-base-body.obj");
    if (!std::filesystem::exists(path)) {
        GTEST_SKIP() << "test data absent: " << path << " (../shared/data beside the checkout)";
    }
    auto body = io::importBody(path);
    ASSERT_TRUE(body.ok()) << body.error().toString();
    const io::BodyImportReport& r = body.value().report;
    EXPECT_EQ(r.units, LengthUnit::Metre);
    EXPECT_EQ(r.up, UpAxis::Y);
    EXPECT_NEAR(r.height, 1.666, 0.001); // the data's README: 1.666 m tall
    EXPECT_EQ(r.triangles, 26756);
    EXPECT_EQ(r.holes, 0);
    EXPECT_EQ(r.nonManifoldEdges, 0);

    // Rescaled to millimetres and turned Z up, it comes back the same body.
    io::RawMesh raw;
    raw.positions = body.value().vertices;
    raw.triangles = body.value().triangles;
    raw.format = "test";
    auto again = io::normaliseBody(scaled(zUp(raw), 1000.0), "mm-zup");
    ASSERT_TRUE(again.ok()) << again.error().toString();
    EXPECT_EQ(again.value().report.units, LengthUnit::Millimetre);
    EXPECT_EQ(again.value().report.up, UpAxis::Z);
    EXPECT_LT((again.value().vertices - body.value().vertices).cwiseAbs().maxCoeff(), 1e-12);

    patterns::BodySource source;
    source.meshPath = path.filename().string();
    std::vector<std::string> warnings;
    const auto loaded = io::loadBody(source, path.parent_path(), "p.atelier", {}, &warnings);
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    EXPECT_FALSE(loaded.value().slots.empty());
    EXPECT_TRUE(warnings.empty());

    // With a triangle missing it still loads, with a warning naming the file and the hole.
    const test::TempDir dir;
    io::SurfaceMesh open;
    open.positions = body.value().vertices;
    open.triangles = body.value().triangles.topRows(r.triangles - 1);
    ASSERT_TRUE(io::exportMesh(dir / "open.obj", open, io::MeshFormat::Obj).ok());
    source.meshPath = "open.obj";
    const auto opened = io::loadBody(source, dir.path(), "p.atelier", {}, &warnings);
    ASSERT_TRUE(opened.ok()) << opened.error().toString();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0],
              (dir / "open.obj").string() + ": the surface is open: 1 hole (3 boundary edges)");
}

} // namespace
} // namespace atelier
