/// Google Benchmarks of the collision stage (detection on refitted hierarchies + narrow phase +
/// response), single-threaded:
/// - `collision/dome/cells:N`: a sheet of N×N cells (2N² triangles: ≈1k … 200k) lying on a sphere
///   cap so that about half its vertices touch; one detection + response over a small step. The
///   sphere's triangles are cloth-cell sized at every N. Counters: `ns_per_triangle`, `contacts`,
///   `candidates` (triangle pairs from the hierarchies), `obstacle_triangles`, `first_update_ms`
///   (the first update, which also checks every vertex for being inside the sphere).
/// - `collision/contacts/cells:N/touching:P`: the same 10k sheet lying flat with P% of it within
///   the contact distance of a plane: cost against contact count.
/// - `collision/self-flat/cells:N`: self-collision of a flat sheet (the curvature culling keeps
///   it near zero: `candidates` should be 0), and `collision/self-wavy/cells:N` (waves of 38°
///   slope: curved, still height fields, still culled). The cost left is the refit.
/// - `collision/drape-step/cells:71`: whole steps (implicit Euler, 1/240 s) of a 10k-triangle
///   sheet with self-collision draping on a 20k-triangle closed sphere; counter
///   `collision_fraction` = collision wall time / step wall time.

#include "sim/collision/collision_stage.h"
#include "sim/collision/obstacle.h"
#include "sim/core/parallel.h"
#include "sim/simulation.h"

#include "bench_scenes.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace atelier::bench {

namespace {

constexpr double CELL = 0.01; // [m]

/// A horizontal sheet of cells×cells centred on the origin at height y = 0.
sim::ClothSpec flatSheet(int cells) {
    sim::ClothSpec c;
    sim::RectangleOptions r;
    r.width = r.height = cells * CELL;
    r.cellsX = r.cellsY = cells;
    sim::MatX2 rest;
    sim::MatX3i tris;
    sim::makeRectangle(r, rest, tris);
    (void)sim::buildClothMesh(rest, tris, c.mesh);
    c.position.resize(rest.rows(), 3);
    for (int i = 0; i < rest.rows(); ++i) {
        c.position.row(i) << rest(i, 0) - r.width / 2, 0.0, r.height / 2 - rest(i, 1);
    }
    c.thickness = 0.002;
    return c;
}

sim::ObstacleSpec sphere(double radius, int subdivisions, const sim::Vec3& centre) {
    sim::ObstacleSpec o;
    sim::makeSphereMesh(radius, subdivisions, o.vertices, o.triangles);
    o.closed = true;
    o.keys.push_back(sim::ObstacleKey{0.0, centre, sim::Vec3::Zero()});
    o.thickness = 0.003;
    return o;
}

/// Times CollisionStage::update over a step moving every vertex by `motion` (a fixed random
/// field, fixed seed).
void timeUpdates(benchmark::State& state, const sim::SceneSpec& scene, double motion) {
    std::vector<int> offsets{0, scene.cloths[0].mesh.vertexCount()};
    const sim::MatX3& x0 = scene.cloths[0].position;
    sim::CollisionStage stage(scene, offsets, x0);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-motion, motion);
    sim::MatX3 delta(x0.rows(), 3);
    for (int i = 0; i < delta.rows(); ++i) {
        delta.row(i) << u(rng), u(rng), u(rng);
    }
    const sim::VecX invMass = sim::VecX::Ones(x0.rows());
    sim::MatX3 xe, ve;
    // The first update also runs the inside check of every vertex (then every 1/30 s of
    // simulated time, 1 update in 34 here): timed on its own, outside the loop.
    const auto first = Clock::now();
    xe = x0 + delta;
    ve = delta / 1e-3;
    stage.update(0.0, 1e-3, x0, xe, ve, invMass);
    state.counters["first_update_ms"] =
        std::chrono::duration<double, std::milli>(Clock::now() - first).count();
    double t = 1e-3;
    const auto start = Clock::now();
    for (auto _ : state) {
        xe = x0 + delta;
        ve = delta / 1e-3;
        stage.update(t, t + 1e-3, x0, xe, ve, invMass);
        t += 1e-3;
        benchmark::DoNotOptimize(xe.data());
    }
    const auto elapsed = Clock::now() - start;
    const double triangles = scene.cloths[0].mesh.triangleCount();
    state.counters["triangles"] = triangles;
    state.counters["contacts"] = static_cast<double>(stage.figures().contacts);
    state.counters["candidates"] =
        static_cast<double>(stage.figures().candidatePairs) /
        static_cast<double>(std::max<std::int64_t>(1, state.iterations()));
    state.counters["ns_per_triangle"] = nsPerItem(elapsed, state.iterations(), triangles);
    state.SetComplexityN(static_cast<std::int64_t>(triangles));
}

