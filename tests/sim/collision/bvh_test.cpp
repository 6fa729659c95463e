#include "sim/collision/bvh.h"
#include "sim/collision/geometry.h"
#include "sim/core/parallel.h"
#include "sim/mesh/cloth_mesh.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>

namespace atelier::sim {
namespace {

using Pairs = std::vector<std::pair<int, int>>;

/// A triangle mesh with positions.
struct TestMesh {
    MatX3i triangles; ///< (|F|×3)
    MatX3 x;          ///< (|V|×3) [m]
};

/// A sheet of nx×ny square cells of side h (criss-cross diagonals), vertex (i, j) at index
/// j·(nx+1)+i, placed by `place(i, j)`; counter-clockwise in the (i, j) plane.
template <typename Place> TestMesh gridSheet(int nx, int ny, Place place) {
    RectangleOptions r;
    r.cellsX = nx;
    r.cellsY = ny;
    r.width = nx;
    r.height = ny;
    MatX2 rest;
    TestMesh m;
    makeRectangle(r, rest, m.triangles);
    m.x.resize(rest.rows(), 3);
    for (int j = 0; j <= ny; ++j) {
        for (int i = 0; i <= nx; ++i) {
            m.x.row(j * (nx + 1) + i) = place(i, j).transpose();
        }
    }
    return m;
}

TestMesh flatSheet(int n, double h) {
    return gridSheet(n, n, [h](int i, int j) { return Vec3(i * h, j * h, 0.0); });
}

/// A sheet of side 1 m crumpled by two waves and random jitter of `jitter` cells (fixed seed).
TestMesh crumpledSheet(int n, double jitter, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const double h = 1.0 / n;
    return gridSheet(n, n, [&](int i, int j) {
        const double x = i * h;
        const double y = j * h;
        const double z =
            0.15 * std::sin(3 * std::numbers::pi * x) * std::cos(2 * std::numbers::pi * y);
        return Vec3(Vec3(x, y, z) + jitter * h * Vec3(u(rng), u(rng), u(rng)));
    });
}

/// UV sphere: `rings` latitude bands, `segments` longitudes, outward normals.
TestMesh sphereMesh(const Vec3& c, double radius, int rings, int segments) {
    TestMesh m;
    const int nv = 2 + (rings - 1) * segments;
    m.x.resize(nv, 3);
    m.x.row(0) = (c + radius * Vec3::UnitZ()).transpose();
    m.x.row(nv - 1) = (c - radius * Vec3::UnitZ()).transpose();
    for (int r = 1; r < rings; ++r) {
        const double theta = std::numbers::pi * r / rings;
        for (int s = 0; s < segments; ++s) {
            const double phi = 2 * std::numbers::pi * s / segments;
            const Vec3 d(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta));
            m.x.row(1 + (r - 1) * segments + s) = (c + radius * d).transpose();
        }
    }
    std::vector<std::array<int, 3>> t;
    const auto ring = [&](int r, int s) { return 1 + (r - 1) * segments + (s % segments); };
    for (int s = 0; s < segments; ++s) {
        t.push_back({0, ring(1, s), ring(1, s + 1)});
        t.push_back({nv - 1, ring(rings - 1, s + 1), ring(rings - 1, s)});
        for (int r = 1; r + 1 < rings; ++r) {
            t.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
            t.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
        }
    }
    m.triangles.resize(static_cast<Eigen::Index>(t.size()), 3);
    for (std::size_t i = 0; i < t.size(); ++i) {
        m.triangles.row(static_cast<Eigen::Index>(i)) << t[i][0], t[i][1], t[i][2];
    }
    return m;
}

/// Random soup: `nt` triangles on random vertices of `nv` random points in a cube of side
/// `size` (random connectivity; triangles share vertices and edges by chance), a few of them
/// degenerate (a repeated vertex).
TestMesh randomSoup(int nt, int nv, double size, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, size);
    std::uniform_int_distribution<int> pick(0, nv - 1);
    TestMesh m;
    m.x.resize(nv, 3);
    for (int i = 0; i < nv; ++i) {
        m.x.row(i) << u(rng), u(rng), u(rng);
    }
    m.triangles.resize(nt, 3);
    for (int t = 0; t < nt; ++t) {
        const int a = pick(rng);
        int b = pick(rng);
        int c = pick(rng);
        if (t % 50 == 7) {
            c = a; // degenerate
        }
        m.triangles.row(t) << a, b, c;
    }
    return m;
}

/// Tiny OBJ reader (v and f lines; polygons fanned), or nullopt if the file is absent.
std::optional<TestMesh> readObj(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        return std::nullopt;
    }
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> f;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            Vec3 p;
            ls >> p.x() >> p.y() >> p.z();
            v.push_back(p);
        } else if (tag == "f") {
            std::vector<int> ids;
            std::string word;
            while (ls >> word) {
                ids.push_back(std::stoi(word.substr(0, word.find('/'))) - 1);
            }
            for (std::size_t k = 2; k < ids.size(); ++k) {
                f.push_back({ids[0], ids[k - 1], ids[k]});
            }
        }
    }
    TestMesh m;
    m.x.resize(static_cast<Eigen::Index>(v.size()), 3);
    for (std::size_t i = 0; i < v.size(); ++i) {
        m.x.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
    }
    m.triangles.resize(static_cast<Eigen::Index>(f.size()), 3);
    for (std::size_t i = 0; i < f.size(); ++i) {
        m.triangles.row(static_cast<Eigen::Index>(i)) << f[i][0], f[i][1], f[i][2];
    }
    return m;
}

/// The body mesh from the shared test data, loaded once; null if absent.
const TestMesh* bodyMesh() {
    static const std::optional<TestMesh> body =
        readObj(std::string(ATELIER_SOURCE_DIR) + "/../shared/data/bodies/makehuman-base-body.obj");
    return body ? &*body : nullptr;
}
#define REQUIRE_BODY(body)                                                                         \
    const TestMesh* body = bodyMesh();                                                             \
    if (body == nullptr) {                                                                         \
        GTEST_SKIP() << "no body mesh at ../shared/data/bodies/makehuman-base-body.obj";           \
    }

