/// `atelier-cli batch MANIFEST.json --out DIR [--shard I/N]`: drape, export and draw every job
/// of a manifest (or a worker's share of them), each in its own folder and its own process;
/// `atelier-cli batch-summary DIR` merges the jobs' results. docs/batch.md.

#include "app/cli/batch.h"
#include "app/cli/child_process.h"
#include "app/cli/commands.h"
#include "app/cli/interrupt.h"

#include "ui/render/camera.h"

#include "io/atomic_file.h"
#include "io/batch_manifest.h"
#include "io/body_file.h"
#include "io/garmentcode.h"
#include "io/materials.h"
#include "io/project_file.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <iterator>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace atelier::app {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

struct BatchOptions {
    std::string manifest;
    std::string out;
    std::string shard = "0/1";
    double jobTimeout = 0; ///< [s]; 0 = none
    bool dryRun = false;
};

/// A GarmentCode specification (a `.json` project of a job) imported onto the job's body: the
/// mannequin its project would have (each body made once per run), or the default mannequin
/// for a body mesh. Warnings are printed once per specification and body.
Result<patterns::Project> importedProject(const io::BatchJob& job) {
    static std::vector<std::pair<patterns::BodySource, patterns::Body>> bodies;
    static std::set<std::pair<std::string, std::string>> warned;
    patterns::BodySource source;
    if (job.body && job.body->meshPath.empty()) {
        source = *job.body;
    }
    auto cached = std::find_if(bodies.begin(), bodies.end(),
                               [&](const auto& b) { return b.first == source; });
    if (cached == bodies.end()) {
        auto made = io::makeBody(source, job.project.string());
        if (!made.ok()) {
            return made.error();
        }
        bodies.emplace_back(source, std::move(made.value().body));
        cached = std::prev(bodies.end());
    }
    auto imported = io::importGarmentCode(job.project, cached->second);
    if (!imported.ok()) {
        return imported.error();
    }
    std::string bodyKey = source.base;
    for (const auto& [name, value] : source.measurements) {
        bodyKey += " " + name + "=" + std::to_string(value);
    }
    if (warned.insert({job.project.string(), bodyKey}).second) {
        for (const std::string& w : imported.value().warnings) {
            std::cerr << "warning: " << job.project.string() << ": " << w << "\n";
        }
    }
    patterns::Project project = std::move(imported.value().project);
    project.body = source;
    return project;
}

/// The job's project as the job drapes it: the manifest's project (or a GarmentCode
/// specification imported) with the job's body, fabric and settings, in canonical form
/// (version 2), its body mesh path made absolute.
Result<std::string> jobProjectText(const io::BatchJob& job) {
    auto loaded =
        job.project.extension() == ".json" ? importedProject(job) : io::loadProject(job.project);
    if (!loaded.ok()) {
        return loaded.error();
    }
    patterns::Project project = std::move(loaded.value());
    if (!project.body.meshPath.empty() && fs::path(project.body.meshPath).is_relative()) {
        project.body.meshPath =
            fs::absolute(job.project.parent_path() / project.body.meshPath).lexically_normal();
    }
    if (job.body) {
        project.body = *job.body;
    }
    if (!job.fabric.empty()) {
        const sim::Material& preset = io::builtinMaterialPresets().at(job.fabric);
        for (patterns::GarmentMaterial& m : project.document.materials) {
            m.material = preset;
        }
        patterns::syncGarment(project);
    }
    if (job.particleDistance) {
        project.drape.particleDistance = *job.particleDistance;
    }
    if (job.timeLimit) {
        project.drape.timeLimit = *job.timeLimit;
    }
    std::string text = io::formatProject(project);
    // Read back as the drape will: the job's body and settings checked before any work.
    const std::string file = job.name + ".atelier";
    if (auto checked = io::parseProject(text, file); !checked.ok()) {
        return checked.error();
    }
    return text;
}

std::string sizeText(const io::BatchJob& job) {
    return std::to_string(job.width) + "x" + std::to_string(job.height);
}

