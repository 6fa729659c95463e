/// Google Benchmarks of the narrow-phase geometry, one query per iteration over a fixed set of
/// 4096 random cases (fixed seed), single-threaded. Counter `ns_per_query`.
/// - `geometry/swept-vertex-triangle/case:C/distance:D` and `geometry/swept-edge-edge/...`:
///   continuous tests with distance 0 (D = 0) or 5% of the primitive size (D = 1), on
///   C = 0 "near": boxes overlapping but mostly no contact (what the broad phase hands over),
///   C = 1 "crossing": every case crosses, C = 2 "flat": everything in one plane, moving in it
///   (a flat sheet: the coplanarity cubic vanishes, the conservative search runs).
/// - `geometry/triangles-intersect/case:C`: C = 0 random nearby pairs, C = 1 coplanar nearby
///   pairs in a tilted plane (exact fallbacks), C = 2 pairs on a small integer grid (touching and
///   degenerate).
/// - `geometry/orient3d/case:C`: C = 0 generic points (the filter decides), C = 1 nearly coplanar
///   points (the exact expansion runs).

#include "sim/collision/geometry.h"

#include "bench_scenes.h"

#include <Eigen/Geometry>
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace atelier::bench {

namespace {

using sim::Vec3;

constexpr std::size_t CASES = 4096;
constexpr double SIZE = 0.01; ///< primitive size [m]

/// Eight points: a pair of primitives at the start and end of a step (vertex–triangle: p, a, b,
/// c; edge–edge: pa, pb, qa, qb), each as (start, end).
using SweepCase = std::array<Vec3, 8>;

Vec3 randomVec(std::mt19937& rng, double half) {
    std::uniform_real_distribution<double> u(-half, half);
    return {u(rng), u(rng), u(rng)};
}

std::vector<SweepCase> sweepCases(int kind, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<SweepCase> cases(CASES);
    const Vec3 tiltU = Vec3(1, 2, 3).normalized();
    const Vec3 tiltV = tiltU.cross(Vec3(0, 0, 1)).normalized();
    for (SweepCase& c : cases) {
        for (std::size_t i = 0; i < 8; i += 2) {
            Vec3 start = randomVec(rng, SIZE);
            Vec3 motion = randomVec(rng, kind == 0 ? 0.2 * SIZE : SIZE);
            if (kind == 2) {
                start = start.x() * tiltU + start.y() * tiltV;
                motion = motion.x() * tiltU + motion.y() * tiltV;
            }
            c[i] = start;
            c[i + 1] = start + motion;
        }
        if (kind == 1) {
            // First point goes from the centroid of the others + one side to the other side.
            const Vec3 mid0 = (c[2] + c[4] + c[6]) / 3;
            const Vec3 mid1 = (c[3] + c[5] + c[7]) / 3;
            const Vec3 n = (c[4] - c[2]).cross(c[6] - c[2]).normalized();
            c[0] = mid0 + SIZE * n;
            c[1] = mid1 - SIZE * n;
        }
    }
    return cases;
}

void sweptVertexTriangle(benchmark::State& state) {
    const auto cases = sweepCases(static_cast<int>(state.range(0)), 11);
    const double distance = state.range(1) == 0 ? 0.0 : 0.05 * SIZE;
    std::size_t i = 0;
    std::int64_t hits = 0;
    const auto start = Clock::now();
    for (auto _ : state) {
        const SweepCase& c = cases[i++ % CASES];
        const auto hit =
            sim::sweptVertexTriangle(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], distance);
        hits += hit.has_value();
        benchmark::DoNotOptimize(hit);
    }
    const auto elapsed = Clock::now() - start;
    state.counters["ns_per_query"] = nsPerItem(elapsed, state.iterations(), 1.0);
    state.counters["hit_fraction"] =
        state.iterations() > 0 ? double(hits) / double(state.iterations()) : 0.0;
}

void sweptEdgeEdge(benchmark::State& state) {
    auto cases = sweepCases(static_cast<int>(state.range(0)), 12);
    if (state.range(0) == 1) {
        // Crossing edges: edge q passes through the middle of edge p.
        for (SweepCase& c : cases) {
            const Vec3 mid0 = 0.5 * (c[0] + c[2]);
            const Vec3 mid1 = 0.5 * (c[1] + c[3]);
            const Vec3 n = (c[2] - c[0]).cross(c[6] - c[4]).normalized();
            const Vec3 half0 = 0.5 * (c[6] - c[4]);
            const Vec3 half1 = 0.5 * (c[7] - c[5]);
            c[4] = mid0 + SIZE * n - half0;
            c[6] = mid0 + SIZE * n + half0;
            c[5] = mid1 - SIZE * n - half1;
            c[7] = mid1 - SIZE * n + half1;
        }
    }
    const double distance = state.range(1) == 0 ? 0.0 : 0.05 * SIZE;
    std::size_t i = 0;
    std::int64_t hits = 0;
    const auto start = Clock::now();
    for (auto _ : state) {
        const SweepCase& c = cases[i++ % CASES];
        const auto hit =
            sim::sweptEdgeEdge(c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7], distance);
        hits += hit.has_value();
        benchmark::DoNotOptimize(hit);
    }
    const auto elapsed = Clock::now() - start;
    state.counters["ns_per_query"] = nsPerItem(elapsed, state.iterations(), 1.0);
    state.counters["hit_fraction"] =
        state.iterations() > 0 ? double(hits) / double(state.iterations()) : 0.0;
}

