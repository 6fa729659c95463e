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

void CrossingFailSafe::findCrossings(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                     DetectionScratch& scratch, const MatX3& xs, const MatX3& xe,
                                     std::vector<int>& hits) {
    clothBvh.refit(xs, &xe, 0.0);
    scratch.pairs.clear();
    SelfQueryOptions noCulling;
    noCulling.cullingAngle = 4.0; // exact: the cone test is only a heuristic (see README)
    clothBvh.selfOverlaps(scratch.pairs, noCulling);
    const std::size_t used =
        scratch.inChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
            const std::size_t before = out.hits.size();
            pairCrossings(mesh, pair.first, pair.second, xs, xe, out.hits);
            if (out.hits.size() > before) {
                out.crossingPairs.push_back(pair);
            }
        });
    for (std::size_t c = 0; c < used; ++c) {
        hits.insert(hits.end(), scratch.chunks[c].hits.begin(), scratch.chunks[c].hits.end());
        m_found.insert(m_found.end(), scratch.chunks[c].crossingPairs.begin(),
                       scratch.chunks[c].crossingPairs.end());
    }
}

void CrossingFailSafe::undoCrossings(const std::vector<int>& hits, const MatX3& xs, MatX3& xe,
                                     MatX3& ve, const VecX& invMass, std::vector<int>& changed) {
    std::vector<Undone>& undone = m_undone;
    const auto at = [&](int v) -> Undone& { return undone[static_cast<std::size_t>(v)]; };
    for (std::size_t i = 0; i + 3 < hits.size(); i += 4) {
        const int* pair = &hits[i];
        // A drive (a kinematic vertex that moves) or a vertex carried by one cannot be put
        // back: the pair follows it, translated as one, so it crosses no more than at xs.
        int driver = -1;
        for (int k = 0; k < 4 && driver < 0; ++k) {
            const int v = pair[k];
            const bool drive = !(invMass[v] > 0) && (xe.row(v) - xs.row(v)).squaredNorm() > 0;
            if (drive || at(v) == Undone::Carried) {
                driver = v;
            }
        }
        for (int k = 0; k < 4; ++k) {
            const int v = pair[k];
            if (!(invMass[v] > 0) || v == driver || at(v) == Undone::Carried) {
                continue;
            }
            if (driver >= 0) {
                xe.row(v) = xs.row(v) + (xe.row(driver) - xs.row(driver));
                ve.row(v) = ve.row(driver);
                at(v) = Undone::Carried;
            } else if (at(v) == Undone::No) {
                xe.row(v) = xs.row(v);
                ve.row(v).setZero();
                at(v) = Undone::PutBack;
            } else {
                continue;
            }
            changed.push_back(v);
        }
    }
}

long CrossingFailSafe::rollBack(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                DetectionScratch& scratch, const MatX3& xs, MatX3& xe, MatX3& ve,
                                const VecX& invMass) {
    m_undone.resize(static_cast<std::size_t>(xe.rows()), Undone::No);
    // Age the watched pairs: one step more since each was last seen crossing.
    std::erase_if(m_watched, [](Watched& w) { return --w.stepsLeft <= 0; });
    m_found.clear();
    std::vector<int> all; // every vertex undone this step, to clear the flags at the end
    std::vector<int> changed;
    std::vector<int>& hits = m_crossings;
    for (int round = 0; round < 32; ++round) {
        hits.clear();
        if (round == 0) {
            findCrossings(mesh, clothBvh, scratch, xs, xe, hits);
        } else {
            // Only the vertices moved last round moved since: a feature pair without one
            // crosses now exactly as it did then, and then it was undone already.
            findCrossingsAround(mesh, clothBvh, xs, xe, changed, hits);
        }
        changed.clear();
        undoCrossings(hits, xs, xe, ve, invMass, changed);
        if (changed.empty()) {
            break;
        }
        all.insert(all.end(), changed.begin(), changed.end());
    }
    for (int v : all) {
        m_undone[static_cast<std::size_t>(v)] = Undone::No;
    }
    watch(m_found);
    return static_cast<long>(all.size());
}

void CrossingFailSafe::watch(const std::vector<std::pair<int, int>>& found) {
    for (const auto& pair : found) {
        const auto it = std::lower_bound(
            m_watched.begin(), m_watched.end(), pair,
            [](const Watched& w, const std::pair<int, int>& p) { return w.pair < p; });
        if (it != m_watched.end() && it->pair == pair) {
            it->stepsLeft = WATCH_STEPS;
        } else {
            m_watched.insert(it, Watched{pair, WATCH_STEPS});
        }
    }
    m_watchedPairs.clear();
    for (const Watched& w : m_watched) {
        m_watchedPairs.push_back(w.pair);
    }
}

std::vector<int> CrossingFailSafe::crossingVertices(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                                    const MatX3& xs, const MatX3& xe,
                                                    const std::vector<int>& moved) {
    std::vector<int> marked;
    if (!mesh.anySelf || moved.empty()) {
        return marked;
    }
    std::vector<int>& hits = m_crossings;
    hits.clear();
    findCrossingsAround(mesh, clothBvh, xs, xe, moved, hits);
    m_found.clear(); // a hypothetical move's crossings are not watched (nor kept: no rollBack
                     // may follow to clear them when the fail-safe is off)
    marked = hits;
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    return marked;
}

void CrossingFailSafe::findCrossingsAround(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                           const MatX3& xs, const MatX3& xe,
                                           const std::vector<int>& moved, std::vector<int>& hits) {
    // Only triangles with a moved corner can cross anything: each is tested against the
    // triangles its swept box overlaps.
    clothBvh.refit(xs, &xe, 0.0);
    const std::vector<int> triangles = mesh.trianglesAround(moved);
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
            const std::size_t before = hits.size();
            pairCrossings(mesh, t, u, xs, xe, hits);
            if (hits.size() > before) {
                m_found.emplace_back(std::min(t, u), std::max(t, u));
            }
        }
    }
}

} // namespace atelier::sim
