/// Google Benchmarks of the surface BVH (sim/collision/bvh.h): build, refit (static and swept,
/// serial and on all threads), self-overlap query on a flat and a crumpled sheet, and the
/// overlap query of a sheet against a sphere. Arg: cells per side of a square sheet of 10 mm
/// cells, 2n² triangles: 22 → 968, 71 → 10 082, 224 → 100 352, 316 → 199 712.
/// Counters: `triangles`, `ns_per_triangle` (wall time per triangle [ns]) and, for the queries,
/// `pairs` (pairs reported per query).

#include "sim/collision/bvh.h"
#include "sim/core/parallel.h"
#include "sim/mesh/cloth_mesh.h"

#include "bench_scenes.h"

#include <benchmark/benchmark.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

namespace atelier::bench {

namespace {

/// Sheet bvhSizes (cells per side): about 1k, 10k, 100k and 200k triangles.
constexpr std::array<int, 4> BVH_CELLS = {22, 71, 224, 316};
/// Collision margin of the queries [m].
constexpr double MARGIN = 0.002;

struct Sheet {
    sim::MatX3i triangles; ///< (|F|×3)
    sim::MatX3 x;          ///< (|V|×3) [m]
};

/// A square of n×n cells of BENCH_CELL_SIZE in the plane z = 0, or crumpled: along y, a
/// looped (prolate trochoid) profile of period 16 cells, so the sheet folds over itself once
/// per period (normals turning all the way round, real self-overlaps) with smooth stretches in
/// between; along x, a wave of 2 cells' amplitude; and every vertex moved by up to 10% of a
/// cell on each axis (fixed seed).
Sheet makeSheet(int cells, bool crumpled) {
    sim::RectangleOptions rect;
    rect.width = rect.height = cells * BENCH_CELL_SIZE;
    rect.cellsX = rect.cellsY = cells;
    sim::MatX2 rest;
    Sheet s;
    sim::makeRectangle(rect, rest, s.triangles);
    s.x = sim::MatX3::Zero(rest.rows(), 3);
    s.x.leftCols(2) = rest;
    if (crumpled) {
        std::mt19937 rng(7);
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        const double k = 2 * std::numbers::pi / (16 * BENCH_CELL_SIZE);
        const double loop = 1.5 / k; // > 1/k: the profile loops
        const double kx = 2 * std::numbers::pi / (24 * BENCH_CELL_SIZE);
        for (int i = 0; i < s.x.rows(); ++i) {
            const double x = rest(i, 0);
            const double y = rest(i, 1);
            s.x(i, 1) = y - loop * std::sin(k * y);
            s.x(i, 2) = -loop * std::cos(k * y) + 2 * BENCH_CELL_SIZE * std::sin(kx * x);
            for (int a = 0; a < 3; ++a) {
                s.x(i, a) += 0.1 * BENCH_CELL_SIZE * u(rng);
            }
        }
    }
    return s;
}

/// UV sphere of `rings` latitude bands and `segments` longitudes.
Sheet makeSphere(const sim::Vec3& centre, double radius, int rings, int segments) {
    Sheet m;
    const int nv = 2 + (rings - 1) * segments;
    m.x.resize(nv, 3);
    m.x.row(0) = (centre + radius * sim::Vec3::UnitZ()).transpose();
    m.x.row(nv - 1) = (centre - radius * sim::Vec3::UnitZ()).transpose();
    for (int r = 1; r < rings; ++r) {
        const double theta = std::numbers::pi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double phi = 2 * std::numbers::pi * s / segments;
            const sim::Vec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                              std::cos(theta));
            m.x.row(1 + (r - 1) * segments + s) = (centre + radius * d).transpose();
        }
    }
    const auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
    m.triangles.resize(2 * segments * (rings - 1), 3);
    int t = 0;
    for (int s = 0; s < segments; ++s) {
        m.triangles.row(t++) << 0, ring(1, s), ring(1, s + 1);
        m.triangles.row(t++) << nv - 1, ring(rings - 1, s + 1), ring(rings - 1, s);
        for (int r = 1; r + 1 < rings; ++r) {
            m.triangles.row(t++) << ring(r, s), ring(r + 1, s), ring(r + 1, s + 1);
            m.triangles.row(t++) << ring(r, s), ring(r + 1, s + 1), ring(r, s + 1);
        }
    }
    return m;
}

void finish(benchmark::State& state, Clock::time_point start, double triangles) {
    const auto elapsed = Clock::now() - start;
    state.counters["triangles"] = triangles;
    state.counters["ns_per_triangle"] = nsPerItem(elapsed, state.iterations(), triangles);
    state.SetComplexityN(static_cast<std::int64_t>(triangles));
}

