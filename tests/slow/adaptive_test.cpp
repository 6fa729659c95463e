// Adaptive stepping pays: on stiff-sheet.json rk45 finishes stable with fewer force
// evaluations than fixed-step rk4 at the largest step at which rk4 is stable.

#include "io/scene_file.h"

#include "sim/simulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace atelier {
namespace {

struct Outcome {
    bool stable = false;
    long forceEvaluations = 0;
};

Outcome runWith(sim::SceneSpec scene) {
    sim::Simulation simulation(std::move(scene));
    const bool fixedStep = simulation.scene().integrator.kind != sim::IntegratorKind::Rk45;
    sim::RunStatus status = sim::RunStatus::Finished;
    // Frame by frame, so a fixed-step run stops at its first rejected (diverging) step.
    const double frame = 1.0 / simulation.scene().frameRate;
    while (simulation.time() < simulation.scene().duration - 1e-9 &&
           status == sim::RunStatus::Finished &&
           !(fixedStep && simulation.stats().rejectedSteps > 0)) {
        status =
            simulation.advance(std::min(frame, simulation.scene().duration - simulation.time()));
    }
    const auto& st = simulation.stats();
    Outcome o;
    // Stable: finished, finite, no step had to be rejected (for a fixed-step method a
    // rejection means the engine caught a diverging step), energy bounded, sane shape.
    o.stable = status == sim::RunStatus::Finished && st.finite &&
               (simulation.scene().integrator.kind == sim::IntegratorKind::Rk45 ||
                st.rejectedSteps == 0) &&
               simulation.kineticEnergy() <= st.energyInput && simulation.maxEdgeStrain() < 0.5;
    o.forceEvaluations = st.forceEvaluations;
    return o;
}

TEST(AdaptiveStepping, Rk45BeatsFixedRk4AtItsLargestStableStep) {
    const auto path = std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/scenes/stiff-sheet.json";
    auto loaded = io::loadScene(path.string());
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    sim::SceneSpec scene = loaded.value();
    scene.duration = std::min(scene.duration, 1.0);
    ASSERT_EQ(scene.integrator.kind, sim::IntegratorKind::Rk45);

    const Outcome adaptive = runWith(scene);
    ASSERT_TRUE(adaptive.stable);

    // Largest stable fixed rk4 step on a ladder of steps 2^(-k/4) apart, from 1/60 s down.
    Outcome fixedBest;
    double stableStep = 0;
    for (int k = 0; k < 60 && stableStep == 0; ++k) {
        sim::SceneSpec fixed = scene;
        fixed.integrator.kind = sim::IntegratorKind::Rk4;
        fixed.integrator.dt = (1.0 / 60) * std::pow(2.0, -k / 4.0);
        fixed.integrator.maxDt = fixed.integrator.dt;
        const Outcome o = runWith(fixed);
        if (o.stable) {
            fixedBest = o;
            stableStep = fixed.integrator.dt;
        }
    }
    ASSERT_GT(stableStep, 0.0) << "rk4 found no stable step";
    RecordProperty("rk45_force_evaluations", std::to_string(adaptive.forceEvaluations));
    RecordProperty("rk4_force_evaluations", std::to_string(fixedBest.forceEvaluations));
    RecordProperty("rk4_largest_stable_step_s", std::to_string(stableStep));
    std::printf("rk45: %ld force evaluations; rk4 at its largest stable step %.3g s: %ld\n",
                adaptive.forceEvaluations, stableStep, fixedBest.forceEvaluations);
    EXPECT_LT(adaptive.forceEvaluations, fixedBest.forceEvaluations);
}

} // namespace
} // namespace atelier
