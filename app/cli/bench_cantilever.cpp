#include "app/cli/bench_cantilever.h"

#include "app/cli/commands.h"

#include "io/atomic_file.h"

#include "patterns/settle.h"
#include "patterns/triangulate.h"

#include "sim/analysis/heavy_elastica.h"
#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace atelier::app {

namespace {

constexpr double PI = 3.14159265358979323846;
constexpr double DEG = 180.0 / PI;

const char* meshName(CantileverMesh m) {
    switch (m) {
    case CantileverMesh::Regular:
        return "regular";
    case CantileverMesh::Irregular:
        return "irregular";
    case CantileverMesh::Rotated:
        return "rotated";
    }
    return "";
}

/// The strip in its own frame (s along the length, w across): s ∈ [−c, L] with the clamp
/// over s ≤ 0, w ∈ [0, W]. Returns the strip-frame points and triangles (counter-clockwise).
struct StripMesh {
    std::vector<sim::Vec2> points; ///< (s, w) [m]
    sim::MatX3i triangles;
    std::string error;
};

/// Points every ~h along the segment a→b, a included, b excluded.
void sampleSegment(const sim::Vec2& a, const sim::Vec2& b, double h,
                   std::vector<sim::Vec2>& points) {
    const int n = std::max(1, static_cast<int>(std::lround((b - a).norm() / h)));
    for (int i = 0; i < n; ++i) {
        points.push_back(a + (b - a) * (static_cast<double>(i) / n));
    }
}

StripMesh regularStrip(double length, double width, double h, double clamp) {
    StripMesh m;
    sim::RectangleOptions r;
    r.width = length + clamp;
    r.height = width;
    r.cellsX = static_cast<int>(std::lround(r.width / h));
    r.cellsY = std::max(1, static_cast<int>(std::lround(width / h)));
    sim::MatX2 rest;
    sim::makeRectangle(r, rest, m.triangles);
    for (int i = 0; i < rest.rows(); ++i) {
        m.points.emplace_back(rest(i, 0) - clamp, rest(i, 1));
    }
    return m;
}

/// Constrained Delaunay: the strip's outline and the clamp line s = 0 sampled every h, plus
/// `inner` points; refined to edges of at most `maxEdge`.
StripMesh delaunayStrip(double length, double width, double h, double clamp,
                        const std::vector<sim::Vec2>& inner, double maxEdge) {
    StripMesh m;
    patterns::TriangulationInput in;
    const sim::Vec2 c0(-clamp, 0);
    const sim::Vec2 c1(0, 0);
    const sim::Vec2 c2(length, 0);
    const sim::Vec2 c3(length, width);
    const sim::Vec2 c4(0, width);
    const sim::Vec2 c5(-clamp, width);
    for (const auto& [a, b] : std::vector<std::pair<sim::Vec2, sim::Vec2>>{
             {c0, c1}, {c1, c2}, {c2, c3}, {c3, c4}, {c4, c5}, {c5, c0}}) {
        sampleSegment(a, b, h, in.points);
    }
    const int outline = static_cast<int>(in.points.size());
    for (int i = 0; i < outline; ++i) {
        in.constraints.push_back({i, (i + 1) % outline});
    }
    // The clamp line from (0, 0) to (0, W): its inner points, chained to the outline's ends.
    const auto indexOf = [&](const sim::Vec2& p) {
        for (int i = 0; i < outline; ++i) {
            if ((in.points[static_cast<std::size_t>(i)] - p).norm() < 1e-12) {
                return i;
            }
        }
        return -1;
    };
    std::vector<sim::Vec2> line;
    sampleSegment(c1, c4, h, line);
    int previous = indexOf(c1);
    for (std::size_t i = 1; i < line.size(); ++i) {
        in.points.push_back(line[i]);
        const int k = static_cast<int>(in.points.size()) - 1;
        in.constraints.push_back({previous, k});
        previous = k;
    }
    in.constraints.push_back({previous, indexOf(c4)});
    for (const sim::Vec2& p : inner) {
        in.points.push_back(p);
    }
    in.maxEdge = maxEdge;
    in.minAngleDeg = 25;
    patterns::TriangulationOutput out;
    if (auto e = patterns::triangulate(in, out)) {
        m.error = *e;
        return m;
    }
    m.points = out.points;
    m.triangles = out.triangles;
    return m;
}

/// A weft-aligned square lattice of spacing h seen from the strip's frame (rotated by −45°),
/// kept where it is at least 0.4·h from the outline and the clamp line.
std::vector<sim::Vec2> rotatedLattice(double length, double width, double h, double clamp) {
    std::vector<sim::Vec2> points;
    const double reach = length + clamp + width;
    const int n = static_cast<int>(std::ceil(reach / h)) + 2;
    const double c = std::sqrt(0.5);
    const double margin = 0.4 * h;
    for (int i = -n; i <= n; ++i) {
        for (int j = -n; j <= n; ++j) {
            // Material (weft, warp) = (i h, j h); strip frame = R(−45°)·material.
            const double s = c * (i + j) * h;
            const double w = c * (j - i) * h;
            if (s > -clamp + margin && s < length - margin && w > margin && w < width - margin &&
                std::abs(s) > margin) {
                points.emplace_back(s, w);
            }
        }
    }
    return points;
}

/// Heavy-elastica reference and the tip measures of a settled strip.
struct TipMeasure {
    double angle = 0;      ///< [rad]
    double deflection = 0; ///< [m]
};

TipMeasure measureTip(const sim::MatX3& x, const std::vector<int>& tip, double width) {
    sim::Vec3 mean = sim::Vec3::Zero();
    for (int i : tip) {
        mean += x.row(i).transpose();
    }
    mean /= static_cast<double>(tip.size());
    // The clamp line's middle is (0, 0, W/2); gravity is −y.
    const double horizontal = std::hypot(mean.x(), mean.z() - 0.5 * width);
    TipMeasure t;
    t.deflection = -mean.y();
    t.angle = std::atan2(t.deflection, horizontal);
    return t;
}

} // namespace

