#include "patterns/settle.h"

namespace atelier::patterns {

Stillness noVertexMovedMoreThan(double motion) {
    return [motion](const sim::MatX3& now, const sim::MatX3& before) {
        return (now - before).rowwise().norm().maxCoeff() < motion;
    };
}

SettleResult settle(sim::Simulation& simulation, const SettleOptions& o, const Stillness& still) {
    SettleResult r;
    sim::MatX3 last = simulation.positions();
    const double start = simulation.time();
    for (int k = 1; start + k * o.interval <= o.maxTime + 1e-9; ++k) {
        const double t = start + k * o.interval;
        const sim::RunStatus status = simulation.run(t, {}, o.cancel);
        if (status == sim::RunStatus::Cancelled) {
            r.error = "cancelled";
            return r;
        }
        if (status != sim::RunStatus::Finished) {
            r.error = "simulation: " + simulation.error();
            return r;
        }
        const sim::MatX3& x = simulation.positions();
        r.time = t;
        if (t >= o.minTime - 1e-9 && still(x, last)) {
            r.atRest = true;
            break;
        }
        last = x;
    }
    return r;
}

} // namespace atelier::patterns