using TrianglePair = std::array<Vec3, 6>;

std::vector<TrianglePair> trianglePairs(int kind) {
    std::mt19937 rng(13);
    std::uniform_int_distribution<int> grid(0, 3);
    std::vector<TrianglePair> pairs(CASES);
    const Vec3 tiltU = Vec3(1, 2, 3).normalized();
    const Vec3 tiltV = tiltU.cross(Vec3(0, 0, 1)).normalized();
    for (TrianglePair& t : pairs) {
        for (Vec3& v : t) {
            if (kind == 2) {
                v = SIZE * Vec3(grid(rng), grid(rng), grid(rng));
            } else {
                v = randomVec(rng, SIZE);
                if (kind == 1) {
                    v = Vec3(0.3, -0.2, 1.1) + v.x() * tiltU + v.y() * tiltV;
                }
            }
        }
    }
    return pairs;
}

void trianglesIntersect(benchmark::State& state) {
    const auto pairs = trianglePairs(static_cast<int>(state.range(0)));
    std::size_t i = 0;
    std::int64_t hits = 0;
    const auto start = Clock::now();
    for (auto _ : state) {
        const TrianglePair& t = pairs[i++ % CASES];
        const bool hit = sim::trianglesIntersect(t[0], t[1], t[2], t[3], t[4], t[5]);
        hits += hit;
        benchmark::DoNotOptimize(hit);
    }
    const auto elapsed = Clock::now() - start;
    state.counters["ns_per_query"] = nsPerItem(elapsed, state.iterations(), 1.0);
    state.counters["hit_fraction"] =
        state.iterations() > 0 ? double(hits) / double(state.iterations()) : 0.0;
}

void orient3d(benchmark::State& state) {
    std::mt19937 rng(14);
    std::vector<std::array<Vec3, 4>> cases(CASES);
    for (auto& c : cases) {
        for (Vec3& v : c) {
            v = randomVec(rng, 1.0);
        }
        if (state.range(0) == 1) { // d on the plane of a, b, c up to rounding
            c[3] = c[0] + 0.3 * (c[1] - c[0]) + 0.6 * (c[2] - c[0]);
        }
    }
    std::size_t i = 0;
    const auto start = Clock::now();
    for (auto _ : state) {
        const auto& c = cases[i++ % CASES];
        const int sign = sim::orient3d(c[0], c[1], c[2], c[3]);
        benchmark::DoNotOptimize(sign);
    }
    const auto elapsed = Clock::now() - start;
    state.counters["ns_per_query"] = nsPerItem(elapsed, state.iterations(), 1.0);
}

void sweepArgs(benchmark::internal::Benchmark* b) {
    b->ArgNames({"case", "distance"});
    for (int kind : {0, 1, 2}) {
        for (int distance : {0, 1}) {
            b->Args({kind, distance});
        }
    }
}

} // namespace

BENCHMARK(sweptVertexTriangle)->Name("geometry/swept-vertex-triangle")->Apply(sweepArgs);
BENCHMARK(sweptEdgeEdge)->Name("geometry/swept-edge-edge")->Apply(sweepArgs);
BENCHMARK(trianglesIntersect)
    ->Name("geometry/triangles-intersect")
    ->ArgName("case")
    ->Arg(0)
    ->Arg(1)
    ->Arg(2);
BENCHMARK(orient3d)->Name("geometry/orient3d")->ArgName("case")->Arg(0)->Arg(1);

} // namespace atelier::bench
