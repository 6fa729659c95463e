#include "patterns/body_measure.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numeric>
#include <unordered_map>

namespace atelier::patterns {

using sim::Vec2;
using sim::Vec3;

namespace {

std::uint64_t key(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
}

std::uint64_t undirected(int a, int b) {
    return key(std::min(a, b), std::max(a, b));
}

int findRoot(std::vector<int>& parent, int v) {
    while (parent[static_cast<std::size_t>(v)] != v) {
        parent[static_cast<std::size_t>(v)] =
            parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
        v = parent[static_cast<std::size_t>(v)];
    }
    return v;
}

/// Perimeter of the convex hull of 2D points (Andrew's monotone chain).
double hullPerimeter(std::vector<Vec2> p) {
    std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
        return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
    });
    if (p.size() < 3) {
        return p.size() == 2 ? 2 * (p[1] - p[0]).norm() : 0.0;
    }
    auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
        return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
    };
    std::vector<Vec2> hull(2 * p.size());
    std::size_t k = 0;
    for (const Vec2& q : p) {
        while (k >= 2 && cross(hull[k - 2], hull[k - 1], q) <= 0) {
            --k;
        }
        hull[k++] = q;
    }
    for (std::size_t i = p.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) {
            --k;
        }
        hull[k++] = p[i];
    }
    hull.resize(k - 1);
    double perimeter = 0;
    for (std::size_t i = 0; i < hull.size(); ++i) {
        perimeter += (hull[(i + 1) % hull.size()] - hull[i]).norm();
    }
    return perimeter;
}

} // namespace

MeshTopology meshTopology(const sim::MatX3& vertices, const sim::MatX3i& triangles) {
    MeshTopology topo;
    const int nv = static_cast<int>(vertices.rows());
    std::unordered_map<std::uint64_t, int> directed;
    std::unordered_map<std::uint64_t, int> uses;
    std::vector<int> parent(static_cast<std::size_t>(nv));
    std::iota(parent.begin(), parent.end(), 0);
    std::vector<char> used(static_cast<std::size_t>(nv), 0);
    std::vector<std::vector<std::array<int, 2>>> link(static_cast<std::size_t>(nv));
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        const std::array<int, 3> v = {triangles(t, 0), triangles(t, 1), triangles(t, 2)};
        const Vec3 a = vertices.row(v[0]);
        const Vec3 b = vertices.row(v[1]);
        const Vec3 c = vertices.row(v[2]);
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2] || !((b - a).cross(c - a).norm() > 0)) {
            ++topo.degenerateTriangles;
        }
        for (int e = 0; e < 3; ++e) {
            const int p = v[static_cast<std::size_t>(e)];
            const int q = v[static_cast<std::size_t>((e + 1) % 3)];
            const int r = v[static_cast<std::size_t>((e + 2) % 3)];
            ++directed[key(p, q)];
            ++uses[undirected(p, q)];
            used[static_cast<std::size_t>(p)] = 1;
            link[static_cast<std::size_t>(p)].push_back({q, r});
            parent[static_cast<std::size_t>(findRoot(parent, p))] = findRoot(parent, q);
        }
    }
    topo.edges = static_cast<long>(uses.size());
    for (const auto& [k, n] : uses) {
        if (n == 1) {
            ++topo.boundaryEdges;
        } else if (n > 2) {
            ++topo.nonManifoldEdges;
        } else {
            const int a = static_cast<int>(k >> 32);
            const int b = static_cast<int>(k & 0xffffffffu);
            if (directed[key(a, b)] != 1 || directed[key(b, a)] != 1) {
                ++topo.misorientedEdges;
            }
        }
    }
    for (int v = 0; v < nv; ++v) {
        if (!used[static_cast<std::size_t>(v)]) {
            continue;
        }
        ++topo.vertices;
        if (findRoot(parent, v) == v) {
            ++topo.components;
        }
        // The link edges (q → r) of a manifold vertex form one cycle (or one path on a
        // boundary): follow q → r from the first and count how many are reached.
        const auto& l = link[static_cast<std::size_t>(v)];
        std::map<int, int> next;
        for (const auto& e : l) {
            next[e[0]] = e[1];
        }
        std::size_t steps = 0;
        int at = l.front()[0];
        while (steps <= l.size()) {
            const auto it = next.find(at);
            if (it == next.end()) {
                break;
            }
            at = it->second;
            ++steps;
            if (at == l.front()[0]) {
                break;
            }
        }
        if (next.size() != l.size() || (steps != l.size() && topo.boundaryEdges == 0)) {
            ++topo.nonManifoldVertices;
        }
    }
    topo.eulerCharacteristic = topo.vertices - topo.edges + static_cast<long>(triangles.rows());
    return topo;
}

