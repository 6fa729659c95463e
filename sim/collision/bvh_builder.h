#pragma once
/// Construction of a SurfaceBvh, bottom-up from adjacent triangles (Volino & Magnenat-Thalmann
/// 1997 §4.2): each level pairs every node with an unpaired node sharing an edge, so every inner
/// node is a connected patch; disconnected components are joined at the top by proximity.

#include "sim/collision/bvh.h"
#include "sim/core/types.h"

#include <vector>

namespace atelier::sim {

/// The nodes of a SurfaceBvh in the order they were made: the leaves (triangle t is node t),
/// then the parents level by level. Each node's boundary vertices are its range of `boundary`.
struct BuiltSurfaceTree {
    std::vector<SurfaceBvh::Node> nodes;
    std::vector<int> boundary;
    int root = -1;
};

/// Builds the tree of a non-empty triangle mesh; `x` (|V|×3, local indices) only guides the
/// grouping (compact patches). O(N log N).
BuiltSurfaceTree buildSurfaceTree(const MatX3i& triangles, const MatX3& x);

} // namespace atelier::sim
