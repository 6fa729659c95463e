/// atelier-cli with other tools' files: `body FILE` imports a body mesh and says what it
/// detected; `drape --out` writes the garment as one surface in the format of its extension.

#include "app/cli_run.h"

#include "io/mesh_import.h"
#include "io/obj.h"
#include "io/temp_dir.h"

#include "source_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <filesystem>
#include <set>
#include <string>

namespace atelier {
namespace {

using test::CliRun;
using test::inQuotes;
using test::runCli;

/// A closed box 400 × 1700 × 250 mm standing on z = 0 (Z up) as ASCII STL, in millimetres.
std::string boxStlZUpMm() {
    const double lo[3] = {-200, -250, 0};
    const double hi[3] = {200, 0, 1700};
    const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    const auto corner = [&](int i) {
        return std::to_string((i & 1) != 0 ? hi[0] : lo[0]) + " " +
               std::to_string((i & 2) != 0 ? hi[1] : lo[1]) + " " +
               std::to_string((i & 4) != 0 ? hi[2] : lo[2]);
    };
    std::string out = "solid box\n";
    for (const auto& q : quads) {
        for (const auto& t : {std::array{q[0], q[1], q[2]}, std::array{q[0], q[2], q[3]}}) {
            out += "facet normal 0 0 0\nouter loop\n";
            for (const int v : t) {
                out += "vertex " + corner(v) + "\n";
            }
            out += "endloop\nendfacet\n";
        }
    }
    return out + "endsolid box\n";
}

TEST(CliInterop, BodyReportPrintsWhatWasDetected) {
    const test::TempDir dir;
    const auto stl = dir.write("box.stl", boxStlZUpMm());
    const CliRun run =
        runCli(dir, "body " + inQuotes(stl) + " --report --out " + inQuotes(dir / "box.glb") +
                        " > " + inQuotes(dir / "out.txt"));
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const std::string out = test::readText(dir / "out.txt");
    EXPECT_NE(out.find("format:            STL\n"), std::string::npos) << out;
    EXPECT_NE(out.find("units:             mm (the height)\n"), std::string::npos) << out;
    EXPECT_NE(out.find("up axis:           z (the bounding box)\n"), std::string::npos) << out;
    EXPECT_NE(out.find("height:            1.7000 m (1700 file units)\n"), std::string::npos)
        << out;
    EXPECT_NE(out.find("vertices:          8 (36 as read)\n"), std::string::npos) << out;
    EXPECT_NE(out.find("holes:             0 (0 boundary edges)\n"), std::string::npos) << out;
    // The normalised body written as glTF reads back in metres, Y up.
    auto back = io::importBody(dir / "box.glb");
    ASSERT_TRUE(back.ok()) << back.error().toString();
    EXPECT_EQ(back.value().report.units, io::LengthUnit::Metre);
    EXPECT_EQ(back.value().report.up, io::UpAxis::Y);
    EXPECT_EQ(back.value().report.upFrom, "the file's metadata");
    EXPECT_NEAR(back.value().report.height, 1.7, 1e-5);

    // JSON report with the units given.
    const CliRun json = runCli(dir, "body " + inQuotes(stl) + " --units mm --up z --report " +
                                        inQuotes(dir / "r.json"));
    ASSERT_EQ(json.exitCode, 0) << json.stderrText;
    const auto r = nlohmann::json::parse(test::readText(dir / "r.json"));
    EXPECT_EQ(r["units"], "mm");
    EXPECT_EQ(r["units_from"], "given");
    EXPECT_EQ(r["up_from"], "given");
    EXPECT_NEAR(r["height_m"].get<double>(), 1.7, 1e-9);
    EXPECT_TRUE(r.contains("slots"));
}

TEST(CliInterop, BodyReportPrintsTheLandmarksFoundFromTheShape) {
    const std::filesystem::path body =
        std::filesystem::path(ATELIER_SOURCE_DIR) / "../shared/data/bodies/makehuman-base-body.obj";
    if (!std::filesystem::is_regular_file(body)) {
        GTEST_SKIP() << "test data absent: " << body << " (../shared/data beside the checkout)";
    }
    const test::TempDir dir;
    const CliRun run =
        runCli(dir, "body " + inQuotes(body) + " --report > " + inQuotes(dir / "out.txt"));
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const std::string out = test::readText(dir / "out.txt");
    for (const char* line : {"crotch:", "waist:", "hip:", "bust:", "armpits:", "shoulders:",
                             "neck base:", "neck:", "left arm:", "right leg:"}) {
        EXPECT_NE(out.find(std::string("\n") + line), std::string::npos) << line << "\n" << out;
    }
    const CliRun json =
        runCli(dir, "body " + inQuotes(body) + " --report " + inQuotes(dir / "r.json"));
    ASSERT_EQ(json.exitCode, 0) << json.stderrText;
    const auto r = nlohmann::json::parse(test::readText(dir / "r.json"));
    ASSERT_TRUE(r["landmarks"].is_object()) << r.dump(1);
    // Heights from the floor, as printed; the crotch as the unit test bounds it.
    const double crotch = r["landmarks"]["crotch_y"].get<double>();
    const double height = r["landmarks"]["height"].get<double>();
    EXPECT_GT(crotch / height, 0.42);
    EXPECT_LT(crotch / height, 0.50);
    EXPECT_GT(r["landmarks"]["girths"]["waist"].get<double>(), 0.4);
    EXPECT_EQ(r["slots"].size(), 15u);
}

TEST(CliInterop, WhatCannotBeABodyIsRefusedNamingTheFile) {
    const test::TempDir dir;
    std::string tall = boxStlZUpMm();
    const std::string height = "1700.000000";
    for (std::size_t at = tall.find(height); at != std::string::npos; at = tall.find(height)) {
        tall.replace(at, height.size(), "10000000"); // 10 km in mm
    }
    const auto stl = dir.write("tall.stl", tall);
    CliRun run = runCli(dir, "body " + inQuotes(stl) + " --report");
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("error: " + stl.string() + ": the mesh is 1e+07 file units tall"),
              std::string::npos)
        << run.stderrText;
    run = runCli(dir, "body " + inQuotes(dir.write("empty.ply", "")) + " --report");
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("error: " + (dir / "empty.ply").string() + ": "),
              std::string::npos)
        << run.stderrText;
    run = runCli(dir, "body --report");
    EXPECT_EQ(run.exitCode, 2) << "printing the report needs a body mesh";
}

