#include "ui/render/overlays.h"

#include "ui/render/text.h"

#include "sim/collision/collision_obstacle.h"
#include "sim/collision/distance/obstacle_distance.h"
#include "sim/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <unordered_map>
#include <utility>

namespace atelier::render {

sim::VecX triangleStrain(const sim::MatX3& positions, const sim::MatX3i& triangles,
                         const sim::MatX2& rest) {
    sim::VecX strain(triangles.rows());
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        const int i = triangles(t, 0);
        const int j = triangles(t, 1);
        const int k = triangles(t, 2);
        Eigen::Matrix2d dm;
        dm.col(0) = (rest.row(j) - rest.row(i)).transpose();
        dm.col(1) = (rest.row(k) - rest.row(i)).transpose();
        const double det = dm.determinant();
        // A rest triangle thinner than 1e-9 of its edges' squared length has no usable inverse.
        if (!(std::abs(det) > 1e-9 * (dm.col(0).squaredNorm() + dm.col(1).squaredNorm()))) {
            strain[t] = std::numeric_limits<double>::quiet_NaN();
            continue;
        }
        Eigen::Matrix<double, 3, 2> ds;
        ds.col(0) = (positions.row(j) - positions.row(i)).transpose();
        ds.col(1) = (positions.row(k) - positions.row(i)).transpose();
        const Eigen::Matrix<double, 3, 2> f = ds * dm.inverse();
        const Eigen::Matrix2d c = f.transpose() * f; // right Cauchy–Green tensor
        const double mean = 0.5 * (c(0, 0) + c(1, 1));
        const double radius = std::hypot(0.5 * (c(0, 0) - c(1, 1)), c(0, 1));
        const double s1 = std::sqrt(std::max(mean + radius, 0.0));
        const double s2 = std::sqrt(std::max(mean - radius, 0.0));
        strain[t] = s1 - 1 >= 1 - s2 ? s1 - 1 : s2 - 1;
    }
    return strain;
}

std::vector<Colour> strainColours(const sim::VecX& strain, double rangeFraction) {
    const double r = rangeFraction > 0 ? rangeFraction : 0.1;
    return scalarColours(strain, -r, r);
}

namespace {

std::string percentLabel(double fraction) {
    char text[32];
    const double pct = 100 * fraction;
    std::snprintf(text, sizeof text, pct > 0 ? "+%g%%" : "%g%%", pct);
    return text;
}

} // namespace

void drawStrainLegend(io::RgbaImage& image, double rangeFraction) {
    const double r = rangeFraction > 0 ? rangeFraction : 0.1;
    const int scale = image.height >= 512 ? 2 : 1;
    const int barWidth = 10 * scale;
    const int barHeight = std::max(image.height / 2, 5 * LINE_HEIGHT * scale);
    const int pad = 4 * scale;
    const std::vector<double> ticks = {r, r / 2, 0, -r / 2, -r};
    int labelWidth = textWidth("strain", scale);
    for (const double t : ticks) {
        labelWidth = std::max(labelWidth, textWidth(percentLabel(t), scale));
    }
    const int panelWidth = pad + barWidth + pad + labelWidth + pad;
    const int panelHeight = pad + LINE_HEIGHT * scale + barHeight + GLYPH_HEIGHT * scale + pad;
    const int left = image.width - panelWidth - pad;
    const int top = (image.height - panelHeight) / 2;
    const Colour ink{0.15f, 0.15f, 0.15f, 1.0f};
    fillRect(image, left, top, panelWidth, panelHeight, {1.0f, 1.0f, 1.0f, 0.85f});
    drawText(image, left + pad, top + pad, "strain", scale, ink);

    const int barTop = top + pad + LINE_HEIGHT * scale + GLYPH_HEIGHT * scale / 2;
    const int barLeft = left + pad;
    sim::VecX values(barHeight);
    for (int y = 0; y < barHeight; ++y) {
        values[y] = r - 2 * r * double(y) / double(std::max(barHeight - 1, 1));
    }
    const std::vector<Colour> colours = strainColours(values, r);
    for (int y = 0; y < barHeight; ++y) {
        fillRect(image, barLeft, barTop + y, barWidth, 1, colours[static_cast<std::size_t>(y)]);
    }
    const Colour frame{0.4f, 0.4f, 0.4f, 1.0f};
    fillRect(image, barLeft - 1, barTop - 1, barWidth + 2, 1, frame);
    fillRect(image, barLeft - 1, barTop + barHeight, barWidth + 2, 1, frame);
    fillRect(image, barLeft - 1, barTop, 1, barHeight, frame);
    fillRect(image, barLeft + barWidth, barTop, 1, barHeight, frame);
    for (std::size_t k = 0; k < ticks.size(); ++k) {
        const int y = barTop + static_cast<int>(std::lround(double(k) / double(ticks.size() - 1) *
                                                            double(barHeight - 1)));
        fillRect(image, barLeft + barWidth, y, pad / 2 + 1, 1, frame);
        drawText(image, barLeft + barWidth + pad, y - GLYPH_HEIGHT * scale / 2,
                 percentLabel(ticks[k]), scale, ink);
    }
}

