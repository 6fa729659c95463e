/// atelier-cli against interruptions and hostile input: signals at any moment, outputs that
/// would overwrite inputs or cannot be written, meshes too large, file names that are not
/// UTF-8.

#include "app/cli_run.h"

#include "io/obj.h"
#include "io/temp_dir.h"

#include "source_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>

namespace atelier {
namespace {

using test::CliRun;
using test::inQuotes;
using test::runCli;
using test::TINY_SCENE;

/// `timeout` sending `signal` after `seconds`.
std::string after(double seconds, const char* signal) {
    char text[64];
    std::snprintf(text, sizeof text, "timeout --preserve-status -s %s %.3f ", signal, seconds);
    return text;
}

/// The scene of TINY_SCENE running for ever, with an output frame every 10000 s of simulated
/// time (the tiny scene simulates about 300 s a second).
std::string endlessScene() {
    std::string scene = TINY_SCENE;
    scene.replace(scene.find("\"duration\": 0.05"), 16, "\"duration\": 1000000");
    scene.replace(scene.find("\"frame_rate\": 100"), 17, "\"frame_rate\": 0.0001");
    return scene;
}

/// An interrupted drape or simulation: exit 130, a readable OBJ, a report marked interrupted
/// with the simulated time reached.
nlohmann::json expectInterrupted(const test::TempDir& dir, const CliRun& run, const char* signal) {
    EXPECT_EQ(run.exitCode, 130) << run.stderrText;
    const auto mesh = io::readObj(dir / "out.obj");
    EXPECT_TRUE(mesh.ok()) << run.stderrText;
    if (mesh.ok()) {
        EXPECT_GT(mesh.value().triangles.rows(), 0);
        EXPECT_TRUE(mesh.value().positions.allFinite());
    }
    const std::string text = test::readText(dir / "r.json");
    EXPECT_FALSE(text.empty()) << run.stderrText;
    if (text.empty()) {
        return {};
    }
    const auto r = nlohmann::json::parse(text);
    EXPECT_EQ(r["interrupted"], true);
    EXPECT_EQ(r["signal"], signal);
    EXPECT_EQ(r["exit_code"], 130);
    EXPECT_TRUE(r["sim_time_s"].is_number());
    return r;
}

TEST(CliInterrupts, SigintAtARandomMomentOfADrape) {
    const unsigned seed = static_cast<unsigned>(
        std::chrono::steady_clock::now().time_since_epoch().count() & 0xffffffU);
    std::mt19937 random(seed);
    const double seconds = std::uniform_real_distribution<double>(0.2, 1.5)(random);
    std::printf("seed %u: SIGINT after %.3f s\n", seed, seconds);
    SCOPED_TRACE("seed " + std::to_string(seed) + ", SIGINT after " + std::to_string(seconds));
    test::TempDir dir;
    const CliRun run =
        runCli(dir,
               "drape " + inQuotes(test::SKIRT_PROJECT) +
                   " --particle-distance 20 --time-limit 60 --threads 1 --out " +
                   inQuotes(dir / "out.obj") + " --report " + inQuotes(dir / "r.json"),
               after(seconds, "INT"));
    const auto r = expectInterrupted(dir, run, "SIGINT");
    if (!r.empty()) {
        EXPECT_TRUE(r["time_to_rest_s"].is_null());
        EXPECT_TRUE(r["sim_time_to_rest_s"].is_null());
        EXPECT_TRUE(r["drape_time_s"].is_number());
        EXPECT_EQ(r["warnings"], r["warning_messages"].size());
        EXPECT_TRUE(std::filesystem::exists(dir / "out.body.obj"));
    }
}

TEST(CliInterrupts, TheSameSignalTwiceAtOnceIsOneRequest) {
    // `timeout` sends its signal to the command and then to the command's process group: the
    // command gets it twice within microseconds, and must still stop cleanly, not die.
    test::TempDir dir;
    const std::string command =
        std::string("\"") + ATELIER_CLI + "\" drape " + inQuotes(test::SKIRT_PROJECT) +
        " --particle-distance 20 --time-limit 60 --threads 1 --out " + inQuotes(dir / "out.obj") +
        " --report " + inQuotes(dir / "r.json") + " 2> " + inQuotes(dir / "stderr.txt") +
        " & pid=$!; sleep 0.6; kill -TERM $pid; kill -TERM $pid; wait $pid";
    const int status = std::system(command.c_str());
    CliRun run;
    run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.stderrText = test::readText(dir / "stderr.txt");
    expectInterrupted(dir, run, "SIGTERM");
}

TEST(CliInterrupts, SigtermStopsASimulationWithinAStep) {
    // A run stopping only at frames would go on for about half a minute.
    test::TempDir dir;
    const auto scene = dir.write("endless.json", endlessScene());
    const CliRun run =
        runCli(dir,
               "simulate " + inQuotes(scene) + " --out " + inQuotes(dir / "out.obj") +
                   " --report " + inQuotes(dir / "r.json"),
               after(0.5, "TERM"));
    const auto r = expectInterrupted(dir, run, "SIGTERM");
    if (!r.empty()) {
        EXPECT_LT(r["sim_time_s"].get<double>(), 10000.0) << "stopped before the first frame";
    }
}

TEST(CliInterrupts, SigtermStopsABenchDrape) {
    test::TempDir dir;
    const CliRun run = runCli(dir,
                              "bench drape " + inQuotes(test::SKIRT_PROJECT) +
                                  " --particle-distance 20 --time-limit 60 --threads 1 --out " +
                                  inQuotes(dir / "b.json"),
                              after(0.8, "TERM"));
    EXPECT_EQ(run.exitCode, 130) << run.stderrText;
    const std::string text = test::readText(dir / "b.json");
    ASSERT_FALSE(text.empty()) << run.stderrText;
    const auto figures = nlohmann::json::parse(text);
    EXPECT_EQ(figures["interrupted"], true);
    // The figures so far include whether the garment fits (here: still sewing, seams open).
    EXPECT_TRUE(figures["fit"].is_string());
    EXPECT_GE(figures["strain_max"].get<double>(), 0.0);
}

TEST(CliOutputs, AnOutputOverAnInputIsRefusedBeforeAnyWork) {
    test::TempDir dir;
    const auto scene = dir.write("tiny.json", TINY_SCENE);
    CliRun run = runCli(dir, "simulate " + inQuotes(scene) + " --out " + inQuotes(scene));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("--out: " + scene.string() + ": is the input scene"),
              std::string::npos)
        << run.stderrText;
    EXPECT_EQ(test::readText(scene), TINY_SCENE);

