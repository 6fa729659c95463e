#pragma once
/// Shared inputs of the benchmarks: square cloths of n×n cells, deformed with a fixed seed.

#include "sim/mesh/cloth_mesh.h"
#include "sim/scene.h"

#include <array>
#include <chrono>
#include <cstdint>
#include <random>

namespace atelier::bench {

using Clock = std::chrono::steady_clock;

/// Wall time per iteration and item [ns] (the `ns_per_triangle` counters; measured around the
/// whole benchmark loop, so it is real time also for multi-threaded runs).
inline double nsPerItem(Clock::duration elapsed, std::int64_t iterations, double items) {
    const double ns = std::chrono::duration<double, std::nano>(elapsed).count();
    return iterations > 0 && items > 0 ? ns / (static_cast<double>(iterations) * items) : 0.0;
}

/// Cells per side of the benchmark squares: 2n² ≈ 1k, 10k, 100k triangles.
inline constexpr std::array<int, 3> BENCH_CELLS = {22, 71, 224};

/// Side of a benchmark cell [m] (cell size, not sheet size, is fixed so that the explicit
/// integrators' stability limit does not depend on the mesh size).
inline constexpr double BENCH_CELL_SIZE = 0.01;

/// A cloth in a generic deformed state: the square (x, y) → (x, y, 0) with every vertex moved
/// by up to 10% of a cell (fixed seed), random small velocities.
struct BenchCloth {
    sim::ClothMesh mesh;
    sim::MatX3 x; ///< (|V|×3) [m]
    sim::MatX3 v; ///< (|V|×3) [m/s]
};

inline BenchCloth makeBenchCloth(int cells, std::uint32_t seed = 7) {
    BenchCloth c;
    sim::RectangleOptions rect;
    rect.width = rect.height = cells * BENCH_CELL_SIZE;
    rect.cellsX = rect.cellsY = cells;
    sim::MatX2 rest;
    sim::MatX3i triangles;
    sim::makeRectangle(rect, rest, triangles);
    sim::buildClothMesh(rest, triangles, c.mesh);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const int n = c.mesh.vertexCount();
    c.x.resize(n, 3);
    c.v.resize(n, 3);
    for (int i = 0; i < n; ++i) {
        for (int a = 0; a < 3; ++a) {
            const double base = a < 2 ? rest(i, a) : 0.0;
            c.x(i, a) = base + 0.1 * BENCH_CELL_SIZE * u(rng);
            c.v(i, a) = 0.01 * u(rng);
        }
    }
    return c;
}

/// A hanging-sheet scene on the benchmark square: pinned at the two top corners, gravity,
/// fem stretch + bending, starting flat in the vertical plane.
inline sim::SceneSpec makeBenchScene(int cells, sim::IntegratorKind kind, double dt) {
    sim::SceneSpec scene;
    sim::ClothSpec cloth;
    const BenchCloth c = makeBenchCloth(cells);
    cloth.mesh = c.mesh;
    cloth.position = sim::MatX3::Zero(c.mesh.vertexCount(), 3);
    cloth.position.leftCols(2) = c.mesh.rest;
    cloth.model = sim::StretchModel::Fem;
    scene.cloths.push_back(cloth);
    scene.pins = {cells * (cells + 1), (cells + 1) * (cells + 1) - 1}; // top-left, top-right
    scene.integrator.kind = kind;
    scene.integrator.dt = dt;
    scene.integrator.maxDt = dt;
    scene.integrator.tolerance = 1e3; // rk45: accept every step (one step per advance)
    scene.duration = 1e9;
    return scene;
}

} // namespace atelier::bench
