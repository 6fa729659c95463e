/// Google Benchmarks of one force evaluation per model (stretch: springs, volino, fem; bending)
/// over mesh size and thread count. Args: (cells per side, threads); a square of n×n cells has
/// 2n² triangles: 22 → 968, 71 → 10 082, 224 → 100 352.
/// Counter `ns_per_triangle`: wall time of one evaluation per triangle [ns].

#include "sim/core/parallel.h"
#include "sim/forces/bending.h"
#include "sim/forces/fem.h"
#include "sim/forces/springs.h"
#include "sim/forces/volino.h"

#include "bench_scenes.h"

#include <benchmark/benchmark.h>

#include <memory>

namespace atelier::bench {

namespace {

enum class Model { Springs, Volino, Fem, Bending };

std::unique_ptr<sim::ForceModel> makeModel(Model model, const sim::ClothMesh& mesh,
                                           const sim::Material& material) {
    switch (model) {
    case Model::Springs:
        return std::make_unique<sim::SpringStretch>(mesh, 0, material, false);
    case Model::Volino:
        return std::make_unique<sim::VolinoStretch>(mesh, 0, material,
                                                    sim::lumpedMasses(mesh, material.density));
    case Model::Fem:
        return std::make_unique<sim::FemStretch>(mesh, 0, material);
    case Model::Bending:
        return std::make_unique<sim::DihedralBending>(mesh, 0, material, sim::VecX(), false);
    }
    return nullptr;
}

template <Model M> void forceEvaluation(benchmark::State& state) {
    const int cells = static_cast<int>(state.range(0));
    const int threads = static_cast<int>(state.range(1));
    const BenchCloth cloth = makeBenchCloth(cells);
    const sim::Material material;
    const auto model = makeModel(M, cloth.mesh, material);
    sim::MatX3 f = sim::MatX3::Zero(cloth.x.rows(), 3);
    sim::setThreadCount(threads);
    const auto start = Clock::now();
    for (auto _ : state) {
        f.setZero();
        model->addForces(cloth.x, cloth.v, f);
        benchmark::DoNotOptimize(f.data());
        benchmark::ClobberMemory();
    }
    const auto elapsed = Clock::now() - start;
    sim::setThreadCount(0);
    const double triangles = cloth.mesh.triangleCount();
    state.counters["triangles"] = triangles;
    state.counters["ns_per_triangle"] = nsPerItem(elapsed, state.iterations(), triangles);
}

void sizesAndThreads(benchmark::internal::Benchmark* b) {
    b->ArgNames({"cells", "threads"});
    for (int cells : BENCH_CELLS) {
        for (int threads : {1, 2}) {
            b->Args({cells, threads});
        }
    }
    b->UseRealTime()->Unit(benchmark::kMicrosecond);
}

} // namespace

BENCHMARK(forceEvaluation<Model::Springs>)->Name("force/springs")->Apply(sizesAndThreads);
BENCHMARK(forceEvaluation<Model::Volino>)->Name("force/volino")->Apply(sizesAndThreads);
BENCHMARK(forceEvaluation<Model::Fem>)->Name("force/fem")->Apply(sizesAndThreads);
BENCHMARK(forceEvaluation<Model::Bending>)->Name("force/bending")->Apply(sizesAndThreads);

} // namespace atelier::bench

BENCHMARK_MAIN();