Vec3 vertex(const TestMesh& m, int t, int k) {
    return m.x.row(m.triangles(t, k)).transpose();
}

/// Leaf boxes computed independently: the triangle at x0 (∪ x1) grown by margin.
std::vector<Aabb> leafBoxes(const TestMesh& m, const MatX3* x1 = nullptr, double margin = 0) {
    std::vector<Aabb> boxes(static_cast<std::size_t>(m.triangles.rows()));
    for (int t = 0; t < m.triangles.rows(); ++t) {
        Aabb& b = boxes[static_cast<std::size_t>(t)];
        for (int k = 0; k < 3; ++k) {
            b.add(vertex(m, t, k));
            if (x1 != nullptr) {
                b.add(Vec3(x1->row(m.triangles(t, k)).transpose()));
            }
        }
        b.lo.array() -= margin;
        b.hi.array() += margin;
    }
    return boxes;
}

Pairs bruteCross(const std::vector<Aabb>& a, const std::vector<Aabb>& b) {
    Pairs out;
    for (std::size_t i = 0; i < a.size(); ++i) {
        for (std::size_t j = 0; j < b.size(); ++j) {
            if (a[i].overlaps(b[j])) {
                out.emplace_back(static_cast<int>(i), static_cast<int>(j));
            }
        }
    }
    return out;
}

Pairs bruteSelf(const std::vector<Aabb>& boxes) {
    Pairs out;
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        for (std::size_t j = i + 1; j < boxes.size(); ++j) {
            if (boxes[i].overlaps(boxes[j])) {
                out.emplace_back(static_cast<int>(i), static_cast<int>(j));
            }
        }
    }
    return out;
}

Pairs sorted(Pairs p) {
    std::sort(p.begin(), p.end());
    return p;
}

bool shareVertex(const TestMesh& m, int a, int b) {
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            if (m.triangles(a, i) == m.triangles(b, j)) {
                return true;
            }
        }
    }
    return false;
}

/// Triangles of a node's patch.
std::vector<int> patch(const SurfaceBvh& bvh, int node) {
    std::vector<int> out;
    std::vector<int> stack{node};
    while (!stack.empty()) {
        const int n = stack.back();
        stack.pop_back();
        const auto& nd = bvh.nodes()[static_cast<std::size_t>(n)];
        if (nd.isLeaf()) {
            out.push_back(nd.triangle);
        }
        for (const int c : nd.children) {
            if (c >= 0) {
                stack.push_back(c);
            }
        }
    }
    return out;
}

std::vector<int> patchVertices(const SurfaceBvh& bvh, const MatX3i& f, int node) {
    std::vector<int> v;
    for (const int t : patch(bvh, node)) {
        for (int k = 0; k < 3; ++k) {
            v.push_back(f(t, k));
        }
    }
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return v;
}

int treeDepth(const SurfaceBvh& bvh) {
    int depth = 0;
    std::vector<std::pair<int, int>> stack{{bvh.root(), 1}};
    while (!stack.empty()) {
        const auto [n, d] = stack.back();
        stack.pop_back();
        depth = std::max(depth, d);
        for (const int c : bvh.nodes()[static_cast<std::size_t>(n)].children) {
            if (c >= 0) {
                stack.emplace_back(c, d + 1);
            }
        }
    }
    return depth;
}

/// Edge adjacency of triangles (lists of neighbours), and the component of each triangle.
struct Topology {
    std::vector<std::vector<int>> neighbours;
    std::vector<int> component;
};

Topology topology(const MatX3i& f) {
    const int nt = static_cast<int>(f.rows());
    Topology topo;
    topo.neighbours.resize(static_cast<std::size_t>(nt));
    std::vector<std::array<int, 3>> e;
    for (int t = 0; t < nt; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int a = f(t, k);
            const int b = f(t, (k + 1) % 3);
            if (a != b) {
                e.push_back({std::min(a, b), std::max(a, b), t});
            }
        }
    }
    std::sort(e.begin(), e.end());
    for (std::size_t s = 0; s < e.size();) {
        std::size_t end = s;
        while (end < e.size() && e[end][0] == e[s][0] && e[end][1] == e[s][1]) {
            ++end;
        }
        for (std::size_t i = s; i < end; ++i) {
            for (std::size_t j = s; j < end; ++j) {
                if (i != j) {
                    topo.neighbours[static_cast<std::size_t>(e[i][2])].push_back(e[j][2]);
                }
            }
        }
        s = end;
    }
    topo.component.assign(static_cast<std::size_t>(nt), -1);
    int count = 0;
    for (int t = 0; t < nt; ++t) {
        if (topo.component[static_cast<std::size_t>(t)] >= 0) {
            continue;
        }
        std::vector<int> stack{t};
        topo.component[static_cast<std::size_t>(t)] = count;
        while (!stack.empty()) {
            const int u = stack.back();
            stack.pop_back();
            for (const int w : topo.neighbours[static_cast<std::size_t>(u)]) {
                if (topo.component[static_cast<std::size_t>(w)] < 0) {
                    topo.component[static_cast<std::size_t>(w)] = count;
                    stack.push_back(w);
                }
            }
        }
        ++count;
    }
    return topo;
}

