#pragma once
/// Vertices joined into groups by pairs (welded seams): union–find.

#include <utility>
#include <vector>

namespace atelier::sim {

/// Per vertex 0..vertexCount−1, the smallest index of the group that `pairs` join it into (its
/// own index when no pair names it). Pairs' indices must be in range.
std::vector<int> joinedGroups(int vertexCount, const std::vector<std::pair<int, int>>& pairs);

} // namespace atelier::sim