/// The OBJ's `v` positions and its triangles over them (not split by UV).
struct ObjSurface {
    sim::MatX3 positions;
    sim::MatX3i triangles;
};

ObjSurface readSurface(const std::filesystem::path& path) {
    auto obj = io::readObj(path);
    EXPECT_TRUE(obj.ok()) << obj.error().toString();
    ObjSurface s;
    const auto& m = obj.value();
    const int n = 1 + *std::max_element(m.sourceVertex.begin(), m.sourceVertex.end());
    s.positions.resize(n, 3);
    for (Eigen::Index i = 0; i < m.positions.rows(); ++i) {
        s.positions.row(m.sourceVertex[static_cast<std::size_t>(i)]) = m.positions.row(i);
    }
    s.triangles.resize(m.triangles.rows(), 3);
    for (Eigen::Index f = 0; f < m.triangles.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            s.triangles(f, k) = m.sourceVertex[static_cast<std::size_t>(m.triangles(f, k))];
        }
    }
    return s;
}

long duplicatedPositions(const sim::MatX3& x) {
    std::set<std::array<double, 3>> seen;
    long duplicates = 0;
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
        duplicates += seen.insert({x(i, 0), x(i, 1), x(i, 2)}).second ? 0 : 1;
    }
    return duplicates;
}

TEST(CliInterop, TheDrapedGarmentIsOneSurface) {
    const test::TempDir dir;
    const CliRun run =
        runCli(dir, "drape " + inQuotes(test::SKIRT_PROJECT) +
                        " --particle-distance 40 --time-limit 0.6 --threads 1 --out " +
                        inQuotes(dir / "skirt.obj") + " --frames-dir " + inQuotes(dir / "frames") +
                        " --report " + inQuotes(dir / "r.json"));
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const auto report = nlohmann::json::parse(test::readText(dir / "r.json"));
    const long pairs = report["welded_seam_pairs"].get<long>();
    ASSERT_GT(pairs, 0);

    // The last frame is the same drape with each panel's own vertices.
    std::filesystem::path last;
    for (const auto& entry : std::filesystem::directory_iterator(dir / "frames")) {
        last = std::max(last, entry.path());
    }
    const ObjSurface split = readSurface(last);
    const ObjSurface one = readSurface(dir / "skirt.obj");
    EXPECT_EQ(one.triangles.rows(), split.triangles.rows());
    EXPECT_GT(duplicatedPositions(split.positions), 0) << "welded pairs, written twice";
    EXPECT_EQ(duplicatedPositions(one.positions), 0);
    // Each welded pair removes one vertex, but pairs at a seam's corner join three or more.
    EXPECT_LT(one.positions.rows(), split.positions.rows());
    EXPECT_GE(one.positions.rows(), split.positions.rows() - pairs);

    const io::EdgeFigures splitEdges = io::edgeFigures(split.triangles, split.positions.rows());
    const io::EdgeFigures oneEdges = io::edgeFigures(one.triangles, one.positions.rows());
    EXPECT_EQ(oneEdges.nonManifoldEdges, 0);
    // The seams are closed: the skirt is open only at its waist and its hem.
    EXPECT_LT(oneEdges.boundaryEdges, splitEdges.boundaryEdges);
    EXPECT_EQ(oneEdges.holes, 2);
    EXPECT_TRUE(std::filesystem::exists(dir / "skirt.mtl"));
}

TEST(CliInterop, DrapeOutputFormatFollowsTheExtensionOrFormat) {
    const test::TempDir dir;
    CliRun run =
        runCli(dir, "drape " + inQuotes(test::SKIRT_PROJECT) + " --out " + inQuotes(dir / "s.stl"));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("unknown mesh format extension"), std::string::npos)
        << run.stderrText;
    run = runCli(dir, "drape " + inQuotes(test::SKIRT_PROJECT) +
                          " --format ply --particle-distance 20 " +
                          "--time-limit 0.02 --threads 1 --out " + inQuotes(dir / "s.mesh"));
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    auto back = io::readMesh(dir / "s.ply");
    EXPECT_FALSE(back.ok()) << "written as s.mesh, not s.ply";
    std::filesystem::copy_file(dir / "s.mesh", dir / "copy.ply");
    back = io::readMesh(dir / "copy.ply");
    ASSERT_TRUE(back.ok()) << back.error().toString();
    EXPECT_GT(back.value().triangles.rows(), 0);
}

} // namespace
} // namespace atelier
