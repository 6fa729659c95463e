#include "app/cli/bench_drape.h"

#include "app/cli/commands.h"
#include "app/cli/interrupt.h"
#include "app/cli/limits_option.h"
#include "app/cli/preflight.h"

#include "io/atomic_file.h"
#include "io/body_file.h"
#include "io/json_text.h"
#include "io/project_file.h"

#include "patterns/assemble.h"
#include "patterns/drape_session.h"
#include "patterns/fit.h"

#include "sim/core/parallel.h"

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <numbers>
#include <thread>
#include <vector>

namespace atelier::app {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

/// Processes that each keep a core busy until destroyed (forked before any thread starts).
class BusyProcesses {
  public:
    explicit BusyProcesses(int count) {
        for (int k = 0; k < count; ++k) {
            const pid_t pid = ::fork();
            if (pid == 0) {
                volatile unsigned long spin = 0;
                for (;;) {
                    spin = spin + 1;
                }
            }
            if (pid > 0) {
                m_pids.push_back(pid);
            }
        }
    }
    ~BusyProcesses() {
        for (pid_t pid : m_pids) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, nullptr, 0);
        }
    }
    BusyProcesses(const BusyProcesses&) = delete;
    BusyProcesses& operator=(const BusyProcesses&) = delete;
    int count() const { return static_cast<int>(m_pids.size()); }

  private:
    std::vector<pid_t> m_pids;
};

} // namespace