CantileverResult runCantilever(const CantileverOptions& o) {
    CantileverResult r;
    if (!(o.particleDistance > 0) || !(o.length > 0) || !(o.width > 0) || !(o.ratio > 0) ||
        !std::isfinite(o.particleDistance + o.length + o.width + o.ratio) ||
        o.particleDistance > o.width) {
        r.error = "need a positive ratio, strip size and particle distance (at most the width)";
        return r;
    }
    const double h = o.particleDistance;
    // One cell of clamp: the hinges along s = 0 hold the slope.
    const double cells = std::max(1.0, std::round(o.length / h));
    const double clamp = o.length / cells;
    StripMesh strip;
    switch (o.mesh) {
    case CantileverMesh::Regular:
        strip = regularStrip(o.length, o.width, h, clamp);
        break;
    case CantileverMesh::Irregular:
        strip = delaunayStrip(o.length, o.width, h, clamp, {}, h);
        break;
    case CantileverMesh::Rotated:
        strip = delaunayStrip(o.length, o.width, h, clamp,
                              rotatedLattice(o.length, o.width, h, clamp), 1.5 * h);
        break;
    }
    if (!strip.error.empty()) {
        r.error = "meshing: " + strip.error;
        return r;
    }
    const int n = static_cast<int>(strip.points.size());
    // Rest coordinates in the material frame: the rotated strip runs at 45° to the weft.
    const double angle = o.mesh == CantileverMesh::Rotated ? 0.25 * PI : 0.0;
    const double ca = std::cos(angle);
    const double sa = std::sin(angle);
    sim::MatX2 rest(n, 2);
    sim::MatX3 position(n, 3);
    std::vector<int> pins;
    std::vector<int> tip;
    const double eps = 1e-9 * o.length;
    for (int i = 0; i < n; ++i) {
        const sim::Vec2& p = strip.points[static_cast<std::size_t>(i)];
        rest.row(i) << ca * p.x() - sa * p.y(), sa * p.x() + ca * p.y();
        position.row(i) << p.x(), 0.0, p.y();
        if (p.x() < eps) {
            pins.push_back(i);
        }
        if (p.x() > o.length - eps) {
            tip.push_back(i);
        }
    }
    sim::SceneSpec scene;
    sim::ClothSpec cloth;
    cloth.name = "strip";
    if (auto e = sim::buildClothMesh(rest, strip.triangles, cloth.mesh)) {
        r.error = "mesh: " + *e;
        return r;
    }
    cloth.position = position;
    cloth.material = o.material;
    cloth.material.bending =
        o.material.density * sim::STANDARD_GRAVITY * std::pow(o.length, 3) / o.ratio;
    r.bending = cloth.material.bending;
    cloth.model = sim::StretchModel::Fem;
    cloth.bendingModel = o.bendingModel;
    scene.cloths.push_back(cloth);
    scene.pins = pins;
    scene.integrator.kind = sim::IntegratorKind::ImplicitEuler;
    scene.integrator.dt = o.dt;
    scene.integrator.maxDt = o.dt;
    scene.integrator.cgTolerance = 1e-10;
    scene.integrator.cgMaxIterations = 2000;
    scene.frameRate = 4;
    scene.duration = o.maxTime;
    r.vertices = n;
    if (auto e = sim::Simulation::validate(scene)) {
        r.error = *e;
        return r;
    }
    sim::Simulation simulation(std::move(scene));
    if (!simulation.error().empty()) {
        r.error = simulation.error();
        return r;
    }
    const sim::HeavyElastica exact = sim::solveHeavyElastica(o.ratio);
    r.exactAngleDeg = exact.tipLineAngle * DEG;
    r.exactDeflection = exact.tipDrop * o.length;
    const auto tipAngle = [&](const sim::MatX3& x) {
        return measureTip(x, tip, o.width).angle * DEG;
    };
    patterns::SettleOptions settling;
    settling.minTime = 1.25;
    settling.maxTime = o.maxTime;
    const patterns::SettleResult settled = patterns::settle(
        simulation, settling, [&](const sim::MatX3& now, const sim::MatX3& before) {
            return std::abs(tipAngle(now) - tipAngle(before)) < o.restAngleDeg;
        });
    if (!settled.error.empty()) {
        r.error = settled.error;
        return r;
    }
    const TipMeasure m = measureTip(simulation.positions(), tip, o.width);
    r.angleDeg = m.angle * DEG;
    r.deflection = m.deflection;
    r.settledTime = settled.time;
    r.atRest = settled.atRest;
    return r;
}

