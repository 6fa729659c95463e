#include "sim/mesh/cloth_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <sstream>
#include <unordered_map>

namespace atelier::sim {

std::optional<std::string> buildClothMesh(const MatX2& rest, const MatX3i& triangles,
                                          ClothMesh& out, double minArea) {
    const int nv = static_cast<int>(rest.rows());
    const int nf = static_cast<int>(triangles.rows());
    if (nf == 0) {
        return std::string("the mesh has no triangles");
    }
    if (!rest.allFinite()) {
        for (int i = 0; i < nv; ++i) {
            if (!rest.row(i).allFinite()) {
                return "vertex " + std::to_string(i) + ": rest coordinates are not finite";
            }
        }
    }
    out.rest = rest;
    out.triangles = triangles;
    out.restArea.resize(nf);
    for (int t = 0; t < nf; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int v = triangles(t, k);
            if (v < 0 || v >= nv) {
                return "triangle " + std::to_string(t) + ": vertex index " + std::to_string(v) +
                       " out of range [0, " + std::to_string(nv) + ")";
            }
        }
        const int a = triangles(t, 0);
        const int b = triangles(t, 1);
        const int c = triangles(t, 2);
        if (a == b || b == c || a == c) {
            return "triangle " + std::to_string(t) + ": repeats a vertex";
        }
        const double area = signedArea(rest.row(a), rest.row(b), rest.row(c));
        if (std::abs(area) <= minArea) {
            std::ostringstream s;
            s << "triangle " << t << ": zero area in the rest shape (" << area << " m²)";
            return s.str();
        }
        if (area < 0) {
            std::ostringstream s;
            s << "triangle " << t << ": inverted (clockwise) in the rest shape (signed area "
              << area << " m²)";
            return s.str();
        }
        out.restArea[t] = area;
    }

    // Edges: key (min, max) -> edge index.
    std::unordered_map<std::uint64_t, int> edgeIndex;
    edgeIndex.reserve(static_cast<std::size_t>(nf) * 2);
    std::vector<std::array<int, 2>> edges;
    std::vector<std::array<int, 2>> edgeTris;
    edges.reserve(static_cast<std::size_t>(nf) * 2);
    for (int t = 0; t < nf; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(t, k);
            const int b = triangles(t, (k + 1) % 3);
            const int lo = std::min(a, b);
            const int hi = std::max(a, b);
            const std::uint64_t key =
                (static_cast<std::uint64_t>(lo) << 32) | static_cast<std::uint32_t>(hi);
            auto [it, inserted] = edgeIndex.try_emplace(key, static_cast<int>(edges.size()));
            if (inserted) {
                edges.push_back({lo, hi});
                edgeTris.push_back({t, -1});
            } else {
                auto& et = edgeTris[static_cast<std::size_t>(it->second)];
                if (et[1] != -1) {
                    return "edge (" + std::to_string(lo) + ", " + std::to_string(hi) +
                           "): non-manifold, shared by more than two triangles (triangle " +
                           std::to_string(t) + " is the third)";
                }
                et[1] = t;
            }
        }
    }
    const int ne = static_cast<int>(edges.size());
    out.edges.resize(ne, 2);
    out.edgeTriangles.resize(ne, 2);
    int nh = 0;
    for (int e = 0; e < ne; ++e) {
        out.edges(e, 0) = edges[static_cast<std::size_t>(e)][0];
        out.edges(e, 1) = edges[static_cast<std::size_t>(e)][1];
        out.edgeTriangles(e, 0) = edgeTris[static_cast<std::size_t>(e)][0];
        out.edgeTriangles(e, 1) = edgeTris[static_cast<std::size_t>(e)][1];
        nh += edgeTris[static_cast<std::size_t>(e)][1] >= 0 ? 1 : 0;
    }
    out.hinges.resize(nh, 4);
    int h = 0;
    auto opposite = [&](int t, int a, int b) {
        for (int k = 0; k < 3; ++k) {
            const int v = triangles(t, k);
            if (v != a && v != b) {
                return v;
            }
        }
        return -1;
    };
    auto runsCcw = [&](int t, int a, int b) {
        for (int k = 0; k < 3; ++k) {
            if (triangles(t, k) == a && triangles(t, (k + 1) % 3) == b) {
                return true;
            }
        }
        return false;
    };
    for (int e = 0; e < ne; ++e) {
        int t0 = out.edgeTriangles(e, 0);
        int t1 = out.edgeTriangles(e, 1);
        if (t1 < 0) {
            continue;
        }
        const int a = out.edges(e, 0);
        const int b = out.edges(e, 1);
        if (!runsCcw(t0, a, b)) {
            std::swap(t0, t1);
        }
        out.hinges(h, 0) = a;
        out.hinges(h, 1) = b;
        out.hinges(h, 2) = opposite(t0, a, b);
        out.hinges(h, 3) = opposite(t1, a, b);
        ++h;
    }
    return std::nullopt;
}

VecX lumpedMasses(const ClothMesh& mesh, double density) {
    VecX m = VecX::Zero(mesh.vertexCount());
    for (int t = 0; t < mesh.triangleCount(); ++t) {
        const double third = mesh.restArea[t] * density / 3.0;
        for (int k = 0; k < 3; ++k) {
            m[mesh.triangles(t, k)] += third;
        }
    }
    return m;
}

void makeRectangle(const RectangleOptions& o, MatX2& rest, MatX3i& triangles) {
    const int nx = std::max(1, o.cellsX);
    const int ny = std::max(1, o.cellsY);
    const double hx = o.width / nx;
    const double hy = o.height / ny;
    rest.resize((nx + 1) * (ny + 1), 2);
    std::mt19937 rng(o.seed);
    std::uniform_real_distribution<double> jitter(-0.4, 0.4);
    const bool irregular = o.triangulation == Triangulation::Irregular;
    for (int j = 0; j <= ny; ++j) {
        for (int i = 0; i <= nx; ++i) {
            double x = i * hx;
            double y = j * hy;
            if (irregular && i > 0 && i < nx && j > 0 && j < ny) {
                x += jitter(rng) * hx;
                y += jitter(rng) * hy;
            }
            rest.row(j * (nx + 1) + i) << x, y;
        }
    }
    triangles.resize(2 * nx * ny, 3);
    std::bernoulli_distribution coin(0.5);
    int t = 0;
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            const int v00 = j * (nx + 1) + i;
            const int v10 = v00 + 1;
            const int v01 = v00 + nx + 1;
            const int v11 = v01 + 1;
            bool diagonal00to11 = ((i + j) % 2) == 0;
            if (irregular) {
                diagonal00to11 = coin(rng);
                // Keep both triangles counter-clockwise: a jittered quad may be non-convex.
                const auto ok = [&](int a, int b, int c) {
                    return signedArea(rest.row(a), rest.row(b), rest.row(c)) > 0;
                };
                const bool firstOk = ok(v00, v10, v11) && ok(v00, v11, v01);
                const bool secondOk = ok(v00, v10, v01) && ok(v10, v11, v01);
                if (diagonal00to11 && !firstOk) {
                    diagonal00to11 = false;
                } else if (!diagonal00to11 && !secondOk) {
                    diagonal00to11 = true;
                }
            }
            if (diagonal00to11) {
                triangles.row(t++) << v00, v10, v11;
                triangles.row(t++) << v00, v11, v01;
            } else {
                triangles.row(t++) << v00, v10, v01;
                triangles.row(t++) << v10, v11, v01;
            }
        }
    }
}

} // namespace atelier::sim
