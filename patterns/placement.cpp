#include "patterns/placement.h"

#include "sim/collision/intersection/triangle_triangle.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace atelier::patterns {

sim::MatX2 placementCoordinates(const Panel& panel, const PanelMesh& mesh) {
    sim::MatX2 p = mesh.pattern;
    if (panel.side == PanelSide::Back) {
        p.col(0) = -p.col(0);
    }
    if (p.rows() == 0) {
        return p;
    }
    const Vec2 centre = 0.5 * (p.colwise().minCoeff() + p.colwise().maxCoeff()).transpose();
    const double c = std::cos(panel.placement.rotation), s = std::sin(panel.placement.rotation);
    for (int i = 0; i < p.rows(); ++i) {
        const Vec2 q = p.row(i).transpose() - centre;
        p.row(i) = (Vec2(c * q.x() - s * q.y(), s * q.x() + c * q.y()) + panel.placement.offset)
                       .transpose();
    }
    return p;
}

sim::MatX3 wrapOnSlot(const sim::MatX2& coordinates, const ArrangementSlot& slot,
                      double clearance) {
    const Eigen::Index n = coordinates.rows();
    sim::MatX3 x(n, 3);
    if (n == 0) {
        return x;
    }
    // The panel's rows, 1 cm apart along v: each gets the radius that clears the body there
    // and lets the row's widest point stay within ±maxAngle.
    constexpr double STEP = 0.01;
    const double vMin = coordinates.col(1).minCoeff();
    const double vMax = coordinates.col(1).maxCoeff();
    const int rows = static_cast<int>(std::ceil((vMax - vMin) / STEP)) + 1;
    std::vector<double> halfWidth(static_cast<std::size_t>(rows), 0.0);
    for (Eigen::Index i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(std::clamp(
            static_cast<int>(std::lround((coordinates(i, 1) - vMin) / STEP)), 0, rows - 1));
        halfWidth[k] = std::max(halfWidth[k], std::abs(coordinates(i, 0)));
    }
    std::vector<double> need(static_cast<std::size_t>(rows));
    for (int k = 0; k < rows; ++k) {
        const double v = vMin + k * STEP;
        need[static_cast<std::size_t>(k)] =
            std::max(slot.radiusAt(v) + clearance,
                     halfWidth[static_cast<std::size_t>(k)] / std::max(slot.maxAngle, 0.1));
    }
    // Smooth without dropping below the need: a moving maximum, then a moving average, both
    // over ±3 rows (every average then includes the centre row's need).
    auto window = [&](const std::vector<double>& in, bool maximum) {
        std::vector<double> out(in.size());
        for (int k = 0; k < rows; ++k) {
            double acc = 0;
            int count = 0;
            for (int j = std::max(0, k - 3); j <= std::min(rows - 1, k + 3); ++j) {
                const double value = in[static_cast<std::size_t>(j)];
                acc = maximum ? std::max(acc, value) : acc + value;
                ++count;
            }
            out[static_cast<std::size_t>(k)] = maximum ? acc : acc / count;
        }
        return out;
    };
    const std::vector<double> r = window(window(need, true), false);
    // Each row's section centre (off the axis on a leg slot), looked up at the row's v as its
    // radius is, not at the height it is placed at.
    std::vector<Vec3> c(static_cast<std::size_t>(rows));
    for (int k = 0; k < rows; ++k) {
        c[static_cast<std::size_t>(k)] = slot.centreAt(vMin + k * STEP);
    }
    // Along the axis: the meridian's arc length equals v, anchored at the panel's top row.
    // Where the centre moves (a leg slot, from the pelvis to the thigh) the rows also move
    // sideways, which lengthens the meridians a little; taking that move out of the rows'
    // spacing along the axis instead shortened them more where the move is sideways to the
    // meridian: the trousers' area went 0.9% under the pattern's, against < 0.5% this way.
    std::vector<double> along(static_cast<std::size_t>(rows));
    along[static_cast<std::size_t>(rows - 1)] = vMin + (rows - 1) * STEP;
    for (int k = rows - 2; k >= 0; --k) {
        const double dr = r[static_cast<std::size_t>(k + 1)] - r[static_cast<std::size_t>(k)];
        const double da = std::sqrt(std::max(STEP * STEP - dr * dr, 0.25 * STEP * STEP));
        along[static_cast<std::size_t>(k)] = along[static_cast<std::size_t>(k + 1)] - da;
    }
    const Vec3 right = slot.right();
    for (Eigen::Index i = 0; i < n; ++i) {
        const double u =
            std::clamp((coordinates(i, 1) - vMin) / STEP, 0.0, static_cast<double>(rows - 1));
        const auto k = std::min(static_cast<int>(u), rows - 2 < 0 ? 0 : rows - 2);
        const double f = rows > 1 ? u - k : 0.0;
        const auto kk = static_cast<std::size_t>(k);
        const auto k1 = static_cast<std::size_t>(std::min(k + 1, rows - 1));
        const double radius = (1 - f) * r[kk] + f * r[k1];
        const double a = (1 - f) * along[kk] + f * along[k1];
        const Vec3 centre = (1 - f) * c[kk] + f * c[k1];
        const double angle = coordinates(i, 0) / radius;
        x.row(i) = (slot.origin + a * slot.axis + centre +
                    radius * (std::cos(angle) * slot.facing + std::sin(angle) * right))
                       .transpose();
    }
    return x;
}

