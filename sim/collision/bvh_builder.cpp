#include "sim/collision/bvh_builder.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <numeric>
#include <utility>

namespace atelier::sim {

namespace {

/// Morton codes use this many bits per axis (3 × 21 = 63 bits).
constexpr int MORTON_BITS = 21;
/// Nodes in Morton order a node looks ahead at when components are joined by proximity.
constexpr int JOIN_WINDOW = 8;

/// Spreads the low 21 bits of v so that there are two zero bits between consecutive ones.
std::uint64_t spreadBits(std::uint64_t v) {
    v &= 0x1fffffULL;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

/// Indices 0..|centres|-1 sorted along the Morton (Z-order) curve of the points.
std::vector<int> mortonOrder(const std::vector<Vec3>& centres) {
    Aabb bounds;
    for (const Vec3& c : centres) {
        bounds.add(c);
    }
    const Vec3 extent = (bounds.hi - bounds.lo).cwiseMax(Vec3::Constant(1e-300));
    const double cells = static_cast<double>((1 << MORTON_BITS) - 1);
    std::vector<std::pair<std::uint64_t, int>> keyed(centres.size());
    for (std::size_t i = 0; i < centres.size(); ++i) {
        const Vec3 q = ((centres[i] - bounds.lo).array() / extent.array() * cells).matrix();
        std::uint64_t code = 0;
        for (int a = 0; a < 3; ++a) {
            const double clamped = std::clamp(q[a], 0.0, cells);
            code |= spreadBits(static_cast<std::uint64_t>(clamped)) << a;
        }
        keyed[i] = {code, static_cast<int>(i)};
    }
    std::sort(keyed.begin(), keyed.end());
    std::vector<int> order(keyed.size());
    for (std::size_t i = 0; i < keyed.size(); ++i) {
        order[i] = keyed[i].second;
    }
    return order;
}

/// Undirected weighted graph in compressed rows: the neighbours of node i are
/// nbr[begin[i] .. begin[i+1]) with the number of shared mesh edges in `weight`.
struct Graph {
    std::vector<int> begin;
    std::vector<int> nbr;
    std::vector<int> weight;
    bool hasEdges() const { return !nbr.empty(); }
};

/// Graph of `n` nodes from undirected edges (a, b, weight), a != b; duplicates are merged
/// (weights summed).
Graph buildGraph(int n, std::vector<std::array<int, 3>>& edges) {
    std::vector<std::array<int, 3>> directed;
    directed.reserve(2 * edges.size());
    for (const auto& e : edges) {
        directed.push_back({e[0], e[1], e[2]});
        directed.push_back({e[1], e[0], e[2]});
    }
    edges.clear();
    std::sort(directed.begin(), directed.end(), [](const auto& p, const auto& q) {
        return p[0] != q[0] ? p[0] < q[0] : p[1] < q[1];
    });
    Graph g;
    g.begin.assign(static_cast<std::size_t>(n) + 1, 0);
    g.nbr.reserve(directed.size());
    g.weight.reserve(directed.size());
    for (std::size_t k = 0; k < directed.size(); ++k) {
        const auto& e = directed[k];
        if (!g.nbr.empty() && k > 0 && directed[k - 1][0] == e[0] && directed[k - 1][1] == e[1]) {
            g.weight.back() += e[2];
            continue;
        }
        g.nbr.push_back(e[1]);
        g.weight.push_back(e[2]);
        ++g.begin[static_cast<std::size_t>(e[0]) + 1];
    }
    std::partial_sum(g.begin.begin(), g.begin.end(), g.begin.begin());
    return g;
}

/// Triangle edge adjacency: triangles sharing an edge (all pairs on a non-manifold edge).
Graph triangleAdjacency(const MatX3i& triangles) {
    const int nt = static_cast<int>(triangles.rows());
    std::vector<std::array<int, 3>> halfEdges; // (lower vertex, upper vertex, triangle)
    halfEdges.reserve(3 * static_cast<std::size_t>(nt));
    for (int t = 0; t < nt; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int u = triangles(t, k);
            const int v = triangles(t, (k + 1) % 3);
            if (u != v) {
                halfEdges.push_back({std::min(u, v), std::max(u, v), t});
            }
        }
    }
    std::sort(halfEdges.begin(), halfEdges.end());
    std::vector<std::array<int, 3>> edges;
    edges.reserve(halfEdges.size());
    for (std::size_t s = 0; s < halfEdges.size();) {
        std::size_t e = s + 1;
        while (e < halfEdges.size() && halfEdges[e][0] == halfEdges[s][0] &&
               halfEdges[e][1] == halfEdges[s][1]) {
            ++e;
        }
        for (std::size_t i = s; i < e; ++i) {
            for (std::size_t j = i + 1; j < e; ++j) {
                if (halfEdges[i][2] != halfEdges[j][2]) {
                    edges.push_back({halfEdges[i][2], halfEdges[j][2], 1});
                }
            }
        }
        s = e;
    }
    return buildGraph(nt, edges);
}

/// A group of 2 or 3 nodes of one level (local indices) that becomes one parent.
struct Group {
    std::array<int, 3> members{-1, -1, -1};
    int size = 0;
    Aabb box;
};

/// The state of one construction: the nodes made so far, the current level (node ids) and its
/// adjacency graph, and the grouping of the level into parents.
class TreeBuilder {
  public:
    TreeBuilder(const MatX3i& triangles, const MatX3& x);
    BuiltSurfaceTree build();

