#include "patterns/drape.h"

#include <atomic>
#include <chrono>

namespace atelier::patterns {

DrapeOutcome drapeUntilRest(sim::Simulation& simulation, const DrapeSettings& settings,
                            const std::function<void(int, double, double)>& onFrame) {
    DrapeOutcome out;
    const auto start = std::chrono::steady_clock::now();
    const double vertices = std::max(1.0, static_cast<double>(simulation.positions().rows()));
    std::atomic<bool> stop{false};
    double restSince = -1;
    out.status = simulation.run(
        settings.timeLimit,
        [&](int frame, double t) {
            const double ke = simulation.kineticEnergy() / vertices;
            out.kineticEnergyPerVertex = ke;
            // Rest counts after sewing: at its set end, or earlier once every seam is sewn.
            const double sewn = simulation.stats().sewingEndTime;
            const double sewingEnd = sewn >= 0 ? sewn : settings.sewingTime;
            if (t >= sewingEnd - 1e-12 && ke < settings.restKineticEnergy) {
                if (restSince < 0) {
                    restSince = t;
                }
                if (t - restSince >= settings.restDuration - 1e-12) {
                    out.rested = true;
                    stop = true;
                }
            } else {
                restSince = -1;
            }
            if (onFrame) {
                onFrame(frame, t, ke);
            }
        },
        &stop);
    if (out.status == sim::RunStatus::Cancelled && out.rested) {
        out.status = sim::RunStatus::Finished;
    }
    out.simulatedTime = simulation.time();
    out.kineticEnergyPerVertex = simulation.kineticEnergy() / vertices;
    out.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

} // namespace atelier::patterns