/// The files a finished job has, relative to its folder.
std::vector<std::string> jobOutputs(const io::BatchJob& job) {
    std::vector<std::string> out = {job.name + ".atelier", job.name + ".report.json",
                                    job.name + ".obj", job.name + ".mtl", job.name + ".body.obj"};
    for (const std::string& format : job.exports) {
        if (format != "obj") {
            out.push_back(job.name + "." + format);
        }
    }
    for (const std::string& view : job.views) {
        out.push_back(job.name + "-" + view + ".png");
    }
    return out;
}

/// Whether `dir/job.json` says the job is done with this fingerprint, and its outputs are
/// all there.
bool jobComplete(const fs::path& dir, const io::BatchJob& job, const std::string& print) {
    auto text = io::readFile(dir / JOB_RESULT_FILE, 16 * 1024 * 1024);
    if (!text.ok()) {
        return false;
    }
    const json result = json::parse(text.value(), nullptr, false);
    if (!result.is_object() || result.value("status", "") != "done" ||
        result.value("fingerprint", "") != print) {
        return false;
    }
    std::error_code ec;
    for (const std::string& file : jobOutputs(job)) {
        if (!fs::is_regular_file(dir / file, ec)) {
            return false;
        }
    }
    return true;
}

/// The last non-empty line of a log that starts with "error:", or else its last line.
std::string logError(const fs::path& log) {
    auto text = io::readFile(log, 64 * 1024 * 1024);
    if (!text.ok()) {
        return "";
    }
    std::string last;
    std::string lastError;
    std::size_t start = 0;
    const std::string& t = text.value();
    while (start < t.size()) {
        std::size_t end = t.find('\n', start);
        if (end == std::string::npos) {
            end = t.size();
        }
        std::string line = t.substr(start, end - start);
        if (const auto cr = line.rfind('\r'); cr != std::string::npos) {
            line = line.substr(cr + 1); // a progress line redrawn in place
        }
        if (!line.empty()) {
            last = line;
            if (line.rfind("error:", 0) == 0) {
                lastError = line.substr(7);
            }
        }
        start = end + 1;
    }
    return lastError.empty() ? last : lastError;
}

/// The drape report's quality figures, copied into the job's result.
void copyFigures(const fs::path& report, json& result) {
    auto text = io::readFile(report, 64 * 1024 * 1024);
    if (!text.ok()) {
        return;
    }
    const json r = json::parse(text.value(), nullptr, false);
    if (!r.is_object()) {
        return;
    }
    for (const char* key :
         {"status", "rested", "drape_time_s", "sim_time_to_rest_s", "drape_wall_time_s",
          "intersecting_triangle_pairs", "intersecting_pairs_with_obstacles", "seam_gap_max_m",
          "area_ratio", "max_edge_strain", "max_penetration_m", "triangles", "warnings", "fit",
          "fit_message"}) {
        if (r.contains(key)) {
            result["drape"][key] = r[key];
        }
    }
}

struct Tally {
    int done = 0;
    int failed = 0;
    int skipped = 0;
};

enum class JobEnd { Done, Failed, Skipped, Interrupted };

