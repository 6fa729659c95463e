#include "sim/collision/obstacle.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace atelier::sim {

namespace {

void setRows(MatX3& v, const std::vector<Vec3>& pts) {
    v.resize(static_cast<Eigen::Index>(pts.size()), 3);
    for (std::size_t i = 0; i < pts.size(); ++i) {
        v.row(static_cast<Eigen::Index>(i)) = pts[i].transpose();
    }
}

void setTris(MatX3i& f, const std::vector<std::array<int, 3>>& tris) {
    f.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (std::size_t i = 0; i < tris.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            f(static_cast<Eigen::Index>(i), k) = tris[i][static_cast<std::size_t>(k)];
        }
    }
}

/// Rotation matrix of a rotation vector (Rodrigues).
Mat3 rotationOf(const Vec3& r) {
    const double angle = r.norm();
    if (angle < 1e-300) {
        return Mat3::Identity();
    }
    return Eigen::AngleAxisd(angle, r / angle).toRotationMatrix();
}

/// Index of the segment [times[k], times[k+1]] holding t and the weight of k+1 (clamped).
std::pair<std::size_t, double> locate(const std::vector<double>& times, double t) {
    if (times.size() < 2 || t <= times.front()) {
        return {0, 0.0};
    }
    if (t >= times.back()) {
        return {times.size() - 2, 1.0};
    }
    const auto it = std::upper_bound(times.begin(), times.end(), t);
    const std::size_t k = static_cast<std::size_t>(it - times.begin()) - 1;
    return {k, (t - times[k]) / (times[k + 1] - times[k])};
}

} // namespace

void makePlaneMesh(double size, int cells, MatX3& vertices, MatX3i& triangles) {
    cells = std::max(cells, 1);
    std::vector<Vec3> pts;
    std::vector<std::array<int, 3>> tris;
    const int n = cells + 1;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            pts.emplace_back(size * (i / double(cells) - 0.5), 0.0,
                             size * (j / double(cells) - 0.5));
        }
    }
    for (int j = 0; j < cells; ++j) {
        for (int i = 0; i < cells; ++i) {
            const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
            // Counter-clockwise seen from +Y: x to the right, z toward the viewer.
            tris.push_back({a, c, b});
            tris.push_back({b, c, d});
        }
    }
    setRows(vertices, pts);
    setTris(triangles, tris);
}

void makeSphereMesh(double radius, int subdivisions, MatX3& vertices, MatX3i& triangles) {
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Vec3> pts = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0},
                             {0, -1, p}, {0, 1, p}, {0, -1, -p}, {0, 1, -p},
                             {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
    std::vector<std::array<int, 3>> tris = {
        {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (Vec3& q : pts) {
        q.normalize();
    }
    for (int s = 0; s < subdivisions; ++s) {
        std::map<std::pair<int, int>, int> mid;
        auto midpoint = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            const auto it = mid.find(key);
            if (it != mid.end()) {
                return it->second;
            }
            pts.push_back(
                (pts[static_cast<std::size_t>(a)] + pts[static_cast<std::size_t>(b)]).normalized());
            const int id = static_cast<int>(pts.size()) - 1;
            mid.emplace(key, id);
            return id;
        };
        std::vector<std::array<int, 3>> next;
        next.reserve(tris.size() * 4);
        for (const auto& t : tris) {
            const int ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]),
                      ca = midpoint(t[2], t[0]);
            next.push_back({t[0], ab, ca});
            next.push_back({t[1], bc, ab});
            next.push_back({t[2], ca, bc});
            next.push_back({ab, bc, ca});
        }
        tris.swap(next);
    }
    for (Vec3& q : pts) {
        q *= radius;
    }
    setRows(vertices, pts);
    setTris(triangles, tris);
}

void makeBoxMesh(const Vec3& size, int cells, MatX3& vertices, MatX3i& triangles) {
    cells = std::max(cells, 1);
    std::vector<Vec3> pts;
    std::vector<std::array<int, 3>> tris;
    std::map<std::array<long long, 3>, int> index; // shared vertices along box edges
    const Vec3 h = 0.5 * size;
    auto vertexAt = [&](const Vec3& q) {
        const std::array<long long, 3> key = {std::llround(q.x() * 1e9), std::llround(q.y() * 1e9),
                                              std::llround(q.z() * 1e9)};
        const auto it = index.find(key);
        if (it != index.end()) {
            return it->second;
        }
        pts.push_back(q);
        const int id = static_cast<int>(pts.size()) - 1;
        index.emplace(key, id);
        return id;
    };
    for (int axis = 0; axis < 3; ++axis) {
        for (int sign = -1; sign <= 1; sign += 2) {
            const int u = (axis + 1) % 3, w = (axis + 2) % 3;
            std::vector<int> ids;
            for (int j = 0; j <= cells; ++j) {
                for (int i = 0; i <= cells; ++i) {
                    Vec3 q;
                    q[axis] = sign * h[axis];
                    q[u] = h[u] * (2.0 * i / cells - 1.0);
                    q[w] = h[w] * (2.0 * j / cells - 1.0);
                    ids.push_back(vertexAt(q));
                }
            }
            for (int j = 0; j < cells; ++j) {
                for (int i = 0; i < cells; ++i) {
                    const int n = cells + 1;
                    const int a = ids[static_cast<std::size_t>(j * n + i)];
                    const int b = ids[static_cast<std::size_t>(j * n + i + 1)];
                    const int c = ids[static_cast<std::size_t>((j + 1) * n + i)];
                    const int d = ids[static_cast<std::size_t>((j + 1) * n + i + 1)];
                    // (u, w, axis) is right-handed, so a→b→d runs counter-clockwise seen from
                    // +axis.
                    if (sign > 0) {
                        tris.push_back({a, b, d});
                        tris.push_back({a, d, c});
                    } else {
                        tris.push_back({a, d, b});
                        tris.push_back({a, c, d});
                    }
                }
            }
        }
    }
    setRows(vertices, pts);
    setTris(triangles, tris);
}

