#pragma once
/// Bounding-volume hierarchy of a triangle surface built bottom-up from adjacent triangles
/// (Volino & Magnenat-Thalmann 1997 §4.2), with normal cones for curvature-culled
/// self-collision detection (Volino & Magnenat-Thalmann 1994).

#include "sim/collision/geometry.h"
#include "sim/core/types.h"

#include <utility>
#include <vector>

namespace atelier::sim {

/// Axis-aligned box [m]. Empty when lo > hi.
struct Aabb {
    Vec3 lo = Vec3::Constant(1e300);
    Vec3 hi = Vec3::Constant(-1e300);
    void add(const Vec3& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    void add(const Aabb& b) {
        lo = lo.cwiseMin(b.lo);
        hi = hi.cwiseMax(b.hi);
    }
    /// The smallest box holding this one and b.
    Aabb merged(const Aabb& b) const {
        Aabb m = *this;
        m.add(b);
        return m;
    }
    /// Surface area [m²] (extents below zero count as zero).
    double surfaceArea() const {
        const Vec3 d = (hi - lo).cwiseMax(Vec3::Zero());
        return 2.0 * (d.x() * d.y() + d.y() * d.z() + d.z() * d.x());
    }
    /// Centre [m].
    Vec3 centre() const { return 0.5 * (lo + hi); }
    bool overlaps(const Aabb& b) const {
        return (lo.array() <= b.hi.array()).all() && (b.lo.array() <= hi.array()).all();
    }
    /// Squared distance from p to the box (0 inside) [m²].
    double squaredDistance(const Vec3& p) const {
        const Vec3 d = (lo - p).cwiseMax(p - hi).cwiseMax(Vec3::Zero());
        return d.squaredNorm();
    }
};

/// Cone of directions around a unit axis: every normal n of the node has angle(n, axis) <=
/// halfAngle [rad]. halfAngle >= π means "any direction".
struct NormalCone {
    Vec3 axis = Vec3::UnitZ();
    double halfAngle = 0;
};
/// Smallest cone containing both cones.
NormalCone mergeCones(const NormalCone& a, const NormalCone& b);

/// Options of the self-collision traversal.
struct SelfQueryOptions {
    /// Curvature culling: a node (or a pair of adjacent nodes) whose normal cone's half-angle
    /// is below this is not tested against itself [rad]. π/2: the patch is a height field over
    /// its cone axis and cannot fold onto itself. A value > π disables culling (brute force).
    double cullingAngle = 1.5707963267948966;
};

/// Hierarchy over one triangle mesh. Built once (bvh_builder.h); `refit` moves it with the
/// surface.
class SurfaceBvh {
  public:
    struct Node {
        Aabb box;
        NormalCone cone;
        int children[3] = {-1, -1, -1}; ///< child nodes (2 or 3; -1 unused); all -1 for a leaf
        int triangle = -1;              ///< leaf: its triangle
        /// Range [boundaryBegin, boundaryEnd) in boundaryVertices(): the sorted vertices of
        /// the node's patch that are also on other triangles (for adjacency of nodes).
        int boundaryBegin = 0;
        int boundaryEnd = 0;
        /// The node's triangles form one edge-connected patch. False for the nodes that join
        /// disconnected components (separate cloths stacked flat can still collide, so such
        /// nodes are never curvature-culled).
        bool connected = true;
        bool isLeaf() const { return triangle >= 0; }
    };

    SurfaceBvh() = default;
    /// Builds the tree: leaves are triangles; each level pairs every node with an unpaired
    /// node sharing an edge (a node left alone joins a neighbouring pair as a third child,
    /// or is carried up), so every inner node is a connected patch. Disconnected components
    /// are joined at the top by proximity of their boxes. `x` (|V|×3, local indices) only
    /// guides the grouping (compact patches). O(N log N).
    SurfaceBvh(const MatX3i& triangles, const MatX3& x);

    /// Refits boxes and cones bottom-up to positions: boxes enclose each triangle at `x0` and,
    /// when `x1` is given, at `x1` too (swept over a step), grown by `margin` [m] on every
    /// side; cones enclose the normals at x0 (and x1). Rows of x0/x1 for this mesh start at
    /// `vertexOffset`. O(N).
    void refit(const MatX3& x0, const MatX3* x1, double margin, int vertexOffset = 0);

    /// Triangle pairs (a of this, b of other) whose leaf boxes overlap, appended to `out`.
    void overlaps(const SurfaceBvh& other, std::vector<std::pair<int, int>>& out) const;
    /// Appends the triangles whose (refitted) leaf box overlaps `box`.
    void query(const Aabb& box, std::vector<int>& out) const;
    /// Triangle pairs (a < b) of this mesh whose leaf boxes overlap, with curvature culling:
    /// a node is descended into itself only if its cone is wide enough, two adjacent nodes
    /// only if their merged cone is; pairs sharing a vertex are reported too (the narrow phase
    /// excludes primitives that share vertices). Appended to `out`.
    void selfOverlaps(std::vector<std::pair<int, int>>& out,
                      const SelfQueryOptions& options = {}) const;

    /// Closest triangle to p within `maxDistance` [m] at positions x (the boxes must be
    /// refitted to positions enclosing x, margins allowed): best-first descent pruned by box
    /// distance. Returns the triangle (-1 if none within maxDistance) and its closest point.
    std::pair<int, TrianglePoint> closestTriangle(const MatX3& x, const Vec3& p, double maxDistance,
                                                  int vertexOffset = 0) const;

    const std::vector<Node>& nodes() const { return m_nodes; }
    int root() const { return m_root; }
    const std::vector<int>& boundaryVertices() const { return m_boundary; }
    const MatX3i& triangles() const { return m_triangles; }
    bool empty() const { return m_root < 0; }
    /// Whether nodes a and b share a vertex.
    bool adjacent(int a, int b) const;

  private:
    /// Reorders the built nodes (children before parents) depth-first from `root` and fills
    /// m_subtreeEnd.
    void storeDepthFirst(int root);

    MatX3i m_triangles;
    std::vector<Node> m_nodes;
    std::vector<int> m_boundary;
    /// Nodes are stored depth-first (pre-order) from the root (m_root = 0): node n's subtree is
    /// [n, m_subtreeEnd[n]), so children come after their parent (a reverse scan refits
    /// bottom-up, reading memory in order, and subtrees refit in parallel) and a is an
    /// ancestor of b when a < b < m_subtreeEnd[a].
    std::vector<int> m_subtreeEnd;
    int m_root = -1;
};

} // namespace atelier::sim
