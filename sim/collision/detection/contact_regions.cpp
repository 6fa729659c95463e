#include "sim/collision/detection/contact_regions.h"

#include "sim/collision/indexing.h"
#include "sim/collision/triangle_normal.h"

#include <array>
#include <cstddef>
#include <numeric>

namespace atelier::sim {

namespace {

/// Union–find over contact indices, with path halving.
struct UnionFind {
    std::vector<int> parent;
    explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int i) {
        while (parent[static_cast<std::size_t>(i)] != i) {
            parent[static_cast<std::size_t>(i)] =
                parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
            i = parent[static_cast<std::size_t>(i)];
        }
        return i;
    }
};

/// Joins the self vertex–face contacts `members` whose vertices are equal or adjacent and whose
/// faces share a vertex into regions, within one smooth layer pair.
void groupRegions(const CollisionMesh& mesh, const MatX3& xe, const std::vector<Contact>& contacts,
                  const std::vector<int>& members, UnionFind& regions) {
    std::unordered_map<int, std::vector<int>> byVertex;
    for (int i : members) {
        byVertex[contacts[static_cast<std::size_t>(i)].vertex[0]].push_back(i);
    }
    auto faceOf = [&](int i) {
        const Contact& c = contacts[static_cast<std::size_t>(i)];
        return std::array<int, 3>{c.vertex[1], c.vertex[2], c.vertex[3]};
    };
    // Members of one region lie on one smooth layer pair: faces of a crease (normals apart)
    // are not grouped, their sides are not comparable.
    auto faceNormal = [&](int i) {
        const auto f = faceOf(i);
        return triangleNormal(row(xe, f[0]), row(xe, f[1]), row(xe, f[2]));
    };
    auto vertexNormal = [&](int v) {
        const int t = mesh.vertexTriangle[static_cast<std::size_t>(v)];
        return triangleNormal(row(xe, mesh.triangles(t, 0)), row(xe, mesh.triangles(t, 1)),
                              row(xe, mesh.triangles(t, 2)));
    };
    auto shareVertex = [](const std::array<int, 3>& a, const std::array<int, 3>& b) {
        for (int u : a) {
            for (int w : b) {
                if (u == w) {
                    return true;
                }
            }
        }
        return false;
    };
    for (int i : members) {
        const int p = contacts[static_cast<std::size_t>(i)].vertex[0];
        const auto fi = faceOf(i);
        auto visit = [&](int q) {
            const auto it = byVertex.find(q);
            if (it == byVertex.end()) {
                return;
            }
            for (int j : it->second) {
                if (j != i && shareVertex(fi, faceOf(j)) &&
                    faceNormal(i).dot(faceNormal(j)) > 0.7 &&
                    vertexNormal(p).dot(vertexNormal(q)) > 0.7) {
                    regions.parent[static_cast<std::size_t>(regions.find(i))] = regions.find(j);
                }
            }
        };
        visit(p);
        for (int q : mesh.neighbours[static_cast<std::size_t>(p)]) {
            visit(q);
        }
    }
}

/// The vote: members whose side is certain decide; a region with none of them (a tangled
/// start) is decided by all its members. Returns the number of members flipped.
long voteSides(const std::vector<int>& members, UnionFind& regions, std::vector<Contact>& contacts,
               std::vector<signed char>& sides, const std::vector<char>& reliable) {
    std::unordered_map<int, long> vote, voteAll;
    for (int i : members) {
        const int side =
            sides[static_cast<std::size_t>(i)]; // NOLINT(bugprone-signed-char-misuse): -1, 0 or +1
        voteAll[regions.find(i)] += side;
        if (reliable[static_cast<std::size_t>(i)]) {
            vote[regions.find(i)] += side;
        }
    }
    long flips = 0;
    for (int i : members) {
        const auto decided = vote.find(regions.find(i));
        const long v = decided != vote.end() ? decided->second : voteAll[regions.find(i)];
        signed char& side = sides[static_cast<std::size_t>(i)];
        const signed char regionSide = v > 0 ? 1 : (v < 0 ? -1 : side);
        if (regionSide != side && !reliable[static_cast<std::size_t>(i)]) {
            ++flips;
            contacts[static_cast<std::size_t>(i)].normal *= -1.0;
            side = regionSide;
        }
    }
    return flips;
}

/// Edge–edge contacts take their side from the step's start; where the vote found that start
/// tangled, that side is wrong, so edge–edge contacts touching a flipped region are dropped
/// and the vertex–face contacts alone pull the layers apart.
void dropFlippedEdgeEdges(std::size_t vertexCount, const std::vector<int>& members,
                          const std::vector<signed char>& flippedFrom,
                          std::vector<Contact>& contacts, std::vector<std::uint64_t>& keys,
                          std::vector<signed char>& sides, std::vector<char>& reliable) {
    std::vector<char> flipped;
    for (int i : members) {
        const Contact& c = contacts[static_cast<std::size_t>(i)];
        if (sides[static_cast<std::size_t>(i)] != flippedFrom[static_cast<std::size_t>(i)]) {
            if (flipped.empty()) {
                flipped.assign(vertexCount, 0);
            }
            for (int k = 0; k < 4; ++k) {
                flipped[static_cast<std::size_t>(c.vertex[k])] = 1;
            }
        }
    }
    if (flipped.empty()) {
        return;
    }
    std::size_t out = 0;
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        const Contact& c = contacts[i];
        const bool drop = c.kind == Contact::Kind::SelfEdgeEdge &&
                          (flipped[static_cast<std::size_t>(c.vertex[0])] ||
                           flipped[static_cast<std::size_t>(c.vertex[1])] ||
                           flipped[static_cast<std::size_t>(c.vertex[2])] ||
                           flipped[static_cast<std::size_t>(c.vertex[3])]);
        if (!drop) {
            contacts[out] = c;
            keys[out] = keys[i];
            sides[out] = sides[i];
            reliable[out] = reliable[i];
            ++out;
        }
    }
    contacts.resize(out);
    keys.resize(out);
    sides.resize(out);
    reliable.resize(out);
}

} // namespace

long ContactRegions::vote(const CollisionMesh& mesh, const MatX3& xe,
                          std::vector<Contact>& contacts, std::vector<std::uint64_t>& keys,
                          std::vector<signed char>& sides, std::vector<char>& reliable) {
    // Contact regions (§5.2): self vertex–face contacts whose vertices are equal or adjacent
    // and whose faces share a vertex belong to one region; the region takes the side most of
    // its members hold, and every member is given it.
    std::vector<int> members;
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        if (contacts[i].kind == Contact::Kind::SelfVertexFace) {
            members.push_back(static_cast<int>(i));
        }
    }
    if (members.empty()) {
        m_memory.clear();
        return 0;
    }
    UnionFind regions(contacts.size());
    groupRegions(mesh, xe, contacts, members, regions);
    m_flippedFrom = sides;
    const long flips = voteSides(members, regions, contacts, sides, reliable);
    // Remember the sides of the pairs in contact now; a pair that leaves proximity is forgotten
    // (a vertex may come back around a border from the other side).
    m_memory.clear();
    for (int i : members) {
        m_memory[keys[static_cast<std::size_t>(i)]] = sides[static_cast<std::size_t>(i)];
    }
    dropFlippedEdgeEdges(mesh.neighbours.size(), members, m_flippedFrom, contacts, keys, sides,
                         reliable);
    return flips;
}

} // namespace atelier::sim
