#pragma once
/// `atelier-cli bench drape`: a project draped as a window drapes it, measured. How fast the
/// drape goes (simulated seconds per wall second: 1.0 is real time), the longest step (what a
/// user dragging the cloth waits for), optionally with a reader thread taking snapshots as a
/// viewport does and with other processes keeping cores busy, as on a desktop.
/// Plain C++ (no CLI11): the parsing is in bench_command.cpp.

#include "app/cli/preflight.h"

#include <string>
#include <vector>

namespace atelier::app {

struct DrapeBenchOptions {
    std::string project;
    std::string out;                ///< JSON output (default: stdout)
    double particleDistanceMm = -1; ///< override of the project's [mm]
    double timeLimit = -1;          ///< override of the project's simulated time limit [s]
    double dt = -1;                 ///< step [s] (< 0: the window's, patterns::interactiveStep)
    std::string linearSolver;       ///< override of the project's linear solver; empty = keep
    bool settlingStep = true;       ///< one step a frame once sewn and slow, as the window
    int threads = 0;                ///< engine threads (0: all cores)
    double readerHz = 0;            ///< snapshots read by another thread per second (0: none)
    int busy = 0;                   ///< processes spinning on a core each during the drape
    int spinUs = -1;                ///< the pool's spin before sleeping [µs] (< 0: default)
    long maxVertices = DEFAULT_MAX_VERTICES; ///< refuse meshes estimated larger
    std::vector<std::string> limits;         ///< --limit NAME=VALUE
};

/// Runs the benchmark; returns an exit code (commands.h) and writes the JSON figures.
int runDrapeBench(const DrapeBenchOptions& options);

} // namespace atelier::app
