#include "patterns/cusick.h"

#include "patterns/garment.h"
#include "patterns/mesh.h"
#include "patterns/settle.h"

#include "sim/mesh/cloth_mesh.h"
#include "sim/scene.h"
#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace atelier::patterns {

namespace {

constexpr double SHADOW_CELL = 0.001;     // grid of the shadow [m]
constexpr double NODE_PROMINENCE = 0.005; // a fold rises at least this above its neighbours [m]
constexpr int PEDESTAL_SIDES = 64;

/// A circle of radius r as four quarter arcs, counter-clockwise.
Loop circle(double r) {
    Loop loop;
    const double bulge = std::tan(std::numbers::pi / 8); // tan(θ/4) for θ = 90°
    for (int k = 0; k < 4; ++k) {
        const double a0 = k * std::numbers::pi / 2;
        const double a1 = (k + 1) * std::numbers::pi / 2;
        Segment s;
        s.kind = SegmentKind::Arc;
        s.start = Vec2(r * std::cos(a0), r * std::sin(a0));
        s.end = Vec2(r * std::cos(a1), r * std::sin(a1));
        s.bulge = bulge;
        loop.push_back(s);
    }
    return loop;
}

/// The support under the specimen: a closed cylinder of radius r from y = top − depth to top.
sim::ObstacleSpec pedestal(double r, double top, double depth) {
    sim::ObstacleSpec o;
    o.name = "support";
    o.closed = true;
    const int n = PEDESTAL_SIDES;
    o.vertices.resize(2 * n + 2, 3);
    for (int k = 0; k < n; ++k) {
        const double a = 2 * std::numbers::pi * k / n;
        o.vertices.row(k) << r * std::cos(a), top, r * std::sin(a);
        o.vertices.row(n + k) << r * std::cos(a), top - depth, r * std::sin(a);
    }
    o.vertices.row(2 * n) << 0, top, 0;
    o.vertices.row(2 * n + 1) << 0, top - depth, 0;
    o.triangles.resize(4 * n, 3);
    for (int k = 0; k < n; ++k) {
        const int k1 = (k + 1) % n;
        // Outward: the top cap faces +y, the bottom −y, the sides away from the axis (the
        // angle runs from +x towards +z, clockwise seen from above).
        o.triangles.row(4 * k) << 2 * n, k1, k;
        o.triangles.row(4 * k + 1) << 2 * n + 1, n + k, n + k1;
        o.triangles.row(4 * k + 2) << k, k1, n + k1;
        o.triangles.row(4 * k + 3) << k, n + k1, n + k;
    }
    return o;
}

/// Calls `visit(i, j)` for every grid cell whose centre lies in the union of the triangles
/// projected onto (x, z); cells of `cell` size, the grid centred on the vertical axis with
/// `half` cells on each side. Each cell is visited once.
template <class F>
void rasterise(const sim::MatX3& x, const sim::MatX3i& triangles, double cell, F&& visit) {
    double extent = 0;
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
        extent = std::max({extent, std::abs(x(i, 0)), std::abs(x(i, 2))});
    }
    const int half = static_cast<int>(std::ceil(extent / cell)) + 1;
    const int size = 2 * half;
    std::vector<char> covered(static_cast<std::size_t>(size) * static_cast<std::size_t>(size), 0);
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        Vec2 p[3];
        for (int c = 0; c < 3; ++c) {
            const auto v = triangles(t, c);
            p[c] = Vec2(x(v, 0), x(v, 2));
        }
        const double area =
            (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
        if (area == 0) {
            continue;
        }
        const Vec2 lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
        const Vec2 hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
        const int i0 = std::max(0, static_cast<int>(std::floor(lo.x() / cell)) + half);
        const int i1 = std::min(size - 1, static_cast<int>(std::floor(hi.x() / cell)) + half);
        const int j0 = std::max(0, static_cast<int>(std::floor(lo.y() / cell)) + half);
        const int j1 = std::min(size - 1, static_cast<int>(std::floor(hi.y() / cell)) + half);
        for (int i = i0; i <= i1; ++i) {
            for (int j = j0; j <= j1; ++j) {
                const Vec2 q((i - half + 0.5) * cell, (j - half + 0.5) * cell);
                bool inside = true;
                for (int c = 0; c < 3 && inside; ++c) {
                    const Vec2 a = p[c];
                    const Vec2 b = p[(c + 1) % 3];
                    const double side = (b - a).x() * (q - a).y() - (b - a).y() * (q - a).x();
                    inside = side * area >= 0;
                }
                char& seen = covered[static_cast<std::size_t>(i) * static_cast<std::size_t>(size) +
                                     static_cast<std::size_t>(j)];
                if (inside && seen == 0) {
                    seen = 1;
                    visit(q);
                }
            }
        }
    }
}

} // namespace

double shadowArea(const sim::MatX3& positions, const sim::MatX3i& triangles, double cell) {
    long cells = 0;
    rasterise(positions, triangles, cell, [&](const Vec2&) { ++cells; });
    return static_cast<double>(cells) * cell * cell;
}