double angleBetween(const Vec3& a, const Vec3& b) {
    return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Whether cone `outer` contains cone `inner` (up to `tol` [rad]).
bool coneContains(const NormalCone& outer, const NormalCone& inner, double tol = 1e-9) {
    return outer.halfAngle >= std::numbers::pi ||
           angleBetween(outer.axis, inner.axis) + inner.halfAngle <= outer.halfAngle + tol;
}

/// Structural invariants of a tree: each triangle in exactly one leaf, 2–3 children per inner
/// node, boxes and cones of parents containing their children's, sorted boundary lists, and
/// (when `checkBoundary`) boundary lists equal to a brute-force computation.
void expectInvariants(const SurfaceBvh& bvh, const MatX3i& f, bool checkBoundary) {
    ASSERT_FALSE(bvh.empty());
    const int nt = static_cast<int>(f.rows());
    const auto& nodes = bvh.nodes();
    std::vector<int> seen(static_cast<std::size_t>(nt), 0);
    std::vector<int> stack{bvh.root()};
    std::vector<int> trianglesOnVertex(static_cast<std::size_t>(f.maxCoeff() + 1), 0);
    for (int t = 0; t < nt; ++t) {
        std::array<int, 3> v{f(t, 0), f(t, 1), f(t, 2)};
        std::sort(v.begin(), v.end());
        for (int k = 0; k < 3; ++k) {
            if (k == 0 || v[static_cast<std::size_t>(k)] != v[static_cast<std::size_t>(k - 1)]) {
                ++trianglesOnVertex[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])];
            }
        }
    }
    while (!stack.empty()) {
        const int n = stack.back();
        stack.pop_back();
        const auto& node = nodes[static_cast<std::size_t>(n)];
        const auto& bv = bvh.boundaryVertices();
        ASSERT_LE(node.boundaryBegin, node.boundaryEnd);
        EXPECT_TRUE(std::is_sorted(bv.begin() + node.boundaryBegin, bv.begin() + node.boundaryEnd));
        EXPECT_EQ(
            std::adjacent_find(bv.begin() + node.boundaryBegin, bv.begin() + node.boundaryEnd),
            bv.begin() + node.boundaryEnd);
        if (node.isLeaf()) {
            ASSERT_LT(node.triangle, nt);
            ++seen[static_cast<std::size_t>(node.triangle)];
            for (const int c : node.children) {
                EXPECT_EQ(c, -1);
            }
            const std::vector<int> expected(bv.begin() + node.boundaryBegin,
                                            bv.begin() + node.boundaryEnd);
            EXPECT_EQ(expected, patchVertices(bvh, f, n)) << "leaf lists all its vertices";
            continue;
        }
        const int count = static_cast<int>(std::count_if(
            std::begin(node.children), std::end(node.children), [](int c) { return c >= 0; }));
        EXPECT_TRUE(count == 2 || count == 3) << "node " << n << " has " << count << " children";
        EXPECT_GE(node.children[0], 0);
        EXPECT_GE(node.children[1], 0);
        for (const int c : node.children) {
            if (c < 0) {
                continue;
            }
            const auto& child = nodes[static_cast<std::size_t>(c)];
            EXPECT_TRUE((node.box.lo.array() <= child.box.lo.array()).all() &&
                        (child.box.hi.array() <= node.box.hi.array()).all())
                << "node " << n << " does not contain child " << c;
            EXPECT_TRUE(coneContains(node.cone, child.cone))
                << "cone of node " << n << " does not contain child " << c;
            stack.push_back(c);
        }
        if (checkBoundary) {
            std::vector<int> inside(trianglesOnVertex.size(), 0);
            for (const int t : patch(bvh, n)) {
                std::array<int, 3> v{f(t, 0), f(t, 1), f(t, 2)};
                std::sort(v.begin(), v.end());
                for (int k = 0; k < 3; ++k) {
                    if (k == 0 ||
                        v[static_cast<std::size_t>(k)] != v[static_cast<std::size_t>(k - 1)]) {
                        ++inside[static_cast<std::size_t>(v[static_cast<std::size_t>(k)])];
                    }
                }
            }
            std::vector<int> expected;
            for (const int v : patchVertices(bvh, f, n)) {
                if (inside[static_cast<std::size_t>(v)] <
                    trianglesOnVertex[static_cast<std::size_t>(v)]) {
                    expected.push_back(v);
                }
            }
            EXPECT_EQ(
                std::vector<int>(bv.begin() + node.boundaryBegin, bv.begin() + node.boundaryEnd),
                expected)
                << "boundary of node " << n;
        }
    }
    for (int t = 0; t < nt; ++t) {
        EXPECT_EQ(seen[static_cast<std::size_t>(t)], 1) << "triangle " << t;
    }
}

/// Every inner node's patch is edge-connected if it lies in one component of the mesh (the
/// adjacency levels), else it is a union of whole components (joined by proximity at the top).
void expectConnectedPatches(const SurfaceBvh& bvh, const MatX3i& f) {
    const Topology topo = topology(f);
    const auto nt = static_cast<std::size_t>(f.rows());
    std::vector<int> stamp(nt, -1);
    std::vector<int> componentSize;
    for (const int c : topo.component) {
        if (static_cast<std::size_t>(c) >= componentSize.size()) {
            componentSize.resize(static_cast<std::size_t>(c) + 1, 0);
        }
        ++componentSize[static_cast<std::size_t>(c)];
    }
    const auto& nodes = bvh.nodes();
    for (std::size_t n = 0; n < nodes.size(); ++n) {
        if (nodes[n].isLeaf()) {
            continue;
        }
        const std::vector<int> tris = patch(bvh, static_cast<int>(n));
        for (const int t : tris) {
            stamp[static_cast<std::size_t>(t)] = static_cast<int>(n);
        }
        std::vector<int> components;
        for (const int t : tris) {
            components.push_back(topo.component[static_cast<std::size_t>(t)]);
        }
        std::sort(components.begin(), components.end());
        components.erase(std::unique(components.begin(), components.end()), components.end());
        if (components.size() > 1) {
            std::size_t total = 0;
            for (const int c : components) {
                total += static_cast<std::size_t>(componentSize[static_cast<std::size_t>(c)]);
            }
            EXPECT_EQ(total, tris.size()) << "node " << n << " splits a component";
            continue;
        }
        // Flood fill inside the patch from its first triangle.
        std::vector<int> queue{tris.front()};
        stamp[static_cast<std::size_t>(tris.front())] = -2;
        std::size_t reached = 1;
        while (!queue.empty()) {
            const int u = queue.back();
            queue.pop_back();
            for (const int w : topo.neighbours[static_cast<std::size_t>(u)]) {
                if (stamp[static_cast<std::size_t>(w)] == static_cast<int>(n)) {
                    stamp[static_cast<std::size_t>(w)] = -2;
                    ++reached;
                    queue.push_back(w);
                }
            }
        }
        EXPECT_EQ(reached, tris.size()) << "patch of node " << n << " is not edge-connected";
    }
}

