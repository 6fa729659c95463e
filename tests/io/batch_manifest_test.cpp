#include "io/batch_manifest.h"
#include "io/temp_dir.h"

#include "source_paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>

namespace atelier::io {
namespace {

Result<BatchManifest> parseManifest(const std::string& text) {
    return parseBatchManifest(text, "m.json", test::GARMENTS_DIR);
}

std::string manifest(const std::string& body) {
    return R"({"format": "atelier-batch", "version": 1, )" + body + "}";
}

TEST(BatchManifest, JobsTakeTheDefaultsAndOverrideThem) {
    const auto m = parseManifest(manifest(R"(
      "bodies": {"M": {"base": "male", "measurements": {"waist": 0.84, "hip": 0.98}}},
      "defaults": {"views": ["front", "back"], "size": [256, 128], "particle_distance_mm": 20,
                   "fabric": "denim", "threads": 2},
      "jobs": [{"name": "a", "project": "skirt.atelier"},
               {"name": "b", "project": "tshirt.atelier", "body": "M", "fabric": "silk",
                "views": ["top"], "time_limit_s": 2}])"));
    ASSERT_TRUE(m.ok()) << m.error().toString();
    const auto& jobs = m.value().jobs;
    ASSERT_EQ(jobs.size(), 2U);
    EXPECT_EQ(jobs[0].name, "a");
    EXPECT_EQ(jobs[0].project, std::filesystem::absolute(test::GARMENTS_DIR / "skirt.atelier"));
    EXPECT_EQ(jobs[0].views, (std::vector<std::string>{"front", "back"}));
    EXPECT_EQ(jobs[0].width, 256);
    EXPECT_EQ(jobs[0].height, 128);
    EXPECT_DOUBLE_EQ(*jobs[0].particleDistance, 0.02);
    EXPECT_EQ(jobs[0].fabric, "denim");
    EXPECT_EQ(jobs[0].threads, 2);
    EXPECT_FALSE(jobs[0].body.has_value());
    EXPECT_FALSE(jobs[0].timeLimit.has_value());
    EXPECT_EQ(jobs[0].exports, (std::vector<std::string>{"obj"}));

    EXPECT_EQ(jobs[1].fabric, "silk");
    EXPECT_EQ(jobs[1].views, (std::vector<std::string>{"top"}));
    EXPECT_DOUBLE_EQ(*jobs[1].timeLimit, 2.0);
    ASSERT_TRUE(jobs[1].body.has_value());
    EXPECT_EQ(jobs[1].body->base, "male");
    EXPECT_EQ(jobs[1].bodyLabel, "M");
    // Measurements keep the manifest's order.
    ASSERT_EQ(jobs[1].body->measurements.size(), 2U);
    EXPECT_EQ(jobs[1].body->measurements[0].first, "waist");
    EXPECT_EQ(jobs[1].pointer, "/jobs/1");
}

TEST(BatchManifest, TheMatrixIsEveryProjectBodyAndFabric) {
    const auto m = parseManifest(manifest(R"(
      "bodies": {"S": {"base": "female"}, "L": {"base": "male"}},
      "matrix": {"projects": ["skirt.atelier", "dress.atelier"], "bodies": ["S", "L"],
                 "fabrics": ["cotton", "denim", "silk"], "views": ["front"]})"));
    ASSERT_TRUE(m.ok()) << m.error().toString();
    const auto& jobs = m.value().jobs;
    ASSERT_EQ(jobs.size(), 12U);
    std::set<std::string> names;
    for (const BatchJob& j : jobs) {
        names.insert(j.name);
        EXPECT_EQ(j.views, (std::vector<std::string>{"front"}));
    }
    EXPECT_EQ(names.size(), 12U);
    EXPECT_EQ(jobs.front().name, "skirt-S-cotton");
    EXPECT_EQ(jobs.back().name, "dress-L-silk");
    EXPECT_EQ(jobs.back().body->base, "male");
}

TEST(BatchManifest, ShardsSplitTheJobsWithoutOverlap) {
    std::vector<int> taken(10, 0);
    for (int i = 0; i < 3; ++i) {
        for (const std::size_t k : shardJobs(10, i, 3)) {
            ++taken[k];
        }
    }
    for (const int t : taken) {
        EXPECT_EQ(t, 1);
    }
    EXPECT_EQ(shardJobs(10, 1, 3), (std::vector<std::size_t>{1, 4, 7}));
    EXPECT_TRUE(shardJobs(2, 2, 3).empty());
    EXPECT_TRUE(shardJobs(10, 3, 3).empty()); // out of range: nothing, not a crash
    EXPECT_TRUE(shardJobs(10, 0, 0).empty());
}

TEST(BatchManifest, ErrorsNameTheJsonPointer) {
    struct Case {
        std::string body;
        std::string where;
        std::string words;
    };
    const std::vector<Case> cases = {
        {R"("jobs": [{"name": "a", "project": "nope.atelier"}])", "/jobs/0/project",
         "project not found"},
        {R"("jobs": [{"name": "a b", "project": "skirt.atelier"}])", "/jobs/0/name",
         "letters, digits"},
        {R"("jobs": [{"name": "..", "project": "skirt.atelier"}])", "/jobs/0/name", "folder"},
        {R"("jobs": [{"name": "a", "project": "skirt.atelier"},
                     {"name": "a", "project": "skirt.atelier"}])",
         "/jobs/1", "already used at /jobs/0"},
        {R"("jobs": [{"name": "a", "project": "skirt.atelier", "fabric": "tweed"}])",
         "/jobs/0/fabric", "unknown fabric preset"},
        {R"("jobs": [{"name": "a", "project": "skirt.atelier", "body": "XL"}])", "/jobs/0/body",
         "no body named"},
        {R"("jobs": [{"name": "a", "project": "skirt.atelier", "size": [0, 10]}])", "/jobs/0/size",
         "between 1 and 4096"},
        {R"("jobs": [{"name": "a", "project": "skirt.atelier", "exports": ["stl"]}])",
         "/jobs/0/exports/0", "unknown export format"},
        {R"("jobs": [{"name": "a", "project": "skirt.atelier", "thread": 2}])", "/jobs/0/thread",
         ""},
        {R"("jobs": [{"name": "a", "project": "skirt.atelier", "particle_distance_mm": 0.1}])",
         "/jobs/0/particle_distance_mm", "between 1 and 1000"},
        {R"("matrix": {"projects": ["skirt.atelier"], "fabrics": ["velvet"]})", "/matrix/fabrics/0",
         "unknown fabric preset"},
        {R"("jobs": [])", "/jobs", "no jobs"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.body);
        const auto m = parseManifest(manifest(c.body));
        ASSERT_FALSE(m.ok());
        EXPECT_EQ(m.error().file, "m.json");
        EXPECT_EQ(m.error().where, c.where);
        EXPECT_NE(m.error().message.find(c.words), std::string::npos) << m.error().message;
    }
    const auto version = parseManifest(R"({"format": "atelier-batch", "version": 2, "jobs": []})");
    ASSERT_FALSE(version.ok());
    EXPECT_EQ(version.error().where, "/version");
    const auto syntax = parseManifest(R"({"format": "atelier-batch", )");
    ASSERT_FALSE(syntax.ok());
    EXPECT_NE(syntax.error().where.find("line 1"), std::string::npos);
}

TEST(BatchManifest, LoadResolvesPathsAgainstTheManifestsFolder) {
    test::TempDir dir;
    const auto path = dir.write("m.json", manifest(R"(
      "jobs": [{"name": "a", "project": ")" + (test::GARMENTS_DIR / "skirt.atelier").string() +
                                                   R"("},
               {"name": "b", "project": "missing.atelier"}])"));
    const auto m = loadBatchManifest(path);
    ASSERT_FALSE(m.ok());
    EXPECT_EQ(m.error().where, "/jobs/1/project");
    EXPECT_NE(m.error().message.find((dir / "missing.atelier").string()), std::string::npos)
        << m.error().message;
}

TEST(BatchManifest, TheBundledManifestsRead) {
    const auto folder = test::GARMENTS_DIR.parent_path() / "batch";
    int read = 0;
    for (const auto& entry : std::filesystem::directory_iterator(folder)) {
        if (entry.path().extension() != ".json") {
            continue;
        }
        const auto m = loadBatchManifest(entry.path());
        ASSERT_TRUE(m.ok()) << m.error().toString();
        // catalogue, fit matrix: 24 jobs each; fabric matrix: 4 samples x 7 presets
        const std::size_t jobs = entry.path().stem() == "fabric-matrix" ? 28U : 24U;
        EXPECT_EQ(m.value().jobs.size(), jobs) << entry.path();
        ++read;
    }
    EXPECT_GE(read, 3);
}

TEST(BatchManifest, FingerprintsDiffer) {
    EXPECT_EQ(fingerprint(""), 14695981039346656037ULL); // FNV-1a's offset basis
    EXPECT_NE(fingerprint("views front"), fingerprint("views back"));
}

} // namespace
} // namespace atelier::io
