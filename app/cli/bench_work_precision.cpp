#include "app/cli/bench_work_precision.h"

#include "app/cli/commands.h"
#include "app/cli/interrupt.h"
#include "app/cli/limits_option.h"
#include "app/cli/preflight.h"

#include "io/atomic_file.h"
#include "io/scene_file.h"
#include "io/xml_text.h"

#include "sim/core/parallel.h"
#include "sim/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>

namespace atelier::app {

namespace {

/// A figure a run could not measure.
constexpr double NOT_MEASURED = std::numeric_limits<double>::quiet_NaN();
constexpr double FIRST_DT = 1.0 / 30;    ///< largest fixed step of the sweep [s]
constexpr double FIRST_TOLERANCE = 1e-2; ///< loosest rk45 tolerance of the sweep [m]

const std::vector<sim::IntegratorKind> ALL_INTEGRATORS = {
    sim::IntegratorKind::Euler, sim::IntegratorKind::Midpoint, sim::IntegratorKind::Rk4,
    sim::IntegratorKind::Rk45, sim::IntegratorKind::ImplicitEuler};

using Clock = std::chrono::steady_clock;

/// A run of the scene to `duration`: the figures and final positions.
struct RunOutcome {
    WorkPrecisionRow row;
    sim::MatX3 positions;
    bool completed = false;   ///< reached the end time with a finite state
    bool timedOut = false;    ///< stopped at the wall-time cap
    bool interrupted = false; ///< stopped by SIGINT or SIGTERM
    std::string error;
};

RunOutcome runScene(const sim::SceneSpec& scene, double duration, double maxRunSeconds) {
    RunOutcome out;
    sim::Simulation simulation(scene);
    if (!simulation.error().empty()) {
        out.error = simulation.error();
        return out;
    }
    const bool fixedStep = scene.integrator.kind != sim::IntegratorKind::Rk45;
    // Advance in chunks of whole steps (about a frame) to check the wall-time cap between them.
    const double chunk =
        fixedStep ? scene.integrator.dt * std::max(1.0, std::round(FIRST_DT / scene.integrator.dt))
                  : FIRST_DT;
    const auto start = Clock::now();
    sim::RunStatus status = sim::RunStatus::Finished;
    bool timedOut = false;
    bool diverged = false;
    while (simulation.time() < duration - 1e-12 * std::max(1.0, duration)) {
        status = simulation.advance(std::min(chunk, duration - simulation.time()));
        if (status != sim::RunStatus::Finished) {
            break;
        }
        if (fixedStep && simulation.stats().rejectedSteps > 0) {
            // A fixed-step method that needed a rejection has diverged at this step: it is
            // unstable here, and finishing it (with the engine's rescue steps) costs much.
            diverged = true;
            break;
        }
        if (InterruptGuard::interrupted()) {
            out.interrupted = true;
            break;
        }
        if (std::chrono::duration<double>(Clock::now() - start).count() > maxRunSeconds) {
            timedOut = simulation.time() < duration - 1e-12 * std::max(1.0, duration);
            break;
        }
    }
    const sim::RunStats& stats = simulation.stats();
    out.row.integrator = std::string(sim::integratorName(scene.integrator.kind));
    out.row.setting = fixedStep ? scene.integrator.dt : scene.integrator.tolerance;
    out.row.wallSeconds = stats.wallTime;
    out.row.forceEvaluations = stats.forceEvaluations;
    out.positions = simulation.positions();
    out.completed = status == sim::RunStatus::Finished && !timedOut && !diverged && stats.finite &&
                    out.positions.allFinite();
    out.row.stable = out.completed && (!fixedStep || stats.rejectedSteps == 0);
    out.timedOut = timedOut;
    if (out.interrupted) {
        out.error = std::string("interrupted (") + InterruptGuard::signalName() + ")";
    } else if (diverged) {
        out.error =
            "diverged: a step was rejected at t = " + std::to_string(simulation.time()) + " s";
    } else if (timedOut) {
        out.error = "stopped after " + std::to_string(maxRunSeconds) + " s of wall time";
    } else if (!out.completed) {
        out.error = !stats.error.empty() ? stats.error : std::string("the state is not finite");
    } else if (out.row.stable != out.completed) {
        out.error = std::to_string(stats.rejectedSteps) + " rejected steps";
    }
    return out;
}

std::string formatNumber(double value) {
    if (!std::isfinite(value)) {
        return "nan";
    }
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.9g", value);
    return buf;
}

const char* integratorColour(const std::string& name) {
    static const std::map<std::string, const char*> colours = {
        {"euler", "#d62728"}, {"midpoint", "#ff7f0e"},       {"rk4", "#2ca02c"},
        {"rk45", "#1f77b4"},  {"implicit-euler", "#9467bd"},
    };
    const auto it = colours.find(name);
    return it != colours.end() ? it->second : "#555555";
}

/// Decade range [lo, hi] (exponents) covering the positive finite values, at least one decade.
std::pair<int, int> decades(const std::vector<double>& values) {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (double v : values) {
        if (std::isfinite(v) && v > 0) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    if (!std::isfinite(lo)) {
        return {0, 1};
    }
    int a = static_cast<int>(std::floor(std::log10(lo)));
    int b = static_cast<int>(std::ceil(std::log10(hi)));
    if (b <= a) {
        b = a + 1;
    }
    return {a, b};
}

} // namespace

std::vector<double> sweepSettings(sim::IntegratorKind kind, const WorkPrecisionOptions& o,
                                  double duration) {
    std::vector<double> settings;
    if (kind == sim::IntegratorKind::Rk45) {
        for (int k = 0; FIRST_TOLERANCE * std::pow(10.0, -k) >= o.minTolerance * (1 - 1e-9); ++k) {
            settings.push_back(FIRST_TOLERANCE * std::pow(10.0, -k));
        }
        return settings;
    }
    for (int k = 0; FIRST_DT * std::ldexp(1.0, -k) >= o.minDt * (1 - 1e-9); ++k) {
        const double dt = FIRST_DT * std::ldexp(1.0, -k);
        if (duration / dt <= static_cast<double>(o.maxSteps)) {
            settings.push_back(dt);
        }
    }
    return settings;
}

std::string workPrecisionSvg(const std::vector<WorkPrecisionRow>& rows, const std::string& title) {
    constexpr double W = 760;
    constexpr double H = 500;
    constexpr double LEFT = 90;
    constexpr double RIGHT = 190; // legend
    constexpr double TOP = 50;
    constexpr double BOTTOM = 70;
    const double plotW = W - LEFT - RIGHT;
    const double plotH = H - TOP - BOTTOM;

    std::vector<double> xs, ys;
    for (const WorkPrecisionRow& r : rows) {
        if (r.wallSeconds > 0 && r.rmsError > 0 && std::isfinite(r.rmsError)) {
            xs.push_back(r.wallSeconds);
            ys.push_back(r.rmsError);
        }
    }
    const auto [x0, x1] = decades(xs);
    const auto [y0, y1] = decades(ys);
    const auto px = [&](double v) {
        return LEFT + (std::log10(v) - x0) / static_cast<double>(x1 - x0) * plotW;
    };
    const auto py = [&](double v) {
        return TOP + plotH - (std::log10(v) - y0) / static_cast<double>(y1 - y0) * plotH;
    };

    std::ostringstream s;
    s.precision(6);
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" viewBox=\"0 0 " << W << " " << H
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    s << "<rect x=\"0\" y=\"0\" width=\"" << W << "\" height=\"" << H << "\" fill=\"white\"/>\n";
    s << "<text x=\"" << LEFT + plotW / 2 << "\" y=\"" << TOP / 2 + 5
      << "\" text-anchor=\"middle\" font-size=\"14\">" << io::xmlEscape(title) << "</text>\n";

    // Grid, decade ticks and labels.
    s << "<g stroke=\"#dddddd\" stroke-width=\"1\">\n";
    for (int e = x0; e <= x1; ++e) {
        for (int m = 1; m <= 9 && !(e == x1 && m > 1); ++m) {
            const double X = px(m * std::pow(10.0, e));
            s << "<line x1=\"" << X << "\" y1=\"" << TOP << "\" x2=\"" << X << "\" y2=\""
              << TOP + plotH << "\"" << (m == 1 ? " stroke=\"#bbbbbb\"" : "") << "/>\n";
        }
    }
    for (int e = y0; e <= y1; ++e) {
        for (int m = 1; m <= 9 && !(e == y1 && m > 1); ++m) {
            const double Y = py(m * std::pow(10.0, e));
            s << "<line x1=\"" << LEFT << "\" y1=\"" << Y << "\" x2=\"" << LEFT + plotW
              << "\" y2=\"" << Y << "\"" << (m == 1 ? " stroke=\"#bbbbbb\"" : "") << "/>\n";
        }
    }
    s << "</g>\n";
    s << "<rect x=\"" << LEFT << "\" y=\"" << TOP << "\" width=\"" << plotW << "\" height=\""
      << plotH << "\" fill=\"none\" stroke=\"black\"/>\n";
    for (int e = x0; e <= x1; ++e) {
        const double X = px(std::pow(10.0, e));
        s << "<line x1=\"" << X << "\" y1=\"" << TOP + plotH << "\" x2=\"" << X << "\" y2=\""
          << TOP + plotH + 6 << "\" stroke=\"black\"/>\n";
        s << "<text x=\"" << X << "\" y=\"" << TOP + plotH + 22
          << "\" text-anchor=\"middle\">10<tspan dy=\"-6\" font-size=\"9\">" << e
          << "</tspan></text>\n";
    }
    for (int e = y0; e <= y1; ++e) {
        const double Y = py(std::pow(10.0, e));
        s << "<line x1=\"" << LEFT - 6 << "\" y1=\"" << Y << "\" x2=\"" << LEFT << "\" y2=\"" << Y
          << "\" stroke=\"black\"/>\n";
        s << "<text x=\"" << LEFT - 10 << "\" y=\"" << Y + 4
          << "\" text-anchor=\"end\">10<tspan dy=\"-6\" font-size=\"9\">" << e
          << "</tspan></text>\n";
    }
    s << "<text x=\"" << LEFT + plotW / 2 << "\" y=\"" << H - 20
      << "\" text-anchor=\"middle\">wall time [s]</text>\n";
    s << "<text x=\"24\" y=\"" << TOP + plotH / 2
      << "\" text-anchor=\"middle\" transform=\"rotate(-90 24 " << TOP + plotH / 2
      << ")\">RMS position error at end [m]</text>\n";

    // Series in order of first appearance.
    std::vector<std::string> names;
    for (const WorkPrecisionRow& r : rows) {
        if (std::find(names.begin(), names.end(), r.integrator) == names.end()) {
            names.push_back(r.integrator);
        }
    }
    const auto plottable = [](const WorkPrecisionRow& r) {
        return r.wallSeconds > 0 && r.rmsError > 0 && std::isfinite(r.rmsError);
    };
    for (std::size_t k = 0; k < names.size(); ++k) {
        const std::string& name = names[k];
        const char* colour = integratorColour(name);
        s << "<g class=\"series\" id=\"" << io::xmlEscape(name) << "\">\n";
        std::ostringstream points;
        points.precision(6);
        int count = 0;
        for (const WorkPrecisionRow& r : rows) {
            if (r.integrator == name && r.stable && plottable(r)) {
                points << (count++ > 0 ? " " : "") << px(r.wallSeconds) << "," << py(r.rmsError);
            }
        }
        if (count > 1) {
            s << "<polyline fill=\"none\" stroke=\"" << colour
              << "\" stroke-width=\"1.5\" points=\"" << points.str() << "\"/>\n";
        }
        for (const WorkPrecisionRow& r : rows) {
            if (r.integrator != name || !plottable(r)) {
                continue;
            }
            const double X = px(r.wallSeconds);
            const double Y = py(r.rmsError);
            if (r.stable) {
                s << "<circle cx=\"" << X << "\" cy=\"" << Y << "\" r=\"3.5\" fill=\"" << colour
                  << "\"><title>" << io::xmlEscape(name) << " " << formatNumber(r.setting)
                  << "</title></circle>\n";
            } else {
                s << "<path d=\"M" << X - 4 << "," << Y - 4 << " l8,8 m0,-8 l-8,8\" stroke=\""
                  << colour << "\" stroke-width=\"1.5\"><title>" << io::xmlEscape(name) << " "
                  << formatNumber(r.setting) << " (unstable)</title></path>\n";
            }
        }
        // Legend entry.
        const double LY = TOP + 10 + 22.0 * static_cast<double>(k);
        const double LX = LEFT + plotW + 20;
        s << "<line x1=\"" << LX << "\" y1=\"" << LY << "\" x2=\"" << LX + 24 << "\" y2=\"" << LY
          << "\" stroke=\"" << colour << "\" stroke-width=\"1.5\"/>\n";
        s << "<circle cx=\"" << LX + 12 << "\" cy=\"" << LY << "\" r=\"3.5\" fill=\"" << colour
          << "\"/>\n";
        s << "<text x=\"" << LX + 32 << "\" y=\"" << LY + 4 << "\">" << io::xmlEscape(name)
          << "</text>\n";
        s << "</g>\n";
    }
    const double noteY = TOP + 10 + 22.0 * static_cast<double>(names.size()) + 10;
    s << "<text x=\"" << LEFT + plotW + 20 << "\" y=\"" << noteY
      << "\" font-size=\"10\">× = unstable run</text>\n";
    s << "</svg>\n";
    return s.str();
}

/// The sweep's CSV: header comments (scene, reference run, notes, columns), then one row per
/// run.
std::string workPrecisionCsv(const WorkPrecisionOptions& o, double duration, double referenceMaxDt,
                             const WorkPrecisionRow& reference,
                             const std::vector<std::string>& notes,
                             const std::vector<WorkPrecisionRow>& rows) {
    std::ostringstream csv;
    csv << "# atelier-cli bench work-precision " << o.scene << "\n";
    csv << "# duration_s=" << formatNumber(duration) << " threads=" << sim::threadCount() << "\n";
    csv << "# reference: rk45 (Cash-Karp) tolerance=" << formatNumber(o.referenceTolerance)
        << " m max_dt=" << formatNumber(referenceMaxDt)
        << " s; wall_s=" << formatNumber(reference.wallSeconds)
        << " force_evaluations=" << reference.forceEvaluations << "\n";
    for (const std::string& note : notes) {
        csv << "# " << note << "\n";
    }
    csv << "# setting: fixed step [s] (euler, midpoint, rk4, implicit-euler) or tolerance [m] "
           "(rk45); errors: |x - x_ref| over vertices at the end time; stable: finished, finite "
           "and (fixed step) no rejected step\n";
    csv << "integrator,setting,wall_s,force_evaluations,rms_error_m,max_error_m,stable\n";
    for (const WorkPrecisionRow& r : rows) {
        csv << r.integrator << "," << formatNumber(r.setting) << "," << formatNumber(r.wallSeconds)
            << "," << r.forceEvaluations << "," << formatNumber(r.rmsError) << ","
            << formatNumber(r.maxError) << "," << (r.stable ? "true" : "false") << "\n";
    }
    return csv.str();
}

int runWorkPrecision(const WorkPrecisionOptions& o) {
    const InterruptGuard interrupts; // a signal stops the sweep; the runs so far are written
    if (o.out.empty()) {
        std::cerr << "error: bench work-precision: --out is required\n";
        return EXIT_BAD_INPUT;
    }
    if (auto problem = checkOutputs({{"scene", o.scene}}, {{"--out", o.out}, {"--plot", o.plot}})) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    std::vector<sim::IntegratorKind> kinds;
    for (const std::string& name : o.integrators) {
        const auto kind = sim::integratorFromName(name);
        if (!kind) {
            std::cerr << "error: bench work-precision: unknown integrator \"" << name
                      << "\" (euler, midpoint, rk4, rk45, implicit-euler)\n";
            return EXIT_BAD_INPUT;
        }
        kinds.push_back(*kind);
    }
    if (kinds.empty()) {
        kinds = ALL_INTEGRATORS;
    }
    if (!(o.minDt > 0) || !(o.minTolerance > 0) || !(o.referenceTolerance > 0) ||
        !(o.referenceMaxDt > 0) || !(o.maxRunSeconds > 0) || o.maxSteps < 1) {
        std::cerr << "error: bench work-precision: step, tolerance and limits must be positive\n";
        return EXIT_BAD_INPUT;
    }
    std::optional<sim::SceneSpec> loaded = loadSceneOrReport(o.scene, o.limits);
    if (!loaded) {
        return EXIT_BAD_INPUT;
    }
    const sim::SceneSpec base = std::move(*loaded);
    const double duration = o.duration > 0 ? o.duration : base.duration;
    if (!(duration > 0)) {
        std::cerr << "error: bench work-precision: the duration must be positive\n";
        return EXIT_BAD_INPUT;
    }
    if (o.threads > 0) {
        sim::setThreadCount(o.threads);
    }

    // Reference: rk45 at a much tighter tolerance and a small largest step.
    sim::SceneSpec refScene = base;
    refScene.integrator.kind = sim::IntegratorKind::Rk45;
    refScene.integrator.tolerance = o.referenceTolerance;
    refScene.integrator.maxDt = std::min(base.integrator.maxDt, o.referenceMaxDt);
    refScene.integrator.dt = std::min(base.integrator.dt, refScene.integrator.maxDt);
    refScene.integrator.minDt = std::min(base.integrator.minDt, 1e-12);
    std::cerr << "bench work-precision: reference (rk45, tolerance " << o.referenceTolerance
              << " m, max step " << refScene.integrator.maxDt << " s) to t = " << duration
              << " s\n";
    const RunOutcome reference =
        runScene(refScene, duration, std::numeric_limits<double>::infinity());
    if (reference.interrupted) {
        std::cerr << "bench work-precision: " << reference.error
                  << " during the reference run; nothing measured, nothing written\n";
        return EXIT_CANCELLED;
    }
    if (!reference.completed) {
        std::cerr << "error: " << o.scene << ": the reference run failed: " << reference.error
                  << "\n";
        return EXIT_RUN_FAILED;
    }
    std::cerr << "bench work-precision: reference took " << reference.row.wallSeconds << " s, "
              << reference.row.forceEvaluations << " force evaluations\n";

    std::vector<WorkPrecisionRow> rows;
    std::vector<std::string> notes; // settings skipped or not measured, for the CSV header
    bool interrupted = false;
    for (sim::IntegratorKind kind : kinds) {
        if (interrupted) {
            break;
        }
        if (kind != sim::IntegratorKind::Rk45) {
            for (int k = 0; FIRST_DT * std::ldexp(1.0, -k) >= o.minDt * (1 - 1e-9); ++k) {
                const double dt = FIRST_DT * std::ldexp(1.0, -k);
                if (duration / dt > static_cast<double>(o.maxSteps)) {
                    notes.push_back(std::string(sim::integratorName(kind)) + " " +
                                    formatNumber(dt) + ": skipped (more than " +
                                    std::to_string(o.maxSteps) + " steps)");
                }
            }
        }
        for (double setting : sweepSettings(kind, o, duration)) {
            sim::SceneSpec scene = base;
            scene.integrator.kind = kind;
            if (kind == sim::IntegratorKind::Rk45) {
                scene.integrator.tolerance = setting;
            } else {
                scene.integrator.dt = setting;
                scene.integrator.maxDt = std::max(base.integrator.maxDt, setting);
            }
            RunOutcome run = runScene(scene, duration, o.maxRunSeconds);
            if (run.interrupted) {
                std::cerr << "bench work-precision: " << run.error << "; writing the "
                          << rows.size() << " runs measured\n";
                notes.push_back(run.row.integrator + " " + formatNumber(setting) + ": " +
                                run.error + "; the sweep stops here");
                interrupted = true;
                break;
            }
            if (run.completed) {
                const Eigen::VectorXd d = (run.positions - reference.positions).rowwise().norm();
                run.row.rmsError = std::sqrt(d.squaredNorm() / static_cast<double>(d.size()));
                run.row.maxError = d.maxCoeff();
            } else {
                run.row.rmsError = NOT_MEASURED;
                run.row.maxError = NOT_MEASURED;
            }
            char line[256];
            std::snprintf(
                line, sizeof line,
                "bench work-precision: %-14s %-10.4g wall %8.3f s  evals %9ld  rms %.3g m  %s",
                run.row.integrator.c_str(), setting, run.row.wallSeconds, run.row.forceEvaluations,
                run.row.rmsError, run.row.stable ? "stable" : ("unstable: " + run.error).c_str());
            std::cerr << line << "\n";
            if (run.timedOut) {
                notes.push_back(run.row.integrator + " " + formatNumber(setting) +
                                ": not measured (" + run.error + ")");
            }
            rows.push_back(run.row);
        }
    }

    const std::string csv =
        workPrecisionCsv(o, duration, refScene.integrator.maxDt, reference.row, notes, rows);
    if (auto written = io::writeFileAtomically(o.out, csv); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    if (!o.plot.empty()) {
        const std::string title =
            "Work-precision: " + o.scene + " (t = " + formatNumber(duration) + " s)";
        if (auto written = io::writeFileAtomically(o.plot, workPrecisionSvg(rows, title));
            !written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            return EXIT_RUN_FAILED;
        }
    }
    return interrupted ? EXIT_CANCELLED : EXIT_OK;
}

} // namespace atelier::app
