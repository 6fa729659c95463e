#include "sim/collision/fail_safe.h"

#include "sim/collision/ccd/crossing_tests.h"
#include "sim/collision/ccd/edge_edge_ccd.h"
#include "sim/collision/indexing.h"

#include <algorithm>
#include <cstddef>
#include <utility>

namespace atelier::sim {

namespace {

/// Appends the four vertices of every feature pair of cloth triangles ta, tb (vertex–triangle
/// both ways, edge–edge; sewn or shared vertices excluded) that crosses over xs → xe.
void pairCrossings(const CollisionMesh& mesh, int ta, int tb, const MatX3& xs, const MatX3& xe,
                   std::vector<int>& hits) {
    if (!mesh.selfPair(ta, tb)) {
        return;
    }
    for (int dir = 0; dir < 2; ++dir) {
        const int a = dir == 0 ? ta : tb;
        const int b = dir == 0 ? tb : ta;
        const int f0 = mesh.triangles(b, 0), f1 = mesh.triangles(b, 1), f2 = mesh.triangles(b, 2);
        for (int p : mesh.ownedVertices[static_cast<std::size_t>(a)]) {
            if (mesh.same(p, f0) || mesh.same(p, f1) || mesh.same(p, f2)) {
                continue;
            }
            const Vec3 p0 = row(xs, p), p1 = row(xe, p), a0 = row(xs, f0), a1 = row(xe, f0),
                       b0 = row(xs, f1), b1 = row(xe, f1), c0 = row(xs, f2), c1 = row(xe, f2);
            if (vertexCrosses(p0, p1, a0, a1, b0, b1, c0, c1)) {
                hits.insert(hits.end(), {p, f0, f1, f2});
            }
        }
    }
    for (int e : mesh.ownedEdges[static_cast<std::size_t>(ta)]) {
        const int e0 = mesh.edges(e, 0), e1 = mesh.edges(e, 1);
        for (int g : mesh.ownedEdges[static_cast<std::size_t>(tb)]) {
            const int g0 = mesh.edges(g, 0), g1 = mesh.edges(g, 1);
            if (mesh.same(e0, g0) || mesh.same(e0, g1) || mesh.same(e1, g0) || mesh.same(e1, g1)) {
                continue;
            }
            const Vec3 p0 = row(xs, e0), p1 = row(xe, e0), p2 = row(xs, e1), p3 = row(xe, e1),
                       q0 = row(xs, g0), q1 = row(xe, g0), q2 = row(xs, g1), q3 = row(xe, g1);
            if (sweptBoxesNear<4, 4>({&p0, &p1, &p2, &p3}, {&q0, &q1, &q2, &q3}, 0.0) &&
                sweptEdgeEdge(p0, p1, p2, p3, q0, q1, q2, q3, 0.0)) {
                hits.insert(hits.end(), {e0, e1, g0, g1});
            }
        }
    }
}

} // namespace

void CrossingFailSafe::markCrossings(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                     DetectionScratch& scratch, const MatX3& xs, const MatX3& xe,
                                     const VecX* invMass, std::vector<int>& marked) {
    std::vector<char>& back = m_putBack;
    back.resize(static_cast<std::size_t>(xe.rows()), 0);
    clothBvh.refit(xs, &xe, 0.0);
    scratch.pairs.clear();
    SelfQueryOptions noCulling;
    noCulling.cullingAngle = 4.0; // exact: the cone test is only a heuristic (see README)
    clothBvh.selfOverlaps(scratch.pairs, noCulling);
    const std::size_t used =
        scratch.inChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
            pairCrossings(mesh, pair.first, pair.second, xs, xe, out.hits);
        });
    for (std::size_t c = 0; c < used; ++c) {
        for (int v : scratch.chunks[c].hits) {
            if (!back[static_cast<std::size_t>(v)] && (invMass == nullptr || (*invMass)[v] > 0)) {
                back[static_cast<std::size_t>(v)] = 1;
                marked.push_back(v);
            }
        }
    }
}