void dome(benchmark::State& state) {
    sim::setThreadCount(1);
    const int cells = static_cast<int>(state.range(0));
    sim::SceneSpec s;
    sim::ClothSpec c = flatSheet(cells);
    // A sphere of radius half the sheet; the sheet lies on its cap (inner half) at the contact
    // distance and flat beyond.
    const double radius = cells * CELL * 0.5;
    const double d0 = 0.005;
    for (int i = 0; i < c.position.rows(); ++i) {
        const double x = c.position(i, 0), z = c.position(i, 2);
        const double r2 = x * x + z * z;
        const double cap = 0.7 * radius;
        const double rr = std::min(std::sqrt(r2), cap);
        c.position(i, 1) = std::sqrt(radius * radius - rr * rr) + d0 - 0.0001;
    }
    s.cloths.push_back(c);
    // Sphere triangles the size of cloth triangles at every N (so that both meshes and the
    // contacts per triangle scale together): a latitude–longitude sphere with cell-sized quads at
    // its equator, turned so that the equator runs under the sheet (the poles, where its
    // triangles crowd, are off to the sides).
    sim::ObstacleSpec o;
    o.closed = true;
    o.keys.push_back(sim::ObstacleKey{0.0, sim::Vec3::Zero(), sim::Vec3::Zero()});
    o.thickness = 0.003;
    const int segments = std::max(8, static_cast<int>(std::lround(2 * M_PI * radius / CELL)));
    sim::makeCapsuleMesh(radius, 0.0, segments, o.vertices, o.triangles);
    for (int i = 0; i < o.vertices.rows(); ++i) { // a quarter turn about z: the poles go to ±x
        const double x = o.vertices(i, 0), y = o.vertices(i, 1);
        o.vertices(i, 0) = y;
        o.vertices(i, 1) = -x;
    }
    s.obstacles.push_back(o);
    state.counters["obstacle_triangles"] = static_cast<double>(o.triangles.rows());
    timeUpdates(state, s, 1e-5);
    sim::setThreadCount(0);
}

void contacts(benchmark::State& state) {
    sim::setThreadCount(1);
    const int cells = static_cast<int>(state.range(0));
    const double touching = static_cast<double>(state.range(1)) / 100.0;
    sim::SceneSpec s;
    sim::ClothSpec c = flatSheet(cells);
    const double width = cells * CELL;
    // The sheet lies on a plane for the first `touching` fraction along x, then rises steeply.
    for (int i = 0; i < c.position.rows(); ++i) {
        const double along = (c.position(i, 0) + width / 2) / width;
        c.position(i, 1) = 0.0039 + std::max(0.0, along - touching) * 0.5;
    }
    s.cloths.push_back(c);
    sim::ObstacleSpec plane;
    sim::makePlaneMesh(2 * width, 16, plane.vertices, plane.triangles);
    plane.thickness = 0.002;
    s.obstacles.push_back(plane);
    timeUpdates(state, s, 1e-5);
    sim::setThreadCount(0);
}