  private:
    /// One leaf per triangle, its boundary its distinct vertices, its box at x.
    void addLeaves(const MatX3& x);
    /// Appends the parent of 2 or 3 nodes; its boundary is the merge of the children's, less
    /// the vertices whose triangles are now all inside the patch.
    int addParent(const std::array<int, 3>& children, int count);
    /// Turns the groups of the current level into parents; ungrouped nodes are carried up.
    /// Fills m_nextOf (local index → local index in the next level) and replaces m_level.
    void promote();
    /// Starts grouping the current level: its box centres, no groups; returns its local
    /// indices in Morton order.
    std::vector<int> startLevel();
    const Aabb& boxOf(int local) const {
        return m_nodes[static_cast<std::size_t>(m_level[static_cast<std::size_t>(local)])].box;
    }
    /// Pairs each node with its ungrouped neighbour giving the smallest merged box (ties: the
    /// one sharing more edges).
    void pairNeighbours(const std::vector<int>& order);
    /// A node left alone (all its neighbours grouped) joins a neighbouring pair as a third
    /// child, the one giving the smallest box; if every neighbouring group is full it is
    /// carried up.
    void joinLoners(const std::vector<int>& order);
    /// The next level's adjacency: the current one's edges between different parents.
    void nextGraph();
    /// One level of joining disconnected components by proximity of their box centres.
    void joinByProximity();