long CrossingFailSafe::rollBack(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                DetectionScratch& scratch, const MatX3& xs, MatX3& xe, MatX3& ve,
                                const VecX& invMass) {
    std::vector<int>& marked = m_putBackList;
    std::vector<int> all; // every vertex put back this step, to clear the flags at the end
    std::vector<int> changed;
    long rolledBack = 0;
    for (int round = 0; round < 32; ++round) {
        marked.clear();
        if (round == 0) {
            markCrossings(mesh, clothBvh, scratch, xs, xe, &invMass, marked);
        } else {
            // Only the vertices put back last round moved since: a feature pair without one
            // crosses now exactly as it did then, and then its vertices were marked already.
            markCrossingsAround(mesh, clothBvh, xs, xe, changed, &invMass, marked);
        }
        if (marked.empty()) {
            break;
        }
        changed = marked;
        for (int v : marked) {
            xe.row(v) = xs.row(v);
            ve.row(v).setZero();
        }
        all.insert(all.end(), marked.begin(), marked.end());
        rolledBack += static_cast<long>(marked.size());
    }
    for (int v : all) {
        m_putBack[static_cast<std::size_t>(v)] = 0;
    }
    return rolledBack;
}

std::vector<int> CrossingFailSafe::crossingVertices(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                                    const MatX3& xs, const MatX3& xe,
                                                    const std::vector<int>& moved) {
    std::vector<int> marked;
    if (!mesh.anySelf || moved.empty()) {
        return marked;
    }
    m_putBack.resize(static_cast<std::size_t>(xe.rows()), 0);
    markCrossingsAround(mesh, clothBvh, xs, xe, moved, nullptr, marked);
    for (int v : marked) {
        m_putBack[static_cast<std::size_t>(v)] = 0;
    }
    return marked;
}

void CrossingFailSafe::markCrossingsAround(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                           const MatX3& xs, const MatX3& xe,
                                           const std::vector<int>& moved, const VecX* invMass,
                                           std::vector<int>& marked) {
    const std::size_t nv = static_cast<std::size_t>(xe.rows());
    if (m_vertexTriangles.size() != nv) {
        m_vertexTriangles.assign(nv, {});
        for (int f = 0; f < mesh.triangles.rows(); ++f) {
            for (int k = 0; k < 3; ++k) {
                m_vertexTriangles[static_cast<std::size_t>(mesh.triangles(f, k))].push_back(f);
            }
        }
    }
    // Only triangles with a moved corner can cross anything: each is tested against the
    // triangles its swept box overlaps.
    clothBvh.refit(xs, &xe, 0.0);
    std::vector<int> triangles;
    for (int v : moved) {
        const auto& incident = m_vertexTriangles[static_cast<std::size_t>(v)];
        triangles.insert(triangles.end(), incident.begin(), incident.end());
    }
    std::sort(triangles.begin(), triangles.end());
    triangles.erase(std::unique(triangles.begin(), triangles.end()), triangles.end());
    std::vector<char>& flagged = m_putBack;
    std::vector<int>& hits = m_hits;
    std::vector<int> candidates;
    for (int t : triangles) {
        Aabb box;
        for (int k = 0; k < 3; ++k) {
            box.add(row(xs, mesh.triangles(t, k)));
            box.add(row(xe, mesh.triangles(t, k)));
        }
        candidates.clear();
        clothBvh.query(box, candidates);
        for (int u : candidates) {
            if (u == t) {
                continue;
            }
            hits.clear();
            pairCrossings(mesh, t, u, xs, xe, hits);
            for (int v : hits) {
                if (!flagged[static_cast<std::size_t>(v)] &&
                    (invMass == nullptr || (*invMass)[v] > 0)) {
                    flagged[static_cast<std::size_t>(v)] = 1;
                    marked.push_back(v);
                }
            }
        }
    }
}

} // namespace atelier::sim