std::vector<Vec3> normals(const TestMesh& m) {
    std::vector<Vec3> n;
    for (int t = 0; t < m.triangles.rows(); ++t) {
        n.push_back(triangleNormal(vertex(m, t, 0), vertex(m, t, 1), vertex(m, t, 2)));
    }
    return n;
}

// ---------------------------------------------------------------------------------------------

TEST(MergeCones, ContainsBothAndIsTightForRandomCones) {
    std::mt19937 rng(3);
    std::normal_distribution<double> g;
    std::uniform_real_distribution<double> angle(0.0, 1.2);
    for (int trial = 0; trial < 2000; ++trial) {
        // Every fourth pair: two triangle normals (zero half-angles); every fourth: equal
        // half-angles; else any.
        const NormalCone a{Vec3(g(rng), g(rng), g(rng)).normalized(),
                           trial % 4 == 0 ? 0.0 : angle(rng)};
        const NormalCone b{Vec3(g(rng), g(rng), g(rng)).normalized(),
                           trial % 4 < 2 ? a.halfAngle : angle(rng)};
        const NormalCone m = mergeCones(a, b);
        EXPECT_NEAR(m.axis.norm(), 1.0, 1e-14);
        EXPECT_TRUE(coneContains(m, a, 1e-10));
        EXPECT_TRUE(coneContains(m, b, 1e-10));
        const double theta = angleBetween(a.axis, b.axis);
        if (theta + b.halfAngle <= a.halfAngle) {
            EXPECT_EQ(m.halfAngle, a.halfAngle); // a contains b: a itself
        } else if (theta + a.halfAngle <= b.halfAngle) {
            EXPECT_EQ(m.halfAngle, b.halfAngle);
        } else {
            EXPECT_NEAR(m.halfAngle,
                        std::min(std::numbers::pi, 0.5 * (a.halfAngle + b.halfAngle + theta)),
                        5e-12);
        }
        EXPECT_TRUE(std::isfinite(m.halfAngle));
    }
}

TEST(MergeCones, SpecialCases) {
    const NormalCone up{Vec3::UnitZ(), 0.0};
    const NormalCone down{-Vec3::UnitZ(), 0.0};
    const NormalCone same = mergeCones(up, up);
    EXPECT_EQ(same.halfAngle, 0.0);
    EXPECT_EQ(same.axis, Vec3::UnitZ());
    const NormalCone opposite = mergeCones(up, down);
    EXPECT_GE(opposite.halfAngle,
              std::numbers::pi / 2); // never below: the default culling would cull it
    EXPECT_NEAR(opposite.halfAngle, std::numbers::pi / 2, 1e-9);
    EXPECT_NEAR(opposite.axis.dot(Vec3::UnitZ()), 0.0, 1e-12);
    EXPECT_GE(mergeCones(NormalCone{Vec3::UnitZ(), 2.0}, NormalCone{-Vec3::UnitZ(), 2.0}).halfAngle,
              std::numbers::pi);
    EXPECT_EQ(mergeCones(up, NormalCone{Vec3::UnitX(), std::numbers::pi}).halfAngle,
              std::numbers::pi);
    // Nearly parallel and nearly opposite axes, equal and unequal half-angles.
    for (const double eps : {1e-14, 1e-10, 1e-6, 1e-3}) {
        for (const double sign : {1.0, -1.0}) {
            const Vec3 axis = Vec3(eps, -0.5 * eps, sign).normalized();
            for (const auto& [ha, hb] : {std::pair{0.0, 0.0}, {0.3, 0.3}, {0.1, 0.4}}) {
                const NormalCone a{Vec3::UnitZ(), ha};
                const NormalCone b{axis, hb};
                const NormalCone m = mergeCones(a, b);
                SCOPED_TRACE(std::to_string(eps) + " " + std::to_string(sign) + " " +
                             std::to_string(hb));
                EXPECT_TRUE(coneContains(m, a, 1e-12));
                EXPECT_TRUE(coneContains(m, b, 1e-12));
                EXPECT_NEAR(m.axis.norm(), 1.0, 1e-14);
                // Nearly opposite axes fix the merged axis only to ~1e-15 / sin θ.
                const double theta = angleBetween(a.axis, b.axis);
                const double expected =
                    theta + ha <= hb ? hb : std::min(std::numbers::pi, 0.5 * (ha + hb + theta));
                EXPECT_NEAR(m.halfAngle, expected, 1e-11 + 1e-14 / std::sin(theta));
            }
        }
    }
    const NormalCone wide{Vec3::UnitZ(), 1.0};
    const NormalCone narrow{Vec3(std::sin(0.3), 0, std::cos(0.3)), 0.2};
    EXPECT_EQ(mergeCones(wide, narrow).halfAngle, 1.0);
    EXPECT_EQ(mergeCones(narrow, wide).halfAngle, 1.0);
}

