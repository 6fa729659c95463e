#include "sim/collision/detection/obstacle_detection.h"

#include "sim/collision/ccd/crossing_tests.h"
#include "sim/collision/distance/point_triangle.h"
#include "sim/collision/indexing.h"
#include "sim/collision/triangle_normal.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <utility>

namespace atelier::sim {

namespace {

/// One detection pass against one obstacle: the feature tests of each candidate pair (cloth
/// triangle a, obstacle triangle b) and the drivers of the First and Again passes.
class ObstacleDetector {
  public:
    ObstacleDetector(const DetectionContext& ctx, std::size_t k, CollisionObstacle& o,
                     const std::vector<int>& trapped, double h, const MatX3& xs, const MatX3& xe,
                     ObstaclePass which, DetectionScratch& scratch)
        : m_ctx(ctx), m_mesh(ctx.mesh), m_o(o), m_spec(*o.spec), m_trapped(trapped), m_xs(xs),
          m_xe(xe), m_scratch(scratch), m_ki(static_cast<int>(k)), m_h(h),
          m_factor(1.0 + ctx.scene.collision.proximityFactor),
          m_swept(which == ObstaclePass::First && ctx.scene.collision.continuous && h > 0),
          m_which(which) {}

    DetectionResult run();

  private:
    /// What the feature tests of one candidate pair (cloth triangle a, obstacle triangle b)
    /// share.
    // NOLINTNEXTLINE(bugprone-reserved-identifier): the copy of its arrays names `__i0`
    struct Frame {
        int a = -1, b = -1;
        int ob[3];
        Vec3 b0[3], b1[3], nb1;
        int ca[3];
        Vec3 as[3], ae[3];
        double d0 = 0;              ///< the cloth triangle's thickness + the obstacle's
        bool trappedCorner = false; ///< a corner of a is trapped: only its vertex–face tests
    };

    Vec3 obstacleVelocity(int v) const {
        return (m_o.moves && m_h > 0) ? Vec3((row(m_o.x1, v) - row(m_o.x0, v)) / m_h)
                                      : Vec3::Zero();
    }
    bool trapped(int v) const { return m_trapped[static_cast<std::size_t>(v)] == m_ki; }
    void markExtracting();
    void setOpenSides();
    void friction(Contact& c, int clothVertex) const;
    Frame frameOf(const std::pair<int, int>& pair) const;
    void keep(DetectionChunk& out, const Contact& c, int feature0, int feature1) const;
    void vertexFace(DetectionChunk& out, const Frame& fr, int p) const;
    void faceVertex(DetectionChunk& out, const Frame& fr, int q) const;
    void edgeEdge(DetectionChunk& out, int e, int g) const;
    void testPair(DetectionChunk& out, const std::pair<int, int>& pair) const;
    DetectionResult again();
    DetectionResult first();
    void rememberFirst(std::size_t used);

