// The bundled sample garments, draped whole with `atelier-cli drape` on the default body, as a
// user runs them. The figures of the report are checked, and the written meshes are checked
// again independently of the engine: penetration of every garment vertex into the body and
// exact triangle–triangle intersections, computed here from the OBJ files alone.

#include "io/obj.h"
#include "io/temp_dir.h"

#include "sim/collision/geometry.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <unordered_map>

namespace atelier {
namespace {

namespace fs = std::filesystem;

struct Box {
    sim::Vec3 lo, hi;
};

Box triangleBox(const sim::MatX3& x, const sim::MatX3i& f, int t) {
    Box b{x.row(f(t, 0)).transpose(), x.row(f(t, 0)).transpose()};
    for (int k = 1; k < 3; ++k) {
        b.lo = b.lo.cwiseMin(x.row(f(t, k)).transpose());
        b.hi = b.hi.cwiseMax(x.row(f(t, k)).transpose());
    }
    return b;
}

/// Exact intersecting triangle pairs between mesh A and mesh B (or A with itself when
/// `self`), by a uniform grid over triangle boxes. In the garment, vertices at identical
/// positions are one vertex (welded seams are written as coincident vertices), and triangles
/// sharing a vertex are not counted.
long intersections(const sim::MatX3& xa, const sim::MatX3i& fa, const sim::MatX3& xb,
                   const sim::MatX3i& fb, bool self) {
    std::vector<int> id(static_cast<std::size_t>(xa.rows()));
    {
        std::map<std::array<double, 3>, int> seen;
        for (int i = 0; i < xa.rows(); ++i) {
            id[static_cast<std::size_t>(i)] =
                seen.emplace(std::array<double, 3>{xa(i, 0), xa(i, 1), xa(i, 2)}, i).first->second;
        }
    }
    const double cell = 0.02;
    auto key = [&](int i, int j, int k) {
        return (static_cast<long long>(i) * 73856093LL) ^ (static_cast<long long>(j) * 19349663LL) ^
               (static_cast<long long>(k) * 83492791LL);
    };
    std::unordered_multimap<long long, int> grid;
    for (int t = 0; t < fb.rows(); ++t) {
        const Box b = triangleBox(xb, fb, t);
        for (int i = int(std::floor(b.lo.x() / cell)); i <= int(std::floor(b.hi.x() / cell)); ++i)
            for (int j = int(std::floor(b.lo.y() / cell)); j <= int(std::floor(b.hi.y() / cell));
                 ++j)
                for (int k = int(std::floor(b.lo.z() / cell));
                     k <= int(std::floor(b.hi.z() / cell)); ++k)
                    grid.emplace(key(i, j, k), t);
    }
    std::vector<std::pair<int, int>> candidates;
    for (int t = 0; t < fa.rows(); ++t) {
        const Box b = triangleBox(xa, fa, t);
        for (int i = int(std::floor(b.lo.x() / cell)); i <= int(std::floor(b.hi.x() / cell)); ++i)
            for (int j = int(std::floor(b.lo.y() / cell)); j <= int(std::floor(b.hi.y() / cell));
                 ++j)
                for (int k = int(std::floor(b.lo.z() / cell));
                     k <= int(std::floor(b.hi.z() / cell)); ++k) {
                    const auto range = grid.equal_range(key(i, j, k));
                    for (auto it = range.first; it != range.second; ++it) {
                        if (!self || it->second > t) {
                            candidates.emplace_back(t, it->second);
                        }
                    }
                }
    }
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    long count = 0;
    for (const auto& [a, b] : candidates) {
        if (self) {
            bool shared = false;
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    shared = shared || id[static_cast<std::size_t>(fa(a, i))] ==
                                           id[static_cast<std::size_t>(fa(b, j))];
            if (shared) {
                continue;
            }
        }
        if (sim::trianglesIntersect(xa.row(fa(a, 0)), xa.row(fa(a, 1)), xa.row(fa(a, 2)),
                                    xb.row(fb(b, 0)), xb.row(fb(b, 1)), xb.row(fb(b, 2)))) {
            ++count;
        }
    }
    return count;
}

/// What a drape must reach beyond finite, sewn shut, area kept and a good mesh.
struct Bar {
    bool rest = false;                ///< came to rest before the time limit
    bool noIntersections = false;     ///< garment free of itself and of the body (from the files)
    double maxPenetration = INFINITY; ///< [m], over all frames (report)
    std::string fit = "fits";         ///< the verdict, checked with noIntersections
    /// Every seam pair welded; otherwise the verdict names each seam left open.
    bool sewn = true;
};

/// The bundled sample `name`, or a copy of it in `dir` on `body` when one is given.
fs::path sampleProject(const std::string& name, const fs::path& dir,
                       const nlohmann::json& body = nullptr) {
    const fs::path sample = fs::path(ATELIER_SOURCE_DIR) / "assets/garments" / (name + ".atelier");
    if (body.is_null()) {
        return sample;
    }
    auto p = nlohmann::json::parse(test::readText(sample));
    p["body"] = body;
    const fs::path copy = dir / (name + ".atelier");
    std::ofstream(copy) << p.dump(1);
    return copy;
}

/// A body of the fit matrix (assets/batch/fit-matrix.json), by its name there.
nlohmann::json fitMatrixBody(const std::string& name) {
    return nlohmann::json::parse(test::readText(fs::path(ATELIER_SOURCE_DIR) /
                                                "assets/batch/fit-matrix.json"))["bodies"][name];
}

/// Runs `atelier-cli drape PROJECT --report DIR/report.json ARGS` with its stderr in
/// DIR/stderr.txt: success when it exits with 0.
::testing::AssertionResult runDrape(const fs::path& project, const std::string& args,
                                    const fs::path& dir) {
    const std::string command = std::string("\"") + ATELIER_CLI + "\" drape \"" + project.string() +
                                "\" --report \"" + (dir / "report.json").string() + "\" " + args +
                                " 2> \"" + (dir / "stderr.txt").string() + "\"";
    const int status = std::system(command.c_str());
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
        return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure() << command << "\n" << test::readText(dir / "stderr.txt");
}

/// From a drape's written meshes alone (OUT and OUT.body.obj): the garment's triangles and its
/// intersecting triangle pairs with itself and with the body.
struct FileFigures {
    long triangles = 0, self = 0, withBody = 0;
};
void figuresFromFiles(const fs::path& out, FileFigures& f) {
    auto garment = io::readObj(out);
    ASSERT_TRUE(garment.ok()) << garment.error().toString();
    fs::path bodyPath = out;
    bodyPath.replace_extension(".body.obj");
    auto body = io::readObj(bodyPath);
    ASSERT_TRUE(body.ok()) << body.error().toString();
    const auto& g = garment.value();
    const auto& b = body.value();
    f.triangles = static_cast<long>(g.triangles.rows());
    f.self = intersections(g.positions, g.triangles, g.positions, g.triangles, true);
    f.withBody = intersections(g.positions, g.triangles, b.positions, b.triangles, false);
}

/// Drapes a sample with `atelier-cli drape ARGS` (on `body` instead of its own when given),
/// then checks the report's figures and, from the written meshes alone, the intersections with
/// itself and with the body.
void drapeAndCheck(const std::string& name, const std::string& args, const Bar& bar,
                   const nlohmann::json& body = nullptr) {
    test::TempDir dir;
    const fs::path out = dir / "draped.obj";
    const fs::path report = dir / "report.json";
    ASSERT_TRUE(runDrape(sampleProject(name, dir.path(), body),
                         "--out \"" + out.string() + "\" " + args, dir.path()));
    const auto r = nlohmann::json::parse(test::readText(report));
    EXPECT_TRUE(r["finite"].get<bool>());
    if (bar.sewn) {
        EXPECT_LT(r["seam_gap_max_m"].get<double>(), 0.002);
        EXPECT_EQ(r["welded_seam_pairs"].get<long>(), r["seam_pairs"].get<long>());
    } else if (r["welded_seam_pairs"].get<long>() < r["seam_pairs"].get<long>()) {
        EXPECT_NE(r["fit_message"].get<std::string>().find("left open"), std::string::npos)
            << r["fit_message"];
    }
    EXPECT_GE(r["area_ratio"].get<double>(), 0.95);
    EXPECT_LE(r["area_ratio"].get<double>(), 1.05);
    EXPECT_GE(r["mesh_min_angle_deg"].get<double>(), 25.0);

    // Independently, from the written files.
    FileFigures files;
    ASSERT_NO_FATAL_FAILURE(figuresFromFiles(out, files));
    EXPECT_EQ(files.triangles, r["triangles"].get<long>());
    const long self = files.self;
    const long withBody = files.withBody;
    // The engine's count is exact too: both must agree.
    EXPECT_EQ(self + withBody, r["intersecting_triangle_pairs"].get<long>());
    std::printf("%s: rested %d, intersecting pairs %ld with itself and %ld with the body, max "
                "penetration %.4f m\n",
                name.c_str(), r["rested"].get<bool>() ? 1 : 0, self, withBody,
                r["max_penetration_m"].get<double>());
    if (bar.rest) {
        EXPECT_TRUE(r["rested"].get<bool>()) << "stopped at " << r["sim_time_to_rest_s"] << " s";
    }
    // The panels' strains, from the written mesh by an independent tool: the same lines.
    ASSERT_EQ(r["panel_strain"].size(), r["panels"].get<std::size_t>());
    const fs::path strains = dir / "strains.txt";
    const std::string tool = "python3 \"" + std::string(ATELIER_SOURCE_DIR) +
                             "/tools/fit_strain.py\" \"" + out.string() + "\" > \"" +
                             strains.string() + "\"";
    ASSERT_EQ(std::system(tool.c_str()), 0) << tool;
    std::istringstream lines(test::readText(strains));
    std::string line;
    for (const auto& reported : r["panel_strain"]) {
        ASSERT_TRUE(std::getline(lines, line));
        EXPECT_EQ(line, reported.get<std::string>());
    }
    if (bar.noIntersections) {
        EXPECT_EQ(r["start_intersecting_pairs"].get<long>(), 0);
        EXPECT_EQ(r["fit"], bar.fit) << r["fit_message"];
        EXPECT_EQ(self, 0) << "garment with itself";
        EXPECT_EQ(withBody, 0) << "garment with the body";
    }
    EXPECT_LT(r["max_penetration_m"].get<double>(), bar.maxPenetration);
}

// The samples at 20 mm (4–6k triangles), up to 1 s of sewing then up to 3 s under gravity on the
// default body: finite, every seam welded, area kept, the intersections counted from the written
// files agreeing with the engine's; each comes to rest free of intersections and under 1 mm of
// penetration (README, "Patterns, the mannequin and draping").
class SampleGarmentCoarse : public ::testing::TestWithParam<std::string> {};

TEST_P(SampleGarmentCoarse, SewsAndDrapesToRestOnTheDefaultBody) {
    drapeAndCheck(GetParam(), "--particle-distance 20 --threads 1", {true, true, 0.001});
}

INSTANTIATE_TEST_SUITE_P(Garments, SampleGarmentCoarse,
                         ::testing::Values("skirt", "dress", "trousers"));

// Open (issue 4): at 20 mm and 10 ms steps the tshirt sews shut and ends free of intersections,
// but its kinetic energy hovers at 1-4e-8 J per vertex, above the rest threshold, to the 4 s
// limit (until its armholes were deepened it kept a 26 mm fin open at the right shoulder); run
// with --gtest_also_run_disabled_tests.
class SampleGarmentCoarseOpen : public ::testing::TestWithParam<std::string> {};

TEST_P(SampleGarmentCoarseOpen, DISABLED_SewsAndDrapesToRestOnTheDefaultBody) {
    drapeAndCheck(GetParam(), "--particle-distance 20 --threads 1", {true, true, 0.001});
}

INSTANTIATE_TEST_SUITE_P(Garments, SampleGarmentCoarseOpen, ::testing::Values("tshirt"));

// The same, stepped as the window drapes them (patterns::interactiveStep: 1/60 s at 20 mm
// instead of the projects' 10 ms), the tshirt included: with these steps its shoulder closes.
class SampleGarmentInteractive : public ::testing::TestWithParam<std::string> {};

TEST_P(SampleGarmentInteractive, SewsAndDrapesToRestOnTheDefaultBody) {
    drapeAndCheck(GetParam(), "--particle-distance 20 --interactive --threads 1",
                  {true, true, 0.001});
}

INSTANTIATE_TEST_SUITE_P(Garments, SampleGarmentInteractive,
                         ::testing::Values("tshirt", "skirt", "dress", "trousers"));

// Too small a body: the tshirt, drafted for the default female mannequin, on the fit matrix's
// large male one. It ends stretched and says so (bodice and sleeves, and a shoulder seam that
// could not close without carrying cloth through cloth), and does not tear through itself: a
// welded group that the collision corrections left apart is not brought back together through
// the cloth at the next step's start (7 intersecting pairs before, on the default male body
// with the tshirt's earlier, tighter armholes).
TEST(SampleGarmentTooSmall, EndsStretchedWithoutTearingThroughItself) {
    Bar bar{false, true, 0.001, "does not fit"};
    bar.sewn = false;
    drapeAndCheck("tshirt", "--particle-distance 20 --threads 1", bar, fitMatrixBody("male-L"));
}

// Whatever the drape, the report tells the truth about its seams: a seam left open at rest is a
// warning that names it with its gap (and a drape that welds every pair has no such warning).
TEST(SampleReport, ASeamLeftOpenIsAWarningNamingIt) {
    test::TempDir dir;
    ASSERT_TRUE(
        runDrape(sampleProject("tshirt", dir.path()),
                 "--particle-distance 20 --threads 1 --out \"" + (dir / "t.obj").string() + "\"",
                 dir.path()));
    const auto r = nlohmann::json::parse(test::readText(dir / "report.json"));
    const auto& messages = r["warning_messages"];
    EXPECT_EQ(r["warnings"].get<long>(), static_cast<long>(messages.size()));
    const long open = r["seam_pairs"].get<long>() - r["welded_seam_pairs"].get<long>();
    std::string all;
    for (const auto& m : messages) {
        all += m.get<std::string>() + "\n";
    }
    if (open > 0) {
        EXPECT_NE(all.find("seam pairs not welded after sewing"), std::string::npos) << all;
        EXPECT_NE(all.find(std::to_string(open) + " pairs"), std::string::npos) << all;
        EXPECT_GT(r["seam_gap_max_m"].get<double>(), 0.0);
    } else {
        EXPECT_EQ(all.find("not welded"), std::string::npos) << all;
    }
}

// Panels placed through each other would stay crossed (the engine keeps cloth from crossing, it
// cannot undo a crossing it starts with): the drape lifts them off their slots until they clear,
// and the report and a warning say which and by how much. The trousers on the fit matrix's small
// female body: the leg slots bring the front panels through each other at the crotch (24 pairs
// as placed).
TEST(SampleReport, APlacementThroughItselfIsLiftedApart) {
    test::TempDir dir;
    ASSERT_TRUE(runDrape(sampleProject("trousers", dir.path(), fitMatrixBody("female-S")),
                         "--particle-distance 20 --threads 1 --time-limit 0.01", dir.path()));
    const auto r = nlohmann::json::parse(test::readText(dir / "report.json"));
    const long placed = r["placed_crossings"].get<long>();
    EXPECT_GT(placed, 0);
    EXPECT_EQ(r["start_intersecting_pairs"].get<long>(), 0);
    ASSERT_EQ(r["placement_lifts"].size(), 1u);
    const std::string lift = r["placement_lifts"][0].get<std::string>();
    EXPECT_TRUE(lift.rfind("front_right", 0) == 0 || lift.rfind("front_left", 0) == 0) << lift;
    EXPECT_NE(lift.find(" mm out (crossed front_"), std::string::npos) << lift;
    const std::string warning =
        "panels placed through each other (" + std::to_string(placed) +
        " intersecting triangle pairs) were moved apart on their slots: " + lift;
    bool found = false;
    for (const auto& m : r["warning_messages"]) {
        found = found || m.get<std::string>() == warning;
    }
    EXPECT_TRUE(found) << r["warning_messages"].dump();
    EXPECT_NE(test::readText(dir / "stderr.txt").find(warning), std::string::npos);
}

// Lifted apart, the trousers on the small female body sew shut and rest free of intersections
// (they ended with 24 intersecting pairs and the centre front seam 27.6 mm open when placed
// crossed).
TEST(SampleGarmentSmall, TrousersPlacedThroughThemselvesDrapeClean) {
    drapeAndCheck("trousers", "--particle-distance 20 --threads 1", {true, true, 0.001},
                  fitMatrixBody("female-S"));
}

/// Drapes sample `name` on the fit matrix's `body` at 20 mm up to `seconds` and checks, from the
/// written meshes and against the report, that no cloth went through itself or the body.
void drapeFreeOfTheBody(const std::string& name, const std::string& body, double seconds) {
    test::TempDir dir;
    const fs::path out = dir / "draped.obj";
    ASSERT_TRUE(runDrape(sampleProject(name, dir.path(), fitMatrixBody(body)),
                         "--particle-distance 20 --threads 1 --time-limit " +
                             std::to_string(seconds) + " --out \"" + out.string() + "\"",
                         dir.path()));
    const auto r = nlohmann::json::parse(test::readText(dir / "report.json"));
    FileFigures files;
    ASSERT_NO_FATAL_FAILURE(figuresFromFiles(out, files));
    EXPECT_EQ(files.self, 0);
    EXPECT_EQ(files.withBody, 0);
    EXPECT_EQ(r["intersecting_triangle_pairs"].get<long>(), 0);
    EXPECT_LT(r["max_penetration_m"].get<double>(), 0.001);
}

// A cloth face wedged between the arm and the torso, pierced by both (the dress on the large
// female body at t = 1.10 s): its opposed contacts rocked it, and a vertex walked 25 mm into the
// torso (1 + 14 intersecting pairs, 7.4 mm deep, to the end).
TEST(SampleGarmentLarge, AFaceSqueezedAtTheArmpitStaysOutOfTheBody) {
    drapeFreeOfTheBody("dress", "female-L", 1.3);
}

// Side seams welded by force 36 mm apart (the dress on the large male body at the end of its
// 2 s of sewing) carried the front into the torso (10 pairs, 13.8 mm deep): the welds are put
// off until they can be made clear of the body. (Before faces squeezed at the armpit were
// handled, this drape happened to end clean; with that alone it ends through the body.)
TEST(SampleGarmentLarge, AForcedWeldDoesNotCarryClothIntoTheBody) {
    drapeFreeOfTheBody("dress", "male-L", 2.3);
}

// At the project's own 10 mm (16–25k triangles), as `atelier-cli drape` runs them.
class SampleGarment : public ::testing::TestWithParam<std::string> {};

TEST_P(SampleGarment, DrapesToRestOnTheDefaultBody) {
    drapeAndCheck(GetParam(), "--threads 1", {true, true, 0.001});
}

INSTANTIATE_TEST_SUITE_P(Garments, SampleGarment,
                         ::testing::Values("tshirt", "skirt", "dress", "trousers"));

} // namespace
} // namespace atelier