TEST(SurfaceBvh, BoxQueryReturnsExactlyTheOverlappingTriangles) {
    // Against brute force on a crumpled sheet: every triangle whose own bounding box overlaps
    // the query box, and no other (leaf boxes are the triangles' boxes with no margin).
    const TestMesh m = crumpledSheet(16, 0.3, 5);
    SurfaceBvh bvh(m.triangles, m.x);
    bvh.refit(m.x, nullptr, 0.0);
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(-0.1, 1.1);
    std::uniform_real_distribution<double> size(0.0, 0.3);
    for (int q = 0; q < 50; ++q) {
        Aabb box;
        const Vec3 c(u(rng), u(rng), 0.2 * u(rng));
        box.add(c);
        box.add(c + Vec3(size(rng), size(rng), size(rng)));
        std::vector<int> got;
        bvh.query(box, got);
        std::sort(got.begin(), got.end());
        std::vector<int> expected;
        for (int f = 0; f < m.triangles.rows(); ++f) {
            Aabb t;
            for (int k = 0; k < 3; ++k) {
                t.add(m.x.row(m.triangles(f, k)).transpose());
            }
            if (t.overlaps(box)) {
                expected.push_back(f);
            }
        }
        EXPECT_EQ(got, expected) << "query " << q;
    }
}

TEST(SurfaceBvh, EmptyMesh) {
    const SurfaceBvh bvh(MatX3i(0, 3), MatX3(0, 3));
    EXPECT_TRUE(bvh.empty());
    Pairs out;
    bvh.selfOverlaps(out);
    bvh.overlaps(bvh, out);
    EXPECT_TRUE(out.empty());
    EXPECT_EQ(bvh.closestTriangle(MatX3(0, 3), Vec3::Zero(), 1.0).first, -1);
}

TEST(SurfaceBvh, SingleTriangle) {
    TestMesh m;
    m.x.resize(3, 3);
    m.x << 0, 0, 0, 1, 0, 0, 0, 1, 0;
    m.triangles.resize(1, 3);
    m.triangles << 0, 1, 2;
    const SurfaceBvh bvh(m.triangles, m.x);
    ASSERT_EQ(bvh.nodes().size(), 1u);
    EXPECT_EQ(bvh.root(), 0);
    Pairs out;
    bvh.selfOverlaps(out, {.cullingAngle = 4.0});
    EXPECT_TRUE(out.empty());
    bvh.overlaps(bvh, out);
    EXPECT_EQ(out, (Pairs{{0, 0}}));
    const auto [t, p] = bvh.closestTriangle(m.x, Vec3(0.2, 0.2, 0.5), 1.0);
    EXPECT_EQ(t, 0);
    EXPECT_NEAR(p.distance, 0.5, 1e-15);
}

TEST(SurfaceBvh, InvariantsOnGridSoupAndSphere) {
    for (const TestMesh& m : {crumpledSheet(12, 0.3, 1), randomSoup(300, 200, 1.0, 2),
                              sphereMesh(Vec3(0.1, 0.2, 0.3), 0.5, 10, 16), flatSheet(7, 0.01)}) {
        SCOPED_TRACE(std::to_string(m.triangles.rows()) + " triangles");
        const SurfaceBvh bvh(m.triangles, m.x);
        expectInvariants(bvh, m.triangles, true);
        expectConnectedPatches(bvh, m.triangles);
    }
}

TEST(SurfaceBvh, LargeGridIsBalancedAndConnected) {
    const TestMesh m = flatSheet(200, 0.01);
    const SurfaceBvh bvh(m.triangles, m.x);
    const double n = static_cast<double>(m.triangles.rows());
    const int depth = treeDepth(bvh);
    EXPECT_LE(depth, 2.0 * std::log2(n) + 2) << "depth " << depth << " for " << n << " triangles";
    expectInvariants(bvh, m.triangles, false);
    expectConnectedPatches(bvh, m.triangles);
}

TEST(SurfaceBvh, BodyMeshInvariants) {
    REQUIRE_BODY(body);
    const SurfaceBvh bvh(body->triangles, body->x);
    const double n = static_cast<double>(body->triangles.rows());
    EXPECT_LE(treeDepth(bvh), 2.0 * std::log2(n) + 2);
    expectInvariants(bvh, body->triangles, false);
    expectConnectedPatches(bvh, body->triangles);
}

TEST(SurfaceBvh, DisconnectedComponentsAreJoinedIntoOneRoot) {
    // 40 separate small sheets scattered in space.
    TestMesh m;
    std::vector<std::array<int, 3>> tris;
    std::vector<Vec3> verts;
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int s = 0; s < 40; ++s) {
        const TestMesh piece = flatSheet(s % 4 + 1, 0.05);
        const Vec3 shift(u(rng), u(rng), u(rng));
        const int base = static_cast<int>(verts.size());
        for (int i = 0; i < piece.x.rows(); ++i) {
            verts.push_back(piece.x.row(i).transpose() + shift);
        }
        for (int t = 0; t < piece.triangles.rows(); ++t) {
            tris.push_back({base + piece.triangles(t, 0), base + piece.triangles(t, 1),
                            base + piece.triangles(t, 2)});
        }
    }
    m.x.resize(static_cast<Eigen::Index>(verts.size()), 3);
    for (std::size_t i = 0; i < verts.size(); ++i) {
        m.x.row(static_cast<Eigen::Index>(i)) = verts[i].transpose();
    }
    m.triangles.resize(static_cast<Eigen::Index>(tris.size()), 3);
    for (std::size_t i = 0; i < tris.size(); ++i) {
        m.triangles.row(static_cast<Eigen::Index>(i)) << tris[i][0], tris[i][1], tris[i][2];
    }
    const SurfaceBvh bvh(m.triangles, m.x);
    expectInvariants(bvh, m.triangles, true);
    expectConnectedPatches(bvh, m.triangles);
    Pairs out;
    bvh.selfOverlaps(out, {.cullingAngle = 4.0});
    EXPECT_EQ(sorted(out), bruteSelf(leafBoxes(m)));
}