void bvhBuild(benchmark::State& state) {
    const Sheet s = makeSheet(static_cast<int>(state.range(0)), true);
    const auto start = Clock::now();
    for (auto _ : state) {
        sim::SurfaceBvh bvh(s.triangles, s.x);
        benchmark::DoNotOptimize(bvh.root());
        benchmark::ClobberMemory();
    }
    finish(state, start, static_cast<double>(s.triangles.rows()));
}

/// Refit to the crumpled sheet; swept: to the step from it to a moved copy (x1 given).
template <bool Swept, int Threads> void bvhRefit(benchmark::State& state) {
    const Sheet s = makeSheet(static_cast<int>(state.range(0)), true);
    sim::MatX3 x1 = s.x;
    x1.col(2).array() += 0.5 * BENCH_CELL_SIZE;
    sim::SurfaceBvh bvh(s.triangles, s.x);
    sim::setThreadCount(Threads);
    const auto start = Clock::now();
    for (auto _ : state) {
        bvh.refit(s.x, Swept ? &x1 : nullptr, MARGIN);
        benchmark::DoNotOptimize(bvh.nodes().data());
        benchmark::ClobberMemory();
    }
    finish(state, start, static_cast<double>(s.triangles.rows()));
    sim::setThreadCount(0);
}

/// Self-overlap query with the default curvature culling.
template <bool Crumpled> void bvhSelf(benchmark::State& state) {
    const Sheet s = makeSheet(static_cast<int>(state.range(0)), Crumpled);
    sim::SurfaceBvh bvh(s.triangles, s.x);
    bvh.refit(s.x, nullptr, MARGIN);
    std::vector<std::pair<int, int>> out;
    const auto start = Clock::now();
    for (auto _ : state) {
        out.clear();
        bvh.selfOverlaps(out);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    finish(state, start, static_cast<double>(s.triangles.rows()));
    state.counters["pairs"] = static_cast<double>(out.size());
}

/// Overlap query of the crumpled sheet against a sphere of about as many triangles, centred
/// on the sheet with a radius of 30% of its side (a ring of contacts).
void bvhOverlapsSphere(benchmark::State& state) {
    const int cells = static_cast<int>(state.range(0));
    const Sheet s = makeSheet(cells, true);
    const double side = cells * BENCH_CELL_SIZE;
    const Sheet sphere =
        makeSphere(sim::Vec3(0.5 * side, 0.5 * side, 0.0), 0.3 * side, cells / 2 + 2, cells);
    sim::SurfaceBvh sheetBvh(s.triangles, s.x);
    sheetBvh.refit(s.x, nullptr, MARGIN);
    const sim::SurfaceBvh sphereBvh(sphere.triangles, sphere.x);
    std::vector<std::pair<int, int>> out;
    const auto start = Clock::now();
    for (auto _ : state) {
        out.clear();
        sheetBvh.overlaps(sphereBvh, out);
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    finish(state, start, static_cast<double>(s.triangles.rows() + sphere.triangles.rows()));
    state.counters["pairs"] = static_cast<double>(out.size());
}

void bvhSizes(benchmark::internal::Benchmark* b) {
    b->ArgNames({"cells"});
    for (const int cells : BVH_CELLS) {
        b->Arg(cells);
    }
    b->UseRealTime()->Unit(benchmark::kMicrosecond)->Complexity();
}

} // namespace

BENCHMARK(bvhBuild)->Name("bvh/build")->Apply(bvhSizes);
BENCHMARK(bvhRefit<false, 1>)->Name("bvh/refit/threads:1")->Apply(bvhSizes);
BENCHMARK(bvhRefit<false, 0>)->Name("bvh/refit/threads:all")->Apply(bvhSizes);
BENCHMARK(bvhRefit<true, 1>)->Name("bvh/refit_swept/threads:1")->Apply(bvhSizes);
BENCHMARK(bvhRefit<true, 0>)->Name("bvh/refit_swept/threads:all")->Apply(bvhSizes);
BENCHMARK(bvhSelf<false>)->Name("bvh/self_flat")->Apply(bvhSizes);
BENCHMARK(bvhSelf<true>)->Name("bvh/self_crumpled")->Apply(bvhSizes);
BENCHMARK(bvhOverlapsSphere)->Name("bvh/overlaps_sheet_sphere")->Apply(bvhSizes);

} // namespace atelier::bench
