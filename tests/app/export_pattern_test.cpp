// `atelier-cli export-pattern`: every sample exports; bad input (a missing or broken project,
// an --out that cannot be written, a bad allowance) exits 2 with an error naming it, and
// leaves no file behind.
#include "app/cli_run.h"

#include "source_paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace atelier::test {
namespace {

TEST(CliExportPattern, EverySampleExports) {
    const TempDir dir;
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(test::GARMENTS_DIR)) {
        if (entry.path().extension() != ".atelier") {
            continue;
        }
        SCOPED_TRACE(entry.path().filename().string());
        const auto out = dir / (entry.path().stem().string() + ".svg");
        const CliRun run = runCli(dir, "export-pattern " + inQuotes(entry.path()) + " --out " +
                                           inQuotes(out) + " --seam-allowance 15");
        EXPECT_EQ(run.exitCode, 0) << run.stderrText;
        const std::string svg = readText(out);
        EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos);
        EXPECT_NE(svg.find("seam allowance 15 mm"), std::string::npos);
        EXPECT_NE(run.stderrText.find("export-pattern: "), std::string::npos) << run.stderrText;
        ++count;
    }
    EXPECT_EQ(count, 4);
}

TEST(CliExportPattern, BadInputExitsWithTwoAndSaysWhy) {
    const TempDir dir;
    const std::string skirt = inQuotes(test::GARMENTS_DIR / "skirt.atelier");
    const auto out = dir / "pattern.svg";
    struct Case {
        std::string args;
        std::string message;
    };
    const auto broken = dir.write("broken.atelier", "{\"format\": \"atelier-project\", ");
    const std::vector<Case> cases = {
        {"export-pattern " + inQuotes(dir / "missing.atelier") + " --out " + inQuotes(out),
         "missing.atelier"},
        {"export-pattern " + inQuotes(broken) + " --out " + inQuotes(out), "broken.atelier"},
        {"export-pattern " + skirt + " --out " + inQuotes(dir / "no" / "such" / "p.svg"), "--out"},
        {"export-pattern " + skirt + " --out " + inQuotes(dir.path()), "--out"},
        {"export-pattern " + skirt + " --out " + inQuotes(out) + " --seam-allowance -1",
         "--seam-allowance -1: must be from 0"},
        {"export-pattern " + skirt + " --out " + inQuotes(out) + " --seam-allowance nan",
         "--seam-allowance"},
        {"export-pattern " + skirt, "--out"},
        {"export-pattern " + skirt + " --out " + inQuotes(out) + " --sheet-width 200",
         "mm sheet less its 10 mm margins"},
        {"export-pattern " + skirt + " --out " + inQuotes(out) + " --sheet-width -5",
         "--sheet-width -5: must be 0"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.args);
        const CliRun run = runCli(dir, c.args);
        EXPECT_EQ(run.exitCode, 2) << run.stderrText;
        EXPECT_NE(run.stderrText.find(c.message), std::string::npos) << run.stderrText;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
}

} // namespace
} // namespace atelier::test