double enclosedVolume(const sim::MatX3& vertices, const sim::MatX3i& triangles) {
    double six = 0;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        const Vec3 a = vertices.row(triangles(t, 0));
        const Vec3 b = vertices.row(triangles(t, 1));
        const Vec3 c = vertices.row(triangles(t, 2));
        six += a.dot(b.cross(c));
    }
    return six / 6;
}

std::vector<std::vector<Vec3>> planeSection(const sim::MatX3& vertices,
                                            const sim::MatX3i& triangles, const Vec3& point,
                                            const Vec3& normal) {
    const Vec3 n = normal.normalized();
    std::vector<double> d(static_cast<std::size_t>(vertices.rows()));
    for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
        const double s = (Vec3(vertices.row(v)) - point).dot(n);
        d[static_cast<std::size_t>(v)] = s == 0 ? 1e-300 : s; // on the plane: above it
    }
    // Each cut triangle gives a segment between two cut edges; chain them by edge.
    std::unordered_map<std::uint64_t, Vec3> at;
    std::unordered_map<std::uint64_t, std::vector<std::uint64_t>> links;
    auto cutPoint = [&](int a, int b) {
        const std::uint64_t k = undirected(a, b);
        if (at.find(k) == at.end()) {
            const double da = d[static_cast<std::size_t>(a)];
            const double db = d[static_cast<std::size_t>(b)];
            const double t = da / (da - db);
            at[k] = Vec3(vertices.row(a)) + t * (Vec3(vertices.row(b)) - Vec3(vertices.row(a)));
        }
        return k;
    };
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        std::vector<std::uint64_t> cut;
        for (int e = 0; e < 3; ++e) {
            const int a = triangles(t, e);
            const int b = triangles(t, (e + 1) % 3);
            if ((d[static_cast<std::size_t>(a)] < 0) != (d[static_cast<std::size_t>(b)] < 0)) {
                cut.push_back(cutPoint(a, b));
            }
        }
        if (cut.size() == 2) {
            links[cut[0]].push_back(cut[1]);
            links[cut[1]].push_back(cut[0]);
        }
    }
    std::vector<std::vector<Vec3>> loops;
    std::unordered_map<std::uint64_t, char> seen;
    for (const auto& [start, unused] : links) {
        if (seen[start]) {
            continue;
        }
        std::vector<Vec3> loop;
        std::uint64_t prev = start;
        std::uint64_t cur = start;
        while (!seen[cur]) {
            seen[cur] = 1;
            loop.push_back(at[cur]);
            const auto& nb = links[cur];
            std::uint64_t nxt = cur;
            for (std::uint64_t c : nb) {
                if (c != prev && !seen[c]) {
                    nxt = c;
                    break;
                }
            }
            if (nxt == cur) {
                break;
            }
            prev = cur;
            cur = nxt;
        }
        loops.push_back(std::move(loop));
    }
    return loops;
}

std::optional<double> tapeGirth(const sim::MatX3& vertices, const sim::MatX3i& triangles,
                                const Vec3& point, const Vec3& normal) {
    const Vec3 n = normal.normalized();
    const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 e1 = n.cross(helper).normalized();
    const Vec3 e2 = n.cross(e1);
    std::optional<double> best;
    double bestArea = 0;
    for (const auto& loop : planeSection(vertices, triangles, point, n)) {
        std::vector<Vec2> p;
        p.reserve(loop.size());
        for (const Vec3& q : loop) {
            p.emplace_back((q - point).dot(e1), (q - point).dot(e2));
        }
        // Does the loop enclose the origin (even-odd rule)? And its area.
        bool inside = false;
        double area = 0;
        for (std::size_t i = 0, j = p.size() - 1; i < p.size(); j = i++) {
            area += p[j].x() * p[i].y() - p[i].x() * p[j].y();
            if ((p[i].y() > 0) != (p[j].y() > 0) &&
                0 < (p[j].x() - p[i].x()) * (0 - p[i].y()) / (p[j].y() - p[i].y()) + p[i].x()) {
                inside = !inside;
            }
        }
        area = std::abs(area) / 2;
        if (inside && (!best || area < bestArea)) {
            best = hullPerimeter(p);
            bestArea = area;
        }
    }
    return best;
}

} // namespace atelier::patterns