TEST(SurfaceBvh, AdjacentMatchesSharedVerticesForRandomNodePairs) {
    for (const TestMesh& m : {crumpledSheet(16, 0.3, 4), randomSoup(200, 150, 1.0, 5)}) {
        const SurfaceBvh bvh(m.triangles, m.x);
        const int nn = static_cast<int>(bvh.nodes().size());
        std::vector<int> parent(static_cast<std::size_t>(nn), -1);
        for (int n = 0; n < nn; ++n) {
            for (const int c : bvh.nodes()[static_cast<std::size_t>(n)].children) {
                if (c >= 0) {
                    parent[static_cast<std::size_t>(c)] = n;
                }
            }
        }
        std::mt19937 rng(6);
        std::uniform_int_distribution<int> pick(0, nn - 1);
        int adjacentCount = 0;
        for (int trial = 0; trial < 3000; ++trial) {
            const int a = pick(rng);
            int b = pick(rng);
            if (trial % 5 == 0) { // an ancestor of a (or a itself): patches that contain a's
                b = a;
                for (int up = pick(rng) % 4; up > 0 && parent[static_cast<std::size_t>(b)] >= 0;
                     --up) {
                    b = parent[static_cast<std::size_t>(b)];
                }
            }
            const std::vector<int> va = patchVertices(bvh, m.triangles, a);
            const std::vector<int> vb = patchVertices(bvh, m.triangles, b);
            std::vector<int> common;
            std::set_intersection(va.begin(), va.end(), vb.begin(), vb.end(),
                                  std::back_inserter(common));
            EXPECT_EQ(bvh.adjacent(a, b), !common.empty()) << "nodes " << a << ", " << b;
            EXPECT_EQ(bvh.adjacent(a, b), bvh.adjacent(b, a));
            adjacentCount += common.empty() ? 0 : 1;
        }
        EXPECT_GT(adjacentCount, 100);
        EXPECT_LT(adjacentCount, 2900);
    }
}

TEST(SurfaceBvh, RefitConesContainNormalsAndDegenerateIsUnknown) {
    TestMesh m = crumpledSheet(10, 0.4, 8);
    // Collapse triangle 5 onto a line.
    const int a = m.triangles(5, 0);
    const int b = m.triangles(5, 1);
    const int c = m.triangles(5, 2);
    m.x.row(c) = 0.5 * (m.x.row(a) + m.x.row(b));
    SurfaceBvh bvh(m.triangles, m.x);
    MatX3 x1 = m.x;
    x1.col(2).array() += 0.05 * x1.col(0).array().square();
    bvh.refit(m.x, &x1, 0.0);
    const auto& nodes = bvh.nodes();
    const auto leaf5 = std::find_if(nodes.begin(), nodes.end(),
                                    [](const SurfaceBvh::Node& n) { return n.triangle == 5; });
    ASSERT_NE(leaf5, nodes.end());
    EXPECT_EQ(leaf5->cone.halfAngle, std::numbers::pi);
    for (const auto& node : nodes) {
        EXPECT_NEAR(node.cone.axis.norm(), 1.0, 1e-13);
    }
    for (std::size_t n = 0; n < nodes.size(); ++n) {
        for (const int t : patch(bvh, static_cast<int>(n))) {
            if (t == 5) {
                EXPECT_GE(nodes[n].cone.halfAngle, std::numbers::pi)
                    << "a node with a degenerate triangle";
                continue;
            }
            for (const MatX3* x : std::array<const MatX3*, 2>{&m.x, &x1}) {
                const Vec3 normal =
                    triangleNormal(x->row(m.triangles(t, 0)), x->row(m.triangles(t, 1)),
                                   x->row(m.triangles(t, 2)));
                EXPECT_TRUE(coneContains(nodes[n].cone, NormalCone{normal, 0.0}))
                    << "node " << n << " triangle " << t;
            }
        }
    }
    expectInvariants(bvh, m.triangles, false);
}

TEST(SurfaceBvh, OverlapsMatchBruteForceOnRandomSoups) {
    for (std::uint32_t seed : {11u, 12u, 13u}) {
        const TestMesh a = randomSoup(250, 200, 1.0, seed);
        TestMesh b = randomSoup(180, 100, 0.6, seed + 100);
        b.x.array() += 0.5;
        const SurfaceBvh ta(a.triangles, a.x);
        const SurfaceBvh tb(b.triangles, b.x);
        Pairs out;
        ta.overlaps(tb, out);
        const Pairs expected = bruteCross(leafBoxes(a), leafBoxes(b));
        EXPECT_FALSE(expected.empty());
        EXPECT_EQ(sorted(out), expected) << "seed " << seed;
    }
}

TEST(SurfaceBvh, OverlapsMatchBruteForceSheetVersusSphere) {
    const TestMesh sheet = crumpledSheet(40, 0.2, 21);
    const TestMesh sphere = sphereMesh(Vec3(0.5, 0.45, 0.0), 0.3, 16, 24);
    SurfaceBvh ts(sheet.triangles, sheet.x);
    SurfaceBvh tb(sphere.triangles, sphere.x);
    Pairs out;
    ts.overlaps(tb, out);
    Pairs expected = bruteCross(leafBoxes(sheet), leafBoxes(sphere));
    EXPECT_GT(expected.size(), 100u);
    EXPECT_EQ(sorted(out), expected);

    // Swept (x1 given) with a margin, the sphere offset by a vertexOffset in a larger array.
    MatX3 x1 = sheet.x;
    std::mt19937 rng(22);
    std::uniform_real_distribution<double> u(-0.02, 0.02);
    for (int i = 0; i < x1.rows(); ++i) {
        x1.row(i) += Vec3(u(rng), u(rng), 0.05 + u(rng)).transpose();
    }
    ts.refit(sheet.x, &x1, 0.004);
    const int offset = 7;
    MatX3 all = MatX3::Random(offset + sphere.x.rows(), 3);
    all.bottomRows(sphere.x.rows()) = sphere.x;
    tb.refit(all, nullptr, 0.002, offset);
    out.clear();
    ts.overlaps(tb, out);
    Pairs sweptExpected =
        bruteCross(leafBoxes(sheet, &x1, 0.004), leafBoxes(sphere, nullptr, 0.002));
    EXPECT_GT(sweptExpected.size(), expected.size());
    EXPECT_EQ(sorted(out), sweptExpected);
    // Reversed roles.
    out.clear();
    tb.overlaps(ts, out);
    for (auto& [p, q] : sweptExpected) {
        std::swap(p, q);
    }
    EXPECT_EQ(sorted(out), sorted(sweptExpected));
}