    const DetectionContext& m_ctx;
    const CollisionMesh& m_mesh;
    CollisionObstacle& m_o;
    const ObstacleSpec& m_spec;
    const std::vector<int>& m_trapped;
    const MatX3& m_xs;
    const MatX3& m_xe;
    DetectionScratch& m_scratch;
    int m_ki;
    double m_h;
    double m_factor;
    bool m_swept;
    ObstaclePass m_which;
};

void ObstacleDetector::markExtracting() {
    // A cloth being carried out of this obstacle slides on it freely until it is out: held by
    // friction where it enters, it would bunch there instead of being drawn out.
    const std::size_t n = static_cast<std::size_t>(m_xe.rows());
    std::vector<char>& extracting = m_scratch.extracting;
    extracting.assign(m_ctx.scene.cloths.size(), 0);
    for (std::size_t v = 0; v < n; ++v) {
        if (m_trapped[v] == m_ki) {
            extracting[static_cast<std::size_t>(m_mesh.clothOf[v])] = 1;
        }
    }
}

void ObstacleDetector::setOpenSides() {
    // The side of an open obstacle each vertex starts on is set by the first pair (in pair
    // order) that meets it, before the pairs are examined in parallel.
    const MatX3i& f = m_spec.triangles;
    for (const auto& [a, b] : m_scratch.pairs) {
        for (int p : m_mesh.ownedVertices[static_cast<std::size_t>(a)]) {
            signed char& open = m_o.openSide[static_cast<std::size_t>(p)];
            if (open == 0 && !trapped(p)) {
                const Vec3 ps = row(m_xs, p);
                const Vec3 b0[3] = {row(m_o.x0, f(b, 0)), row(m_o.x0, f(b, 1)),
                                    row(m_o.x0, f(b, 2))};
                const TrianglePoint cs = closestPointOnTriangle(ps, b0[0], b0[1], b0[2]);
                open = signOf(triangleNormal(b0[0], b0[1], b0[2]).dot(ps - cs.point));
                open = open == 0 ? 1 : open;
            }
        }
    }
}

void ObstacleDetector::friction(Contact& c, int clothVertex) const {
    const std::size_t cloth =
        static_cast<std::size_t>(m_mesh.clothOf[static_cast<std::size_t>(clothVertex)]);
    const Material& m = m_ctx.scene.cloths[cloth].material;
    const double scale = m_scratch.extracting[cloth] != 0 ? 0.0 : 1.0;
    c.staticFriction = scale * m_ctx.scaledFriction(m.staticFriction, m_spec.staticFriction);
    c.kineticFriction = scale * m_ctx.scaledFriction(m.kineticFriction, m_spec.kineticFriction);
    c.obstacle = m_ki;
}

ObstacleDetector::Frame ObstacleDetector::frameOf(const std::pair<int, int>& pair) const {
    const MatX3i& f = m_spec.triangles;
    Frame fr;
    fr.a = pair.first;
    fr.b = pair.second;
    for (int i = 0; i < 3; ++i) {
        fr.ob[i] = f(fr.b, i);
        fr.b0[i] = row(m_o.x0, fr.ob[i]);
        fr.b1[i] = row(m_o.x1, fr.ob[i]);
        fr.ca[i] = m_mesh.triangles(fr.a, i);
        fr.as[i] = row(m_xs, fr.ca[i]);
        fr.ae[i] = row(m_xe, fr.ca[i]);
    }
    fr.nb1 = triangleNormal(fr.b1[0], fr.b1[1], fr.b1[2]);
    fr.trappedCorner = trapped(fr.ca[0]) || trapped(fr.ca[1]) || trapped(fr.ca[2]);
    const double clothThickness = std::max(
        {m_mesh.thickness[fr.ca[0]], m_mesh.thickness[fr.ca[1]], m_mesh.thickness[fr.ca[2]]});
    fr.d0 = clothThickness + m_spec.thickness;
    return fr;
}

void ObstacleDetector::keep(DetectionChunk& out, const Contact& c, int feature0,
                            int feature1) const {
    out.contacts.push_back(c);
    if (m_which == ObstaclePass::First && m_mesh.anySelf) {
        out.features.push_back({feature0, feature1});
    }
}

// Cloth vertex p (owned by fr.a) against the obstacle's face.
void ObstacleDetector::vertexFace(DetectionChunk& out, const Frame& fr, int p) const {
    const int* ob = fr.ob;
    const Vec3* b0 = fr.b0;
    const Vec3* b1 = fr.b1;
    const Vec3& nb1 = fr.nb1;
    if (trapped(p)) {
        return;
    }
    const double d0 = m_mesh.thickness[p] + m_spec.thickness;
    const Vec3 pe = row(m_xe, p), ps = row(m_xs, p);
    const signed char side = m_spec.closed ? 1 : m_o.openSide[static_cast<std::size_t>(p)];
    const Vec3 faceSide = side * nb1;
    const TrianglePoint cp = closestPointOnTriangle(pe, b1[0], b1[1], b1[2]);
    Contact c;
    c.kind = Contact::Kind::VertexFace;
    c.vertex[0] = p;
    c.weight[0] = 1.0;
    c.distance = d0;
    if (cp.distance < d0 * m_factor) {
        const Vec3 d = pe - cp.point;
        c.normal =
            (d.dot(faceSide) > 0 && cp.distance > TINY_LENGTH) ? Vec3(d / cp.distance) : faceSide;
        c.obstaclePoint = cp.point;
        c.obstacleVelocity = cp.bary[0] * obstacleVelocity(ob[0]) +
                             cp.bary[1] * obstacleVelocity(ob[1]) +
                             cp.bary[2] * obstacleVelocity(ob[2]);
        c.setObstaclePoint(ob, cp.bary.data(), 3);
    } else if (m_swept && (m_o.moves || ps != pe)) {
        c.swept = true;
        // The swept tests look for crossings (distance 0): a pair that ends near is the
        // proximity test's; one that crossed during the step and ended apart is this one's.
        const auto hit = vertexCrosses(ps, pe, b0[0], b1[0], b0[1], b1[1], b0[2], b1[2]);
        if (!hit) {
            return;
        }
        ++out.continuousHits;
        c.normal = faceSide;
        c.obstaclePoint = hit->coords[0] * b1[0] + hit->coords[1] * b1[1] + hit->coords[2] * b1[2];
        c.obstacleVelocity = hit->coords[0] * obstacleVelocity(ob[0]) +
                             hit->coords[1] * obstacleVelocity(ob[1]) +
                             hit->coords[2] * obstacleVelocity(ob[2]);
        c.setObstaclePoint(ob, hit->coords.data(), 3);
    } else {
        return;
    }
    friction(c, p);
    keep(out, c, p, -1);
}

// Obstacle vertex q (owned by fr.b) against the cloth's face (a box corner poking the cloth).
void ObstacleDetector::faceVertex(DetectionChunk& out, const Frame& fr, int q) const {
    const MatX3i& f = m_spec.triangles;
    const int* ca = fr.ca;
    const Vec3* as = fr.as;
    const Vec3* ae = fr.ae;
    const double d0 = fr.d0;
    const Vec3 q0 = row(m_o.x0, q), q1 = row(m_o.x1, q);
    const TrianglePoint cp = closestPointOnTriangle(q1, ae[0], ae[1], ae[2]);
    const bool near = cp.distance < d0 * m_factor;
    std::optional<SweptHit> hit;
    if (!near) {
        if (!m_swept) {
            return;
        }
        hit = vertexCrosses(q0, q1, as[0], ae[0], as[1], ae[1], as[2], ae[2]);
        if (!hit) {
            return;
        }
        ++out.continuousHits;
    }
    // The cloth stays on the side of the obstacle vertex where it was at the start.
    const Vec3 nas = triangleNormal(as[0], as[1], as[2]);
    const TrianglePoint cs = closestPointOnTriangle(q0, as[0], as[1], as[2]);
    double sA = nas.dot(q0 - cs.point) >= 0 ? 1.0 : -1.0;
    if (m_spec.closed) {
        // Trust the obstacle's outside: the cloth point should be outside q's faces.
        Vec3 outward = Vec3::Zero();
        for (int t : m_o.vertexTriangles[static_cast<std::size_t>(q)]) {
            outward +=
                triangleNormal(row(m_o.x1, f(t, 0)), row(m_o.x1, f(t, 1)), row(m_o.x1, f(t, 2)));
        }
        const Vec3 nae = triangleNormal(ae[0], ae[1], ae[2]);
        if (outward.squaredNorm() > 0 && std::abs(outward.normalized().dot(nae)) > 0.5) {
            sA = outward.dot(nae) > 0 ? -1.0 : 1.0;
        }
    }
    const Vec3 away = -sA * triangleNormal(ae[0], ae[1], ae[2]);
    Contact c;
    c.kind = Contact::Kind::FaceVertex;
    c.swept = !near;
    c.distance = d0;
    const std::array<double, 3> bary = near ? cp.bary : hit->coords;
    for (int i = 0; i < 3; ++i) {
        c.vertex[i] = ca[i];
        c.weight[i] = bary[static_cast<std::size_t>(i)];
    }
    const Vec3 d = cp.point - q1;
    c.normal =
        (near && d.dot(away) > 0 && cp.distance > TINY_LENGTH) ? Vec3(d / cp.distance) : away;
    if (c.normal.squaredNorm() == 0) {
        return;
    }
    c.obstaclePoint = q1;
    c.obstacleVelocity = obstacleVelocity(q);
    const double one = 1.0;
    c.setObstaclePoint(&q, &one, 1);
    friction(c, ca[0]);
    keep(out, c, q, -1);
}

// Cloth edge e (owned by fr.a) against obstacle edge g (owned by fr.b).
void ObstacleDetector::edgeEdge(DetectionChunk& out, int e, int g) const {
    const MatX3i& f = m_spec.triangles;
    const CollisionObstacle& o = m_o;
    const MatX3& xs = m_xs;
    const MatX3& xe = m_xe;
    const int e0 = m_mesh.edges(e, 0), e1 = m_mesh.edges(e, 1);
    const double de0 = std::max(m_mesh.thickness[e0], m_mesh.thickness[e1]) + m_spec.thickness;
    const int g0 = o.edges(g, 0), g1 = o.edges(g, 1);
    const auto meeting =
        edgesMeet(row(xs, e0), row(xe, e0), row(xs, e1), row(xe, e1), row(o.x0, g0), row(o.x1, g0),
                  row(o.x0, g1), row(o.x1, g1), de0 * m_factor, m_swept);
    if (!meeting) {
        return;
    }
    const double s = meeting->s, t = meeting->t;
    const bool near = meeting->near;
    out.continuousHits += near ? 0 : 1;
    const Vec3 pe = (1 - s) * row(xe, e0) + s * row(xe, e1);
    const Vec3 qe = (1 - t) * row(o.x1, g0) + t * row(o.x1, g1);
    const Vec3 ds =
        ((1 - s) * row(xs, e0) + s * row(xs, e1)) - ((1 - t) * row(o.x0, g0) + t * row(o.x0, g1));
    const std::optional<Vec3> separation = edgeSeparation(pe - qe, ds, near);
    Vec3 normal;
    if (separation) {
        normal = *separation;
    } else { // the obstacle edge's normal
        const auto& et = o.edgeTriangles[static_cast<std::size_t>(g)];
        normal =
            triangleNormal(row(o.x1, f(et[0], 0)), row(o.x1, f(et[0], 1)), row(o.x1, f(et[0], 2)));
        if (et[1] >= 0) {
            normal += triangleNormal(row(o.x1, f(et[1], 0)), row(o.x1, f(et[1], 1)),
                                     row(o.x1, f(et[1], 2)));
        }
        if (normal.norm() < TINY_LENGTH) {
            return;
        }
        normal.normalize();
    }
    Contact c;
    c.kind = Contact::Kind::EdgeEdge;
    c.swept = !near;
    c.vertex[0] = e0;
    c.vertex[1] = e1;
    c.weight[0] = 1 - s;
    c.weight[1] = s;
    c.distance = de0;
    c.normal = normal;
    c.obstaclePoint = qe;
    c.obstacleVelocity = (1 - t) * obstacleVelocity(g0) + t * obstacleVelocity(g1);
    const int ge[2] = {g0, g1};
    const double gw[2] = {1 - t, t};
    c.setObstaclePoint(ge, gw, 2);
    friction(c, e0);
    keep(out, c, e, g);
}

void ObstacleDetector::testPair(DetectionChunk& out, const std::pair<int, int>& pair) const {
    const Frame fr = frameOf(pair);
    for (int p : m_mesh.ownedVertices[static_cast<std::size_t>(fr.a)]) {
        vertexFace(out, fr, p);
    }
    if (fr.trappedCorner) {
        return;
    }
    for (int q : m_o.ownedVertices[static_cast<std::size_t>(fr.b)]) {
        faceVertex(out, fr, q);
    }
    for (int e : m_mesh.ownedEdges[static_cast<std::size_t>(fr.a)]) {
        for (int g : m_o.ownedEdges[static_cast<std::size_t>(fr.b)]) {
            edgeEdge(out, e, g);
        }
    }
}

DetectionResult ObstacleDetector::again() {
    // A triangle none of whose corners moved since First is where First tested it: its
    // proximity contacts are First's, apart from the normals taken from where the cloth
    // started (face–vertex sides, edge–edge directions), which are tested again at xe.
    const CollisionObstacle& o = m_o;
    std::vector<char>& moved = m_scratch.movedTriangle;
    moved.assign(static_cast<std::size_t>(m_mesh.triangles.rows()), 0);
    for (int t = 0; t < m_mesh.triangles.rows(); ++t) {
        for (int i = 0; i < 3; ++i) {
            const int v = m_mesh.triangles(t, i);
            if (m_xe.row(v) != o.firstPositions.row(v)) {
                moved[static_cast<std::size_t>(t)] = 1;
            }
        }
    }
    const std::pair<int, int>* pairs = m_scratch.pairs.data();
    DetectionResult result;
    result.pieces = m_scratch.inChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
        if (moved[static_cast<std::size_t>(pair.first)] != 0) {
            testPair(out, pair);
            return;
        }
        const std::size_t i = static_cast<std::size_t>(&pair - pairs);
        std::optional<Frame> fr;
        for (int j = o.firstNearStart[i]; j < o.firstNearStart[i + 1]; ++j) {
            const Contact& c = o.firstNear[static_cast<std::size_t>(j)];
            const std::array<int, 2>& feature = o.firstFeature[static_cast<std::size_t>(j)];
            if (c.kind == Contact::Kind::VertexFace) {
                out.contacts.push_back(c);
            } else if (c.kind == Contact::Kind::FaceVertex) {
                if (!fr) {
                    fr = frameOf(pair);
                }
                faceVertex(out, *fr, feature[0]);
            } else {
                edgeEdge(out, feature[0], feature[1]);
            }
        }
    });
    for (const auto& pair : m_scratch.pairs) {
        result.candidatePairs += moved[static_cast<std::size_t>(pair.first)];
    }
    return result;
}

