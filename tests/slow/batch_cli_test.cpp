// `atelier-cli batch` and `batch-summary` end to end: shards, a failed job that does not stop
// the others, re-runs that skip what is complete and redo what changed.
#include "app/cli_run.h"

#include "io/temp_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

namespace atelier::test {
namespace {

const std::string SKIRT = std::string(ATELIER_SOURCE_DIR) + "/assets/garments/skirt.atelier";

nlohmann::json readJson(const std::filesystem::path& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in, nullptr, false);
}

std::string manifestText(const std::string& secondFabric) {
    return R"({"format": "atelier-batch", "version": 1,
      "bodies": {"bad": {"base": "female", "measurements": {"hip": 0.5}}},
      "defaults": {"particle_distance_mm": 40, "time_limit_s": 0.3, "views": [],
                   "threads": 1},
      "jobs": [
        {"name": "one", "project": ")" +
           SKIRT + R"(", "views": ["front"], "size": [64, 64], "exports": ["obj", "glb"]},
        {"name": "two", "project": ")" +
           SKIRT + R"(", "fabric": ")" + secondFabric + R"("},
        {"name": "unfit", "project": ")" +
           SKIRT + R"(", "body": "bad"},
        {"name": "three", "project": ")" +
           SKIRT + R"(", "fabric": "denim"}]})";
}

TEST(BatchCli, ShardsFailuresReRunsAndTheSummary) {
    TempDir dir;
    const auto manifest = dir.write("m.json", manifestText("silk"));
    const auto out = dir / "out";
    const std::string base = "batch " + inQuotes(manifest) + " --out " + inQuotes(out);

    // Two workers: jobs 0 and 2 (one, unfit), then 1 and 3 (two, three).
    const CliRun first = runCli(dir, base + " --shard 0/2");
    EXPECT_EQ(first.exitCode, 1) << first.stderrText; // "unfit" failed
    EXPECT_NE(first.stderrText.find("[1/2] one done"), std::string::npos) << first.stderrText;
    const CliRun second = runCli(dir, base + " --shard 1/2");
    EXPECT_EQ(second.exitCode, 0) << second.stderrText;

    for (const char* name : {"one", "two", "three"}) {
        SCOPED_TRACE(name);
        const auto job = readJson(out / name / "job.json");
        ASSERT_TRUE(job.is_object());
        EXPECT_EQ(job["status"], "done");
        EXPECT_TRUE(job["error"].is_null());
        EXPECT_EQ(job["drape"]["intersecting_triangle_pairs"], 0);
        for (const std::string file : {".obj", ".body.obj", ".report.json", ".atelier"}) {
            EXPECT_TRUE(std::filesystem::is_regular_file(out / name / (name + file))) << file;
        }
    }
    EXPECT_TRUE(std::filesystem::is_regular_file(out / "one" / "one-front.png"));
    EXPECT_GT(std::filesystem::file_size(out / "one" / "one.glb"), 1000U);
    EXPECT_EQ(readJson(out / "two" / "job.json")["fabric"], "silk");
    // The job's project is the manifest's with its fabric: a version-2 project naming it.
    EXPECT_NE(readText(out / "two" / "two.atelier").find("\"silk\""), std::string::npos);

    const auto unfit = readJson(out / "unfit" / "job.json");
    EXPECT_EQ(unfit["status"], "failed");
    ASSERT_TRUE(unfit["error"].is_string());
    EXPECT_NE(unfit["error"].get<std::string>().find("/body/measurements"), std::string::npos)
        << unfit["error"];

    // A re-run skips the complete jobs and tries the failed one again.
    const CliRun again = runCli(dir, base);
    EXPECT_EQ(again.exitCode, 1);
    EXPECT_NE(again.stderrText.find("3 skipped"), std::string::npos) << again.stderrText;
    EXPECT_NE(again.stderrText.find("unfit failed"), std::string::npos) << again.stderrText;

    // A changed job is redone; the others are still skipped.
    dir.write("m.json", manifestText("cotton"));
    const CliRun changed = runCli(dir, base + " --shard 1/2");
    EXPECT_EQ(changed.exitCode, 0) << changed.stderrText;
    EXPECT_NE(changed.stderrText.find("two done"), std::string::npos) << changed.stderrText;
    EXPECT_NE(changed.stderrText.find("three skipped"), std::string::npos) << changed.stderrText;
    EXPECT_EQ(readJson(out / "two" / "job.json")["fabric"], "cotton");

    // A missing output makes a job incomplete again.
    std::filesystem::remove(out / "three" / "three.obj");
    const CliRun repaired = runCli(dir, base + " --shard 1/2");
    EXPECT_NE(repaired.stderrText.find("three done"), std::string::npos) << repaired.stderrText;

    const CliRun summary =
        runCli(dir, "batch-summary " + inQuotes(out) + " --manifest " + inQuotes(manifest));
    EXPECT_EQ(summary.exitCode, 1) << summary.stderrText; // one job failed
    const auto s = readJson(out / "summary.json");
    ASSERT_TRUE(s.is_object());
    EXPECT_EQ(s["done"], 3);
    EXPECT_EQ(s["failed"], 1);
    EXPECT_EQ(s["jobs_with_intersections"], 0);
    EXPECT_EQ(s["jobs_not_fitting"], 0);
    for (const auto& job : s["jobs"]) {
        if (job["status"] == "done") {
            EXPECT_EQ(job["fit"], "fits") << job["name"] << ": " << job["fit_message"];
        }
    }
    ASSERT_EQ(s["failures"].size(), 1U);
    EXPECT_EQ(s["failures"][0]["name"], "unfit");
    EXPECT_EQ(s["jobs"].size(), 4U);
    EXPECT_TRUE(s["missing"].empty());
}

TEST(BatchCli, BadManifestsAndShardsAreInputErrors) {
    TempDir dir;
    const auto manifest = dir.write("m.json", manifestText("silk"));
    const CliRun shard = runCli(dir, "batch " + inQuotes(manifest) + " --out " +
                                         inQuotes(dir / "o") + " --shard 2/2");
    EXPECT_EQ(shard.exitCode, 2);
    EXPECT_NE(shard.stderrText.find("--shard"), std::string::npos) << shard.stderrText;
    const auto bad = dir.write("bad.json", R"({"format": "atelier-batch", "version": 1,
      "jobs": [{"name": "a", "project": "x.atelier", "views": ["sideways"]}]})");
    const CliRun view = runCli(dir, "batch " + inQuotes(bad) + " --out " + inQuotes(dir / "o"));
    EXPECT_EQ(view.exitCode, 2);
    EXPECT_NE(view.stderrText.find("/jobs/0/project"), std::string::npos) << view.stderrText;
    EXPECT_FALSE(std::filesystem::exists(dir / "o"));
}

} // namespace
} // namespace atelier::test
