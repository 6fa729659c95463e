#pragma once
/// Draping until rest: the simulation runs frame by frame until the garment has settled.

#include "patterns/project.h"

#include "sim/simulation.h"

#include <functional>

namespace atelier::patterns {

struct DrapeOutcome {
    sim::RunStatus status = sim::RunStatus::Finished;
    bool rested = false;          ///< reached rest before the time limit
    double simulatedTime = 0;     ///< [s]
    double wallSeconds = 0;       ///< wall time of the run [s]
    double kineticEnergyPerVertex = 0; ///< mean, at the end [J]
};

/// Runs until the mean kinetic energy per vertex has stayed below settings.restKineticEnergy
/// for settings.restDuration of simulated time after the sewing phase (checked at every output
/// frame), or until settings.timeLimit. `onFrame(frame, time, kineticEnergyPerVertex)` is called per frame.
DrapeOutcome drapeUntilRest(sim::Simulation& simulation, const DrapeSettings& settings,
                            const std::function<void(int, double, double)>& onFrame = {});

} // namespace atelier::patterns
