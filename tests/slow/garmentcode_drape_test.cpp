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
    EXPECT_EQ(imported.stderrText.find("warning"), std::string::npos) << imported.stderrText;
    const CliRun draped =
        runCli(dir, "drape " + inQuotes(dir / "g.atelier") + " --particle-distance 20 --out " +
                        inQuotes(dir / "g.obj") + " --report " + inQuotes(dir / "g.json"));
    ASSERT_EQ(draped.exitCode, 0) << draped.stderrText;
    std::ifstream in(dir / "g.json");
    const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
    ASSERT_TRUE(report.is_object());
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

} // namespace
} // namespace atelier::test