sim::MatX2i seamEdgesByPosition(const sim::MatX3& positions, const sim::MatX3i& triangles,
                                const std::vector<int>& trianglePanel, double tolerance) {
    // Boundary edges of each panel: the edges one triangle of the panel uses.
    std::map<std::tuple<int, int, int>, int> edgeUses; // (panel, low, high) → triangles
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        const int panel = trianglePanel[static_cast<std::size_t>(t)];
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(t, k);
            const int b = triangles(t, (k + 1) % 3);
            ++edgeUses[{panel, std::min(a, b), std::max(a, b)}];
        }
    }
    // Boundary vertices of each panel, hashed on a grid of cells `tolerance` wide.
    const double cell = std::max(tolerance, 1e-9);
    using Key = std::tuple<long, long, long>;
    struct KeyHash {
        std::size_t operator()(const Key& k) const {
            return std::size_t(std::get<0>(k)) * 73856093u ^
                   std::size_t(std::get<1>(k)) * 19349663u ^
                   std::size_t(std::get<2>(k)) * 83492791u;
        }
    };
    const auto keyOf = [&](const sim::Vec3& p, int dx, int dy, int dz) {
        return Key{static_cast<long>(std::floor(p.x() / cell)) + dx,
                   static_cast<long>(std::floor(p.y() / cell)) + dy,
                   static_cast<long>(std::floor(p.z() / cell)) + dz};
    };
    std::unordered_map<Key, std::vector<std::pair<int, int>>, KeyHash> grid; // (vertex, panel)
    std::vector<std::pair<int, std::pair<int, int>>> boundary;               // (panel, edge)
    for (const auto& [key, uses] : edgeUses) {
        if (uses != 1) {
            continue;
        }
        const auto [panel, a, b] = key;
        boundary.push_back({panel, {a, b}});
        for (const int v : {a, b}) {
            auto& bucket = grid[keyOf(positions.row(v).transpose(), 0, 0, 0)];
            if (std::find(bucket.begin(), bucket.end(), std::pair{v, panel}) == bucket.end()) {
                bucket.emplace_back(v, panel);
            }
        }
    }
    // The other panels with a boundary vertex within the tolerance of vertex v (of `panel`).
    const auto partners = [&](int v, int panel) {
        std::vector<int> out;
        const sim::Vec3 p = positions.row(v).transpose();
        for (int dx = -1; dx <= 1; ++dx) {
            for (int dy = -1; dy <= 1; ++dy) {
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto found = grid.find(keyOf(p, dx, dy, dz));
                    if (found == grid.end()) {
                        continue;
                    }
                    for (const auto& [w, q] : found->second) {
                        if (q != panel && (positions.row(w).transpose() - p).norm() <= tolerance) {
                            out.push_back(q);
                        }
                    }
                }
            }
        }
        return out;
    };
    std::vector<std::pair<int, int>> seams;
    for (const auto& [panel, edge] : boundary) {
        const std::vector<int> at = partners(edge.first, panel);
        const std::vector<int> bt = partners(edge.second, panel);
        const bool shared = std::any_of(at.begin(), at.end(), [&](int q) {
            return std::find(bt.begin(), bt.end(), q) != bt.end();
        });
        if (shared) {
            seams.push_back(edge);
        }
    }
    sim::MatX2i out(static_cast<Eigen::Index>(seams.size()), 2);
    for (std::size_t k = 0; k < seams.size(); ++k) {
        out(static_cast<Eigen::Index>(k), 0) = seams[k].first;
        out(static_cast<Eigen::Index>(k), 1) = seams[k].second;
    }
    return out;
}

sim::VecX bodyDistances(const sim::MatX3& garment, const sim::MatX3& bodyPositions,
                        const sim::MatX3i& bodyTriangles, double maxDistance) {
    sim::VecX out = sim::VecX::Constant(garment.rows(), std::numeric_limits<double>::infinity());
    if (bodyTriangles.rows() == 0) {
        return out;
    }
    sim::ObstacleSpec spec;
    spec.name = "body";
    spec.vertices = bodyPositions;
    spec.triangles = bodyTriangles;
    spec.closed = true;
    const sim::CollisionObstacle obstacle(spec, 0);
    for (Eigen::Index i = 0; i < garment.rows(); ++i) {
        out[i] =
            sim::signedDistance(obstacle, obstacle.x1, garment.row(i).transpose(), maxDistance);
    }
    return out;
}

} // namespace atelier::render