TEST(SurfaceBvh, OverlapsMatchBruteForceBodyVersusSheet) {
    REQUIRE_BODY(body);
    // A horizontal sheet through the chest, jittered.
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const TestMesh sheet = gridSheet(40, 40, [&](int i, int j) {
        return Vec3(-0.4 + 0.02 * i, 1.3 + 0.01 * u(rng), -0.4 + 0.02 * j);
    });
    SurfaceBvh tb(body->triangles, body->x);
    const SurfaceBvh ts(sheet.triangles, sheet.x);
    Pairs out;
    tb.overlaps(ts, out);
    const Pairs expected = bruteCross(leafBoxes(*body), leafBoxes(sheet));
    EXPECT_GT(expected.size(), 100u);
    EXPECT_EQ(sorted(out), expected);
    // With a margin.
    tb.refit(body->x, nullptr, 0.01);
    out.clear();
    tb.overlaps(ts, out);
    EXPECT_EQ(sorted(out), bruteCross(leafBoxes(*body, nullptr, 0.01), leafBoxes(sheet)));
}

TEST(SurfaceBvh, SelfOverlapsWithoutCullingMatchBruteForce) {
    for (const TestMesh& m :
         {crumpledSheet(30, 0.3, 41), crumpledSheet(20, 1.5, 42), randomSoup(300, 200, 1.0, 43)}) {
        SurfaceBvh bvh(m.triangles, m.x);
        Pairs out;
        bvh.selfOverlaps(out, {.cullingAngle = 4.0});
        const Pairs expected = bruteSelf(leafBoxes(m));
        EXPECT_GT(expected.size(), static_cast<std::size_t>(m.triangles.rows()));
        EXPECT_EQ(sorted(out), expected);
        // Swept with a margin.
        MatX3 x1 = m.x;
        x1.col(2).array() += 0.03 * x1.col(0).array();
        bvh.refit(m.x, &x1, 0.003);
        out.clear();
        bvh.selfOverlaps(out, {.cullingAngle = 4.0});
        EXPECT_EQ(sorted(out), bruteSelf(leafBoxes(m, &x1, 0.003)));
    }
}

TEST(SurfaceBvh, TraversalsGiveTheSameOrderForAnyThreadCount) {
    // Large enough for the parallel traversal (split into tasks, outputs concatenated in the
    // depth-first order): the pairs and their order must not depend on the threads, or
    // detection and everything after it would not be reproducible.
    const TestMesh m = crumpledSheet(60, 1.0, 45);
    const TestMesh sphere = sphereMesh(Vec3(0.5, 0.5, 0.0), 0.3, 24, 32);
    SurfaceBvh bvh(m.triangles, m.x);
    MatX3 x1 = m.x;
    x1.col(2).array() += 0.02 * x1.col(0).array();
    bvh.refit(m.x, &x1, 0.003);
    const SurfaceBvh other(sphere.triangles, sphere.x);
    const int threads = threadCount();
    std::vector<std::array<Pairs, 3>> runs;
    for (int t : {1, 2, 3}) {
        setThreadCount(t);
        std::array<Pairs, 3> r;
        bvh.selfOverlaps(r[0]);
        bvh.selfOverlaps(r[1], {.cullingAngle = 4.0});
        bvh.overlaps(other, r[2]);
        runs.push_back(r);
    }
    setThreadCount(threads);
    EXPECT_GT(runs[0][0].size(), 1000u);
    EXPECT_GT(runs[0][1].size(), runs[0][0].size());
    EXPECT_GT(runs[0][2].size(), 1000u);
    EXPECT_EQ(sorted(runs[0][1]), bruteSelf(leafBoxes(m, &x1, 0.003)));
    for (std::size_t k = 0; k < 3; ++k) {
        EXPECT_EQ(runs[1][k], runs[0][k]) << "query " << k;
        EXPECT_EQ(runs[2][k], runs[0][k]) << "query " << k;
    }
}

TEST(SurfaceBvh, SelfOverlapsWithCullingIsSubsetOfBruteForce) {
    const TestMesh m = crumpledSheet(30, 1.0, 44);
    const SurfaceBvh bvh(m.triangles, m.x);
    Pairs out;
    bvh.selfOverlaps(out);
    const Pairs all = bruteSelf(leafBoxes(m));
    const Pairs found = sorted(out);
    EXPECT_EQ(std::adjacent_find(found.begin(), found.end()), found.end()) << "duplicate pair";
    EXPECT_TRUE(std::includes(all.begin(), all.end(), found.begin(), found.end()));
    EXPECT_LT(found.size(), all.size());
    for (const auto& [a, b] : found) {
        EXPECT_LT(a, b);
    }
}

TEST(SurfaceBvh, SelfOverlapsOfFlatSheetAreCulled) {
    const TestMesh m = flatSheet(60, 0.01);
    SurfaceBvh bvh(m.triangles, m.x);
    bvh.refit(m.x, nullptr, 0.002);
    EXPECT_EQ(bvh.nodes()[static_cast<std::size_t>(bvh.root())].cone.halfAngle, 0.0);
    Pairs out;
    bvh.selfOverlaps(out);
    EXPECT_TRUE(out.empty());
    bvh.selfOverlaps(out, {.cullingAngle = 4.0});
    EXPECT_EQ(sorted(out), bruteSelf(leafBoxes(m, nullptr, 0.002)));
}