/// Runs one job in `dir` (created); writes its result file last.
JobEnd runJob(const io::BatchJob& job, const fs::path& dir, const BatchOptions& options,
              std::string& message) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) {
        message = dir.string() + ": cannot create the job's folder: " + ec.message();
        return JobEnd::Failed;
    }
    json result;
    result["format"] = "atelier-batch-job";
    result["version"] = 1;
    result["name"] = job.name;
    result["project"] = job.project.string();
    result["body"] = job.bodyLabel;
    result["fabric"] = job.fabric;
    const auto writeResult = [&](const std::string& status, const std::string& error) {
        result["status"] = status;
        result["error"] = error.empty() ? json(nullptr) : json(error);
        auto written = io::writeFileAtomically(dir / JOB_RESULT_FILE, result.dump(2) + "\n");
        if (!written.ok() && message.empty()) {
            message = written.error().toString();
        }
    };

    auto project = jobProjectText(job);
    if (!project.ok()) {
        message = project.error().toString();
        writeResult("failed", message);
        return JobEnd::Failed;
    }
    std::string spec = project.value() + "\nviews";
    for (const std::string& v : job.views) {
        spec += " " + v;
    }
    spec += "\nsize " + sizeText(job) + "\nthreads " + std::to_string(job.threads) + "\nexports";
    for (const std::string& e : job.exports) {
        spec += " " + e;
    }
    char print[20];
    std::snprintf(print, sizeof print, "%016llx",
                  static_cast<unsigned long long>(io::fingerprint(spec)));
    if (jobComplete(dir, job, print)) {
        return JobEnd::Skipped;
    }
    fs::remove(dir / JOB_RESULT_FILE, ec); // an old result no longer says anything
    result["fingerprint"] = print;

    const auto start = std::chrono::steady_clock::now();
    const fs::path projectFile = dir / (job.name + ".atelier");
    const fs::path log = dir / (job.name + ".log");
    fs::remove(log, ec);
    if (auto written = io::writeFileAtomically(projectFile, project.value()); !written.ok()) {
        message = written.error().toString();
        writeResult("failed", message);
        return JobEnd::Failed;
    }
    const std::string exe = selfExecutable().string();
    const fs::path mesh = dir / (job.name + ".obj");
    std::vector<std::vector<std::string>> steps;
    steps.push_back({exe, "drape", projectFile.string(), "--out", mesh.string(), "--report",
                     (dir / (job.name + ".report.json")).string(), "--threads",
                     std::to_string(job.threads)});
    for (const std::string& format : job.exports) {
        if (format != "obj") {
            steps.front().push_back("--also-out");
            steps.front().push_back((dir / (job.name + "." + format)).string());
        }
    }
    for (const std::string& view : job.views) {
        steps.push_back({exe, "render", mesh.string(), "--out",
                         (dir / (job.name + "-" + view + ".png")).string(), "--view", view,
                         "--size", sizeText(job)});
    }
    std::string error;
    for (const auto& step : steps) {
        const ChildResult child = runChild(step, log, options.jobTimeout);
        if (child.interrupted) {
            return JobEnd::Interrupted;
        }
        if (!child.succeeded()) {
            const std::string detail = logError(log);
            error = step[1] + " " + child.describe(options.jobTimeout) +
                    (detail.empty() ? "" : ": " + detail) + " (log: " + log.string() + ")";
            break;
        }
    }
    result["wall_time_s"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    copyFigures(dir / (job.name + ".report.json"), result);
    result["outputs"] = jobOutputs(job);
    message = error;
    writeResult(error.empty() ? "done" : "failed", error);
    return error.empty() ? JobEnd::Done : JobEnd::Failed;
}

/// "[###.......] 3/24 (2 done, 1 failed, 0 skipped) tshirt-M-cotton" redrawn in place.
void progressBar(std::size_t finished, std::size_t total, const Tally& t, const std::string& now) {
    constexpr int WIDTH = 24;
    const int filled = total == 0 ? WIDTH : static_cast<int>(WIDTH * finished / total);
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(WIDTH, '.');
    std::fprintf(stderr, "\r\033[K[%s] %zu/%zu (%d done, %d failed, %d skipped) %s", bar.c_str(),
                 finished, total, t.done, t.failed, t.skipped, now.c_str());
    std::fflush(stderr);
}

bool parseShard(const std::string& text, int& index, int& count) {
    char rest = 0;
    return std::sscanf(text.c_str(), "%d/%d%c", &index, &count, &rest) == 2 && count >= 1 &&
           index >= 0 && index < count;
}