template <bool Crumpled> void selfSheet(benchmark::State& state) {
    sim::setThreadCount(1);
    const int cells = static_cast<int>(state.range(0));
    sim::SceneSpec s;
    s.collision.failSafe = state.range(1) != 0;
    sim::ClothSpec c = flatSheet(cells);
    c.selfCollision = true;
    if (Crumpled) {
        // Waves of one cell's height every 4 cells: curved everywhere, no contact.
        for (int i = 0; i < c.position.rows(); ++i) {
            c.position(i, 1) = CELL * std::sin(c.position(i, 0) / (4 * CELL) * M_PI) *
                               std::sin(c.position(i, 2) / (4 * CELL) * M_PI);
        }
    }
    s.cloths.push_back(c);
    timeUpdates(state, s, 1e-6);
    sim::setThreadCount(0);
}

void drapeStep(benchmark::State& state) {
    const int cells = static_cast<int>(state.range(0));
    sim::SceneSpec s;
    sim::ClothSpec c = flatSheet(cells);
    c.selfCollision = true;
    const double width = cells * CELL;
    c.position.col(1).array() += 0.75 * width + 0.01;
    s.cloths.push_back(c);
    s.obstacles.push_back(sphere(0.375 * width, 5, sim::Vec3(0, 0.375 * width, 0)));
    s.integrator.kind = sim::IntegratorKind::ImplicitEuler;
    s.integrator.dt = s.integrator.maxDt = 1.0 / 240;
    sim::Simulation simulation(s);
    if (!simulation.error().empty()) {
        state.SkipWithError(simulation.error().c_str());
        return;
    }
    // Let it fall onto the sphere first (contacts everywhere near the top).
    simulation.advance(0.25);
    const double wall0 = simulation.stats().wallTime;
    const double coll0 = simulation.stats().stageSeconds.at("collision");
    for (auto _ : state) {
        if (simulation.advance(1.0 / 240) != sim::RunStatus::Finished) {
            state.SkipWithError(("the step failed: " + simulation.error()).c_str());
            break;
        }
        benchmark::DoNotOptimize(simulation.positions().data());
    }
    const sim::RunStats& stats = simulation.stats();
    const double wall = stats.wallTime - wall0;
    state.counters["triangles"] = c.mesh.triangleCount();
    state.counters["obstacle_triangles"] = static_cast<double>(s.obstacles[0].triangles.rows());
    state.counters["contacts"] = static_cast<double>(stats.contacts);
    state.counters["collision_fraction"] =
        wall > 0 ? (stats.stageSeconds.at("collision") - coll0) / wall : 0.0;
}

} // namespace

BENCHMARK(dome)
    ->Name("collision/dome")
    ->ArgName("cells")
    ->Arg(22)
    ->Arg(71)
    ->Arg(224)
    ->Arg(316)
    ->Unit(benchmark::kMillisecond)
    ->Complexity(benchmark::oNLogN);
BENCHMARK(contacts)
    ->Name("collision/contacts")
    ->ArgNames({"cells", "touching"})
    ->Args({22, 50})
    ->Args({71, 0})
    ->Args({71, 25})
    ->Args({71, 50})
    ->Args({71, 100})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(selfSheet<false>)
    ->Name("collision/self-flat")
    ->ArgNames({"cells", "failsafe"})
    ->Args({22, 0})
    ->Args({71, 0})
    ->Args({224, 0})
    ->Args({316, 0})
    ->Args({22, 1})
    ->Args({71, 1})
    ->Args({224, 1})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(selfSheet<true>)
    ->Name("collision/self-wavy")
    ->ArgNames({"cells", "failsafe"})
    ->Args({22, 0})
    ->Args({71, 0})
    ->Args({224, 0})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(drapeStep)
    ->Name("collision/drape-step")
    ->ArgName("cells")
    ->Arg(71)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(40);

} // namespace atelier::bench
