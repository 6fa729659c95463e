/// Google Benchmarks of one step per integrator on a hanging fem sheet (bending on, gravity,
/// two pins, default material) at ≈1k, 10k and 100k triangles, single-threaded. Explicit methods
/// step at a fixed 5e-6 s (below their stability limit at 1 cm cells, which the strain-rate
/// damping sets near 2e-5 s; rk45 with its error control disabled, so one advance is one
/// Cash–Karp step); implicit Euler at 1e-3 s, its typical step.
/// Counters: `ns_per_triangle` per step, `rejected` steps (should be 0), `force_evals` and
/// `cg_iterations` per accepted step.

#include "sim/core/parallel.h"
#include "sim/simulation.h"

#include "bench_scenes.h"

#include <benchmark/benchmark.h>

namespace atelier::bench {

namespace {

template <sim::IntegratorKind K> void integratorStep(benchmark::State& state) {
    const int cells = static_cast<int>(state.range(0));
    const int threads = static_cast<int>(state.range(1));
    const double dt = K == sim::IntegratorKind::ImplicitEuler ? 1e-3 : 5e-6;
    sim::setThreadCount(threads);
    sim::Simulation simulation(makeBenchScene(cells, K, dt));
    if (!simulation.error().empty()) {
        state.SkipWithError(simulation.error().c_str());
        return;
    }
    const auto start = Clock::now();
    for (auto _ : state) {
        if (simulation.advance(dt) != sim::RunStatus::Finished) {
            state.SkipWithError("the step failed");
            break;
        }
        benchmark::DoNotOptimize(simulation.positions().data());
    }
    const auto elapsed = Clock::now() - start;
    sim::setThreadCount(0);
    const sim::RunStats& stats = simulation.stats();
    const double triangles = simulation.scene().cloths.front().mesh.triangleCount();
    state.counters["triangles"] = triangles;
    state.counters["rejected"] = static_cast<double>(stats.rejectedSteps);
    state.counters["force_evals"] = stats.steps > 0 ? static_cast<double>(stats.forceEvaluations) /
                                                          static_cast<double>(stats.steps)
                                                    : 0.0;
    state.counters["cg_iterations"] =
        stats.steps > 0 ? static_cast<double>(stats.cgIterations) / static_cast<double>(stats.steps)
                        : 0.0;
    state.counters["ns_per_triangle"] = nsPerItem(elapsed, state.iterations(), triangles);
}

void integratorSizes(benchmark::internal::Benchmark* b) {
    b->ArgNames({"cells", "threads"});
    for (int cells : BENCH_CELLS) {
        for (int threads : {1, 2}) {
            b->Args({cells, threads});
        }
    }
    b->UseRealTime()->Unit(benchmark::kMillisecond);
}

} // namespace

BENCHMARK(integratorStep<sim::IntegratorKind::Euler>)->Name("step/euler")->Apply(integratorSizes);
BENCHMARK(integratorStep<sim::IntegratorKind::Midpoint>)
    ->Name("step/midpoint")
    ->Apply(integratorSizes);
BENCHMARK(integratorStep<sim::IntegratorKind::Rk4>)->Name("step/rk4")->Apply(integratorSizes);
BENCHMARK(integratorStep<sim::IntegratorKind::Rk45>)->Name("step/rk45")->Apply(integratorSizes);
BENCHMARK(integratorStep<sim::IntegratorKind::ImplicitEuler>)
    ->Name("step/implicit-euler")
    ->Apply(integratorSizes);

} // namespace atelier::bench