    // The same file by another spelling, and the report over the mesh.
    const std::string other = (dir / "." / "tiny.json").string();
    run = runCli(dir, "simulate " + inQuotes(scene) + " --report " + inQuotes(other));
    EXPECT_EQ(run.exitCode, 2) << run.stderrText;
    EXPECT_EQ(test::readText(scene), TINY_SCENE);
    run = runCli(dir, "simulate " + inQuotes(scene) + " --out " + inQuotes(dir / "a.obj") +
                          " --report " + inQuotes(dir / "a.obj"));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("--report: "), std::string::npos) << run.stderrText;
    EXPECT_NE(run.stderrText.find("is also the output of --out"), std::string::npos);

    run = runCli(dir, "drape " + inQuotes(test::SKIRT_PROJECT) + " --out " +
                          inQuotes(test::SKIRT_PROJECT));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("is the input project"), std::string::npos) << run.stderrText;
    EXPECT_FALSE(std::filesystem::exists(dir / "r.json"));
}

TEST(CliOutputs, AMissingOrReadOnlyFolderIsNoticedAtOnce) {
    test::TempDir dir;
    const auto missing = dir / "no-such-folder" / "out.obj";
    CliRun run = runCli(dir, "drape " + inQuotes(test::SKIRT_PROJECT) +
                                 " --particle-distance 20 --out " + inQuotes(missing));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("--out: " + missing.string() + ": the folder "),
              std::string::npos)
        << run.stderrText;
    EXPECT_EQ(run.stderrText.find("drape: "), std::string::npos) << "nothing meshed";
    run = runCli(dir, "body --report " + inQuotes(dir / "nope" / "b.json"));
    EXPECT_EQ(run.exitCode, 2) << run.stderrText;
    if (::geteuid() == 0) {
        GTEST_SKIP() << "root writes into read-only folders";
    }
    std::filesystem::create_directory(dir / "ro");
    std::filesystem::permissions(dir / "ro", std::filesystem::perms::owner_read |
                                                 std::filesystem::perms::owner_exec);
    run = runCli(dir, "drape " + inQuotes(test::SKIRT_PROJECT) + " --report " +
                          inQuotes(dir / "ro" / "r.json"));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("is not writable"), std::string::npos) << run.stderrText;
    std::filesystem::permissions(dir / "ro", std::filesystem::perms::owner_all);
}

