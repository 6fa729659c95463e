// A sample garment draped at 20 mm on the MakeHuman body of ../shared/data, whose slots are
// found from its shape (patterns/body_landmarks.h): seams closed, none welded across a gap,
// no intersecting triangle pairs, as on the mannequin.
#include "app/cli_run.h"

#include "io/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace atelier::test {
namespace {

/// The sample draped: the skirt, the quickest (it hangs from the waist and hips, on the waist
/// slots fitted to the landmarks; the trousers do not yet drape clean on this body:
/// docs/benchmarks.md#samples-on-the-makehuman-body).
constexpr const char* SAMPLE = "skirt";

TEST(MakeHumanDrape, TheSampleDrapesCleanOnTheImportedBody) {
    const std::filesystem::path body =
        std::filesystem::path(ATELIER_SOURCE_DIR) / "../shared/data/bodies/makehuman-base-body.obj";
    if (!std::filesystem::is_regular_file(body)) {
        GTEST_SKIP() << "test data absent: " << body << " (../shared/data beside the checkout)";
    }
    TempDir dir;
    // The sample with the body mesh in place of its mannequin.
    std::ifstream sample(std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/garments" /
                         (std::string(SAMPLE) + ".atelier"));
    nlohmann::ordered_json project = nlohmann::ordered_json::parse(sample, nullptr, false);
    ASSERT_TRUE(project.is_object());
    project["body"] = {{"mesh", std::filesystem::absolute(body).lexically_normal().string()}};
    const auto file = dir.write("g.atelier", project.dump(1));
    const CliRun draped =
        runCli(dir, "drape " + inQuotes(file) + " --particle-distance 20 --out " +
                        inQuotes(dir / "g.obj") + " --report " + inQuotes(dir / "g.json"));
    ASSERT_EQ(draped.exitCode, 0) << draped.stderrText;
    std::ifstream in(dir / "g.json");
    const nlohmann::json report = nlohmann::json::parse(in, nullptr, false);
    ASSERT_TRUE(report.is_object());
    EXPECT_TRUE(report.value("rested", false)) << draped.stderrText;
    EXPECT_EQ(report.value("intersecting_triangle_pairs", -1), 0) << draped.stderrText;
    EXPECT_EQ(report.value("intersecting_pairs_with_obstacles", -1), 0) << draped.stderrText;
    EXPECT_LE(report.value("seam_gap_max_m", 1.0), 1e-3) << draped.stderrText;
    EXPECT_LE(report.value("largest_forced_weld_m", 1.0), 0.0015) << draped.stderrText;
    EXPECT_LE(report.value("max_penetration_m", 1.0), 1e-3) << draped.stderrText;
    EXPECT_TRUE(report.value("finite", false));
}

} // namespace
} // namespace atelier::test