void makeCapsuleMesh(double radius, double length, int segments, MatX3& vertices,
                     MatX3i& triangles) {
    segments = std::max(segments, 6);
    const int rings = std::max(2, segments / 4); // latitude rings per hemisphere
    // Length 0: a latitude–longitude sphere (no cylinder rows, which would repeat the equator).
    const int body =
        length > 0
            ? std::max(1, static_cast<int>(std::round(length / (2 * M_PI * radius / segments))))
            : 0;
    std::vector<Vec3> pts;
    std::vector<std::array<int, 3>> tris;
    // Latitude rows from the top pole (excluded) to the bottom pole.
    std::vector<std::pair<double, double>> rows; // (y, ring radius)
    for (int k = 1; k <= rings; ++k) {
        const double phi = M_PI / 2 * (1.0 - double(k) / rings);
        rows.emplace_back(0.5 * length + radius * std::sin(phi), radius * std::cos(phi));
    }
    for (int k = 1; k <= body; ++k) {
        rows.emplace_back(0.5 * length - length * k / body, radius);
    }
    for (int k = 1; k < rings; ++k) {
        const double phi = -M_PI / 2 * double(k) / rings;
        rows.emplace_back(-0.5 * length + radius * std::sin(phi), radius * std::cos(phi));
    }
    pts.emplace_back(0.0, 0.5 * length + radius, 0.0);
    for (const auto& [y, r] : rows) {
        for (int i = 0; i < segments; ++i) {
            const double a = 2 * M_PI * i / segments;
            pts.emplace_back(r * std::cos(a), y, -r * std::sin(a));
        }
    }
    pts.emplace_back(0.0, -0.5 * length - radius, 0.0);
    const int nRows = static_cast<int>(rows.size());
    const int bottom = static_cast<int>(pts.size()) - 1;
    tris.reserve(2 * static_cast<std::size_t>(segments) * rows.size());
    auto at = [&](int row, int i) { return 1 + row * segments + (i % segments); };
    for (int i = 0; i < segments; ++i) {
        tris.push_back({0, at(0, i), at(0, i + 1)});
    }
    for (int r = 0; r + 1 < nRows; ++r) {
        for (int i = 0; i < segments; ++i) {
            tris.push_back({at(r, i), at(r + 1, i), at(r + 1, i + 1)});
            tris.push_back({at(r, i), at(r + 1, i + 1), at(r, i + 1)});
        }
    }
    for (int i = 0; i < segments; ++i) {
        tris.push_back({bottom, at(nRows - 1, i + 1), at(nRows - 1, i)});
    }
    setRows(vertices, pts);
    setTris(triangles, tris);
}

bool isClosedOriented(const MatX3i& triangles, int vertexCount) {
    std::map<std::pair<int, int>, int> directed;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(t, k), b = triangles(t, (k + 1) % 3);
            if (a < 0 || a >= vertexCount || b < 0 || b >= vertexCount || a == b) {
                return false;
            }
            if (++directed[{a, b}] > 1) {
                return false;
            }
        }
    }
    for (const auto& [e, count] : directed) {
        (void)count;
        if (directed.find({e.second, e.first}) == directed.end()) {
            return false;
        }
    }
    return !directed.empty();
}

void obstaclePositionsAt(const ObstacleSpec& o, double t, MatX3& out) {
    if (!o.frames.empty()) {
        const auto [k, w] = locate(o.frameTimes, t);
        if (o.frames.size() == 1) {
            out = o.frames[0];
        } else {
            out = (1.0 - w) * o.frames[k] + w * o.frames[k + 1];
        }
        return;
    }
    if (o.keys.empty()) {
        out = o.vertices;
        return;
    }
    std::vector<double> times;
    times.reserve(o.keys.size());
    for (const ObstacleKey& key : o.keys) {
        times.push_back(key.time);
    }
    const auto [k, w] = locate(times, t);
    const ObstacleKey& a = o.keys[k];
    const ObstacleKey& b = o.keys[std::min(k + 1, o.keys.size() - 1)];
    const Vec3 translation = (1.0 - w) * a.translation + w * b.translation;
    const Mat3 r = rotationOf((1.0 - w) * a.rotation + w * b.rotation);
    out.resize(o.vertices.rows(), 3);
    for (Eigen::Index i = 0; i < o.vertices.rows(); ++i) {
        out.row(i) = (r * o.vertices.row(i).transpose() + translation).transpose();
    }
}

bool obstacleMoves(const ObstacleSpec& o) {
    if (!o.frames.empty()) {
        return o.frames.size() > 1;
    }
    for (std::size_t k = 1; k < o.keys.size(); ++k) {
        if (o.keys[k].translation != o.keys[0].translation ||
            o.keys[k].rotation != o.keys[0].rotation) {
            return true;
        }
    }
    return false;
}

double nextObstacleEvent(const ObstacleSpec& o, double t) {
    double next = std::numeric_limits<double>::infinity();
    if (!o.frames.empty()) {
        for (double ft : o.frameTimes) {
            if (ft > t + 1e-12) {
                return ft;
            }
        }
        return next;
    }
    for (const ObstacleKey& k : o.keys) {
        if (k.time > t + 1e-12) {
            return k.time;
        }
    }
    return next;
}

} // namespace atelier::sim