DetectionResult ObstacleDetector::first() {
    const bool remember = m_mesh.anySelf;
    if (remember) {
        m_o.firstNearStart.assign(m_scratch.pairs.size() + 1, 0);
    }
    const std::pair<int, int>* pairs = m_scratch.pairs.data();
    DetectionResult result;
    result.candidatePairs = static_cast<long>(m_scratch.pairs.size());
    result.pieces = m_scratch.inChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
        const std::size_t before = out.contacts.size();
        testPair(out, pair);
        if (remember) {
            int near = 0;
            for (std::size_t j = before; j < out.contacts.size(); ++j) {
                near += out.contacts[j].swept ? 0 : 1;
            }
            m_o.firstNearStart[static_cast<std::size_t>(&pair - pairs) + 1] = near;
        }
    });
    if (remember) {
        rememberFirst(result.pieces);
    }
    return result;
}

void ObstacleDetector::rememberFirst(std::size_t used) {
    CollisionObstacle& o = m_o;
    for (std::size_t i = 1; i < o.firstNearStart.size(); ++i) {
        o.firstNearStart[i] += o.firstNearStart[i - 1];
    }
    o.firstPairs = m_scratch.pairs;
    o.firstPositions = m_xe;
    o.firstNear.clear();
    o.firstFeature.clear();
    // Every contact of the First pass has its features (keep), in the same order.
    for (std::size_t c = 0; c < used; ++c) {
        const DetectionChunk& chunk = m_scratch.chunks[c];
        for (std::size_t j = 0; j < chunk.features.size(); ++j) {
            const Contact& contact = chunk.contacts[j];
            if (!contact.swept) {
                o.firstNear.push_back(contact);
                o.firstFeature.push_back(chunk.features[j]);
            }
        }
    }
}

DetectionResult ObstacleDetector::run() {
    // Again: the hierarchies have not been refitted since First, so its pairs are the same.
    if (m_which == ObstaclePass::First) {
        m_scratch.pairs.clear();
        m_ctx.clothBvh.overlaps(m_o.bvh, m_scratch.pairs);
    } else {
        m_scratch.pairs = m_o.firstPairs;
    }
    markExtracting();
    if (!m_spec.closed) {
        setOpenSides();
    }
    return m_which == ObstaclePass::Again ? again() : first();
}

} // namespace

DetectionResult detectObstacleContacts(const DetectionContext& ctx, std::size_t k,
                                       CollisionObstacle& o, const std::vector<int>& trapped,
                                       double h, const MatX3& xs, const MatX3& xe,
                                       ObstaclePass which, DetectionScratch& scratch) {
    return ObstacleDetector(ctx, k, o, trapped, h, xs, xe, which, scratch).run();
}

} // namespace atelier::sim
