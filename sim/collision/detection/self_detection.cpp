#include "sim/collision/detection/self_detection.h"

#include "sim/collision/ccd/crossing_tests.h"
#include "sim/collision/distance/point_triangle.h"
#include "sim/collision/indexing.h"
#include "sim/collision/triangle_normal.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <utility>

namespace atelier::sim {

namespace {

/// The feature tests of one candidate pair of cloth triangles.
class SelfDetector {
  public:
    SelfDetector(const DetectionContext& ctx, const ContactMemory& memory, const MatX3& xs,
                 const MatX3& xe)
        : m_ctx(ctx), m_mesh(ctx.mesh), m_memory(memory), m_xs(xs), m_xe(xe),
          m_factor(1.0 + ctx.scene.collision.proximityFactor),
          m_swept(ctx.scene.collision.continuous && &xs != &xe) {}

    void testPair(DetectionChunk& out, const std::pair<int, int>& pair) const {
        const auto [ta, tb] = pair;
        if (!m_mesh.selfPair(ta, tb)) {
            return;
        }
        vertexFaces(out, ta, tb);
        vertexFaces(out, tb, ta);
        edgeEdges(out, ta, tb);
    }

  private:
    const Material& material(int v) const {
        return m_ctx.scene
            .cloths[static_cast<std::size_t>(m_mesh.clothOf[static_cast<std::size_t>(v)])]
            .material;
    }
    /// The vertices owned by triangle a against triangle b.
    void vertexFaces(DetectionChunk& out, int a, int b) const;
    /// Edge–edge, each unordered pair of owned edges of ta and tb once.
    void edgeEdges(DetectionChunk& out, int ta, int tb) const;

