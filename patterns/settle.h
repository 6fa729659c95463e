#pragma once
/// Running a simulation until its cloth comes to rest: the loop the lab tests share (the Cusick
/// drape test, the heavy cantilever of `atelier-cli bench cantilever`).

#include "sim/simulation.h"

#include <atomic>
#include <functional>
#include <string>

namespace atelier::patterns {

struct SettleOptions {
    double interval = 0.25; ///< stillness is judged over windows of this simulated time [s]
    double minTime = 1.0;   ///< never at rest before this simulated time [s]
    double maxTime = 8;     ///< gives up at this simulated time [s]
    /// Set from another thread, stops between steps (the result's error says so).
    const std::atomic<bool>* cancel = nullptr;
};

struct SettleResult {
    double time = 0; ///< simulated time when at rest, or when given up [s]
    bool atRest = false;
    std::string error; ///< "cancelled", or the simulation's failure; empty otherwise
};

/// Whether the cloth is still: its positions now and one interval before [m].
using Stillness = std::function<bool(const sim::MatX3& now, const sim::MatX3& before)>;

/// Still when no vertex moved more than `motion` [m] over the interval.
Stillness noVertexMovedMoreThan(double motion);

/// Runs `simulation` interval by interval from its current time until `still` holds (once past
/// minTime) or maxTime is reached.
SettleResult settle(sim::Simulation& simulation, const SettleOptions& options,
                    const Stillness& still);

} // namespace atelier::patterns