TEST(CliLimits, AMeshTooLargeIsRefusedBeforeMeshing) {
    test::TempDir dir;
    CliRun run = runCli(dir, "drape " + inQuotes(test::SKIRT_PROJECT) +
                                 " --particle-distance 0.01 --out " + inQuotes(dir / "out.obj"));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("above the limit of 200000 (--max-vertices N raises it)"),
              std::string::npos)
        << run.stderrText;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.obj"));
    run = runCli(dir, "bench drape " + inQuotes(test::SKIRT_PROJECT) + " --particle-distance 0.01");
    EXPECT_EQ(run.exitCode, 2);
    const auto scene = dir.write("tiny.json", TINY_SCENE); // 16 vertices
    run = runCli(dir, "simulate " + inQuotes(scene) + " --max-vertices 15");
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("about 16 vertices, above the limit of 15"), std::string::npos)
        << run.stderrText;
}

TEST(CliLimits, TheInputLimitsAreListedAndChangedByName) {
    test::TempDir dir;
    const auto scene = dir.write("tiny.json", TINY_SCENE); // 0.05 s at 100 frames/s: 5 frames
    CliRun run = runCli(dir, "limits > " + inQuotes(dir / "limits.txt"));
    EXPECT_EQ(run.exitCode, 0);
    const std::string listed = test::readText(dir / "limits.txt");
    for (const char* name : {"json-bytes", "json-depth", "cloths", "frames", "garment-triangles"}) {
        EXPECT_NE(listed.find(name), std::string::npos) << name;
    }
    // Lowered below what the scene asks: refused, naming the limit and how to change it.
    run = runCli(dir, "simulate " + inQuotes(scene) + " --limit frames=4 --out " +
                          inQuotes(dir / "a.obj"));
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("more than the limit of 4"), std::string::npos) << run.stderrText;
    EXPECT_NE(run.stderrText.find("--limit NAME=VALUE"), std::string::npos) << run.stderrText;
    EXPECT_FALSE(std::filesystem::exists(dir / "a.obj"));
    // Raised back: it runs.
    run =
        runCli(dir, "simulate " + inQuotes(scene) +
                        " --limit frames=5 --limit json-depth=8 --out " + inQuotes(dir / "a.obj"));
    EXPECT_EQ(run.exitCode, 0) << run.stderrText;
    // Unknown names and bad values.
    for (const char* bad : {"frame=5", "frames", "frames=0", "frames=2.5", "body-extent-m=nan"}) {
        run = runCli(dir, "simulate " + inQuotes(scene) + " --limit " + bad);
        EXPECT_EQ(run.exitCode, 2) << bad;
        EXPECT_NE(run.stderrText.find("error: --limit: \"" + std::string(bad)), std::string::npos)
            << run.stderrText;
    }
}

TEST(CliReports, ANameThatIsNotUtf8KeepsItsReport) {
    test::TempDir dir;
    const auto scene = dir.write("tiny\xff.json", TINY_SCENE);
    const CliRun run =
        runCli(dir, "simulate " + inQuotes(scene) + " --report " + inQuotes(dir / "r.json"));
    EXPECT_EQ(run.exitCode, 0) << run.stderrText;
    const auto r = nlohmann::json::parse(test::readText(dir / "r.json"));
    EXPECT_EQ(r["scene"].get<std::string>(), (dir / "tiny\xef\xbf\xbd.json").string());
}

TEST(CliAnimate, ABodyAnimationThatIsNotTheProjectsBodyIsRefusedBeforeAnyWork) {
    test::TempDir dir;
    nlohmann::json project = nlohmann::json::parse(test::readText(test::SKIRT_PROJECT));
    project["body"] = {{"mesh", "body.glb"}};
    const auto file = dir.write("skirt.atelier", project.dump());
    // Never read: the refusals come first.
    dir.write("body.glb", "not read");
    dir.write("other.glb", "not read");
    const std::string out = " --out " + inQuotes(dir / "seq.glb");
    CliRun run = runCli(dir, "animate " + inQuotes(file) + " --body-animation " +
                                 inQuotes(dir / "other.glb") + out);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("/body/mesh: the body is body.glb, not --body-animation"),
              std::string::npos)
        << run.stderrText;
    run = runCli(dir, "animate " + inQuotes(file) + " --body-animation " +
                          inQuotes(dir / "missing.glb") + out);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("missing.glb: the body animation file is not found"),
              std::string::npos)
        << run.stderrText;
    run = runCli(dir, "animate " + inQuotes(file) + out);
    EXPECT_EQ(run.exitCode, 2);
    EXPECT_NE(run.stderrText.find("give the motion as --body-frames or as --body-animation"),
              std::string::npos)
        << run.stderrText;
    EXPECT_FALSE(std::filesystem::exists(dir / "seq.glb"));
}

} // namespace
} // namespace atelier
