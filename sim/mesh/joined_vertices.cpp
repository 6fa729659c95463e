#include "sim/mesh/joined_vertices.h"

#include <algorithm>
#include <cstddef>
#include <numeric>

namespace atelier::sim {

std::vector<int> joinedGroups(int vertexCount, const std::vector<std::pair<int, int>>& pairs) {
    std::vector<int> parent(static_cast<std::size_t>(std::max(vertexCount, 0)));
    std::iota(parent.begin(), parent.end(), 0);
    const auto root = [&parent](int v) {
        while (parent[static_cast<std::size_t>(v)] != v) {
            v = parent[static_cast<std::size_t>(v)] =
                parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
        }
        return v;
    };
    for (const auto& [a, b] : pairs) {
        const int ra = root(a);
        const int rb = root(b);
        // The smaller index is the root: a group is named by its first member.
        parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    }
    for (std::size_t v = 0; v < parent.size(); ++v) {
        parent[v] = root(static_cast<int>(v));
    }
    return parent;
}

} // namespace atelier::sim