namespace {

/// The plot: tip-line angle against λ (log axis), the exact curve and each mesh's points.
std::string
svgPlot(const std::vector<std::pair<std::string, std::vector<std::pair<double, double>>>>& series,
        double lambdaMin, double lambdaMax) {
    const int W = 720;
    const int H = 480;
    const double left = 70;
    const double right = 180;
    const double top = 30;
    const double bottom = 50;
    const double lx0 = std::log10(lambdaMin);
    const double lx1 = std::log10(lambdaMax);
    const auto px = [&](double lambda) {
        return left + (std::log10(lambda) - lx0) / std::max(1e-9, lx1 - lx0) * (W - left - right);
    };
    const auto py = [&](double deg) { return top + (1.0 - deg / 90.0) * (H - top - bottom); };
    std::ostringstream s;
    s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n";
    s << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    s << "<text x=\"" << left << "\" y=\"18\">Heavy cantilever: tip-line angle below the "
      << "horizontal against rho g L^3 / B</text>\n";
    for (int deg = 0; deg <= 90; deg += 15) {
        s << "<line x1=\"" << left << "\" x2=\"" << W - right << "\" y1=\"" << py(deg) << "\" y2=\""
          << py(deg) << "\" stroke=\"#ddd\"/>\n";
        s << "<text x=\"" << left - 8 << "\" y=\"" << py(deg) + 4 << "\" text-anchor=\"end\">"
          << deg << "°</text>\n";
    }
    for (double l = std::pow(10.0, std::floor(lx0)); l <= lambdaMax * 1.0001; l *= 10) {
        for (int k = 1; k < 10; ++k) {
            const double v = l * k;
            if (v < lambdaMin * 0.9999 || v > lambdaMax * 1.0001) {
                continue;
            }
            s << "<line x1=\"" << px(v) << "\" x2=\"" << px(v) << "\" y1=\"" << top << "\" y2=\""
              << H - bottom << "\" stroke=\"" << (k == 1 ? "#bbb" : "#eee") << "\"/>\n";
            if (k == 1 || k == 2 || k == 5) {
                s << "<text x=\"" << px(v) << "\" y=\"" << H - bottom + 16
                  << "\" text-anchor=\"middle\">" << v << "</text>\n";
            }
        }
    }
    s << "<text x=\"" << 0.5 * (left + W - right) << "\" y=\"" << H - 10
      << "\" text-anchor=\"middle\">rho g L^3 / B</text>\n";
    // The exact curve.
    s << "<polyline fill=\"none\" stroke=\"black\" stroke-width=\"2\" points=\"";
    for (int i = 0; i <= 100; ++i) {
        const double lambda = std::pow(10.0, lx0 + (lx1 - lx0) * i / 100.0);
        s << px(lambda) << "," << py(sim::solveHeavyElastica(lambda).tipLineAngle * DEG) << " ";
    }
    s << "\"/>\n";
    s << "<line x1=\"" << W - right + 15 << "\" x2=\"" << W - right + 35 << "\" y1=\"" << top + 10
      << "\" y2=\"" << top + 10 << "\" stroke=\"black\" stroke-width=\"2\"/><text x=\""
      << W - right + 40 << "\" y=\"" << top + 14 << "\">exact</text>\n";
    const char* colours[] = {"#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd",
                             "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22"};
    for (std::size_t k = 0; k < series.size(); ++k) {
        const char* colour = colours[k % 9];
        const double ly = top + 30 + 18.0 * static_cast<double>(k);
        s << "<circle cx=\"" << W - right + 25 << "\" cy=\"" << ly - 4 << "\" r=\"4\" fill=\""
          << colour << "\"/><text x=\"" << W - right + 40 << "\" y=\"" << ly << "\">"
          << series[k].first << "</text>\n";
        for (const auto& [lambda, deg] : series[k].second) {
            s << "<circle cx=\"" << px(lambda) << "\" cy=\"" << py(deg)
              << "\" r=\"4\" fill=\"none\" "
              << "stroke=\"" << colour << "\" stroke-width=\"1.5\"/>\n";
        }
    }
    s << "</svg>\n";
    return s.str();
}

} // namespace

