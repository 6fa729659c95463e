#pragma once
/// `atelier-cli bench work-precision`: speed against accuracy of every integrator on a scene.
/// Plain C++ (no CLI11): the parsing is in bench_command.cpp.

#include "sim/scene.h"

#include <string>
#include <vector>

namespace atelier::app {

/// Options of the work-precision sweep.
struct WorkPrecisionOptions {
    std::string scene;   ///< scene file (JSON)
    std::string out;     ///< CSV output path (required)
    std::string plot;    ///< SVG output path; empty = none
    double duration = 0; ///< simulated time [s]; <= 0 = the scene's duration
    /// Integrators to sweep (names as in scene files); empty = all five.
    std::vector<std::string> integrators;
    /// Fixed steps: 1/30 s halved down to this [s] (the default reaches 1/30·2⁻¹³ ≈ 4.1e-6 s:
    /// the explicit methods' stability limit on the shipped 5 cm cotton scenes is ≈ 1.5e-5 s,
    /// set by the strain-rate damping).
    double minDt = 4e-6;
    /// rk45 tolerances: 1e-2 divided by 10 down to this [m].
    double minTolerance = 1e-7;
    /// Reference: rk45 with this tolerance [m] ...
    double referenceTolerance = 1e-9;
    /// ... and this largest step [s].
    double referenceMaxDt = 1e-3;
    /// A fixed-step setting that needs more steps than this is skipped (not run).
    long maxSteps = 2'000'000;
    /// A run still going after this wall time [s] is stopped and reported unstable with NaN
    /// errors (and named in a CSV comment as not measured).
    double maxRunSeconds = 120;
    int threads = 0;                 ///< engine threads; 0 = the engine's default
    std::vector<std::string> limits; ///< --limit NAME=VALUE
};

/// One run of the sweep: a CSV row.
struct WorkPrecisionRow {
    std::string integrator;
    double setting = 0;     ///< fixed step [s] or rk45 tolerance [m]
    double wallSeconds = 0; ///< wall time of the steps [s]
    long forceEvaluations = 0;
    double rmsError = 0; ///< RMS over vertices of |x − x_ref| at the end [m]
    double maxError = 0; ///< max over vertices of |x − x_ref| at the end [m]
    bool stable = false; ///< finished, finite and (fixed step) no rejected step
};

/// The settings swept for one integrator: fixed steps 1/30·2^-k down to `minDt` (those that
/// need more than `maxSteps` steps over `duration` left out), or rk45 tolerances.
std::vector<double> sweepSettings(sim::IntegratorKind kind, const WorkPrecisionOptions& options,
                                  double duration);

/// The SVG plot (log–log, rms error against wall time, one polyline per integrator; unstable
/// runs as crosses, not joined).
std::string workPrecisionSvg(const std::vector<WorkPrecisionRow>& rows, const std::string& title);

/// Runs the whole sweep and writes the CSV (and SVG) atomically. Returns an exit code
/// (app/cli/commands.h).
int runWorkPrecision(const WorkPrecisionOptions& options);

} // namespace atelier::app
