// The GarmentCode specifications of ../shared/data imported with `atelier-cli import
// garmentcode` and draped on the default body at 20 mm: seams closed, none welded across a gap,
// no intersecting triangle pairs.
#include "app/cli_run.h"

#include "io/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace atelier::test {
namespace {

class GarmentCodeDrape : public ::testing::TestWithParam<const char*> {};

TEST_P(GarmentCodeDrape, ImportsAndDrapesClean) {
    const std::filesystem::path spec =
        std::filesystem::path(ATELIER_SOURCE_DIR) / "../shared/data/garmentcode" / GetParam();
    if (!std::filesystem::is_regular_file(spec)) {
        GTEST_SKIP() << "test data absent: " << spec << " (../shared/data beside the checkout)";
    }
    TempDir dir;
    const CliRun imported = runCli(dir, "import garmentcode " + inQuotes(spec) + " --out " +
                                            inQuotes(dir / "g.atelier"));
    ASSERT_EQ(imported.exitCode, 0) << imported.stderrText;
    EXPECT_EQ(imported.stderrText.find("warning:"), std::string::npos) << imported.stderrText;
    const CliRun draped =
        runCli(dir, "drape " + inQuotes(dir / "g.atelier") + " --particle-distance 20 --out " +
                        inQuotes(dir / "g.obj") + " --report " + inQuotes(dir / "g.json"));
    ASSERT_EQ(draped.exitCode, 0) << draped.stderrText;
    std::ifstream in(dir / "g.json");
    const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
    ASSERT_TRUE(report.is_object());
    // Placed with its panels sewn edge to edge (the seam partners touch, they do not cross:
    // the shirt was reported as starting with 289 crossing pairs).
    EXPECT_EQ(report.value("start_intersecting_pairs", -1), 0) << draped.stderrText;
    EXPECT_EQ(draped.stderrText.find("placed through each other"), std::string::npos)
        << draped.stderrText;
    EXPECT_EQ(report.value("intersecting_triangle_pairs", -1), 0) << draped.stderrText;
    EXPECT_EQ(report.value("intersecting_pairs_with_obstacles", -1), 0) << draped.stderrText;
    EXPECT_LE(report.value("seam_gap_max_m", 1.0), 1e-3) << draped.stderrText;
    // Every seam closed by sewing, none welded across a gap at its end.
    EXPECT_LE(report.value("largest_forced_weld_m", 1.0), 0.0015) << draped.stderrText;
    EXPECT_TRUE(report.value("finite", false));
}

INSTANTIATE_TEST_SUITE_P(Shared, GarmentCodeDrape,
                         ::testing::Values("skirt_2_panels.json", "shirt_mean_specification.json"),
                         [](const auto& info) {
                             std::string name = info.param;
                             return name.substr(0, name.find('.'));
                         });

TEST(GarmentCodeBatch, AJobsProjectMayBeASpecification) {
    TempDir dir;
    // A small two-panel tube (their convention: each loop counter-clockwise seen from outside),
    // imported on the fly onto the job's mannequin.
    const auto spec = dir.write("tube.json", R"({"properties": {"units_in_meter": 100},
      "pattern": {"panels": {
        "front": {"vertices": [[-25, 0], [25, 0], [25, 40], [-25, 40]],
                  "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
                            {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
                  "translation": [0, -45, 15], "rotation": [0, 0, 0]},
        "back": {"vertices": [[-25, 0], [-25, 40], [25, 40], [25, 0]],
                 "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
                           {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
                 "translation": [0, -45, -15], "rotation": [0, 0, 0]}},
      "stitches": [[{"panel": "front", "edge": 1}, {"panel": "back", "edge": 2}],
                   [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 0}]]}})");
    const auto manifest = dir.write("m.json", R"({"format": "atelier-batch", "version": 1,
      "defaults": {"particle_distance_mm": 40, "time_limit_s": 0.3, "views": [], "threads": 1},
      "jobs": [{"name": "tube", "project": "tube.json", "fabric": "denim"}]})");
    const CliRun run =
        runCli(dir, "batch " + inQuotes(manifest) + " --out " + inQuotes(dir / "out"));
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    std::ifstream in(dir / "out" / "tube" / "job.json");
    const nlohmann::json job = nlohmann::json::parse(in, nullptr, false);
    ASSERT_TRUE(job.is_object());
    EXPECT_EQ(job["status"], "done");
    // The project the job draped is the imported one, with the job's fabric.
    std::ifstream projectIn(dir / "out" / "tube" / "tube.atelier");
    const nlohmann::json project = nlohmann::json::parse(projectIn, nullptr, false);
    ASSERT_TRUE(project.is_object());
    ASSERT_EQ(project["panels"].size(), 2u);
    EXPECT_EQ(project["panels"][0]["placement"]["slot"], "waist_back");
    EXPECT_EQ(project["seams"].size(), 2u);
    EXPECT_EQ(project["materials"][0]["fabric"], "denim");
}

} // namespace
} // namespace atelier::test