int runCantileverBench(const CantileverBenchOptions& options) {
    std::vector<CantileverMesh> meshes;
    for (const std::string& name : options.meshes) {
        if (name == "regular") {
            meshes.push_back(CantileverMesh::Regular);
        } else if (name == "irregular") {
            meshes.push_back(CantileverMesh::Irregular);
        } else if (name == "rotated") {
            meshes.push_back(CantileverMesh::Rotated);
        } else {
            std::cerr << "error: bench cantilever: unknown mesh \"" << name
                      << "\" (regular, irregular or rotated)\n";
            return EXIT_BAD_INPUT;
        }
    }
    if (options.ratios.empty() || options.particleDistancesMm.empty() || meshes.empty()) {
        std::cerr << "error: bench cantilever: need at least one ratio, distance and mesh\n";
        return EXIT_BAD_INPUT;
    }
    for (double v : options.ratios) {
        if (!(v > 0) || !std::isfinite(v)) {
            std::cerr << "error: bench cantilever: ratios must be positive and finite\n";
            return EXIT_BAD_INPUT;
        }
    }
    for (double v : options.particleDistancesMm) {
        if (!(v > 0) || !std::isfinite(v)) {
            std::cerr << "error: bench cantilever: particle distances must be positive\n";
            return EXIT_BAD_INPUT;
        }
    }
    std::ostringstream csv;
    csv << "mesh,particle_distance_mm,ratio,bending_n_m,vertices,angle_deg,exact_angle_deg,"
           "error_deg,deflection_mm,exact_deflection_mm,settled_s,at_rest\n";
    std::vector<std::pair<std::string, std::vector<std::pair<double, double>>>> series;
    double worst = 0;
    bool failed = false;
    for (CantileverMesh mesh : meshes) {
        for (double mm : options.particleDistancesMm) {
            char label[64];
            std::snprintf(label, sizeof label, "%s %g mm", meshName(mesh), mm);
            series.emplace_back(label, std::vector<std::pair<double, double>>{});
            for (double ratio : options.ratios) {
                CantileverOptions o = options.scene;
                o.mesh = mesh;
                o.particleDistance = mm / 1000.0;
                o.ratio = ratio;
                const CantileverResult r = runCantilever(o);
                if (!r.error.empty()) {
                    std::cerr << "error: bench cantilever: " << label << ", ratio " << ratio << ": "
                              << r.error << "\n";
                    failed = true;
                    continue;
                }
                const double error = r.angleDeg - r.exactAngleDeg;
                worst = std::max(worst, std::abs(error));
                char line[256];
                std::snprintf(line, sizeof line,
                              "%s,%g,%g,%.6g,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.2f,%s\n", meshName(mesh),
                              mm, ratio, r.bending, r.vertices, r.angleDeg, r.exactAngleDeg, error,
                              1000 * r.deflection, 1000 * r.exactDeflection, r.settledTime,
                              r.atRest ? "1" : "0");
                csv << line;
                std::printf("%-16s ratio %5g: %7.3f deg (exact %7.3f, error %+6.3f), tip drop "
                            "%7.3f mm (exact %7.3f)%s\n",
                            label, ratio, r.angleDeg, r.exactAngleDeg, error, 1000 * r.deflection,
                            1000 * r.exactDeflection, r.atRest ? "" : "  NOT AT REST");
                series.back().second.emplace_back(ratio, r.angleDeg);
            }
        }
    }
    std::printf("largest |error|: %.3f deg\n", worst);
    if (!options.out.empty()) {
        const std::filesystem::path dir(options.out);
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) {
            std::cerr << "error: " << dir.string() << ": " << ec.message() << "\n";
            return EXIT_RUN_FAILED;
        }
        const auto [lo, hi] = std::minmax_element(options.ratios.begin(), options.ratios.end());
        for (const auto& [name, text] :
             {std::pair<std::string, std::string>{"cantilever.csv", csv.str()},
              {"cantilever.svg", svgPlot(series, std::min(*lo, 1.0), std::max(*hi, 10.0))}}) {
            if (auto written = io::writeFileAtomically(dir / name, text); !written.ok()) {
                std::cerr << "error: " << written.error().toString() << "\n";
                return EXIT_RUN_FAILED;
            }
        }
    }
    return failed ? EXIT_RUN_FAILED : EXIT_OK;
}

} // namespace atelier::app
