/// Runs the built atelier-cli (ATELIER_CLI) on tiny scenes and checks exit codes and outputs.

#include "app/cli_run.h"

#include "io/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace atelier {
namespace {

using test::CliRun;
using test::runCli;
using test::TINY_SCENE;

TEST(Cli, SimulateWritesMeshAndReport) {
    test::TempDir dir;
    const auto scene = dir.write("tiny.json", TINY_SCENE);
    const auto out = dir / "out.obj";
    const auto report = dir / "report.json";
    const CliRun run =
        runCli(dir, "simulate \"" + scene.string() + "\" --out \"" + out.string() +
                        "\" --report \"" + report.string() + "\" --threads 1 --frames-dir \"" +
                        (dir / "frames").string() + "\"");
    ASSERT_TRUE(std::filesystem::exists(report)) << run.stderrText;
    const auto json = nlohmann::json::parse(test::readText(report));
    for (const char* key :
         {"steps", "rejected_steps", "force_evaluations", "sim_time_s", "wall_time_s", "min_dt_s",
          "max_dt_s", "finite", "max_edge_strain", "kinetic_energy_j", "energy_input_j",
          "active_stages", "stage_seconds", "integrator", "error", "vertices", "triangles"}) {
        EXPECT_TRUE(json.contains(key)) << key;
    }
    EXPECT_EQ(json["vertices"], 16);
    EXPECT_EQ(json["triangles"], 18);
    EXPECT_EQ(json["integrator"], "implicit-euler");
    EXPECT_TRUE(json["active_stages"].is_array());
    EXPECT_TRUE(json["stage_seconds"].is_object());
    // Exit 0 exactly when the run finished with a finite state; the report says which.
    if (json["finite"] == true && json["error"].is_null()) {
        EXPECT_EQ(run.exitCode, 0) << run.stderrText;
        EXPECT_TRUE(std::filesystem::exists(out));
        const std::string obj = test::readText(out);
        EXPECT_NE(obj.find("g tiny"), std::string::npos);
        EXPECT_NE(obj.find("vt "), std::string::npos);
    } else {
        EXPECT_EQ(run.exitCode, 1) << run.stderrText;
    }
}

TEST(Cli, TheDrapeReportCountsPinsAndTheirDisplacement) {
    test::TempDir dir;
    const auto report = dir / "report.json";
    const CliRun run =
        runCli(dir, "drape \"" ATELIER_SOURCE_DIR "/assets/examples/apron-on-pins.atelier\" "
                    "--particle-distance 40 --time-limit 0.3 --threads 1 --report \"" +
                        report.string() + "\"");
    ASSERT_TRUE(std::filesystem::exists(report)) << run.stderrText;
    const auto json = nlohmann::json::parse(test::readText(report));
    EXPECT_EQ(json["pins"], 2);
    EXPECT_EQ(json["pin_displacement_max_m"], 0.0) << "pinned vertices never move";
    EXPECT_EQ(json["finite"], true);
}

TEST(Cli, BadSceneExitsWithTwoAndNamesTheJsonPath) {
    test::TempDir dir;
    std::string text = TINY_SCENE;
    text.replace(text.find("\"cotton\""), 8, "\"cottn\"");
    const auto scene = dir.write("bad.json", text);
    const CliRun run = runCli(dir, "simulate \"" + scene.string() + "\" --report \"" +
                                       (dir / "r.json").string() + "\"");
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("error: "), std::string::npos) << run.stderrText;
    EXPECT_NE(run.stderrText.find("bad.json: /cloths/0/material: "), std::string::npos)
        << run.stderrText;
    EXPECT_FALSE(std::filesystem::exists(dir / "r.json"));
}

TEST(Cli, MissingSceneAndBadArguments) {
    test::TempDir dir;
    EXPECT_EQ(runCli(dir, "simulate \"" + (dir / "nope.json").string() + "\"").exitCode, 2);
    EXPECT_EQ(runCli(dir, "frobnicate").exitCode, 2);
    EXPECT_EQ(runCli(dir, "simulate x.json --threads 0").exitCode, 2);
    EXPECT_EQ(runCli(dir, "--help > /dev/null").exitCode, 0);
}

/// Ctrl-C (SIGINT, sent by `timeout` after `seconds`) stops a run between steps: exit 130, the
/// state so far written with its report.
nlohmann::json expectInterruptedRunWritesItsState(const test::TempDir& dir, const std::string& args,
                                                  double seconds) {
    const auto out = dir / "out.obj";
    const auto report = dir / "report.json";
    const CliRun run =
        runCli(dir, args + " --out \"" + out.string() + "\" --report \"" + report.string() + "\"",
               "timeout --preserve-status -s INT " + std::to_string(seconds) + " ");
    EXPECT_EQ(run.exitCode, 130) << run.stderrText;
    EXPECT_TRUE(std::filesystem::exists(report)) << run.stderrText;
    if (!std::filesystem::exists(report)) {
        return {};
    }
    EXPECT_TRUE(std::filesystem::exists(out)) << run.stderrText;
    const auto r = nlohmann::json::parse(test::readText(report));
    EXPECT_EQ(r["status"], "cancelled");
    EXPECT_EQ(r["interrupted"], true);
    EXPECT_EQ(r["signal"], "SIGINT");
    EXPECT_EQ(r["exit_code"], 130);
    return r;
}

TEST(Cli, CtrlCStopsASimulationBetweenFramesFarApart) {
    // One output frame every 10000 s of simulated time and no end in sight: the run stops at
    // the next step, not at the next frame (which it would not reach for minutes).
    test::TempDir dir;
    std::string scene = TINY_SCENE;
    scene.replace(scene.find("\"duration\": 0.05"), 16, "\"duration\": 1000000");
    scene.replace(scene.find("\"frame_rate\": 100"), 17, "\"frame_rate\": 0.0001");
    const auto path = dir.write("long.json", scene);
    const auto r =
        expectInterruptedRunWritesItsState(dir, "simulate \"" + path.string() + "\"", 1.0);
    ASSERT_TRUE(r["sim_time_s"].is_number()) << r;
    EXPECT_GT(r["sim_time_s"].get<double>(), 0.0);
    EXPECT_LT(r["sim_time_s"].get<double>(), 10000.0) << "stopped before the first frame";
}

TEST(Cli, CtrlCStopsADrapeAndWritesTheDrapeSoFar) {
    test::TempDir dir;
    const std::string project = std::string(ATELIER_SOURCE_DIR) + "/assets/garments/skirt.atelier";
    expectInterruptedRunWritesItsState(
        dir, "drape \"" + project + "\" --particle-distance 20 --time-limit 60", 1.0);
}

} // namespace
} // namespace atelier
