#include "sim/collision/bvh.h"

#include "sim/collision/bvh_builder.h"
#include "sim/core/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>

namespace atelier::sim {

namespace {

constexpr double PI = std::numbers::pi;
/// Outward rounding of a merged cone's half-angle [rad], so that rounding never leaves a normal
/// outside it (two exactly opposite flat layers must give a cone of at least π/2, never π/2
/// minus an ulp, which the default culling angle would cull).
constexpr double CONE_SLACK = 1e-12;
/// Nearly opposite axes (|a + b|, or the sine of the angle between them, below NEAR_OPPOSITE)
/// fix the merged axis only to about AXIS_ROUNDING over that length [rad]: the merged
/// half-angle is widened by that bound (above NEAR_OPPOSITE, CONE_SLACK covers it).
constexpr double NEAR_OPPOSITE = 1e-3;
constexpr double AXIS_ROUNDING = 8 * std::numeric_limits<double>::epsilon();
/// A triangle whose angle has a sine below this is degenerate: its normal is unknown.
constexpr double DEGENERATE_SINE = 1e-10;

/// Cone of a triangle's normal: zero half-angle around the unit normal, or "any direction"
/// (half-angle π) when the triangle is degenerate up to rounding (the sine of its angle at `a`
/// below DEGENERATE_SINE), whose computed normal would be noise.
NormalCone triangleCone(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 e1 = b - a;
    const Vec3 e2 = c - a;
    const Vec3 n = e1.cross(e2);
    const double len2 = n.squaredNorm();
    if (!(len2 > DEGENERATE_SINE * DEGENERATE_SINE * e1.squaredNorm() * e2.squaredNorm())) {
        return {Vec3::UnitZ(), PI};
    }
    return {n / std::sqrt(len2), 0.0};
}

/// Polynomial Σ c[k] w^k of degree 10 by Estrin's scheme (short dependency chains).
inline double estrin10(const std::array<double, 11>& c, double w) {
    const double w2 = w * w;
    const double w4 = w2 * w2;
    const double w8 = w4 * w4;
    const double q0 = c[0] + c[1] * w;
    const double q1 = c[2] + c[3] * w;
    const double q2 = c[4] + c[5] * w;
    const double q3 = c[6] + c[7] * w;
    const double q4 = c[8] + c[9] * w;
    return (q0 + q1 * w2) + (q2 + q3 * w2) * w4 + (q4 + c[10] * w2) * w8;
}

/// Polynomial Σ c[k] w^k of degree 7 by Estrin's scheme.
inline double estrin7(const std::array<double, 8>& c, double w) {
    const double w2 = w * w;
    const double w4 = w2 * w2;
    return (c[0] + c[1] * w) + (c[2] + c[3] * w) * w2 +
           ((c[4] + c[5] * w) + (c[6] + c[7] * w) * w2) * w4;
}

/// atan(z) for |z| <= tan(π/12) by its Taylor series to z²¹ (truncation error < 1e-14).
inline double atanSmall(double z) {
    // (−1)^k / (2k+1), k = 0..10
    constexpr std::array<double, 11> C = {1.0,      -1.0 / 3,  1.0 / 5,  -1.0 / 7,
                                          1.0 / 9,  -1.0 / 11, 1.0 / 13, -1.0 / 15,
                                          1.0 / 17, -1.0 / 19, 1.0 / 21};
    return z * estrin10(C, z * z);
}

/// Angle of the direction (c, s) with s >= 0, in [0, π]: std::atan2(s, c) to ~1e-14 [rad],
/// with one division (refit merges a cone per node; libm's atan2 and sincos dominated it).
inline double upperAngle(double s, double c) {
    constexpr double SQRT3 = 1.7320508075688772;
    constexpr double TAN_PI_12 = 0.2679491924311227; // 2 − √3
    // Reduce to t = lo / hi ∈ [0, 1], then to z = tan(atan t − π/6) when t > tan(π/12).
    const double ac = std::abs(c);
    const bool swap = s > ac;
    const double lo = swap ? ac : s;
    const double hi = swap ? s : ac;
    const bool shift = lo > TAN_PI_12 * hi;
    const double num = shift ? SQRT3 * lo - hi : lo;
    const double den = shift ? SQRT3 * hi + lo : hi;
    double angle = (shift ? PI / 6 : 0.0) + atanSmall(den > 0 ? num / den : 0.0);
    if (swap) {
        angle = PI / 2 - angle;
    }
    return c < 0 ? PI - angle : angle;
}

/// sin and cos of r in [0, π] by Taylor series on [0, π/4] (truncation error < 1e-16).
inline void sinCos(double r, double& sine, double& cosine) {
    const bool negateCos = r > PI / 2;
    if (negateCos) {
        r = PI - r;
    }
    const bool swap = r > PI / 4;
    if (swap) {
        r = PI / 2 - r;
    }
    // sin r = r Σ (−r²)^k / (2k+1)!, cos r = Σ (−r²)^k / (2k)!, k = 0..7.
    constexpr std::array<double, 8> S = {
        1.0,          -1.0 / 6,        1.0 / 120,          -1.0 / 5040,
        1.0 / 362880, -1.0 / 39916800, 1.0 / 6227020800.0, -1.0 / 1307674368000.0};
    constexpr std::array<double, 8> C = {
        1.0,         -0.5,           1.0 / 24,        -1.0 / 720,
        1.0 / 40320, -1.0 / 3628800, 1.0 / 479001600, -1.0 / 87178291200.0};
    const double r2 = r * r;
    const double s = r * estrin7(S, r2);
    const double c = estrin7(C, r2);
    sine = swap ? c : s;
    cosine = swap ? s : c;
    if (negateCos) {
        cosine = -cosine;
    }
}

/// mergeCones (defined here to be inlined into refit and the self query).
inline NormalCone mergeConesInline(const NormalCone& a, const NormalCone& b) {
    if (a.halfAngle >= PI) {
        return a;
    }
    if (b.halfAngle >= PI) {
        return b;
    }
    if (a.axis == b.axis) { // common inside flat patches
        return a.halfAngle >= b.halfAngle ? a : b;
    }
    if (a.halfAngle == b.halfAngle) { // e.g. two triangles: the axis bisects, no rotation
        const Vec3 sum = a.axis + b.axis;
        const double sumNorm = sum.norm();
        // θ = 2 atan(|a − b| / |a + b|); half = θ/2 + θa
        double half = upperAngle((a.axis - b.axis).norm(), sumNorm) + a.halfAngle + CONE_SLACK;
        if (sumNorm > 0 && sumNorm < NEAR_OPPOSITE) {
            half += AXIS_ROUNDING / sumNorm; // the direction of a short a + b is inexact
        }
        if (half >= PI) {
            return {a.axis, PI};
        }
        return {sumNorm > 0 ? Vec3(sum / sumNorm) : Vec3(a.axis.unitOrthogonal()), half};
    }
    const double cosTheta = a.axis.dot(b.axis);
    const Vec3 perpendicular = b.axis - cosTheta * a.axis;
    const double sinTheta = perpendicular.norm();
    const double theta = upperAngle(sinTheta, cosTheta); // angle between the axes
    if (theta + b.halfAngle <= a.halfAngle) {
        return a;
    }
    if (theta + a.halfAngle <= b.halfAngle) {
        return b;
    }
    double half = 0.5 * (a.halfAngle + b.halfAngle + theta) + CONE_SLACK;
    if (cosTheta < 0 && sinTheta > 0 && sinTheta < NEAR_OPPOSITE) {
        half += AXIS_ROUNDING / sinTheta; // the direction of a short perpendicular is inexact
    }
    if (half >= PI) {
        return {a.axis, PI};
    }
    // Rotate a's axis towards b's on their great circle by (θb + θ − θa)/2 ∈ (0, θ). The result
    // is a unit vector up to rounding (a few ulps, far below CONE_SLACK): not renormalised.
    double sine = 0;
    double cosine = 1;
    sinCos(0.5 * (b.halfAngle + theta - a.halfAngle), sine, cosine);
    if (sinTheta > 0) {
        return {cosine * a.axis + (sine / sinTheta) * perpendicular, half};
    }
    return {cosine * a.axis + sine * a.axis.unitOrthogonal(), half}; // opposite axes
}

/// Box and cone of a leaf: its triangle at x0 (∪ x1) grown by margin.
void refitLeaf(SurfaceBvh::Node& node, const MatX3i& triangles, const MatX3& x0, const MatX3* x1,
               double margin, int vertexOffset) {
    const int i0 = vertexOffset + triangles(node.triangle, 0);
    const int i1 = vertexOffset + triangles(node.triangle, 1);
    const int i2 = vertexOffset + triangles(node.triangle, 2);
    const Vec3 a = x0.row(i0);
    const Vec3 b = x0.row(i1);
    const Vec3 c = x0.row(i2);
    Aabb box;
    box.lo = a.cwiseMin(b).cwiseMin(c);
    box.hi = a.cwiseMax(b).cwiseMax(c);
    NormalCone cone = triangleCone(a, b, c); // π when degenerate: never culled
    if (x1 != nullptr) {
        const Vec3 a1 = x1->row(i0);
        const Vec3 b1 = x1->row(i1);
        const Vec3 c1 = x1->row(i2);
        box.lo = box.lo.cwiseMin(a1).cwiseMin(b1).cwiseMin(c1);
        box.hi = box.hi.cwiseMax(a1).cwiseMax(b1).cwiseMax(c1);
        cone = mergeConesInline(cone, triangleCone(a1, b1, c1));
    }
    box.lo.array() -= margin;
    box.hi.array() += margin;
    node.box = box;
    node.cone = cone;
}

} // namespace

NormalCone mergeCones(const NormalCone& a, const NormalCone& b) {
    return mergeConesInline(a, b);
}

SurfaceBvh::SurfaceBvh(const MatX3i& triangles, const MatX3& x) : m_triangles(triangles) {
    if (m_triangles.rows() == 0) {
        return;
    }
    BuiltSurfaceTree tree = buildSurfaceTree(m_triangles, x);
    m_nodes = std::move(tree.nodes);
    m_boundary = std::move(tree.boundary);
    storeDepthFirst(tree.root);
    refit(x, nullptr, 0.0);
}

void SurfaceBvh::storeDepthFirst(int root) {
    const std::size_t nn = m_nodes.size();
    std::vector<int> order; // pre-order, first child first
    order.reserve(nn);
    std::vector<int> stack{root};
    while (!stack.empty()) {
        const int n = stack.back();
        stack.pop_back();
        order.push_back(n);
        const Node& node = m_nodes[static_cast<std::size_t>(n)];
        for (int k = 2; k >= 0; --k) {
            if (node.children[k] >= 0) {
                stack.push_back(node.children[k]);
            }
        }
    }
    std::vector<int> newIndex(nn, -1);
    for (std::size_t i = 0; i < nn; ++i) {
        newIndex[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
    }
    std::vector<Node> nodes(nn);
    std::vector<int> boundary;
    boundary.reserve(m_boundary.size());
    for (std::size_t i = 0; i < nn; ++i) {
        const Node& old = m_nodes[static_cast<std::size_t>(order[i])];
        Node& node = nodes[i];
        node = old;
        for (int& c : node.children) {
            c = c >= 0 ? newIndex[static_cast<std::size_t>(c)] : -1;
        }
        node.boundaryBegin = static_cast<int>(boundary.size());
        boundary.insert(boundary.end(), m_boundary.begin() + old.boundaryBegin,
                        m_boundary.begin() + old.boundaryEnd);
        node.boundaryEnd = static_cast<int>(boundary.size());
    }
    m_nodes.swap(nodes);
    m_boundary.swap(boundary);
    m_root = 0;
    // Subtree ends, children (later in pre-order) first.
    m_subtreeEnd.assign(nn, 0);
    for (std::size_t n = nn; n-- > 0;) {
        int end = static_cast<int>(n) + 1;
        for (const int c : m_nodes[n].children) {
            if (c >= 0) {
                end = std::max(end, m_subtreeEnd[static_cast<std::size_t>(c)]);
            }
        }
        m_subtreeEnd[n] = end;
    }
}

void SurfaceBvh::refit(const MatX3& x0, const MatX3* x1, double margin, int vertexOffset) {
    if (empty()) {
        return;
    }
    // Children come after their parent: a reverse scan of a subtree's range refits it.
    const auto refitRange = [&](int first, int end) {
        for (int n = end; n-- > first;) {
            Node& node = m_nodes[static_cast<std::size_t>(n)];
            if (node.isLeaf()) {
                refitLeaf(node, m_triangles, x0, x1, margin, vertexOffset);
                continue;
            }
            const Node& c0 = m_nodes[static_cast<std::size_t>(node.children[0])];
            const Node& c1 = m_nodes[static_cast<std::size_t>(node.children[1])];
            Aabb box = c0.box.merged(c1.box);
            NormalCone cone = mergeConesInline(c0.cone, c1.cone);
            if (node.children[2] >= 0) {
                const Node& c2 = m_nodes[static_cast<std::size_t>(node.children[2])];
                box.add(c2.box);
                cone = mergeConesInline(cone, c2.cone);
            }
            node.box = box;
            node.cone = cone;
        }
    };
    const auto nodeCount = static_cast<std::int64_t>(m_nodes.size());
    if (threadCount() <= 1 || nodeCount < PARALLEL_GRAIN) {
        refitRange(0, static_cast<int>(nodeCount));
        return;
    }
    // In parallel: disjoint subtrees of at most `limit` nodes, then, serially, the few nodes
    // above them (which come before their subtrees, so a reverse scan sees them last).
    const std::int64_t limit = std::max<std::int64_t>(256, nodeCount / (16 * threadCount()));
    std::vector<int> subtrees;
    std::vector<int> top;
    std::vector<int> stack{m_root};
    while (!stack.empty()) {
        const int n = stack.back();
        stack.pop_back();
        if (m_subtreeEnd[static_cast<std::size_t>(n)] - n <= limit) {
            subtrees.push_back(n);
            continue;
        }
        top.push_back(n);
        for (const int c : m_nodes[static_cast<std::size_t>(n)].children) {
            if (c >= 0) {
                stack.push_back(c);
            }
        }
    }
    const auto subtreeCount = static_cast<std::int64_t>(subtrees.size());
    // In parallel when there are many nodes; the loop runs over the subtrees holding them.
    parallelForEach(subtreeCount, nodeCount >= PARALLEL_GRAIN, [&](std::int64_t k) {
        const int n = subtrees[static_cast<std::size_t>(k)];
        refitRange(n, m_subtreeEnd[static_cast<std::size_t>(n)]);
    });
    std::sort(top.begin(), top.end());
    for (auto it = top.rbegin(); it != top.rend(); ++it) {
        refitRange(*it, *it + 1);
    }
}

bool SurfaceBvh::adjacent(int a, int b) const {
    if ((a <= b && b < m_subtreeEnd[static_cast<std::size_t>(a)]) ||
        (b <= a && a < m_subtreeEnd[static_cast<std::size_t>(b)])) {
        return true; // one patch contains the other
    }
    const Node& na = m_nodes[static_cast<std::size_t>(a)];
    const Node& nb = m_nodes[static_cast<std::size_t>(b)];
    const int* p = m_boundary.data() + na.boundaryBegin;
    const int* pEnd = m_boundary.data() + na.boundaryEnd;
    const int* q = m_boundary.data() + nb.boundaryBegin;
    const int* qEnd = m_boundary.data() + nb.boundaryEnd;
    while (p != pEnd && q != qEnd) {
        if (*p < *q) {
            ++p;
        } else if (*q < *p) {
            ++q;
        } else {
            return true;
        }
    }
    return false;
}

void SurfaceBvh::query(const Aabb& box, std::vector<int>& out) const {
    if (empty()) {
        return;
    }
    std::vector<int> stack;
    stack.reserve(64);
    stack.push_back(m_root);
    while (!stack.empty()) {
        const Node& node = m_nodes[static_cast<std::size_t>(stack.back())];
        stack.pop_back();
        if (!node.box.overlaps(box)) {
            continue;
        }
        if (node.isLeaf()) {
            out.push_back(node.triangle);
            continue;
        }
        for (const int c : node.children) {
            if (c >= 0) {
                stack.push_back(c);
            }
        }
    }
}

namespace {

using Task = std::pair<int, int>;

/// Pairs a traversal gives, in exactly the order of one depth-first pass with a LIFO stack,
/// computed in parallel. `expand(task, out, children)` processes one task: it appends the
/// triangle pair it finds to `out`, or pushes the tasks under it to `children` (the order the
/// stack would take them: the last is taken first), or neither (culled).
/// With the stack [t0 .. tk] the pass outputs DFS(tk), ..., DFS(t0); so the root is replaced,
/// level by level, by its tasks in that output order until there are enough to share among
/// the threads, and each task is then descended on its own and the outputs are concatenated.
template <class Expand>
void orderedTraversal(const Task& root, bool parallel, std::vector<std::pair<int, int>>& out,
                      const Expand& expand) {
    constexpr std::size_t ENOUGH_TASKS = 256;
    std::vector<Task> tasks{root};
    std::vector<Task> children;
    std::vector<std::pair<int, int>> found;
    if (parallel) {
        std::vector<Task> next;
        bool expanded = true;
        while (expanded && tasks.size() < ENOUGH_TASKS) {
            expanded = false;
            next.clear();
            for (const Task& t : tasks) {
                children.clear();
                found.clear();
                expand(t, found, children);
                if (!found.empty()) {
                    next.push_back(t); // a leaf pair: gives the same pair again below
                } else {
                    next.insert(next.end(), children.rbegin(), children.rend());
                    expanded = true;
                }
            }
            tasks.swap(next);
        }
    }
    const std::int64_t count = static_cast<std::int64_t>(tasks.size());
    // Buffers kept per thread between calls: several traversals run every step.
    // (The calling thread's outputs, by reference: inside the parallel loop the name would
    // mean each worker's own.)
    thread_local std::vector<std::vector<std::pair<int, int>>> callerOutputs;
    std::vector<std::vector<std::pair<int, int>>>& outputs = callerOutputs;
    if (outputs.size() < tasks.size()) {
        outputs.resize(tasks.size());
    }
    parallelForEach(count, parallel && count > 1, [&](std::int64_t i) {
        thread_local std::vector<Task> stack;
        stack.assign(1, tasks[static_cast<std::size_t>(i)]);
        std::vector<std::pair<int, int>>& o = outputs[static_cast<std::size_t>(i)];
        o.clear();
        while (!stack.empty()) {
            const Task t = stack.back();
            stack.pop_back();
            expand(t, o, stack);
        }
    });
    for (std::int64_t i = 0; i < count; ++i) {
        const auto& o = outputs[static_cast<std::size_t>(i)];
        out.insert(out.end(), o.begin(), o.end());
    }
}

} // namespace

void SurfaceBvh::overlaps(const SurfaceBvh& other, std::vector<std::pair<int, int>>& out) const {
    if (empty() || other.empty() ||
        !m_nodes[static_cast<std::size_t>(m_root)].box.overlaps(
            other.m_nodes[static_cast<std::size_t>(other.m_root)].box)) {
        return;
    }
    const auto expand = [&](const Task& task, std::vector<std::pair<int, int>>& found,
                            std::vector<Task>& stack) {
        const auto [i, j] = task;
        const Node& a = m_nodes[static_cast<std::size_t>(i)];
        const Node& b = other.m_nodes[static_cast<std::size_t>(j)];
        if (a.isLeaf() && b.isLeaf()) {
            found.emplace_back(a.triangle, b.triangle);
            return;
        }
        // Descend into the larger node (a leaf cannot be descended).
        if (b.isLeaf() || (!a.isLeaf() && a.box.surfaceArea() >= b.box.surfaceArea())) {
            for (const int c : a.children) {
                if (c >= 0 && m_nodes[static_cast<std::size_t>(c)].box.overlaps(b.box)) {
                    stack.emplace_back(c, j);
                }
            }
        } else {
            for (const int c : b.children) {
                if (c >= 0 && other.m_nodes[static_cast<std::size_t>(c)].box.overlaps(a.box)) {
                    stack.emplace_back(i, c);
                }
            }
        }
    };
    const bool parallel =
        static_cast<std::int64_t>(m_nodes.size() + other.m_nodes.size()) >= PARALLEL_GRAIN;
    orderedTraversal({m_root, other.m_root}, parallel, out, expand);
}

void SurfaceBvh::selfOverlaps(std::vector<std::pair<int, int>>& out,
                              const SelfQueryOptions& options) const {
    if (empty()) {
        return;
    }
    // Every cone has halfAngle <= π, so a threshold above π would cull everything: it means
    // "no culling" instead (the documented brute-force setting).
    const bool culling = options.cullingAngle <= PI;
    const double cullingAngle = options.cullingAngle;
    // A task is a node against itself (second = -1) or two disjoint nodes whose boxes overlap.
    const auto expand = [&](const Task& task, std::vector<std::pair<int, int>>& found,
                            std::vector<Task>& stack) {
        const auto [i, j] = task;
        const Node& a = m_nodes[static_cast<std::size_t>(i)];
        if (j < 0) {
            if (a.isLeaf() || (culling && a.connected && a.cone.halfAngle < cullingAngle)) {
                return; // a flat enough patch cannot fold onto itself
            }
            for (int k = 0; k < 3 && a.children[k] >= 0; ++k) {
                const int ck = a.children[k];
                stack.emplace_back(ck, -1);
                for (int l = k + 1; l < 3 && a.children[l] >= 0; ++l) {
                    const int cl = a.children[l];
                    if (m_nodes[static_cast<std::size_t>(ck)].box.overlaps(
                            m_nodes[static_cast<std::size_t>(cl)].box)) {
                        stack.emplace_back(ck, cl);
                    }
                }
            }
            return;
        }
        const Node& b = m_nodes[static_cast<std::size_t>(j)];
        // Cheapest tests first: the merged cone is at least as wide as either cone.
        if (culling && a.cone.halfAngle < cullingAngle && b.cone.halfAngle < cullingAngle &&
            adjacent(i, j) && mergeConesInline(a.cone, b.cone).halfAngle < cullingAngle) {
            return; // two adjacent patches forming a flat enough surface
        }
        if (a.isLeaf() && b.isLeaf()) {
            found.emplace_back(std::min(a.triangle, b.triangle), std::max(a.triangle, b.triangle));
            return;
        }
        if (b.isLeaf() || (!a.isLeaf() && a.box.surfaceArea() >= b.box.surfaceArea())) {
            for (const int c : a.children) {
                if (c >= 0 && m_nodes[static_cast<std::size_t>(c)].box.overlaps(b.box)) {
                    stack.emplace_back(c, j);
                }
            }
        } else {
            for (const int c : b.children) {
                if (c >= 0 && m_nodes[static_cast<std::size_t>(c)].box.overlaps(a.box)) {
                    stack.emplace_back(i, c);
                }
            }
        }
    };
    orderedTraversal({m_root, -1}, static_cast<std::int64_t>(m_nodes.size()) >= PARALLEL_GRAIN, out,
                     expand);
}

std::pair<int, TrianglePoint> SurfaceBvh::closestTriangle(const MatX3& x, const Vec3& p,
                                                          double maxDistance,
                                                          int vertexOffset) const {
    TrianglePoint none;
    none.point = p;
    none.distance = std::numeric_limits<double>::infinity();
    std::pair<int, TrianglePoint> best{-1, none};
    if (empty() || !(maxDistance >= 0)) {
        return best;
    }
    double bestDistance = maxDistance;
    double bestSquared = maxDistance * maxDistance;
    // Min-heap of (squared box distance, node).
    std::vector<std::pair<double, int>> heap;
    heap.reserve(64);
    const auto closer = [](const std::pair<double, int>& u, const std::pair<double, int>& v) {
        return u.first > v.first;
    };
    const double rootSquared = m_nodes[static_cast<std::size_t>(m_root)].box.squaredDistance(p);
    if (rootSquared <= bestSquared) {
        heap.emplace_back(rootSquared, m_root);
    }
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), closer);
        const auto [d2, n] = heap.back();
        heap.pop_back();
        if (d2 > bestSquared) {
            break; // every remaining box is farther than the best triangle
        }
        const Node& node = m_nodes[static_cast<std::size_t>(n)];
        if (node.isLeaf()) {
            const int t = node.triangle;
            const TrianglePoint tp =
                closestPointOnTriangle(p, x.row(vertexOffset + m_triangles(t, 0)).transpose(),
                                       x.row(vertexOffset + m_triangles(t, 1)).transpose(),
                                       x.row(vertexOffset + m_triangles(t, 2)).transpose());
            if (best.first < 0 ? tp.distance <= bestDistance : tp.distance < bestDistance) {
                best = {t, tp};
                bestDistance = tp.distance;
                bestSquared = bestDistance * bestDistance;
            }
            continue;
        }
        for (const int c : node.children) {
            if (c < 0) {
                continue;
            }
            const double cd2 = m_nodes[static_cast<std::size_t>(c)].box.squaredDistance(p);
            if (cd2 <= bestSquared) {
                heap.emplace_back(cd2, c);
                std::push_heap(heap.begin(), heap.end(), closer);
            }
        }
    }
    return best;
}

} // namespace atelier::sim