    const DetectionContext& m_ctx;
    const CollisionMesh& m_mesh;
    const ContactMemory& m_memory;
    const MatX3& m_xs;
    const MatX3& m_xe;
    double m_factor;
    bool m_swept;
};

void SelfDetector::vertexFaces(DetectionChunk& out, int a, int b) const {
    const MatX3& xs = m_xs;
    const MatX3& xe = m_xe;
    const int fb[3] = {m_mesh.triangles(b, 0), m_mesh.triangles(b, 1), m_mesh.triangles(b, 2)};
    const Vec3 bs[3] = {row(xs, fb[0]), row(xs, fb[1]), row(xs, fb[2])};
    const Vec3 be[3] = {row(xe, fb[0]), row(xe, fb[1]), row(xe, fb[2])};
    const double tb0 =
        std::max({m_mesh.thickness[fb[0]], m_mesh.thickness[fb[1]], m_mesh.thickness[fb[2]]});
    for (int p : m_mesh.ownedVertices[static_cast<std::size_t>(a)]) {
        if (m_mesh.same(p, fb[0]) || m_mesh.same(p, fb[1]) || m_mesh.same(p, fb[2])) {
            continue;
        }
        const double d0 = m_mesh.thickness[p] + tb0;
        const Vec3 pe = row(xe, p);
        const TrianglePoint cp = closestPointOnTriangle(pe, be[0], be[1], be[2]);
        std::array<double, 3> bary = cp.bary;
        if (!(cp.distance < d0 * m_factor)) {
            if (!m_swept) {
                continue;
            }
            const Vec3 ps = row(xs, p);
            const auto hit = vertexCrosses(ps, pe, bs[0], be[0], bs[1], be[1], bs[2], be[2]);
            if (!hit) {
                continue;
            }
            ++out.continuousHits;
            bary = hit->coords;
        }
        // Side: remembered, else where the vertex was at the step's start.
        const std::uint64_t key = pairKey(p, b);
        signed char side = 0;
        const auto mem = m_memory.find(key);
        // The side is certain when remembered from the last step or when the swept test
        // saw the vertex arrive; otherwise it comes from a state that may be tangled and
        // the region vote may overrule it.
        bool reliable = !(cp.distance < d0 * m_factor);
        if (mem != m_memory.end()) {
            side = mem->second;
            reliable = true;
        } else {
            const Vec3 ps = row(xs, p);
            const Vec3 onB = bary[0] * bs[0] + bary[1] * bs[1] + bary[2] * bs[2];
            side = signOf(triangleNormal(bs[0], bs[1], bs[2]).dot(ps - onB));
            side = side == 0 ? 1 : side;
        }
        const Vec3 nb = triangleNormal(be[0], be[1], be[2]);
        if (nb.squaredNorm() == 0) {
            continue;
        }
        Contact c;
        c.kind = Contact::Kind::SelfVertexFace;
        c.vertex[0] = p;
        c.weight[0] = 1.0;
        for (int i = 0; i < 3; ++i) {
            c.vertex[i + 1] = fb[i];
            c.weight[i + 1] = -bary[static_cast<std::size_t>(i)];
        }
        c.distance = d0;
        c.normal = side * nb;
        c.staticFriction =
            m_ctx.scaledFriction(material(p).staticFriction, material(fb[0]).staticFriction);
        c.kineticFriction =
            m_ctx.scaledFriction(material(p).kineticFriction, material(fb[0]).kineticFriction);
        out.contacts.push_back(c);
        out.keys.push_back(key);
        out.sides.push_back(side);
        out.reliable.push_back(reliable ? 1 : 0);
    }
}

void SelfDetector::edgeEdges(DetectionChunk& out, int ta, int tb) const {
    const MatX3& xs = m_xs;
    const MatX3& xe = m_xe;
    for (int e : m_mesh.ownedEdges[static_cast<std::size_t>(ta)]) {
        const int e0 = m_mesh.edges(e, 0), e1 = m_mesh.edges(e, 1);
        for (int g : m_mesh.ownedEdges[static_cast<std::size_t>(tb)]) {
            const int g0 = m_mesh.edges(g, 0), g1 = m_mesh.edges(g, 1);
            if (m_mesh.same(e0, g0) || m_mesh.same(e0, g1) || m_mesh.same(e1, g0) ||
                m_mesh.same(e1, g1)) {
                continue;
            }
            const double d0 = std::max(m_mesh.thickness[e0], m_mesh.thickness[e1]) +
                              std::max(m_mesh.thickness[g0], m_mesh.thickness[g1]);
            const auto meeting =
                edgesMeet(row(xs, e0), row(xe, e0), row(xs, e1), row(xe, e1), row(xs, g0),
                          row(xe, g0), row(xs, g1), row(xe, g1), d0 * m_factor, m_swept);
            if (!meeting) {
                continue;
            }
            const double s = meeting->s, t = meeting->t;
            const bool near = meeting->near;
            out.continuousHits += near ? 0 : 1;
            const Vec3 de = ((1 - s) * row(xe, e0) + s * row(xe, e1)) -
                            ((1 - t) * row(xe, g0) + t * row(xe, g1));
            const Vec3 ds = ((1 - s) * row(xs, e0) + s * row(xs, e1)) -
                            ((1 - t) * row(xs, g0) + t * row(xs, g1));
            const std::optional<Vec3> separation = edgeSeparation(de, ds, near);
            if (!separation) {
                continue;
            }
            const Vec3& normal = *separation;
            Contact c;
            c.kind = Contact::Kind::SelfEdgeEdge;
            c.vertex[0] = e0;
            c.vertex[1] = e1;
            c.vertex[2] = g0;
            c.vertex[3] = g1;
            c.weight[0] = 1 - s;
            c.weight[1] = s;
            c.weight[2] = -(1 - t);
            c.weight[3] = -t;
            c.distance = d0;
            c.normal = normal;
            c.staticFriction =
                m_ctx.scaledFriction(material(e0).staticFriction, material(g0).staticFriction);
            c.kineticFriction =
                m_ctx.scaledFriction(material(e0).kineticFriction, material(g0).kineticFriction);
            out.contacts.push_back(c);
            out.keys.push_back(0);
            out.sides.push_back(0);
            out.reliable.push_back(1);
        }
    }
}

} // namespace

DetectionResult detectSelfContacts(const DetectionContext& ctx, const ContactMemory& memory,
                                   const MatX3& xs, const MatX3& xe, DetectionScratch& scratch,
                                   const std::vector<std::pair<int, int>>& watched) {
    scratch.pairs.clear();
    ctx.clothBvh.selfOverlaps(scratch.pairs);
    if (!watched.empty()) {
        // Pairs the curvature culling skipped although the fail-safe saw them cross: each
        // tested once (the traversal finds a pair at most once, and `watched` is sorted).
        std::vector<char> found(watched.size(), 0);
        for (const auto& pair : scratch.pairs) {
            const auto it = std::lower_bound(watched.begin(), watched.end(), pair);
            if (it != watched.end() && *it == pair) {
                found[static_cast<std::size_t>(it - watched.begin())] = 1;
            }
        }
        for (std::size_t i = 0; i < watched.size(); ++i) {
            if (!found[i]) {
                scratch.pairs.push_back(watched[i]);
            }
        }
    }
    DetectionResult result;
    result.candidatePairs = static_cast<long>(scratch.pairs.size());
    const SelfDetector detector(ctx, memory, xs, xe);
    result.pieces = scratch.inChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
        detector.testPair(out, pair);
    });
    return result;
}

} // namespace atelier::sim
