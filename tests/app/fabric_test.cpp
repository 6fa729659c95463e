/// `atelier-cli fabric fit`, run as a user would.
#include "app/cli_run.h"

#include "io/materials.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace atelier {
namespace {

using test::inQuotes;
using test::readText;
using test::runCli;
using test::TempDir;

TEST(FabricCli, FitsAPresetFromLabValuesThatLoadsAndShowsThem) {
    const TempDir dir;
    const auto preset = dir / "my-fabrics.json";
    const auto out = dir / "out.txt";
    const auto run = runCli(
        dir, "fabric fit --name twill --density 250 --bending-length-weft 30 "
             "--bending-length-warp 36 --tensile-weft 12000 --tensile-warp 20000 --poisson 0.2 "
             "--tensile-bias 900 --no-drape --out " +
                 inQuotes(preset) + " > " + inQuotes(out));
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const auto loaded = io::loadMaterialPresets(preset);
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    ASSERT_EQ(loaded.value().count("twill"), 1u);
    const sim::Material& m = loaded.value().at("twill");
    EXPECT_DOUBLE_EQ(m.density, 0.25);
    EXPECT_NEAR(m.bendingWeft, 0.25 * 9.80665 * 0.03 * 0.03 * 0.03, 1e-12);
    EXPECT_NEAR(m.bendingWarp, 0.25 * 9.80665 * 0.036 * 0.036 * 0.036, 1e-12);
    EXPECT_DOUBLE_EQ(m.stretchWeft, 12000);
    EXPECT_DOUBLE_EQ(m.stretchWarp, 20000);
    // 1/G = 4/E45 - 1/E1 - 1/E2 + 2 nu12/E1
    EXPECT_NEAR(m.shear, 1 / (4.0 / 900 - 1.0 / 12000 - 1.0 / 20000 + 0.4 / 12000), 1e-6);
    // What it prints is what the lab would measure: the bending lengths given.
    const std::string text = readText(out);
    EXPECT_NE(text.find("weft 30.0 mm, warp 36.0 mm"), std::string::npos) << text;
    EXPECT_NE(text.find("wrote preset \"twill\""), std::string::npos) << text;

    // Read back through --fabrics, the preset shows the same figures.
    const auto shown = dir / "shown.txt";
    const auto again = runCli(dir, "fabric fit --fabrics " + inQuotes(preset) +
                                       " --fabric twill --no-drape > " + inQuotes(shown));
    ASSERT_EQ(again.exitCode, 0) << again.stderrText;
    EXPECT_NE(readText(shown).find("weft 30.0 mm, warp 36.0 mm"), std::string::npos)
        << readText(shown);
}

TEST(FabricCli, ShowsABuiltInPresetsDrapeCoefficient) {
    // A coarse Cusick test (20 mm particles): the accuracy is bench cusick's business.
    const TempDir dir;
    const auto out = dir / "out.txt";
    const auto run =
        runCli(dir, "fabric fit --fabric cotton --particle-distance 20 > " + inQuotes(out));
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const std::string text = readText(out);
    const auto at = text.find("drape coefficient");
    ASSERT_NE(at, std::string::npos) << text;
    const auto colon = text.find("): ", at);
    ASSERT_NE(colon, std::string::npos) << text;
    const double dc = std::stod(text.substr(colon + 3));
    EXPECT_GT(dc, 0.2) << text;
    EXPECT_LT(dc, 1.0) << text;
}

TEST(FabricCli, BadMeasurementsAreNamed) {
    const TempDir dir;
    auto run = runCli(dir, "fabric fit --density 120 --tensile-bias 1e7 --no-drape --out " +
                               inQuotes(dir / "x.json"));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("--tensile-bias"), std::string::npos) << run.stderrText;
    EXPECT_FALSE(std::filesystem::exists(dir / "x.json"));
    run = runCli(dir, "fabric fit --fabric velvet --no-drape");
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("no fabric \"velvet\""), std::string::npos) << run.stderrText;
    run = runCli(dir, "fabric fit --no-drape --out " + inQuotes(dir / "y.json"));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("needs measurements"), std::string::npos) << run.stderrText;
}

} // namespace
} // namespace atelier
