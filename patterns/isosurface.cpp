#include "patterns/isosurface.h"

#include "sim/core/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <unordered_map>
#include <utility>
#include <vector>

namespace atelier::patterns {

using sim::parallelFor;
using sim::Vec3;

namespace {

/// The six Kuhn tetrahedra of a cube (corner index = x + 2y + 4z): every path from corner 0 to
/// corner 7 along the axes. Neighbouring cubes split their shared face along the same diagonal,
/// so the tetrahedra form one consistent simplicial complex.
constexpr std::array<std::array<int, 4>, 6> KUHN = {{
    {0, 1, 3, 7},
    {0, 2, 3, 7},
    {0, 2, 6, 7},
    {0, 4, 6, 7},
    {0, 4, 5, 7},
    {0, 1, 5, 7},
}};

struct Grid {
    Vec3 origin;
    double h = 0;
    int nx = 0, ny = 0, nz = 0;
    std::vector<double> value;

    std::int64_t index(int i, int j, int k) const {
        return (static_cast<std::int64_t>(k) * ny + j) * nx + i;
    }
    Vec3 point(std::int64_t id) const {
        const std::int64_t i = id % nx;
        const std::int64_t j = (id / nx) % ny;
        const std::int64_t k = id / (static_cast<std::int64_t>(nx) * ny);
        return origin +
               h * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
    }
};

/// Newton steps onto f = 0 along the gradient.
Vec3 project(const ImplicitFunction& f, Vec3 p, double h, int steps) {
    for (int s = 0; s < steps; ++s) {
        const double v = f(p);
        Vec3 g((f(p + Vec3(h, 0, 0)) - f(p - Vec3(h, 0, 0))) / (2 * h),
               (f(p + Vec3(0, h, 0)) - f(p - Vec3(0, h, 0))) / (2 * h),
               (f(p + Vec3(0, 0, h)) - f(p - Vec3(0, 0, h))) / (2 * h));
        const double g2 = g.squaredNorm();
        if (!(g2 > 1e-24)) {
            break;
        }
        p -= (v / g2) * g;
    }
    return p;
}

double angleAt(const Vec3& apex, const Vec3& a, const Vec3& b) {
    const Vec3 u = a - apex;
    const Vec3 v = b - apex;
    return std::atan2(u.cross(v).norm(), u.dot(v));
}

std::uint64_t edgeKey(int a, int b) {
    const auto lo = static_cast<std::uint32_t>(std::min(a, b));
    const auto hi = static_cast<std::uint32_t>(std::max(a, b));
    return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

/// One pass of edge flips: an interior edge flips when the angles opposite it sum beyond π
/// (not locally Delaunay), the two triangles are nearly coplanar (so the surface keeps its
/// shape), the new edge does not exist yet, and both new triangles keep the orientation.
int flipPass(const std::vector<Vec3>& x, std::vector<std::array<int, 3>>& tris) {
    std::unordered_map<std::uint64_t, std::array<int, 2>> edgeTris;
    edgeTris.reserve(tris.size() * 2);
    for (int t = 0; t < static_cast<int>(tris.size()); ++t) {
        for (int e = 0; e < 3; ++e) {
            auto [it, fresh] = edgeTris.try_emplace(edgeKey(tris[t][e], tris[t][(e + 1) % 3]),
                                                    std::array<int, 2>{t, -1});
            if (!fresh) {
                it->second[1] = t;
            }
        }
    }
    std::vector<char> touched(tris.size(), 0);
    int flips = 0;
    const double flatCos = std::cos(20.0 * std::numbers::pi / 180.0);
    for (const auto& [key, pair] : edgeTris) {
        const int t1 = pair[0];
        const int t2 = pair[1];
        if (t2 < 0 || touched[t1] || touched[t2]) {
            continue;
        }
        const int a = static_cast<int>(key >> 32);
        const int b = static_cast<int>(key & 0xffffffffu);
        // Rotate t1 to (p, q, c) with edge p→q = a–b, and find d in t2 = (q, p, d).
        std::array<int, 3> T1 = tris[t1];
        while (!((T1[0] == a && T1[1] == b) || (T1[0] == b && T1[1] == a))) {
            std::rotate(T1.begin(), T1.begin() + 1, T1.end());
        }
        const int p = T1[0];
        const int q = T1[1];
        const int c = T1[2];
        int d = -1;
        for (int v : tris[t2]) {
            if (v != p && v != q) {
                d = v;
            }
        }
        if (d < 0 || c == d || edgeTris.count(edgeKey(c, d)) != 0) {
            continue;
        }
        const double opposite = angleAt(x[c], x[p], x[q]) + angleAt(x[d], x[q], x[p]);
        if (opposite <= std::numbers::pi + 1e-9) {
            continue;
        }
        const Vec3 n1 = (x[q] - x[p]).cross(x[c] - x[p]);
        const Vec3 n2 = (x[p] - x[q]).cross(x[d] - x[q]);
        if (n1.normalized().dot(n2.normalized()) < flatCos) {
            continue;
        }
        const Vec3 n = n1 + n2;
        // New triangles (c, p, d) and (d, q, c): the quad's boundary q→c→p→d kept.
        const Vec3 m1 = (x[p] - x[c]).cross(x[d] - x[c]);
        const Vec3 m2 = (x[q] - x[d]).cross(x[c] - x[d]);
        if (m1.dot(n) <= 0 || m2.dot(n) <= 0) {
            continue;
        }
        tris[t1] = {c, p, d};
        tris[t2] = {d, q, c};
        touched[t1] = touched[t2] = 1;
        ++flips;
    }
    return flips;
}

} // namespace

Vec3 implicitNormal(const ImplicitFunction& f, const Vec3& p, double h) {
    const Vec3 g((f(p + Vec3(h, 0, 0)) - f(p - Vec3(h, 0, 0))),
                 (f(p + Vec3(0, h, 0)) - f(p - Vec3(0, h, 0))),
                 (f(p + Vec3(0, 0, h)) - f(p - Vec3(0, 0, h))));
    const double n = g.norm();
    return n > 0 ? Vec3(g / n) : Vec3(Vec3::UnitY());
}

namespace {

/// The grid over the options' box, sampled with f (values exactly zero or not finite moved to
/// the outside). False when the grid has no cells or too many for 32-bit edge keys.
bool sampleGrid(const ImplicitFunction& f, const IsosurfaceOptions& options, Grid& grid) {
    grid.h = options.cell;
    grid.origin = options.boxMin;
    const Vec3 extent = options.boxMax - options.boxMin;
    grid.nx = static_cast<int>(std::ceil(extent.x() / grid.h)) + 1;
    grid.ny = static_cast<int>(std::ceil(extent.y() / grid.h)) + 1;
    grid.nz = static_cast<int>(std::ceil(extent.z() / grid.h)) + 1;
    const auto cells = static_cast<std::int64_t>(grid.nx) * grid.ny * grid.nz;
    if (cells <= 0 || cells >= (std::int64_t{1} << 32)) {
        return false;
    }
    grid.value.resize(static_cast<std::size_t>(cells));
    // Every sample on its own (f is pure), in parallel: the same values for any thread count.
    parallelFor(cells, [&](std::int64_t id) {
        double v = f(grid.point(id));
        // A zero on the grid would make a degenerate crossing: count it outside.
        if (v == 0 || !std::isfinite(v)) {
            v = std::isfinite(v) ? 1e-300 : 1.0;
        }
        grid.value[static_cast<std::size_t>(id)] = v;
    });
    return true;
}

/// Marching tetrahedra on the sampled grid: one vertex per crossed grid edge (linear
/// interpolation), triangles oriented from inside (f < 0) to outside.
void polygonize(const Grid& grid, std::vector<Vec3>& x, std::vector<std::array<int, 3>>& tris) {
    std::unordered_map<std::uint64_t, int> edgeVertex;
    auto crossing = [&](std::int64_t a, std::int64_t b) {
        if (a > b) {
            std::swap(a, b);
        }
        // Grid indices fit 32 bits (sampleGrid checks), so the key is exact.
        const auto key = (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
        auto [it, fresh] = edgeVertex.try_emplace(key, static_cast<int>(x.size()));
        if (fresh) {
            const double va = grid.value[static_cast<std::size_t>(a)];
            const double vb = grid.value[static_cast<std::size_t>(b)];
            const double t = va / (va - vb);
            x.push_back(grid.point(a) + t * (grid.point(b) - grid.point(a)));
        }
        return it->second;
    };
    auto emit = [&](int v0, int v1, int v2, const Vec3& inside, const Vec3& outside) {
        const Vec3 n = (x[v1] - x[v0]).cross(x[v2] - x[v0]);
        if (n.dot(outside - inside) < 0) {
            std::swap(v1, v2);
        }
        tris.push_back({v0, v1, v2});
    };

    for (int k = 0; k + 1 < grid.nz; ++k) {
        for (int j = 0; j + 1 < grid.ny; ++j) {
            for (int i = 0; i + 1 < grid.nx; ++i) {
                std::array<std::int64_t, 8> corner{};
                int inside = 0;
                for (int c = 0; c < 8; ++c) {
                    corner[c] = grid.index(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                    inside += grid.value[static_cast<std::size_t>(corner[c])] < 0 ? 1 : 0;
                }
                if (inside == 0 || inside == 8) {
                    continue;
                }
                for (const auto& tet : KUHN) {
                    std::array<std::int64_t, 4> in{};
                    std::array<std::int64_t, 4> out{};
                    int ni = 0;
                    int no = 0;
                    for (int c : tet) {
                        if (grid.value[static_cast<std::size_t>(corner[c])] < 0) {
                            in[ni++] = corner[c];
                        } else {
                            out[no++] = corner[c];
                        }
                    }
                    if (ni == 0 || no == 0) {
                        continue;
                    }
                    const Vec3 pin = grid.point(in[0]);
                    const Vec3 pout = grid.point(out[0]);
                    if (ni == 1 || no == 1) {
                        const std::int64_t apex = ni == 1 ? in[0] : out[0];
                        const auto& others = ni == 1 ? out : in;
                        emit(crossing(apex, others[0]), crossing(apex, others[1]),
                             crossing(apex, others[2]), pin, pout);
                    } else {
                        // Two in, two out: the quad in0-out0, in0-out1, in1-out1, in1-out0.
                        const int q0 = crossing(in[0], out[0]);
                        const int q1 = crossing(in[0], out[1]);
                        const int q2 = crossing(in[1], out[1]);
                        const int q3 = crossing(in[1], out[0]);
                        emit(q0, q1, q2, pin, pout);
                        emit(q0, q2, q3, pin, pout);
                    }
                }
            }
        }
    }
}

/// Relaxation: tangential smoothing toward the neighbours' centroid, edge flips, projection
/// (`hGrad`: the gradients' difference step [m]).
void relax(const ImplicitFunction& f, double hGrad, int iterations, std::vector<Vec3>& x,
           std::vector<std::array<int, 3>>& tris) {
    const int nv = static_cast<int>(x.size());
    parallelFor(nv, [&](std::int64_t v64) {
        const int v = static_cast<int>(v64);
        x[static_cast<std::size_t>(v)] = project(f, x[static_cast<std::size_t>(v)], hGrad, 2);
    });
    std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(nv));
    for (int it = 0; it < iterations; ++it) {
        flipPass(x, tris);
        for (auto& n : neighbours) {
            n.clear();
        }
        for (const auto& t : tris) {
            for (int e = 0; e < 3; ++e) {
                neighbours[static_cast<std::size_t>(t[e])].push_back(t[(e + 1) % 3]);
            }
        }
        std::vector<Vec3> next = x;
        parallelFor(nv, [&](std::int64_t v64) {
            const int v = static_cast<int>(v64);
            const auto& nb = neighbours[static_cast<std::size_t>(v)];
            if (nb.empty()) {
                return;
            }
            Vec3 c = Vec3::Zero();
            for (int w : nb) {
                c += x[static_cast<std::size_t>(w)];
            }
            c /= static_cast<double>(nb.size());
            const Vec3& p = x[static_cast<std::size_t>(v)];
            const Vec3 n = implicitNormal(f, p, hGrad);
            Vec3 move = 0.6 * (c - p);
            move -= n * move.dot(n);
            next[static_cast<std::size_t>(v)] = project(f, p + move, hGrad, 1);
        });
        x.swap(next);
    }
    flipPass(x, tris);
}

/// The surface's arrays: vertices projected onto f = 0 once more, with their unit normals.
Isosurface surfaceOf(const ImplicitFunction& f, double hGrad, const std::vector<Vec3>& x,
                     const std::vector<std::array<int, 3>>& tris) {
    const int nv = static_cast<int>(x.size());
    Isosurface out;
    out.vertices.resize(nv, 3);
    out.normals.resize(nv, 3);
    parallelFor(nv, [&](std::int64_t v64) {
        const int v = static_cast<int>(v64);
        const Vec3 p = project(f, x[static_cast<std::size_t>(v)], hGrad, 2);
        out.vertices.row(v) = p.transpose();
        out.normals.row(v) = implicitNormal(f, p, hGrad).transpose();
    });
    out.triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (std::size_t t = 0; t < tris.size(); ++t) {
        out.triangles.row(static_cast<Eigen::Index>(t)) << tris[t][0], tris[t][1], tris[t][2];
    }
    return out;
}

} // namespace

Isosurface extractIsosurface(const ImplicitFunction& f, const IsosurfaceOptions& options) {
    Grid grid;
    if (!sampleGrid(f, options, grid)) {
        return {};
    }
    std::vector<Vec3> x;
    std::vector<std::array<int, 3>> tris;
    polygonize(grid, x, tris);
    grid.value = {};
    const double hGrad = grid.h * 0.05;
    relax(f, hGrad, options.relaxIterations, x, tris);
    return surfaceOf(f, hGrad, x, tris);
}

} // namespace atelier::patterns