int runBatch(const BatchOptions& options) {
    int index = 0;
    int count = 1;
    if (!parseShard(options.shard, index, count)) {
        std::cerr << "error: --shard: '" << options.shard
                  << "' is not I/N with 0 <= I < N (worker I of N, counted from 0)\n";
        return EXIT_BAD_INPUT;
    }
    auto manifest = io::loadBatchManifest(options.manifest);
    if (!manifest.ok()) {
        std::cerr << "error: " << manifest.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }
    const std::vector<io::BatchJob>& jobs = manifest.value().jobs;
    for (const io::BatchJob& job : jobs) {
        for (std::size_t v = 0; v < job.views.size(); ++v) {
            if (!render::viewFromName(job.views[v])) {
                std::cerr << "error: " << options.manifest << ": " << job.pointer << ": view '"
                          << job.views[v]
                          << "' is not one of front, back, left, right, three-quarter, top\n";
                return EXIT_BAD_INPUT;
            }
        }
    }
    const std::vector<std::size_t> mine = io::shardJobs(jobs.size(), index, count);
    if (options.dryRun) {
        for (const std::size_t k : mine) {
            std::printf("%s\t%s\n", jobs[k].name.c_str(), jobs[k].project.string().c_str());
        }
        return EXIT_OK;
    }
    std::error_code ec;
    fs::create_directories(options.out, ec);
    if (ec) {
        std::cerr << "error: " << options.out << ": cannot create the folder: " << ec.message()
                  << "\n";
        return EXIT_BAD_INPUT;
    }

    InterruptGuard interrupts;
    const bool tty = isatty(STDERR_FILENO) != 0;
    Tally tally;
    std::fprintf(stderr, "batch: shard %d/%d: %zu of %zu jobs\n", index, count, mine.size(),
                 jobs.size());
    std::vector<std::string> failures;
    for (std::size_t n = 0; n < mine.size(); ++n) {
        const io::BatchJob& job = jobs[mine[n]];
        if (tty) {
            progressBar(n, mine.size(), tally, job.name);
        }
        const auto start = std::chrono::steady_clock::now();
        std::string message;
        const JobEnd end = runJob(job, fs::path(options.out) / job.name, options, message);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (end == JobEnd::Interrupted || InterruptGuard::interrupted()) {
            std::fprintf(stderr, "%sbatch: interrupted (%s) during %s; re-run to go on\n",
                         tty ? "\n" : "", InterruptGuard::signalName(), job.name.c_str());
            return EXIT_CANCELLED;
        }
        const char* word = end == JobEnd::Done      ? "done"
                           : end == JobEnd::Skipped ? "skipped"
                                                    : "failed";
        (end == JobEnd::Done      ? tally.done
         : end == JobEnd::Skipped ? tally.skipped
                                  : tally.failed)++;
        if (end == JobEnd::Failed) {
            failures.push_back(job.name + ": " + message);
        }
        if (!tty) {
            std::fprintf(stderr, "batch: [%zu/%zu] %s %s in %.1f s%s%s\n", n + 1, mine.size(),
                         job.name.c_str(), word, seconds, message.empty() ? "" : ": ",
                         message.c_str());
        }
    }
    if (tty) {
        progressBar(mine.size(), mine.size(), tally, "");
        std::fputc('\n', stderr);
    }
    for (const std::string& f : failures) {
        std::cerr << "batch: failed: " << f << "\n";
    }
    std::fprintf(stderr, "batch: %d done, %d failed, %d skipped (already complete)\n", tally.done,
                 tally.failed, tally.skipped);
    return tally.failed > 0 ? EXIT_RUN_FAILED : EXIT_OK;
}

} // namespace

void addBatchCommand(CLI::App& app) {
    auto options = std::make_shared<BatchOptions>();
    CLI::App* cmd = app.add_subcommand(
        "batch", "Drape, export and draw every job of a batch manifest, each in DIR/JOB/");
    cmd->add_option("manifest", options->manifest, "Batch manifest (JSON, docs/batch.md)")
        ->required();
    cmd->add_option("--out,-o", options->out, "Output folder (one folder per job)")->required();
    cmd->add_option("--shard", options->shard,
                    "I/N: this worker takes every N-th job starting at I (0 <= I < N)")
        ->capture_default_str();
    cmd->add_option("--job-timeout", options->jobTimeout,
                    "Wall-clock limit of each step of a job [s] (default: none)")
        ->check(CLI::PositiveNumber);
    cmd->add_flag("--dry-run", options->dryRun, "List this shard's jobs and do nothing");
    cmd->callback([options] {
        const int code = runBatch(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