int runDrapeBench(const DrapeBenchOptions& o) {
    const BusyProcesses busy(o.busy); // first: fork before the pool's threads exist
    if (busy.count() != o.busy) {
        std::cerr << "error: could not start " << o.busy << " busy processes\n";
        return EXIT_RUN_FAILED;
    }
    const InterruptGuard interrupts; // a signal stops the drape; its figures so far are written
    if (auto problem = checkOutputs({{"project", o.project}}, {{"--out", o.out}})) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    const std::optional<io::Limits> limits = limitsOrReport(o.limits);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    auto loaded = io::loadProject(o.project, *limits);
    if (!loaded.ok()) {
        std::cerr << inputErrorText(loaded.error());
        return EXIT_BAD_INPUT;
    }
    patterns::Project project = std::move(loaded).value();
    if (o.particleDistanceMm > 0) {
        project.drape.particleDistance = o.particleDistanceMm / 1000.0;
    }
    if (o.timeLimit > 0) {
        project.drape.timeLimit = o.timeLimit;
    }
    if (o.dt > 0) {
        project.drape.dt = o.dt;
    }
    if (const auto solver = sim::linearSolverFromName(o.linearSolver)) {
        project.drape.linearSolver = *solver;
    }
    const double h = project.drape.particleDistance;
    if (auto problem = checkVertexLimit(
            "the garment meshed at a particle distance of " + std::to_string(1000 * h) + " mm",
            patterns::estimateGarmentMesh(project.garment, h).vertices, o.maxVertices)) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    if (o.threads > 0) {
        sim::setThreadCount(o.threads);
    }
    sim::setSpinMicroseconds(o.spinUs);
    const std::filesystem::path dir = std::filesystem::absolute(o.project).parent_path();
    patterns::DrapeSession session([&](const patterns::BodySource& source) {
        return io::loadBody(source, dir, o.project, *limits);
    });
    session.setInteractive(!(o.dt > 0)); // the window's step, unless --dt sets one
    session.setSettlingStep(o.settlingStep);
    if (!o.linearSolver.empty()) {
        session.setSettlingSolver(std::nullopt); // the one given, throughout
    }
    session.setProject(std::move(project));
    if (auto prepared = session.prepare(); !prepared.ok()) {
        std::cerr << "error: " << o.project << ": " << prepared.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }

    std::atomic<bool> done{false};
    long reads = 0;
    double longestRead = 0;
    std::thread reader;
    if (o.readerHz > 0) {
        session.setPublishing(true);
        reader = std::thread([&] {
            sim::Snapshot snap;
            const auto period = std::chrono::duration<double>(1.0 / o.readerHz);
            auto next = Clock::now();
            while (!done.load()) {
                const auto start = Clock::now();
                if (session.snapshots().read(snap)) {
                    ++reads;
                }
                longestRead = std::max(longestRead, since(start));
                next += std::chrono::duration_cast<Clock::duration>(period);
                std::this_thread::sleep_until(next);
            }
        });
    }
    std::vector<double> stepSeconds;
    // CG iterations a step: the most, and those of the longest step (counts repeat exactly,
    // so they say on a loaded machine what the longest step will cost on an idle one).
    long mostIterations = 0;
    long longestStepIterations = 0;
    double longestStep = -1;
    const auto iterations = [&] {
        return session.simulation() != nullptr ? session.simulation()->stats().cgIterations : 0L;
    };
    const auto start = Clock::now();
    patterns::DrapeStatus status = patterns::DrapeStatus::Running;
    while (!InterruptGuard::interrupted()) {
        const long before = iterations();
        const auto stepStart = Clock::now();
        status = session.step();
        const double seconds = since(stepStart);
        const long stepIterations = iterations() - before;
        mostIterations = std::max(mostIterations, stepIterations);
        if (seconds > longestStep) {
            longestStep = seconds;
            longestStepIterations = stepIterations;
        }
        stepSeconds.push_back(seconds);
        if (status != patterns::DrapeStatus::Running) {
            break;
        }
    }
    const double wall = since(start);
    done = true;
    if (reader.joinable()) {
        reader.join();
    }
    std::sort(stepSeconds.begin(), stepSeconds.end());
    const auto quantile = [&](double q) {
        return stepSeconds.empty() ? 0.0
                                   : stepSeconds[static_cast<std::size_t>(
                                         q * static_cast<double>(stepSeconds.size() - 1))];
    };
    const patterns::DrapeFigures f = session.figures();
    nlohmann::ordered_json j;
    j["project"] = o.project;
    j["particle_distance_mm"] = 1000 * session.project().drape.particleDistance;
    j["triangles"] = f.triangles;
    j["threads"] = sim::threadCount();
    j["spin_us"] = sim::spinMicroseconds();
    j["busy_processes"] = o.busy;
    j["reader_hz"] = o.readerHz;
    j["snapshots_read"] = reads;
    j["longest_read_s"] = longestRead;
    j["status"] =
        std::string(patterns::phaseName(f.phase)) + (f.timeLimitReached ? " (time limit)" : "");
    j["interrupted"] = InterruptGuard::interrupted();
    j["sim_time_s"] = f.time;
    j["wall_time_s"] = wall;
    j["sim_seconds_per_wall_second"] = wall > 0 ? f.time / wall : 0.0;
    j["steps"] = stepSeconds.size();
    j["step_median_s"] = quantile(0.5);
    j["step_p99_s"] = quantile(0.99);
    j["step_longest_s"] = stepSeconds.empty() ? 0.0 : stepSeconds.back();
    j["dt_s"] = session.simulation()->scene().integrator.dt;
    j["interactive_step"] = session.interactive();
    j["settling_step"] = session.interactive() && session.settlingStep();
    j["frame_steps"] = session.frameSteps();
    const sim::RunStats& stats = session.simulation()->stats();
    j["linear_solver"] = std::string(sim::linearSolverName(session.project().drape.linearSolver));
    j["settling_linear_solver"] =
        std::string(sim::linearSolverName(session.simulation()->linearSolver()));
    j["cg_iterations"] = stats.cgIterations;
    j["cg_iterations_step_max"] = mostIterations;
    j["cg_iterations_longest_step"] = longestStepIterations;
    j["linear_solves_capped"] = stats.cappedSolves;
    j["linear_solves_unconverged"] = stats.unconvergedSolves;
    j["linear_solve_worst_residual"] = stats.worstRelativeResidual;
    j["seam_gap_max_m"] = f.seamGapMax;
    const patterns::FoldFigures folds =
        patterns::foldFigures(session.assembled(), session.simulation()->positions());
    j["seam_fold_median_deg"] = folds.seamMedian * 180.0 / std::numbers::pi;
    j["seam_fold_max_deg"] = folds.seamMax * 180.0 / std::numbers::pi;
    j["cloth_fold_median_deg"] = folds.clothMedian * 180.0 / std::numbers::pi;
    // Whether the garment fits, as the drape report has it (patterns/fit.h).
    const patterns::GarmentFit fit = session.fit();
    j["fit"] = std::string(patterns::fitName(fit.verdict.fit));
    j["fit_message"] = fit.verdict.message;
    j["strain_max"] = fit.largestStrain();
    j["strain_beyond_10pct_share_max"] = fit.largestShareBeyond10();
    j["intersecting_triangle_pairs"] = session.simulation()->intersectingTrianglePairs();
    j["max_penetration_m"] = stats.maxPenetration;
    j["largest_forced_weld_m"] = session.simulation()->stats().largestForcedWeld;
    const std::string text = io::jsonText(j);
    if (o.out.empty()) {
        std::cout << text;
    } else if (auto written = io::writeFileAtomically(o.out, text); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    if (InterruptGuard::interrupted()) {
        std::cerr << "bench drape: interrupted (" << InterruptGuard::signalName()
                  << ") at t = " << f.time << " s; the figures so far are written\n";
        return EXIT_CANCELLED;
    }
    return status == patterns::DrapeStatus::Failed ? EXIT_RUN_FAILED : EXIT_OK;
}

} // namespace atelier::app