TEST(SurfaceBvh, SelfOverlapsOfFoldedSheetKeepOppositeLayers) {
    // A U: bottom layer z = 0 (cells i < n), a 1 mm wall at x = n·h, top layer z = 1 mm folded
    // back over the bottom; grid spacing 10 mm, margin 2 mm.
    const int n = 20;
    const int ny = 12;
    const double h = 0.01;
    const double gap = 0.001;
    const TestMesh m = gridSheet(2 * n + 1, ny, [&](int i, int j) {
        return i <= n ? Vec3(i * h, j * h, 0.0) : Vec3((2 * n + 1 - i) * h, j * h, gap);
    });
    SurfaceBvh bvh(m.triangles, m.x);
    const double margin = 0.002;
    bvh.refit(m.x, nullptr, margin);
    Pairs out;
    bvh.selfOverlaps(out);
    const Pairs found = sorted(out);
    const Pairs all = bruteSelf(leafBoxes(m, nullptr, margin));
    EXPECT_EQ(std::adjacent_find(found.begin(), found.end()), found.end()) << "duplicate pair";
    EXPECT_TRUE(std::includes(all.begin(), all.end(), found.begin(), found.end()));
    EXPECT_LT(found.size(), all.size()) << "culling removed nothing";
    const std::vector<Vec3> normal = normals(m);
    const auto layer = [&](int t) {
        double z = 0;
        for (int k = 0; k < 3; ++k) {
            z += vertex(m, t, k).z();
        }
        return z == 0 ? 0 : (z == 3 * gap ? 1 : 2); // bottom, top, wall
    };
    int crossLayer = 0;
    for (const auto& [a, b] : all) {
        const bool isFound = std::binary_search(found.begin(), found.end(), std::pair{a, b});
        if (shareVertex(m, a, b)) {
            continue;
        }
        const double cosine =
            normal[static_cast<std::size_t>(a)].dot(normal[static_cast<std::size_t>(b)]);
        if ((layer(a) == 0 && layer(b) == 1) || (layer(a) == 1 && layer(b) == 0)) {
            ++crossLayer;
            EXPECT_TRUE(isFound) << "layers pair " << a << ", " << b << " culled";
        }
        // Culling only removes pairs of a patch that faces one way (same layer, or a layer and
        // the wall): never two triangles facing each other.
        if (!isFound) {
            EXPECT_GE(cosine, -1e-9) << "pair " << a << ", " << b;
        }
    }
    EXPECT_GE(crossLayer, 2 * n * ny * 2);
}

TEST(SurfaceBvh, ClosestTriangleMatchesBruteForce) {
    std::vector<TestMesh> meshes{crumpledSheet(25, 0.5, 51), sphereMesh(Vec3::Zero(), 0.4, 12, 20),
                                 randomSoup(150, 120, 1.0, 52)};
    if (const TestMesh* body = bodyMesh()) {
        meshes.push_back(*body);
    }
    std::mt19937 rng(53);
    for (const TestMesh& m : meshes) {
        SurfaceBvh bvh(m.triangles, m.x);
        bvh.refit(m.x, nullptr, 0.001); // margins allowed
        Aabb bounds;
        for (int i = 0; i < m.x.rows(); ++i) {
            bounds.add(Vec3(m.x.row(i).transpose()));
        }
        std::uniform_real_distribution<double> u(0.0, 1.0);
        int hits = 0;
        for (int trial = 0; trial < 300; ++trial) {
            const Vec3 r(u(rng), u(rng), u(rng));
            const Vec3 size = bounds.hi - bounds.lo;
            const Vec3 p = bounds.lo - 0.2 * size + (1.4 * size.array() * r.array()).matrix();
            double bruteDistance = std::numeric_limits<double>::infinity();
            for (int t = 0; t < m.triangles.rows(); ++t) {
                bruteDistance =
                    std::min(bruteDistance, closestPointOnTriangle(p, vertex(m, t, 0),
                                                                   vertex(m, t, 1), vertex(m, t, 2))
                                                .distance);
            }
            const double maxDistance =
                trial % 2 == 0 ? std::numeric_limits<double>::infinity() : 0.1 * size.norm();
            const auto [t, cp] = bvh.closestTriangle(m.x, p, maxDistance);
            if (bruteDistance > maxDistance) {
                EXPECT_EQ(t, -1);
                continue;
            }
            ++hits;
            ASSERT_GE(t, 0);
            EXPECT_NEAR(cp.distance, bruteDistance, 1e-12);
            const TrianglePoint check =
                closestPointOnTriangle(p, vertex(m, t, 0), vertex(m, t, 1), vertex(m, t, 2));
            EXPECT_NEAR(check.distance, cp.distance, 1e-12);
            EXPECT_NEAR((cp.point - p).norm(), cp.distance, 1e-12);
        }
        EXPECT_GT(hits, 150);
    }
}

TEST(SurfaceBvh, ClosestTriangleWithVertexOffset) {
    const TestMesh m = sphereMesh(Vec3(1, 2, 3), 0.5, 8, 12);
    const int offset = 5;
    MatX3 all = MatX3::Zero(offset + m.x.rows(), 3);
    all.bottomRows(m.x.rows()) = m.x;
    SurfaceBvh bvh(m.triangles, m.x);
    bvh.refit(all, nullptr, 0.0, offset);
    const auto [t, cp] = bvh.closestTriangle(all, Vec3(1, 2, 4), 10.0, offset);
    ASSERT_GE(t, 0);
    EXPECT_NEAR(cp.distance, 0.5, 1e-12); // the north pole
    EXPECT_EQ(bvh.closestTriangle(all, Vec3(1, 2, 4), 0.4, offset).first, -1);
}

} // namespace
} // namespace atelier::sim