std::vector<double> shadowRadius(const sim::MatX3& positions, const sim::MatX3i& triangles,
                                 double cell) {
    std::vector<double> radius(360, 0.0);
    rasterise(positions, triangles, cell, [&](const Vec2& q) {
        double degrees = std::atan2(q.y(), q.x()) * 180 / std::numbers::pi;
        if (degrees < 0) {
            degrees += 360;
        }
        const auto bin = std::min<std::size_t>(359, static_cast<std::size_t>(degrees));
        radius[bin] = std::max(radius[bin], q.norm());
    });
    return radius;
}

int countNodes(const std::vector<double>& radius, double prominence) {
    const std::size_t n = radius.size();
    if (n < 3) {
        return 0;
    }
    // Start at the lowest point, so the walk round the circle begins in a valley.
    const std::size_t start =
        static_cast<std::size_t>(std::min_element(radius.begin(), radius.end()) - radius.begin());
    double low = radius[start];
    double high = low;
    bool rising = true; // looking for a peak
    int nodes = 0;
    for (std::size_t k = 1; k <= n; ++k) {
        const double r = radius[(start + k) % n];
        if (rising) {
            high = std::max(high, r);
            if (high - r >= prominence && high - low >= prominence) {
                ++nodes; // came down far enough from a peak high enough
                rising = false;
                low = r;
            }
        } else {
            low = std::min(low, r);
            if (r - low >= prominence) {
                rising = true;
                high = r;
            }
        }
    }
    // Back at the start (the lowest point): a peak still being climbed down from counts.
    if (rising && high - low >= prominence && high - radius[start] >= prominence) {
        ++nodes;
    }
    return nodes;
}

CusickResult runCusick(const CusickOptions& o) {
    CusickResult r;
    const double R = o.specimenDiameter / 2;
    const double disc = o.supportDiameter / 2;
    if (!(o.particleDistance > 0) || !(disc > 0) || !(R > disc) || !(o.dt > 0) ||
        !(o.maxTime > 0) || !std::isfinite(R + o.particleDistance + o.dt + o.maxTime)) {
        r.error = "need a specimen wider than its support, a positive particle distance and step";
        return r;
    }
    Garment garment;
    Panel specimen;
    specimen.name = "specimen";
    specimen.outline = circle(R);
    garment.panels.push_back(specimen);
    GarmentMesh meshed;
    MeshOptions meshOptions;
    meshOptions.particleDistance = o.particleDistance;
    if (auto e = meshGarment(garment, meshOptions, meshed)) {
        r.error = "meshing: " + *e;
        return r;
    }
    const PanelMesh& pm = meshed.panels.front();
    const Eigen::Index n = pm.pattern.rows();
    sim::SceneSpec scene;
    sim::ClothSpec cloth;
    cloth.name = "specimen";
    if (auto e = sim::buildClothMesh(pm.rest, pm.triangles, cloth.mesh)) {
        r.error = "mesh: " + *e;
        return r;
    }
    // Pattern (x, y) → world (x, 0, −y): lying flat on the support's top at y = 0, seen from
    // above as drawn.
    std::mt19937 rng(o.seed);
    std::uniform_real_distribution<double> lift(-o.perturbation, o.perturbation);
    cloth.position.resize(n, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
        const Vec2 p = pm.pattern.row(i).transpose();
        const bool clamped = p.norm() <= disc + 1e-9;
        cloth.position.row(i) << p.x(), clamped ? 0.0 : lift(rng), -p.y();
        if (clamped) {
            scene.pins.push_back(static_cast<int>(i));
        }
    }
    cloth.material = o.material;
    cloth.bendingModel = o.bendingModel;
    cloth.selfCollision = false; // a Cusick specimen's folds hang apart
    scene.cloths.push_back(cloth);
    // The support stops just under the clamped cloth (clear of the contact distance), as the
    // lower disc and its stem do.
    sim::ObstacleSpec support = pedestal(disc, 0, 0.4);
    support.vertices.col(1).array() -= cloth.thickness + support.thickness + 0.001;
    scene.obstacles.push_back(support);
    scene.integrator.kind = sim::IntegratorKind::ImplicitEuler;
    scene.integrator.dt = o.dt;
    scene.integrator.maxDt = o.dt;
    scene.frameRate = 4;
    scene.duration = o.maxTime;
    if (auto e = sim::Simulation::validate(scene)) {
        r.error = *e;
        return r;
    }
    sim::Simulation simulation(std::move(scene));
    if (!simulation.error().empty()) {
        r.error = simulation.error();
        return r;
    }
    SettleOptions settling;
    settling.maxTime = o.maxTime;
    settling.cancel = o.cancel;
    const SettleResult settled = settle(simulation, settling, noVertexMovedMoreThan(o.restMotion));
    r.settledTime = settled.time;
    r.atRest = settled.atRest;
    if (!settled.error.empty()) {
        r.error = settled.error;
        return r;
    }
    r.positions = simulation.positions();
    r.triangles = pm.triangles;
    r.shadowArea = shadowArea(r.positions, r.triangles, SHADOW_CELL);
    const double supportArea = std::numbers::pi * disc * disc;
    const double whole = std::numbers::pi * R * R;
    r.drapeCoefficient = (r.shadowArea - supportArea) / (whole - supportArea);
    r.radius = shadowRadius(r.positions, r.triangles, SHADOW_CELL);
    r.nodes = countNodes(r.radius, NODE_PROMINENCE);
    return r;
}

} // namespace atelier::patterns