    const MatX3i& m_triangles;
    std::vector<SurfaceBvh::Node> m_nodes;
    std::vector<int> m_boundary;
    /// Number of distinct triangles on each vertex: a vertex is on the boundary of a patch when
    /// fewer of the patch's triangles are on it.
    std::vector<int> m_trianglesOnVertex;
    /// Per entry of `m_boundary`: how many of the node's triangles are on that vertex.
    std::vector<int> m_boundaryCount;
    std::vector<std::pair<int, int>> m_merging;
    std::vector<int> m_level; // node ids of the current level
    Graph m_graph;
    std::vector<Vec3> m_centres;
    std::vector<int> m_groupOf;
    std::vector<Group> m_groups;
    std::vector<int> m_nextOf;
    std::vector<int> m_next;
    std::vector<std::array<int, 3>> m_nextEdges;
};

TreeBuilder::TreeBuilder(const MatX3i& triangles, const MatX3& x) : m_triangles(triangles) {
    addLeaves(x);
    m_level.resize(static_cast<std::size_t>(m_triangles.rows()));
    std::iota(m_level.begin(), m_level.end(), 0);
    m_graph = triangleAdjacency(m_triangles);
}

void TreeBuilder::addLeaves(const MatX3& x) {
    const int nt = static_cast<int>(m_triangles.rows());
    const int nv = m_triangles.maxCoeff() + 1;
    m_trianglesOnVertex.assign(static_cast<std::size_t>(nv), 0);
    m_nodes.resize(static_cast<std::size_t>(nt));
    m_boundary.reserve(6 * static_cast<std::size_t>(nt));
    m_boundaryCount.reserve(6 * static_cast<std::size_t>(nt));
    for (int t = 0; t < nt; ++t) {
        std::array<int, 3> v{m_triangles(t, 0), m_triangles(t, 1), m_triangles(t, 2)};
        std::sort(v.begin(), v.end());
        const auto end = std::unique(v.begin(), v.end());
        SurfaceBvh::Node& node = m_nodes[static_cast<std::size_t>(t)];
        node.triangle = t;
        node.boundaryBegin = static_cast<int>(m_boundary.size());
        for (auto it = v.begin(); it != end; ++it) {
            ++m_trianglesOnVertex[static_cast<std::size_t>(*it)];
            m_boundary.push_back(*it);
            m_boundaryCount.push_back(1);
            node.box.add(Vec3(x.row(*it).transpose()));
        }
        node.boundaryEnd = static_cast<int>(m_boundary.size());
    }
}

int TreeBuilder::addParent(const std::array<int, 3>& children, int count) {
    SurfaceBvh::Node parent;
    m_merging.clear();
    for (std::size_t k = 0; k < static_cast<std::size_t>(count); ++k) {
        const SurfaceBvh::Node& child = m_nodes[static_cast<std::size_t>(children[k])];
        parent.children[k] = children[k];
        parent.box.add(child.box);
        for (int i = child.boundaryBegin; i < child.boundaryEnd; ++i) {
            m_merging.emplace_back(m_boundary[static_cast<std::size_t>(i)],
                                   m_boundaryCount[static_cast<std::size_t>(i)]);
        }
    }
    std::sort(m_merging.begin(), m_merging.end());
    parent.boundaryBegin = static_cast<int>(m_boundary.size());
    for (std::size_t i = 0; i < m_merging.size();) {
        const int v = m_merging[i].first;
        int inside = 0;
        for (; i < m_merging.size() && m_merging[i].first == v; ++i) {
            inside += m_merging[i].second;
        }
        if (inside < m_trianglesOnVertex[static_cast<std::size_t>(v)]) {
            m_boundary.push_back(v);
            m_boundaryCount.push_back(inside);
        }
    }
    parent.boundaryEnd = static_cast<int>(m_boundary.size());
    m_nodes.push_back(parent);
    return static_cast<int>(m_nodes.size()) - 1;
}

void TreeBuilder::promote() {
    const std::size_t m = m_level.size();
    m_next.clear();
    m_nextOf.assign(m, -1);
    for (const Group& g : m_groups) {
        std::array<int, 3> ids{-1, -1, -1};
        for (int k = 0; k < g.size; ++k) {
            const auto local = static_cast<std::size_t>(g.members[static_cast<std::size_t>(k)]);
            ids[static_cast<std::size_t>(k)] = m_level[local];
            m_nextOf[local] = static_cast<int>(m_next.size());
        }
        m_next.push_back(addParent(ids, g.size));
    }
    for (std::size_t i = 0; i < m; ++i) {
        if (m_nextOf[i] < 0) {
            m_nextOf[i] = static_cast<int>(m_next.size());
            m_next.push_back(m_level[i]);
        }
    }
    m_level.swap(m_next);
}

std::vector<int> TreeBuilder::startLevel() {
    const std::size_t m = m_level.size();
    m_centres.resize(m);
    for (std::size_t i = 0; i < m; ++i) {
        m_centres[i] = m_nodes[static_cast<std::size_t>(m_level[i])].box.centre();
    }
    m_groupOf.assign(m, -1);
    m_groups.clear();
    return mortonOrder(m_centres);
}

void TreeBuilder::pairNeighbours(const std::vector<int>& order) {
    for (const int i : order) {
        if (m_groupOf[static_cast<std::size_t>(i)] >= 0) {
            continue;
        }
        int best = -1;
        double bestArea = std::numeric_limits<double>::infinity();
        int bestWeight = 0;
        for (int k = m_graph.begin[static_cast<std::size_t>(i)];
             k < m_graph.begin[static_cast<std::size_t>(i) + 1]; ++k) {
            const int j = m_graph.nbr[static_cast<std::size_t>(k)];
            if (m_groupOf[static_cast<std::size_t>(j)] >= 0) {
                continue;
            }
            const double area = boxOf(i).merged(boxOf(j)).surfaceArea();
            const int weight = m_graph.weight[static_cast<std::size_t>(k)];
            if (area < bestArea || (area == bestArea && weight > bestWeight)) {
                best = j;
                bestArea = area;
                bestWeight = weight;
            }
        }
        if (best >= 0) {
            Group g;
            g.members = {i, best, -1};
            g.size = 2;
            g.box = boxOf(i).merged(boxOf(best));
            m_groupOf[static_cast<std::size_t>(i)] = static_cast<int>(m_groups.size());
            m_groupOf[static_cast<std::size_t>(best)] = static_cast<int>(m_groups.size());
            m_groups.push_back(g);
        }
    }
}

void TreeBuilder::joinLoners(const std::vector<int>& order) {
    for (const int i : order) {
        if (m_groupOf[static_cast<std::size_t>(i)] >= 0) {
            continue;
        }
        int best = -1;
        double bestArea = std::numeric_limits<double>::infinity();
        for (int k = m_graph.begin[static_cast<std::size_t>(i)];
             k < m_graph.begin[static_cast<std::size_t>(i) + 1]; ++k) {
            const int g =
                m_groupOf[static_cast<std::size_t>(m_graph.nbr[static_cast<std::size_t>(k)])];
            if (g < 0 || m_groups[static_cast<std::size_t>(g)].size != 2) {
                continue;
            }
            const double area =
                m_groups[static_cast<std::size_t>(g)].box.merged(boxOf(i)).surfaceArea();
            if (area < bestArea) {
                best = g;
                bestArea = area;
            }
        }
        if (best >= 0) {
            Group& g = m_groups[static_cast<std::size_t>(best)];
            g.members[2] = i;
            g.size = 3;
            g.box.add(boxOf(i));
            m_groupOf[static_cast<std::size_t>(i)] = best;
        }
    }
}

void TreeBuilder::nextGraph() {
    m_nextEdges.clear();
    for (std::size_t i = 0; i + 1 < m_graph.begin.size(); ++i) {
        for (int k = m_graph.begin[i]; k < m_graph.begin[i + 1]; ++k) {
            const auto j = static_cast<std::size_t>(m_graph.nbr[static_cast<std::size_t>(k)]);
            if (i < j && m_nextOf[i] != m_nextOf[j]) {
                m_nextEdges.push_back(
                    {m_nextOf[i], m_nextOf[j], m_graph.weight[static_cast<std::size_t>(k)]});
            }
        }
    }
    m_graph = buildGraph(static_cast<int>(m_level.size()), m_nextEdges);
}

void TreeBuilder::joinByProximity() {
    // Pairs each node with the nearest of the next few ungrouped nodes along the Morton curve.
    const std::vector<int> order = startLevel();
    const std::size_t m = order.size();
    int alone = -1;
    for (std::size_t a = 0; a < m; ++a) {
        const int i = order[a];
        if (m_groupOf[static_cast<std::size_t>(i)] >= 0) {
            continue;
        }
        int best = -1;
        double bestDistance = std::numeric_limits<double>::infinity();
        int looked = 0;
        for (std::size_t b = a + 1; b < m && looked < JOIN_WINDOW; ++b) {
            const int j = order[b];
            if (m_groupOf[static_cast<std::size_t>(j)] >= 0) {
                continue;
            }
            ++looked;
            const double d =
                (m_centres[static_cast<std::size_t>(i)] - m_centres[static_cast<std::size_t>(j)])
                    .squaredNorm();
            if (d < bestDistance) {
                best = j;
                bestDistance = d;
            }
        }
        if (best < 0) {
            alone = i; // only the last ungrouped node can be left alone
            continue;
        }
        Group g;
        g.members = {i, best, -1};
        g.size = 2;
        m_groupOf[static_cast<std::size_t>(i)] = static_cast<int>(m_groups.size());
        m_groupOf[static_cast<std::size_t>(best)] = static_cast<int>(m_groups.size());
        m_groups.push_back(g);
    }
    if (alone >= 0) { // join the pair with the nearest centre
        int best = -1;
        double bestDistance = std::numeric_limits<double>::infinity();
        for (std::size_t g = 0; g < m_groups.size(); ++g) {
            const Vec3 c = 0.5 * (m_centres[static_cast<std::size_t>(m_groups[g].members[0])] +
                                  m_centres[static_cast<std::size_t>(m_groups[g].members[1])]);
            const double d = (c - m_centres[static_cast<std::size_t>(alone)]).squaredNorm();
            if (d < bestDistance) {
                best = static_cast<int>(g);
                bestDistance = d;
            }
        }
        if (best >= 0) {
            m_groups[static_cast<std::size_t>(best)].members[2] = alone;
            m_groups[static_cast<std::size_t>(best)].size = 3;
        }
    }
    promote();
}

BuiltSurfaceTree TreeBuilder::build() {
    // Levels of edge-adjacent grouping, until every remaining node is a connected component.
    while (m_graph.hasEdges()) {
        const std::vector<int> order = startLevel();
        pairNeighbours(order);
        joinLoners(order);
        promote();
        nextGraph();
    }
    const std::size_t firstJoin = m_nodes.size();
    // Disconnected components: join nodes by proximity of their box centres, until one root.
    while (m_level.size() > 1) {
        joinByProximity();
    }
    for (std::size_t n = firstJoin; n < m_nodes.size(); ++n) {
        m_nodes[n].connected = false;
    }
    BuiltSurfaceTree tree;
    tree.nodes = std::move(m_nodes);
    tree.boundary = std::move(m_boundary);
    tree.root = m_level.front();
    return tree;
}

} // namespace

BuiltSurfaceTree buildSurfaceTree(const MatX3i& triangles, const MatX3& x) {
    return TreeBuilder(triangles, x).build();
}

} // namespace atelier::sim
