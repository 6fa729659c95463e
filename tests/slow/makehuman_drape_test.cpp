// Sample garments draped at 20 mm on the MakeHuman body of ../shared/data, whose slots are
// found from its shape (patterns/body_landmarks.h): seams closed, no intersecting triangle
// pairs, as on the mannequin.
#include "app/cli_run.h"

#include "io/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <ostream>
#include <string>

namespace atelier::test {
namespace {

/// What a sample's drape on the MakeHuman body must show.
struct Expected {
    const char* sample;
    /// Largest pair welded across a gap at the end of sewing [m]: the trousers' inseams and
    /// centre front do not close within their 1 s of sewing on this body (up to 25 mm;
    /// docs/benchmarks.md#samples-on-the-makehuman-body).
    double largestForcedWeld;
    /// Panels moved apart on their slots as placed (the trousers' backs reach round into each
    /// other between the legs): how many.
    std::size_t moved;
};

void PrintTo(const Expected& e, std::ostream* os) {
    *os << e.sample;
}

class MakeHumanDrape : public ::testing::TestWithParam<Expected> {};

TEST_P(MakeHumanDrape, TheSampleDrapesCleanOnTheImportedBody) {
    const Expected& e = GetParam();
    const std::filesystem::path body =
        std::filesystem::path(ATELIER_SOURCE_DIR) / "../shared/data/bodies/makehuman-base-body.obj";
    if (!std::filesystem::is_regular_file(body)) {
        GTEST_SKIP() << "test data absent: " << body << " (../shared/data beside the checkout)";
    }
    TempDir dir;
    // The sample with the body mesh in place of its mannequin.
    std::ifstream sample(std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/garments" /
                         (std::string(e.sample) + ".atelier"));
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
    EXPECT_EQ(report.value("start_intersecting_pairs", -1), 0) << draped.stderrText;
    EXPECT_EQ(report.value("intersecting_triangle_pairs", -1), 0) << draped.stderrText;
    EXPECT_EQ(report.value("intersecting_pairs_with_obstacles", -1), 0) << draped.stderrText;
    EXPECT_LE(report.value("seam_gap_max_m", 1.0), 1e-3) << draped.stderrText;
    EXPECT_LE(report.value("largest_forced_weld_m", 1.0), e.largestForcedWeld) << draped.stderrText;
    EXPECT_LE(report.value("max_penetration_m", 1.0), 1e-3) << draped.stderrText;
    EXPECT_EQ(report.value("fit", std::string()), "fits") << draped.stderrText;
    EXPECT_EQ(report["placement_lifts"].size(), e.moved) << draped.stderrText;
    EXPECT_TRUE(report.value("finite", false));
}

// The skirt, the quickest (it hangs from the waist and hips, on the waist slots fitted to the
// landmarks), and the trousers, whose panels are placed through each other on this body.
INSTANTIATE_TEST_SUITE_P(Samples, MakeHumanDrape,
                         ::testing::Values(Expected{"skirt", 0.0015, 0},
                                           Expected{"trousers", 0.026, 2}),
                         [](const ::testing::TestParamInfo<Expected>& info) {
                             return std::string(info.param.sample);
                         });

} // namespace
} // namespace atelier::test
