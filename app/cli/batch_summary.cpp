/// `atelier-cli batch-summary DIR [--manifest M]`: merges the results of every job under DIR
/// (whichever workers ran them) into DIR/summary.json and prints a table.

#include "app/cli/batch.h"
#include "app/cli/commands.h"

#include "io/atomic_file.h"
#include "io/batch_manifest.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>

namespace atelier::app {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct SummaryOptions {
    std::string dir;
    std::string manifest;
};

double numberOr(const json& j, const char* key, double fallback) {
    return j.contains(key) && j[key].is_number() ? j[key].get<double>() : fallback;
}

int runSummary(const SummaryOptions& options) {
    std::error_code ec;
    if (!fs::is_directory(options.dir, ec)) {
        std::cerr << "error: " << options.dir << ": not a folder\n";
        return EXIT_BAD_INPUT;
    }
    std::map<std::string, json> results; // by job name: sorted, whatever the shards' order
    for (const fs::directory_entry& entry : fs::directory_iterator(options.dir, ec)) {
        const fs::path file = entry.path() / JOB_RESULT_FILE;
        if (!entry.is_directory(ec) || !fs::is_regular_file(file, ec)) {
            continue;
        }
        auto text = io::readFile(file, 16 * 1024 * 1024);
        json result = text.ok() ? json::parse(text.value(), nullptr, false) : json();
        if (!result.is_object() || result.value("format", "") != "atelier-batch-job") {
            std::cerr << "warning: " << file.string() << ": not a job result; left out\n";
            continue;
        }
        results[entry.path().filename().string()] = std::move(result);
    }
    std::vector<std::string> missing;
    if (!options.manifest.empty()) {
        auto manifest = io::loadBatchManifest(options.manifest);
        if (!manifest.ok()) {
            std::cerr << "error: " << manifest.error().toString() << "\n";
            return EXIT_BAD_INPUT;
        }
        for (const io::BatchJob& job : manifest.value().jobs) {
            if (!results.contains(job.name)) {
                missing.push_back(job.name);
            }
        }
    }

    int done = 0;
    int failed = 0;
    int rested = 0;
    int intersecting = 0;
    int notFitting = 0;
    double wall = 0;
    double worstGap = 0;
    double worstStrain = 0;
    json jobs = json::array();
    json failures = json::array();
    std::printf("%-32s %-7s %8s %6s %6s %10s %8s  %s\n", "job", "status", "wall s", "rested",
                "pairs", "seam gap", "strain", "fit");
    for (const auto& [name, r] : results) {
        const std::string status = r.value("status", "");
        const json drape = r.contains("drape") ? r["drape"] : json::object();
        const bool isDone = status == "done";
        done += isDone ? 1 : 0;
        failed += isDone ? 0 : 1;
        const double seconds = numberOr(r, "wall_time_s", 0);
        wall += seconds;
        const bool rest = drape.value("rested", false);
        const double pairs = numberOr(drape, "intersecting_triangle_pairs", -1);
        const double gap = numberOr(drape, "seam_gap_max_m", -1);
        const double strain = numberOr(drape, "max_edge_strain", -1);
        const std::string fit = drape.contains("fit") && drape["fit"].is_string()
                                    ? drape["fit"].get<std::string>()
                                    : "-";
        if (isDone) {
            rested += rest ? 1 : 0;
            notFitting += fit == "does not fit" ? 1 : 0;
            intersecting += pairs > 0 ? 1 : 0;
            worstGap = std::max(worstGap, gap);
            worstStrain = std::max(worstStrain, strain);
        } else {
            failures.push_back({{"name", name}, {"error", r.value("error", json(nullptr))}});
        }
        const auto figure = [](double value, double scale, const char* format) {
            char text[32] = "-";
            if (value >= 0) {
                std::snprintf(text, sizeof text, format, scale * value);
            }
            return std::string(text);
        };
        std::printf("%-32s %-7s %8.1f %6s %6s %10s %8s  %s\n", name.c_str(), status.c_str(),
                    seconds, rest ? "yes" : "no", figure(pairs, 1, "%.0f").c_str(),
                    figure(gap, 1000, "%.2fmm").c_str(), figure(strain, 100, "%.1f%%").c_str(),
                    fit.c_str());
        json row = {{"name", name},
                    {"status", status},
                    {"body", r.value("body", "")},
                    {"fabric", r.value("fabric", "")},
                    {"wall_time_s", seconds}};
        for (const auto& [key, value] : drape.items()) {
            row[key] = value;
        }
        jobs.push_back(std::move(row));
    }
    const int count = done + failed;
    json summary = {
        {"format", "atelier-batch-summary"},
        {"version", 1},
        {"jobs_with_results", count},
        {"done", done},
        {"failed", failed},
        {"missing", missing},
        {"wall_time_s_total", wall},
        {"wall_time_s_mean", count > 0 ? wall / count : 0.0},
        {"rested", rested},
        {"jobs_with_intersections", intersecting},
        {"jobs_not_fitting", notFitting},
        {"worst_seam_gap_m", worstGap},
        {"worst_edge_strain", worstStrain},
        {"failures", failures},
        {"jobs", jobs},
    };
    const fs::path out = fs::path(options.dir) / SUMMARY_FILE;
    if (auto written = io::writeFileAtomically(out, summary.dump(2) + "\n"); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    std::printf("%d done, %d failed, %zu missing; %d of the done at rest, %d with intersecting "
                "pairs, %d not fitting; %.1f s per job (wall); %s\n",
                done, failed, missing.size(), rested, intersecting, notFitting,
                count > 0 ? wall / count : 0.0, out.string().c_str());
    for (const json& f : failures) {
        std::printf("failed: %s: %s\n", f["name"].get<std::string>().c_str(),
                    f["error"].is_string() ? f["error"].get<std::string>().c_str() : "");
    }
    return failed > 0 || !missing.empty() ? EXIT_RUN_FAILED : EXIT_OK;
}

} // namespace

void addBatchSummaryCommand(CLI::App& app) {
    auto options = std::make_shared<SummaryOptions>();
    CLI::App* cmd = app.add_subcommand(
        "batch-summary", "Merge the job results under a batch folder into DIR/summary.json");
    cmd->add_option("dir", options->dir, "The folder of `atelier-cli batch --out`")->required();
    cmd->add_option("--manifest", options->manifest,
                    "The batch's manifest: also list its jobs that have no result yet");
    cmd->callback([options] {
        const int code = runSummary(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