std::vector<PanelCrossing> panelCrossings(const std::vector<sim::MatX3>& positions,
                                          const std::vector<sim::MatX3i>& triangles,
                                          const std::vector<std::vector<int>>* joined,
                                          bool withinPanels) {
    // Every triangle's box, swept along x: the pairs of different panels (and of one panel,
    // withinPanels) whose boxes overlap are tested exactly.
    struct Box {
        Vec3 lo, hi;
        int panel, triangle;
    };
    std::vector<Box> boxes;
    for (std::size_t p = 0; p < positions.size() && p < triangles.size(); ++p) {
        const sim::MatX3& x = positions[p];
        const sim::MatX3i& t = triangles[p];
        for (Eigen::Index k = 0; k < t.rows(); ++k) {
            Box b{Vec3(x.row(t(k, 0))), Vec3(x.row(t(k, 0))), static_cast<int>(p),
                  static_cast<int>(k)};
            for (int i = 1; i < 3; ++i) {
                b.lo = b.lo.cwiseMin(Vec3(x.row(t(k, i))));
                b.hi = b.hi.cwiseMax(Vec3(x.row(t(k, i))));
            }
            boxes.push_back(b);
        }
    }
    std::sort(boxes.begin(), boxes.end(),
              [](const Box& l, const Box& r) { return l.lo.x() < r.lo.x(); });
    auto corner = [&](const Box& b, int i) {
        return Vec3(positions[static_cast<std::size_t>(b.panel)].row(
            triangles[static_cast<std::size_t>(b.panel)](b.triangle, i)));
    };
    // Whether two triangles share a vertex: its name when joined, else (one panel) its index.
    auto share = [&](const Box& u, const Box& w) {
        const sim::MatX3i& tu = triangles[static_cast<std::size_t>(u.panel)];
        const sim::MatX3i& tw = triangles[static_cast<std::size_t>(w.panel)];
        auto name = [&](const Box& b, int v) {
            return joined != nullptr
                       ? (*joined)[static_cast<std::size_t>(b.panel)][static_cast<std::size_t>(v)]
                       : v;
        };
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                if (name(u, tu(u.triangle, i)) == name(w, tw(w.triangle, j))) {
                    return true;
                }
            }
        }
        return false;
    };
    std::map<std::pair<int, int>, long> count;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        const Box& u = boxes[i];
        for (std::size_t j = i + 1; j < boxes.size() && boxes[j].lo.x() <= u.hi.x(); ++j) {
            const Box& w = boxes[j];
            if ((w.panel == u.panel && !withinPanels) || w.lo.y() > u.hi.y() ||
                u.lo.y() > w.hi.y() || w.lo.z() > u.hi.z() || u.lo.z() > w.hi.z()) {
                continue;
            }
            if ((joined != nullptr || w.panel == u.panel) && share(u, w)) {
                continue;
            }
            if (sim::trianglesIntersect(corner(u, 0), corner(u, 1), corner(u, 2), corner(w, 0),
                                        corner(w, 1), corner(w, 2))) {
                ++count[{std::min(u.panel, w.panel), std::max(u.panel, w.panel)}];
            }
        }
    }
    std::vector<PanelCrossing> out;
    for (const auto& [ab, pairs] : count) {
        out.push_back({ab.first, ab.second, pairs});
    }
    return out;
}

} // namespace atelier::patterns
