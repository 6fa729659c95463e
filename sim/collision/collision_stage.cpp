#include "sim/collision/collision_stage.h"

#include "sim/collision/geometry.h"
#include "sim/collision/obstacle.h"
#include "sim/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <queue>

namespace atelier::sim {

namespace {

constexpr double INF = std::numeric_limits<double>::infinity();
/// Below this length [m] a direction is taken as undefined.
constexpr double TINY = 1e-12;
/// Contacts whose gap is within this fraction of the contact distance count as touching.
constexpr double TOUCH = 0.01;

std::uint64_t pairKey(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
}

Vec3 row(const MatX3& x, int i) { return x.row(i).transpose(); }

/// Whether the boxes swept by two groups of moving points (start/end pairs) come within d:
/// a cheap test before the continuous ones.
template <std::size_t N, std::size_t M>
bool sweptBoxesNear(const std::array<const Vec3*, N>& a, const std::array<const Vec3*, M>& b,
                    double d) {
    Vec3 alo = *a[0], ahi = *a[0], blo = *b[0], bhi = *b[0];
    for (const Vec3* p : a) {
        alo = alo.cwiseMin(*p);
        ahi = ahi.cwiseMax(*p);
    }
    for (const Vec3* p : b) {
        blo = blo.cwiseMin(*p);
        bhi = bhi.cwiseMax(*p);
    }
    return (alo.array() <= bhi.array() + d).all() && (blo.array() <= ahi.array() + d).all();
}

/// Whether a segment parameter is strictly inside (not at an end).
bool interior(double s) { return s > 1e-9 && s < 1.0 - 1e-9; }

/// The direction in which two meeting edges must stay apart: the one between their meeting
/// points at the end (de) where they are near and have not turned over since the start (ds),
/// else the one at the start; none when both are too short to tell.
std::optional<Vec3> edgeSeparation(const Vec3& de, const Vec3& ds, bool near) {
    if (near && de.dot(ds) > 0 && de.norm() > TINY) {
        return de.normalized();
    }
    if (ds.norm() > TINY) {
        return ds.normalized();
    }
    return std::nullopt;
}

/// When a point moving p0 → p1 passes through the triangle (a, b, c), each corner moving
/// …0 → …1, during the step (first contact), if it does; only where the swept boxes overlap.
std::optional<SweptHit> vertexCrosses(const Vec3& p0, const Vec3& p1, const Vec3& a0, const Vec3& a1,
                                      const Vec3& b0, const Vec3& b1, const Vec3& c0, const Vec3& c1) {
    if (!sweptBoxesNear<2, 6>({&p0, &p1}, {&a0, &a1, &b0, &b1, &c0, &c1}, 0.0)) {
        return std::nullopt;
    }
    return sweptVertexTriangle(p0, p1, a0, a1, b0, b1, c0, c1, 0.0);
}

/// Where edge (a, b) meets edge (c, d), each end moving from …0 to …1 over the step: the
/// closest points at the end when interior to both and closer than `reach` (`near`), else, if
/// `swept`, interior points that meet during the step. Where the closest points are an end, the
/// vertex–face tests cover it, and the direction between them is not a surface normal.
struct EdgeMeeting {
    double s = 0, t = 0; ///< parameters along (a, b) and (c, d)
    bool near = false;
};
std::optional<EdgeMeeting> edgesMeet(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                     const Vec3& c0, const Vec3& c1, const Vec3& d0, const Vec3& d1,
                                     double reach, bool swept) {
    if (!sweptBoxesNear<4, 4>({&a0, &a1, &b0, &b1}, {&c0, &c1, &d0, &d1}, reach)) {
        return std::nullopt;
    }
    const SegmentPoints sp = closestPointsOfSegments(a1, b1, c1, d1);
    if (sp.distance < reach && interior(sp.s) && interior(sp.t)) {
        return EdgeMeeting{sp.s, sp.t, true};
    }
    // The swept test looks for a crossing: the swept boxes must overlap.
    if (!swept || !sweptBoxesNear<4, 4>({&a0, &a1, &b0, &b1}, {&c0, &c1, &d0, &d1}, 0.0)) {
        return std::nullopt;
    }
    const auto hit = sweptEdgeEdge(a0, a1, b0, b1, c0, c1, d0, d1, 0.0);
    if (!hit || !interior(hit->coords[0]) || !interior(hit->coords[1])) {
        return std::nullopt;
    }
    return EdgeMeeting{hit->coords[0], hit->coords[1], false};
}

double combine(double a, double b) { return std::sqrt(std::max(0.0, a) * std::max(0.0, b)); }

signed char signOf(double v) { return v > 0 ? 1 : (v < 0 ? -1 : 0); }

/// Σ w_k invMass_k w_k over the contact's cloth vertices.
double effectiveInverseMass(const Contact& c, const VecX& invMass) {
    double w = 0;
    for (int k = 0; k < 4; ++k) {
        if (c.vertex[k] >= 0) {
            w += c.weight[k] * c.weight[k] * invMass[c.vertex[k]];
        }
    }
    return w;
}

Vec3 combination(const Contact& c, const MatX3& x) {
    Vec3 r = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
        if (c.vertex[k] >= 0) {
            r += c.weight[k] * row(x, c.vertex[k]);
        }
    }
    return r;
}

/// Adds `delta` to the contact's relative quantity, split by inverse mass:
/// each vertex moves by w_k invMass_k / W · delta, so Σ w_k Δ_k = delta.
void distribute(const Contact& c, const VecX& invMass, double w, const Vec3& delta, MatX3& y) {
    for (int k = 0; k < 4; ++k) {
        const int i = c.vertex[k];
        if (i >= 0 && invMass[i] > 0) {
            y.row(i) += (c.weight[k] * invMass[i] / w * delta).transpose();
        }
    }
}

/// The velocity-level contact and Coulomb friction of one contact on velocities v: raises the
/// relative normal velocity to at least `minNormal` [m/s] (0: no approach), then, if
/// `friction`, cancels the tangential velocity when it is within the static cone of that
/// impulse, or reduces it by the kinetic friction.
void velocityCorrection(const Contact& c, const VecX& invMass, MatX3& v, double minNormal,
                        bool friction) {
    const double w = effectiveInverseMass(c, invMass);
    if (!(w > 0)) {
        return;
    }
    const Vec3 u = combination(c, v) - c.obstacleVelocity;
    const double un = c.normal.dot(u);
    if (un >= minNormal) {
        return;
    }
    const double jn = minNormal - un;
    Vec3 delta = jn * c.normal;
    if (friction && c.grip != Contact::Grip::Slip) {
        const Vec3 ut = u - un * c.normal;
        const double utn = ut.norm();
        if ((c.grip == Contact::Grip::Stick && c.staticFriction > 0) || utn <= c.staticFriction * jn) {
            delta -= ut;
        } else if (utn > 0) {
            delta -= (c.kineticFriction * jn / utn) * ut;
        }
    }
    distribute(c, invMass, w, delta, v);
}

/// Angle of triangle (a, b, c) at a [rad].
double cornerAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 u = b - a, w = c - a;
    return std::atan2(u.cross(w).norm(), u.dot(w));
}

} // namespace

double CollisionStage::scaledFriction(double a, double b) const {
    return m_frictionScale * combine(a, b);
}

bool CollisionStage::needed(const SceneSpec& scene) {
    if (!scene.obstacles.empty()) {
        return true;
    }
    return std::any_of(scene.cloths.begin(), scene.cloths.end(),
                       [](const ClothSpec& c) { return c.selfCollision; });
}

CollisionStage::CollisionStage(const SceneSpec& scene, const std::vector<int>& offsets,
                               const MatX3& x)
    : m_scene(scene), m_offsets(offsets) {
    const int n = offsets.back();
    // Sewn vertices are one vertex for adjacency: their triangles touch by design.
    m_alias.resize(static_cast<std::size_t>(n));
    std::iota(m_alias.begin(), m_alias.end(), 0);
    auto root = [&](int v) {
        while (m_alias[static_cast<std::size_t>(v)] != v) {
            v = m_alias[static_cast<std::size_t>(v)];
        }
        return v;
    };
    for (const SeamPair& sp : scene.seams) {
        const int ra = root(sp.a), rb = root(sp.b);
        if (ra != rb) {
            m_alias[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
        }
    }
    for (int v = 0; v < n; ++v) {
        m_alias[static_cast<std::size_t>(v)] = root(v);
    }
    m_clothOf.assign(static_cast<std::size_t>(n), 0);
    m_thickness.resize(n);
    int triangleCount = 0, edgeCount = 0;
    for (const ClothSpec& c : scene.cloths) {
        triangleCount += c.mesh.triangleCount();
        edgeCount += static_cast<int>(c.mesh.edges.rows());
    }
    m_triangles.resize(triangleCount, 3);
    m_edges.resize(edgeCount, 2);
    m_ownedVertices.assign(static_cast<std::size_t>(triangleCount), {});
    m_ownedEdges.assign(static_cast<std::size_t>(triangleCount), {});
    m_neighbours.assign(static_cast<std::size_t>(n), {});
    std::vector<char> owned(static_cast<std::size_t>(n), 0);
    m_vertexTriangle.assign(static_cast<std::size_t>(n), 0);
    int t0 = 0, e0 = 0;
    for (std::size_t ci = 0; ci < scene.cloths.size(); ++ci) {
        const ClothSpec& c = scene.cloths[ci];
        const int off = offsets[ci];
        m_selfCloth.push_back(c.selfCollision ? 1 : 0);
        m_anySelf = m_anySelf || c.selfCollision;
        m_maxThickness = std::max(m_maxThickness, c.thickness);
        for (int i = 0; i < c.mesh.vertexCount(); ++i) {
            m_clothOf[static_cast<std::size_t>(off + i)] = static_cast<int>(ci);
            m_thickness[off + i] = c.thickness;
        }
        for (int t = 0; t < c.mesh.triangleCount(); ++t) {
            m_triangleCloth.push_back(static_cast<int>(ci));
            for (int k = 0; k < 3; ++k) {
                const int v = c.mesh.triangles(t, k) + off;
                m_triangles(t0 + t, k) = v;
                if (!owned[static_cast<std::size_t>(v)]) {
                    owned[static_cast<std::size_t>(v)] = 1;
                    m_vertexTriangle[static_cast<std::size_t>(v)] = t0 + t;
                    m_ownedVertices[static_cast<std::size_t>(t0 + t)].push_back(v);
                }
            }
        }
        for (int e = 0; e < c.mesh.edges.rows(); ++e) {
            const int a = c.mesh.edges(e, 0) + off, b = c.mesh.edges(e, 1) + off;
            m_edges(e0 + e, 0) = a;
            m_edges(e0 + e, 1) = b;
            m_ownedEdges[static_cast<std::size_t>(t0 + c.mesh.edgeTriangles(e, 0))].push_back(e0 + e);
            m_neighbours[static_cast<std::size_t>(a)].push_back(b);
            m_neighbours[static_cast<std::size_t>(b)].push_back(a);
        }
        t0 += c.mesh.triangleCount();
        e0 += static_cast<int>(c.mesh.edges.rows());
    }
    m_clothBvh = SurfaceBvh(m_triangles, x);

    for (const ObstacleSpec& spec : scene.obstacles) {
        ObstacleData o;
        o.spec = &spec;
        o.moves = obstacleMoves(spec);
        obstaclePositionsAt(spec, 0.0, o.x1);
        o.x0 = o.x1;
        const int nv = static_cast<int>(spec.vertices.rows());
        const int nt = static_cast<int>(spec.triangles.rows());
        o.vertexTriangles.assign(static_cast<std::size_t>(nv), {});
        o.vertexOwner.assign(static_cast<std::size_t>(nv), -1);
        o.ownedVertices.assign(static_cast<std::size_t>(nt), {});
        o.ownedEdges.assign(static_cast<std::size_t>(nt), {});
        std::vector<std::array<int, 2>> edges;
        for (int t = 0; t < nt; ++t) {
            for (int k = 0; k < 3; ++k) {
                const int a = spec.triangles(t, k), b = spec.triangles(t, (k + 1) % 3);
                o.vertexTriangles[static_cast<std::size_t>(a)].push_back(t);
                if (o.vertexOwner[static_cast<std::size_t>(a)] < 0) {
                    o.vertexOwner[static_cast<std::size_t>(a)] = t;
                    o.ownedVertices[static_cast<std::size_t>(t)].push_back(a);
                }
                const std::uint64_t key = pairKey(std::min(a, b), std::max(a, b));
                const auto [it, inserted] = o.edgeIndex.emplace(key, static_cast<int>(edges.size()));
                if (inserted) {
                    edges.push_back({std::min(a, b), std::max(a, b)});
                    o.edgeTriangles.push_back({t, -1});
                    o.ownedEdges[static_cast<std::size_t>(t)].push_back(it->second);
                } else {
                    o.edgeTriangles[static_cast<std::size_t>(it->second)][1] = t;
                }
            }
        }
        o.edges.resize(static_cast<Eigen::Index>(edges.size()), 2);
        for (std::size_t e = 0; e < edges.size(); ++e) {
            o.edges(static_cast<Eigen::Index>(e), 0) = edges[e][0];
            o.edges(static_cast<Eigen::Index>(e), 1) = edges[e][1];
        }
        o.bvh = SurfaceBvh(spec.triangles, o.x1);
        m_obstacles.push_back(std::move(o));
    }
    m_trapped.assign(static_cast<std::size_t>(n), -1);
    m_openSide.assign(static_cast<std::size_t>(n) * m_obstacles.size(), 0);
    m_distanceValue.assign(static_cast<std::size_t>(n) * m_obstacles.size(),
                           std::numeric_limits<double>::quiet_NaN());
    m_distancePoint.resize(static_cast<Eigen::Index>(n) * static_cast<Eigen::Index>(m_obstacles.size()), 3);
}

bool CollisionStage::routeAround(const Vec3& p, const Vec3& q, double clearance,
                                 Vec3& via) const {
    // Only a chord that enters an obstacle is routed. One that merely passes within the
    // clearance is the normal case for a seam lying on the body (its ends rest a contact
    // distance off it, and on a convex part the chord dips below that); routing those pulled
    // both ends outwards instead of together, and the tshirt's armpit seams stayed 3-4 cm open.
    double deepest = 0;
    for (std::size_t k = 0; k < m_obstacles.size(); ++k) {
        if (!m_obstacles[k].spec->closed) {
            continue;
        }
        for (const double s : {0.5, 0.25, 0.75}) {
            const Vec3 point = (1 - s) * p + s * q;
            Vec3 closest, outward;
            const double d = signedDistance(k, m_obstacles[k].x1, point, INF, &closest, &outward);
            if (d < deepest) {
                deepest = d;
                via = closest + clearance * outward;
            }
        }
    }
    return deepest < 0;
}

double CollisionStage::signedDistance(std::size_t k, const MatX3& xo, const Vec3& p,
                                      double maxDistance, Vec3* closest, Vec3* outward) const {
    const ObstacleData& o = m_obstacles[k];
    const auto [tri, cp] = o.bvh.closestTriangle(xo, p, maxDistance);
    if (tri < 0) {
        return INF;
    }
    const MatX3i& f = o.spec->triangles;
    const int ids[3] = {f(tri, 0), f(tri, 1), f(tri, 2)};
    auto faceNormal = [&](int t) {
        return triangleNormal(row(xo, f(t, 0)), row(xo, f(t, 1)), row(xo, f(t, 2)));
    };
    // Angle-weighted pseudo-normal of the closest feature (Bærentzen & Aanæs 2005): its sign
    // against p − closest tells inside from outside exactly for a closed oriented mesh.
    int zeros = 0;
    for (double b : cp.bary) {
        zeros += b <= 1e-12 ? 1 : 0;
    }
    Vec3 pseudo = faceNormal(tri);
    if (zeros == 2) {
        int v = ids[0];
        for (int i = 0; i < 3; ++i) {
            if (cp.bary[static_cast<std::size_t>(i)] > 1e-12) {
                v = ids[i];
            }
        }
        pseudo.setZero();
        for (int t : o.vertexTriangles[static_cast<std::size_t>(v)]) {
            int corner = 0;
            for (int i = 0; i < 3; ++i) {
                corner = f(t, i) == v ? i : corner;
            }
            const double angle = cornerAngle(row(xo, f(t, corner)), row(xo, f(t, (corner + 1) % 3)),
                                             row(xo, f(t, (corner + 2) % 3)));
            pseudo += angle * faceNormal(t);
        }
    } else if (zeros == 1) {
        int a = -1, b = -1;
        for (int i = 0; i < 3; ++i) {
            if (cp.bary[static_cast<std::size_t>(i)] > 1e-12) {
                (a < 0 ? a : b) = ids[i];
            }
        }
        const auto it = o.edgeIndex.find(pairKey(std::min(a, b), std::max(a, b)));
        if (it != o.edgeIndex.end()) {
            const auto& et = o.edgeTriangles[static_cast<std::size_t>(it->second)];
            pseudo = faceNormal(et[0]) + (et[1] >= 0 ? faceNormal(et[1]) : Vec3::Zero());
        }
    }
    const Vec3 d = p - cp.point;
    const double sign = d.dot(pseudo) >= 0 ? 1.0 : -1.0;
    if (closest != nullptr) {
        *closest = cp.point;
    }
    if (outward != nullptr) {
        *outward = cp.distance > TINY ? Vec3(sign * d / cp.distance)
                                      : Vec3(pseudo.normalized());
    }
    return sign * cp.distance;
}

double CollisionStage::vertexSignedDistance(std::size_t k, int p, const Vec3& xp, double enough) {
    const ObstacleData& o = m_obstacles[k];
    const std::size_t i = k * static_cast<std::size_t>(m_clothOf.size()) + static_cast<std::size_t>(p);
    if (!o.moves && std::isfinite(m_distanceValue[i])) {
        const double bound =
            m_distanceValue[i] - (xp - m_distancePoint.row(static_cast<Eigen::Index>(i)).transpose()).norm();
        if (bound >= enough) {
            return bound;
        }
    }
    const double sd = signedDistance(k, o.x1, xp, INF);
    if (!o.moves) {
        m_distanceValue[i] = sd;
        m_distancePoint.row(static_cast<Eigen::Index>(i)) = xp.transpose();
    }
    return sd;
}

void CollisionStage::findTrapped(std::size_t k, const MatX3& x) {
    ObstacleData& o = m_obstacles[k];
    if (!o.spec->closed || o.bvh.empty()) {
        return;
    }
    // A vertex outside the obstacle's 26-sided hull (its extent along 13 directions: the axes,
    // the face and the body diagonals) is outside the obstacle: no distance query. Without it,
    // the query from a point far above a smooth surface visits a cap of leaves that grows with
    // the distance (the first check of a large sheet cost more than N log N).
    static const std::array<Vec3, 13> directions = {
        Vec3(1, 0, 0),  Vec3(0, 1, 0),  Vec3(0, 0, 1),  Vec3(1, 1, 0),  Vec3(1, -1, 0),
        Vec3(1, 0, 1),  Vec3(1, 0, -1), Vec3(0, 1, 1),  Vec3(0, 1, -1), Vec3(1, 1, 1),
        Vec3(1, 1, -1), Vec3(1, -1, 1), Vec3(-1, 1, 1)};
    std::array<double, 13>& lo = o.hullLo;
    std::array<double, 13>& hi = o.hullHi;
    if (o.moves || !o.hullFitted) { // a static obstacle's once
        lo.fill(INF);
        hi.fill(-INF);
        for (Eigen::Index v = 0; v < o.x1.rows(); ++v) {
            const Vec3 q = row(o.x1, static_cast<int>(v));
            for (std::size_t d = 0; d < directions.size(); ++d) {
                const double s = directions[d].dot(q);
                lo[d] = std::min(lo[d], s);
                hi[d] = std::max(hi[d], s);
            }
        }
        o.hullFitted = true;
    }
    const auto outsideHull = [&](const Vec3& p) {
        for (std::size_t d = 0; d < directions.size(); ++d) {
            const double s = directions[d].dot(p);
            if (s < lo[d] || s > hi[d]) {
                return true;
            }
        }
        return false;
    };
    // Each vertex on its own (its own slots of m_trapped and of the distance cache).
    const std::int64_t nv = x.rows();
    parallelFor(nv, [&](std::int64_t pp) {
        const int p = static_cast<int>(pp);
        if (m_trapped[static_cast<std::size_t>(p)] >= 0 || outsideHull(row(x, p))) {
            return;
        }
        const double reach = (m_thickness[p] + o.spec->thickness) *
                             (1.0 + m_scene.collision.proximityFactor);
        if (vertexSignedDistance(k, p, row(x, p), -reach) < -reach) {
            m_trapped[static_cast<std::size_t>(p)] = static_cast<int>(k);
        }
    });
}

void CollisionStage::extractTrapped(std::size_t k, double h, MatX3& xe, MatX3& ve) {
    const ObstacleData& o = m_obstacles[k];
    const int ki = static_cast<int>(k);
    std::vector<int> trapped;
    for (int p = 0; p < xe.rows(); ++p) {
        if (m_trapped[static_cast<std::size_t>(p)] != ki) {
            continue;
        }
        // Contacts take over once the vertex is out. Released within the contact reach but still
        // inside, it was pushed out along the surface's normal in one step while its trapped
        // neighbours headed for the entry, and the triangles across the surface got contacts
        // whose sides were taken where they crossed it: through-body ended with its sheet
        // stretched 4.5 times and 24 cloth–body pairs pierced.
        if (signedDistance(k, o.x1, row(xe, p), INF) >= 0) {
            m_trapped[static_cast<std::size_t>(p)] = -1;
        } else {
            trapped.push_back(p);
        }
    }
    if (trapped.empty() || !(h > 0)) {
        return;
    }
    // Each trapped vertex is carried out where the cloth around it enters the obstacle (the side
    // it came from), not to the nearest surface, which for a deep vertex may be the far side.
    // The entries are the surface points nearest the free vertices bordering the trapped part;
    // each trapped vertex heads for the one nearest it along the cloth (Dijkstra over the current
    // edge lengths). The headings are then averaged over trapped neighbours, so that the trapped
    // part slides out as one piece: sent each to its own nearest entry, neighbours were pulled
    // toward entries far apart (edges stretched 2.5 times) or onto one point, where they crossed.
    const std::size_t n = static_cast<std::size_t>(xe.rows());
    auto isTrapped = [&](int v) { return m_trapped[static_cast<std::size_t>(v)] == ki; };
    std::vector<Vec3> entries;
    std::vector<double>& dist = m_extractDistance;
    std::vector<int>& source = m_extractSource;
    std::vector<int>& slot = m_extractSlot;
    dist.assign(n, INF);
    source.assign(n, -1);
    slot.assign(n, -1);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (int p : trapped) {
        for (int f : m_neighbours[static_cast<std::size_t>(p)]) {
            if (isTrapped(f) || source[static_cast<std::size_t>(f)] >= 0) {
                continue;
            }
            Vec3 closest, outward;
            if (std::isfinite(signedDistance(k, o.x1, row(xe, f), INF, &closest, &outward))) {
                const double d0 = m_thickness[f] + o.spec->thickness;
                source[static_cast<std::size_t>(f)] = static_cast<int>(entries.size());
                entries.push_back(closest + 1.5 * d0 * outward);
                dist[static_cast<std::size_t>(f)] = 0;
                queue.emplace(0.0, f);
            }
        }
    }
    while (!queue.empty()) {
        const auto [d, u] = queue.top();
        queue.pop();
        if (d > dist[static_cast<std::size_t>(u)]) {
            continue;
        }
        for (int q : m_neighbours[static_cast<std::size_t>(u)]) {
            const double dq = d + (row(xe, q) - row(xe, u)).norm();
            if (isTrapped(q) && dq < dist[static_cast<std::size_t>(q)]) {
                dist[static_cast<std::size_t>(q)] = dq;
                source[static_cast<std::size_t>(q)] = source[static_cast<std::size_t>(u)];
                queue.emplace(dq, q);
            }
        }
    }
    // Target and heading of each trapped vertex (a part with no free border, wholly inside,
    // heads for the nearest surface).
    std::vector<Vec3> target(trapped.size()), heading(trapped.size());
    for (std::size_t i = 0; i < trapped.size(); ++i) {
        const int p = trapped[i];
        slot[static_cast<std::size_t>(p)] = static_cast<int>(i);
        const int s = source[static_cast<std::size_t>(p)];
        if (s >= 0) {
            target[i] = entries[static_cast<std::size_t>(s)];
        } else {
            Vec3 closest, outward;
            signedDistance(k, o.x1, row(xe, p), INF, &closest, &outward);
            target[i] = closest + 1.5 * (m_thickness[p] + o.spec->thickness) * outward;
        }
        const Vec3 to = target[i] - row(xe, p);
        heading[i] = to.norm() > TINY ? Vec3(to.normalized()) : Vec3::Zero();
    }
    constexpr int SMOOTHING_PASSES = 8;
    std::vector<Vec3> next(trapped.size());
    for (int pass = 0; pass < SMOOTHING_PASSES; ++pass) {
        for (std::size_t i = 0; i < trapped.size(); ++i) {
            Vec3 sum = heading[i];
            for (int q : m_neighbours[static_cast<std::size_t>(trapped[i])]) {
                const int j = slot[static_cast<std::size_t>(q)];
                if (j >= 0) {
                    sum += heading[static_cast<std::size_t>(j)];
                }
            }
            next[i] = sum.norm() > TINY ? Vec3(sum.normalized()) : heading[i];
        }
        heading.swap(next);
    }
    const double maxMove = m_scene.collision.extractionSpeed * h;
    for (std::size_t i = 0; i < trapped.size(); ++i) {
        const int p = trapped[i];
        const Vec3 to = target[i] - row(xe, p);
        if (to.norm() <= TINY) {
            continue;
        }
        // Headings that the average turned away from the vertex's own entry go straight there.
        const Vec3 dir = heading[i].dot(to) > 0 ? heading[i] : Vec3(to.normalized());
        xe.row(p) += (std::min(maxMove, to.norm()) * dir).transpose();
        ve.row(p).setZero();
    }
}

template <class Body>
std::size_t CollisionStage::detectInChunks(Body&& body) {
    const std::int64_t n = static_cast<std::int64_t>(m_pairs.size());
    const std::size_t used = static_cast<std::size_t>(chunkCount(n));
    if (m_chunks.size() < used) {
        m_chunks.resize(used);
    }
    parallelChunks(n, [&](std::int64_t c, std::int64_t begin, std::int64_t end) {
        DetectionChunk& out = m_chunks[static_cast<std::size_t>(c)];
        out.clear();
        for (std::int64_t i = begin; i < end; ++i) {
            body(out, m_pairs[static_cast<std::size_t>(i)]);
        }
    });
    return used;
}

void CollisionStage::gatherChunks(std::size_t used) {
    // Self contacts carry keys, sides and reliability; obstacle contacts none (0, 0, 1).
    m_contactKey.resize(m_contacts.size(), 0);
    m_contactSide.resize(m_contacts.size(), 0);
    m_contactReliable.resize(m_contacts.size(), 1);
    for (std::size_t c = 0; c < used; ++c) {
        const DetectionChunk& chunk = m_chunks[c];
        m_contacts.insert(m_contacts.end(), chunk.contacts.begin(), chunk.contacts.end());
        if (chunk.keys.size() == chunk.contacts.size()) {
            m_contactKey.insert(m_contactKey.end(), chunk.keys.begin(), chunk.keys.end());
            m_contactSide.insert(m_contactSide.end(), chunk.sides.begin(), chunk.sides.end());
            m_contactReliable.insert(m_contactReliable.end(), chunk.reliable.begin(), chunk.reliable.end());
        } else {
            m_contactKey.resize(m_contacts.size(), 0);
            m_contactSide.resize(m_contacts.size(), 0);
            m_contactReliable.resize(m_contacts.size(), 1);
        }
        m_figures.continuousHits += chunk.continuousHits;
    }
}

void CollisionStage::detectObstacle(std::size_t k, double h, const MatX3& xs, const MatX3& xe,
                                    Detection which) {
    ObstacleData& o = m_obstacles[k];
    const ObstacleSpec& spec = *o.spec;
    const int ki = static_cast<int>(k);
    const double factor = 1.0 + m_scene.collision.proximityFactor;
    const bool swept = which == Detection::First && m_scene.collision.continuous && h > 0;
    const MatX3i& f = spec.triangles;
    const std::size_t n = static_cast<std::size_t>(xe.rows());
    // Again: the hierarchies have not been refitted since First, so its pairs are the same.
    if (which == Detection::First) {
        m_pairs.clear();
        m_clothBvh.overlaps(o.bvh, m_pairs);
        m_figures.candidatePairs += static_cast<long>(m_pairs.size());
    } else {
        m_pairs = o.firstPairs;
    }
    auto obstacleVelocity = [&](int v) -> Vec3 {
        return (o.moves && h > 0) ? Vec3((row(o.x1, v) - row(o.x0, v)) / h) : Vec3::Zero();
    };
    auto trapped = [&](int v) { return m_trapped[static_cast<std::size_t>(v)] == ki; };
    // A cloth being carried out of this obstacle slides on it freely until it is out: held by
    // friction where it enters, it would bunch there instead of being drawn out.
    std::vector<char>& extracting = m_extracting;
    extracting.assign(m_scene.cloths.size(), 0);
    for (std::size_t v = 0; v < n; ++v) {
        if (m_trapped[v] == ki) {
            extracting[static_cast<std::size_t>(m_clothOf[v])] = 1;
        }
    }
    auto friction = [&](Contact& c, int clothVertex) {
        const std::size_t cloth = static_cast<std::size_t>(m_clothOf[static_cast<std::size_t>(clothVertex)]);
        const Material& m = m_scene.cloths[cloth].material;
        const double scale = extracting[cloth] != 0 ? 0.0 : 1.0;
        c.staticFriction = scale * scaledFriction(m.staticFriction, spec.staticFriction);
        c.kineticFriction = scale * scaledFriction(m.kineticFriction, spec.kineticFriction);
        c.obstacle = ki;
    };
    // The side of an open obstacle each vertex starts on is set by the first pair (in m_pairs
    // order) that meets it, before the pairs are examined in parallel.
    if (!spec.closed) {
        for (const auto& [a, b] : m_pairs) {
            for (int p : m_ownedVertices[static_cast<std::size_t>(a)]) {
                signed char& open = m_openSide[k * n + static_cast<std::size_t>(p)];
                if (open == 0 && !trapped(p)) {
                    const Vec3 ps = row(xs, p);
                    const Vec3 b0[3] = {row(o.x0, f(b, 0)), row(o.x0, f(b, 1)), row(o.x0, f(b, 2))};
                    const TrianglePoint cs = closestPointOnTriangle(ps, b0[0], b0[1], b0[2]);
                    open = signOf(triangleNormal(b0[0], b0[1], b0[2]).dot(ps - cs.point));
                    open = open == 0 ? 1 : open;
                }
            }
        }
    }
    // What the feature tests of one candidate pair (cloth triangle a, obstacle triangle b) share.
    struct Frame {
        int a = -1, b = -1;
        int ob[3];
        Vec3 b0[3], b1[3], nb1;
        int ca[3];
        Vec3 as[3], ae[3];
        double d0 = 0;              ///< the cloth triangle's thickness + the obstacle's
        bool trappedCorner = false; ///< a corner of a is trapped: only its vertex–face tests
    };
    const auto frameOf = [&](const std::pair<int, int>& pair) {
        Frame fr;
        fr.a = pair.first;
        fr.b = pair.second;
        for (int i = 0; i < 3; ++i) {
            fr.ob[i] = f(fr.b, i);
            fr.b0[i] = row(o.x0, fr.ob[i]);
            fr.b1[i] = row(o.x1, fr.ob[i]);
            fr.ca[i] = m_triangles(fr.a, i);
            fr.as[i] = row(xs, fr.ca[i]);
            fr.ae[i] = row(xe, fr.ca[i]);
        }
        fr.nb1 = triangleNormal(fr.b1[0], fr.b1[1], fr.b1[2]);
        fr.trappedCorner = trapped(fr.ca[0]) || trapped(fr.ca[1]) || trapped(fr.ca[2]);
        const double clothThickness = std::max({m_thickness[fr.ca[0]], m_thickness[fr.ca[1]], m_thickness[fr.ca[2]]});
        fr.d0 = clothThickness + spec.thickness;
        return fr;
    };
    const auto keep = [&](DetectionChunk& out, const Contact& c, int feature0, int feature1) {
        out.contacts.push_back(c);
        if (which == Detection::First && m_anySelf) {
            out.features.push_back({feature0, feature1});
        }
    };
    // Cloth vertex p (owned by fr.a) against the obstacle's face.
    const auto vertexFace = [&](DetectionChunk& out, const Frame& fr, int p) {
        const int* ob = fr.ob;
        const Vec3* b0 = fr.b0;
        const Vec3* b1 = fr.b1;
        const Vec3& nb1 = fr.nb1;
        if (trapped(p)) {
            return;
        }
        const double d0 = m_thickness[p] + spec.thickness;
        const Vec3 pe = row(xe, p), ps = row(xs, p);
        const signed char side = spec.closed ? 1 : m_openSide[k * n + static_cast<std::size_t>(p)];
        const Vec3 faceSide = side * nb1;
        const TrianglePoint cp = closestPointOnTriangle(pe, b1[0], b1[1], b1[2]);
        Contact c;
        c.kind = Contact::Kind::VertexFace;
        c.vertex[0] = p;
        c.weight[0] = 1.0;
        c.distance = d0;
        if (cp.distance < d0 * factor) {
            const Vec3 d = pe - cp.point;
            c.normal = (d.dot(faceSide) > 0 && cp.distance > TINY) ? Vec3(d / cp.distance) : faceSide;
            c.obstaclePoint = cp.point;
            c.obstacleVelocity = cp.bary[0] * obstacleVelocity(ob[0]) +
                                 cp.bary[1] * obstacleVelocity(ob[1]) +
                                 cp.bary[2] * obstacleVelocity(ob[2]);
            c.setObstaclePoint(ob, cp.bary.data(), 3);
        } else if (swept && (o.moves || ps != pe)) {
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
    };
    // Obstacle vertex q (owned by fr.b) against the cloth's face (a box corner poking the cloth).
    const auto faceVertex = [&](DetectionChunk& out, const Frame& fr, int q) {
        const int* ca = fr.ca;
        const Vec3* as = fr.as;
        const Vec3* ae = fr.ae;
        const double d0 = fr.d0;
        const Vec3 q0 = row(o.x0, q), q1 = row(o.x1, q);
        const TrianglePoint cp = closestPointOnTriangle(q1, ae[0], ae[1], ae[2]);
        const bool near = cp.distance < d0 * factor;
        std::optional<SweptHit> hit;
        if (!near) {
            if (!swept) {
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
        if (spec.closed) {
            // Trust the obstacle's outside: the cloth point should be outside q's faces.
            Vec3 outward = Vec3::Zero();
            for (int t : o.vertexTriangles[static_cast<std::size_t>(q)]) {
                outward += triangleNormal(row(o.x1, f(t, 0)), row(o.x1, f(t, 1)), row(o.x1, f(t, 2)));
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
        c.normal = (near && d.dot(away) > 0 && cp.distance > TINY) ? Vec3(d / cp.distance) : away;
        if (c.normal.squaredNorm() == 0) {
            return;
        }
        c.obstaclePoint = q1;
        c.obstacleVelocity = obstacleVelocity(q);
        const double one = 1.0;
        c.setObstaclePoint(&q, &one, 1);
        friction(c, ca[0]);
        keep(out, c, q, -1);
    };
    // Cloth edge e (owned by fr.a) against obstacle edge g (owned by fr.b).
    const auto edgeEdge = [&](DetectionChunk& out, int e, int g) {
        const int e0 = m_edges(e, 0), e1 = m_edges(e, 1);
        const double de0 = std::max(m_thickness[e0], m_thickness[e1]) + spec.thickness;
        const int g0 = o.edges(g, 0), g1 = o.edges(g, 1);
        const auto meeting = edgesMeet(row(xs, e0), row(xe, e0), row(xs, e1), row(xe, e1), row(o.x0, g0),
                                       row(o.x1, g0), row(o.x0, g1), row(o.x1, g1), de0 * factor, swept);
        if (!meeting) {
            return;
        }
        const double s = meeting->s, t = meeting->t;
        const bool near = meeting->near;
        out.continuousHits += near ? 0 : 1;
        const Vec3 pe = (1 - s) * row(xe, e0) + s * row(xe, e1);
        const Vec3 qe = (1 - t) * row(o.x1, g0) + t * row(o.x1, g1);
        const Vec3 ds = ((1 - s) * row(xs, e0) + s * row(xs, e1)) -
                        ((1 - t) * row(o.x0, g0) + t * row(o.x0, g1));
        const std::optional<Vec3> separation = edgeSeparation(pe - qe, ds, near);
        Vec3 normal;
        if (separation) {
            normal = *separation;
        } else { // the obstacle edge's normal
            const auto& et = o.edgeTriangles[static_cast<std::size_t>(g)];
            normal = triangleNormal(row(o.x1, f(et[0], 0)), row(o.x1, f(et[0], 1)), row(o.x1, f(et[0], 2)));
            if (et[1] >= 0) {
                normal += triangleNormal(row(o.x1, f(et[1], 0)), row(o.x1, f(et[1], 1)), row(o.x1, f(et[1], 2)));
            }
            if (normal.norm() < TINY) {
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
    };
    const auto testPair = [&](DetectionChunk& out, const std::pair<int, int>& pair) {
        const Frame fr = frameOf(pair);
        for (int p : m_ownedVertices[static_cast<std::size_t>(fr.a)]) {
            vertexFace(out, fr, p);
        }
        if (fr.trappedCorner) {
            return;
        }
        for (int q : o.ownedVertices[static_cast<std::size_t>(fr.b)]) {
            faceVertex(out, fr, q);
        }
        for (int e : m_ownedEdges[static_cast<std::size_t>(fr.a)]) {
            for (int g : o.ownedEdges[static_cast<std::size_t>(fr.b)]) {
                edgeEdge(out, e, g);
            }
        }
    };
    if (which == Detection::Again) {
        // A triangle none of whose corners moved since First is where First tested it: its
        // proximity contacts are First's, apart from the normals taken from where the cloth
        // started (face–vertex sides, edge–edge directions), which are tested again at xe.
        std::vector<char>& moved = m_movedTriangle;
        moved.assign(static_cast<std::size_t>(m_triangles.rows()), 0);
        for (int t = 0; t < m_triangles.rows(); ++t) {
            for (int i = 0; i < 3; ++i) {
                const int v = m_triangles(t, i);
                if (xe.row(v) != o.firstPositions.row(v)) {
                    moved[static_cast<std::size_t>(t)] = 1;
                }
            }
        }
        const std::pair<int, int>* pairs = m_pairs.data();
        const std::size_t used = detectInChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
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
        for (const auto& pair : m_pairs) {
            m_figures.candidatePairs += moved[static_cast<std::size_t>(pair.first)];
        }
        gatherChunks(used);
        return;
    }
    const bool remember = m_anySelf;
    if (remember) {
        o.firstNearStart.assign(m_pairs.size() + 1, 0);
    }
    const std::pair<int, int>* pairs = m_pairs.data();
    const std::size_t used = detectInChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
        const std::size_t before = out.contacts.size();
        testPair(out, pair);
        if (remember) {
            int near = 0;
            for (std::size_t j = before; j < out.contacts.size(); ++j) {
                near += out.contacts[j].swept ? 0 : 1;
            }
            o.firstNearStart[static_cast<std::size_t>(&pair - pairs) + 1] = near;
        }
    });
    const std::size_t first = m_contacts.size();
    gatherChunks(used);
    if (remember) {
        for (std::size_t i = 1; i < o.firstNearStart.size(); ++i) {
            o.firstNearStart[i] += o.firstNearStart[i - 1];
        }
        o.firstPairs = m_pairs;
        o.firstPositions = xe;
        o.firstNear.clear();
        o.firstFeature.clear();
        std::size_t next = first;
        for (std::size_t c = 0; c < used; ++c) {
            for (const std::array<int, 2>& feature : m_chunks[c].features) {
                const Contact& contact = m_contacts[next++];
                if (!contact.swept) {
                    o.firstNear.push_back(contact);
                    o.firstFeature.push_back(feature);
                }
            }
        }
    }
}

void CollisionStage::detectSelf(const MatX3& xs, const MatX3& xe) {
    const double factor = 1.0 + m_scene.collision.proximityFactor;
    const bool swept = m_scene.collision.continuous && &xs != &xe;
    m_pairs.clear();
    m_clothBvh.selfOverlaps(m_pairs);
    m_figures.candidatePairs += static_cast<long>(m_pairs.size());
    auto material = [&](int v) -> const Material& {
        return m_scene.cloths[static_cast<std::size_t>(m_clothOf[static_cast<std::size_t>(v)])].material;
    };
    const std::size_t used = detectInChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
        const auto [ta, tb] = pair;
        if (!selfPair(ta, tb)) {
            return;
        }
        for (int dir = 0; dir < 2; ++dir) {
            const int a = dir == 0 ? ta : tb;
            const int b = dir == 0 ? tb : ta;
            const int fb[3] = {m_triangles(b, 0), m_triangles(b, 1), m_triangles(b, 2)};
            const Vec3 bs[3] = {row(xs, fb[0]), row(xs, fb[1]), row(xs, fb[2])};
            const Vec3 be[3] = {row(xe, fb[0]), row(xe, fb[1]), row(xe, fb[2])};
            const double tb0 = std::max({m_thickness[fb[0]], m_thickness[fb[1]], m_thickness[fb[2]]});
            for (int p : m_ownedVertices[static_cast<std::size_t>(a)]) {
                if (same(p, fb[0]) || same(p, fb[1]) || same(p, fb[2])) {
                    continue;
                }
                const double d0 = m_thickness[p] + tb0;
                const Vec3 pe = row(xe, p);
                const TrianglePoint cp = closestPointOnTriangle(pe, be[0], be[1], be[2]);
                std::array<double, 3> bary = cp.bary;
                if (!(cp.distance < d0 * factor)) {
                    if (!swept) {
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
                bool reliable = !(cp.distance < d0 * factor);
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
                c.staticFriction = scaledFriction(material(p).staticFriction, material(fb[0]).staticFriction);
                c.kineticFriction = scaledFriction(material(p).kineticFriction, material(fb[0]).kineticFriction);
                out.contacts.push_back(c);
                out.keys.push_back(key);
                out.sides.push_back(side);
                out.reliable.push_back(reliable ? 1 : 0);
            }
        }
        // Edge–edge, each unordered pair of owned edges once.
        for (int e : m_ownedEdges[static_cast<std::size_t>(ta)]) {
            const int e0 = m_edges(e, 0), e1 = m_edges(e, 1);
            for (int g : m_ownedEdges[static_cast<std::size_t>(tb)]) {
                const int g0 = m_edges(g, 0), g1 = m_edges(g, 1);
                if (same(e0, g0) || same(e0, g1) || same(e1, g0) || same(e1, g1)) {
                    continue;
                }
                const double d0 = std::max(m_thickness[e0], m_thickness[e1]) +
                                  std::max(m_thickness[g0], m_thickness[g1]);
                const auto meeting = edgesMeet(row(xs, e0), row(xe, e0), row(xs, e1), row(xe, e1), row(xs, g0),
                                               row(xe, g0), row(xs, g1), row(xe, g1), d0 * factor, swept);
                if (!meeting) {
                    continue;
                }
                const double s = meeting->s, t = meeting->t;
                const bool near = meeting->near;
                out.continuousHits += near ? 0 : 1;
                const Vec3 de = ((1 - s) * row(xe, e0) + s * row(xe, e1)) - ((1 - t) * row(xe, g0) + t * row(xe, g1));
                const Vec3 ds = ((1 - s) * row(xs, e0) + s * row(xs, e1)) - ((1 - t) * row(xs, g0) + t * row(xs, g1));
                const std::optional<Vec3> separation = edgeSeparation(de, ds, near);
                if (!separation) {
                    continue;
                }
                const Vec3 normal = *separation;
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
                c.staticFriction = scaledFriction(material(e0).staticFriction, material(g0).staticFriction);
                c.kineticFriction = scaledFriction(material(e0).kineticFriction, material(g0).kineticFriction);
                out.contacts.push_back(c);
                out.keys.push_back(0);
                out.sides.push_back(0);
                out.reliable.push_back(1);
            }
        }
    });
    gatherChunks(used);
}

void CollisionStage::voteRegions(const MatX3& xe) {
    // Contact regions (§5.2): self vertex–face contacts whose vertices are equal or adjacent
    // and whose faces share a vertex belong to one region; the region takes the side most of
    // its members hold, and every member is given it.
    std::vector<int> members;
    for (std::size_t i = 0; i < m_contacts.size(); ++i) {
        if (m_contacts[i].kind == Contact::Kind::SelfVertexFace) {
            members.push_back(static_cast<int>(i));
        }
    }
    if (members.empty()) {
        m_memory.clear();
        return;
    }
    std::vector<int> parent(m_contacts.size());
    std::iota(parent.begin(), parent.end(), 0);
    auto find = [&](int i) {
        while (parent[static_cast<std::size_t>(i)] != i) {
            parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
            i = parent[static_cast<std::size_t>(i)];
        }
        return i;
    };
    std::unordered_map<int, std::vector<int>> byVertex;
    for (int i : members) {
        byVertex[m_contacts[static_cast<std::size_t>(i)].vertex[0]].push_back(i);
    }
    auto faceOf = [&](int i) {
        const Contact& c = m_contacts[static_cast<std::size_t>(i)];
        return std::array<int, 3>{c.vertex[1], c.vertex[2], c.vertex[3]};
    };
    // Members of one region lie on one smooth layer pair: faces of a crease (normals apart)
    // are not grouped, their sides are not comparable.
    auto faceNormal = [&](int i) {
        const auto f = faceOf(i);
        return triangleNormal(row(xe, f[0]), row(xe, f[1]), row(xe, f[2]));
    };
    auto vertexNormal = [&](int v) {
        const int t = m_vertexTriangle[static_cast<std::size_t>(v)];
        return triangleNormal(row(xe, m_triangles(t, 0)), row(xe, m_triangles(t, 1)),
                              row(xe, m_triangles(t, 2)));
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
        const int p = m_contacts[static_cast<std::size_t>(i)].vertex[0];
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
                    parent[static_cast<std::size_t>(find(i))] = find(j);
                }
            }
        };
        visit(p);
        for (int q : m_neighbours[static_cast<std::size_t>(p)]) {
            visit(q);
        }
    }
    m_flippedFrom = m_contactSide;
    // The vote: members whose side is certain decide; a region with none of them (a tangled
    // start) is decided by all its members.
    std::unordered_map<int, long> vote, voteAll;
    for (int i : members) {
        const int side = m_contactSide[static_cast<std::size_t>(i)];
        voteAll[find(i)] += side;
        if (m_contactReliable[static_cast<std::size_t>(i)]) {
            vote[find(i)] += side;
        }
    }
    for (int i : members) {
        const auto decided = vote.find(find(i));
        const long v = decided != vote.end() ? decided->second : voteAll[find(i)];
        signed char& side = m_contactSide[static_cast<std::size_t>(i)];
        const signed char regionSide = v > 0 ? 1 : (v < 0 ? -1 : side);
        if (regionSide != side && !m_contactReliable[static_cast<std::size_t>(i)]) {
            ++m_figures.regionFlips;
            m_contacts[static_cast<std::size_t>(i)].normal *= -1.0;
            side = regionSide;
        }
    }
    // Remember the sides of the pairs in contact now; a pair that leaves proximity is forgotten
    // (a vertex may come back around a border from the other side).
    m_memory.clear();
    for (int i : members) {
        m_memory[m_contactKey[static_cast<std::size_t>(i)]] = m_contactSide[static_cast<std::size_t>(i)];
    }
    // Edge–edge contacts take their side from the step's start; where the vote found that start
    // tangled, that side is wrong, so edge–edge contacts touching a flipped region are dropped
    // and the vertex–face contacts alone pull the layers apart.
    std::vector<char> flipped;
    for (int i : members) {
        const Contact& c = m_contacts[static_cast<std::size_t>(i)];
        if (m_contactSide[static_cast<std::size_t>(i)] != m_flippedFrom[static_cast<std::size_t>(i)]) {
            if (flipped.empty()) {
                flipped.assign(m_neighbours.size(), 0);
            }
            for (int k = 0; k < 4; ++k) {
                flipped[static_cast<std::size_t>(c.vertex[k])] = 1;
            }
        }
    }
    if (!flipped.empty()) {
        std::size_t out = 0;
        for (std::size_t i = 0; i < m_contacts.size(); ++i) {
            const Contact& c = m_contacts[i];
            const bool drop = c.kind == Contact::Kind::SelfEdgeEdge &&
                              (flipped[static_cast<std::size_t>(c.vertex[0])] || flipped[static_cast<std::size_t>(c.vertex[1])] ||
                               flipped[static_cast<std::size_t>(c.vertex[2])] || flipped[static_cast<std::size_t>(c.vertex[3])]);
            if (!drop) {
                m_contacts[out] = c;
                m_contactKey[out] = m_contactKey[i];
                m_contactSide[out] = m_contactSide[i];
                m_contactReliable[out] = m_contactReliable[i];
                ++out;
            }
        }
        m_contacts.resize(out);
        m_contactKey.resize(out);
        m_contactSide.resize(out);
        m_contactReliable.resize(out);
    }
}

void CollisionStage::project(const MatX3& xs, MatX3& xe, MatX3& ve, const VecX& invMass, double h) {
    for (Contact& c : m_contacts) {
        c.active = false;
    }
    const int iterations = std::max(1, m_scene.collision.iterations);
    for (int it = 0; it < iterations; ++it) {
        bool moved = false;
        for (Contact& c : m_contacts) {
            const double w = effectiveInverseMass(c, invMass);
            if (!(w > 0)) {
                continue;
            }
            const double gap = c.normal.dot(combination(c, xe) - c.obstaclePoint);
            double violation = c.distance - gap;
            if (c.obstacle < 0) {
                // Cloth–cloth pushes are bounded per pass: a large one means a side decided
                // wrongly, and pushing a layer far (through an obstacle behind it) is worse than
                // letting the fail-safe hold the vertices back.
                violation = std::min(violation, c.distance);
            }
            if (violation > 0) {
                distribute(c, invMass, w, violation * c.normal, xe);
                c.active = true; // it pushed: it is a touching contact
                moved = true;
            }
        }
        if (!moved) {
            break;
        }
    }
    // Obstacles are hard: a last pass over their contacts, so a cloth–cloth correction made after
    // them cannot leave a vertex inside an obstacle (where the proximity test would lose it).
    for (Contact& c : m_contacts) {
        if (c.obstacle < 0) {
            continue;
        }
        const double w = effectiveInverseMass(c, invMass);
        const double violation = c.distance - c.normal.dot(combination(c, xe) - c.obstaclePoint);
        if (w > 0 && violation > 0) {
            distribute(c, invMass, w, violation * c.normal, xe);
            c.active = true;
        }
    }
    // Contacts resting in the solve's layer (ContactForces) touch too, for the figures.
    const double layer = m_scene.collision.solveContacts &&
                                 m_scene.integrator.kind == IntegratorKind::ImplicitEuler
                             ? std::max(TOUCH, m_scene.collision.solve.margin)
                             : TOUCH;
    long active = 0;
    for (Contact& c : m_contacts) {
        const double gap = c.normal.dot(combination(c, xe) - c.obstaclePoint);
        c.active = c.active || gap <= c.distance * (1.0 + TOUCH) + TINY;
        active += c.active || gap <= c.distance * (1.0 + layer) + TINY ? 1 : 0;
    }
    markPinches(xs, xe, h);
    // Velocities: touching contacts stop approaching, with friction; contacts still apart may
    // approach only as fast as closes their gap within a step of the same length, so the next
    // step does not carry them into each other (no friction until they touch).
    for (int pass = 0; pass < 2; ++pass) {
        for (const Contact& c : m_contacts) {
            if (c.active) {
                velocityCorrection(c, invMass, ve, 0.0, true);
            } else if (h > 0) {
                const double gap = c.normal.dot(combination(c, xe) - c.obstaclePoint);
                velocityCorrection(c, invMass, ve, -(gap - c.distance) / h, false);
            }
        }
    }
    m_figures.contacts = active;
}

void CollisionStage::markPinches(const MatX3& xs, MatX3& xe, double h) {
    // A vertex squeezed between two obstacles (touching vertex–face contacts with opposing
    // normals, closer together than the two contact distances) is pressed by both with the same
    // force, as large as the squeeze makes it: by Coulomb's law it slides on the surface that
    // grips less and is held by the one that grips more, positions included (held by velocities
    // alone, the cloth's pull moved it back a little at every step). Taken one contact at a time,
    // each with the friction of its own small normal impulse, the last contact applied won: a
    // sheet squeezed under a sweeping press stayed with the floor and was torn apart.
    if (m_obstacles.size() < 2) {
        return; // every contact keeps Coulomb's law (Contact::grip's default)
    }
    std::vector<std::pair<int, std::size_t>>& touching = m_pinchScratch;
    touching.clear();
    for (std::size_t i = 0; i < m_contacts.size(); ++i) {
        const Contact& c = m_contacts[i];
        if (c.active && c.obstacle >= 0 && c.kind == Contact::Kind::VertexFace) {
            touching.emplace_back(c.vertex[0], i);
        }
    }
    std::sort(touching.begin(), touching.end());
    for (std::size_t a = 0; a < touching.size();) {
        std::size_t b = a + 1;
        while (b < touching.size() && touching[b].first == touching[a].first) {
            ++b;
        }
        bool squeezed = false;
        for (std::size_t i = a; i < b && !squeezed; ++i) {
            for (std::size_t j = i + 1; j < b; ++j) {
                const Contact& ci = m_contacts[touching[i].second];
                const Contact& cj = m_contacts[touching[j].second];
                if (ci.obstacle != cj.obstacle && ci.normal.dot(cj.normal) < -0.5 &&
                    (ci.obstaclePoint - cj.obstaclePoint).dot(cj.normal) < ci.distance + cj.distance) {
                    squeezed = true;
                    break;
                }
            }
        }
        if (squeezed) {
            std::size_t grip = touching[a].second;
            for (std::size_t i = a; i < b; ++i) {
                if (m_contacts[touching[i].second].staticFriction > m_contacts[grip].staticFriction) {
                    grip = touching[i].second;
                }
            }
            for (std::size_t i = a; i < b; ++i) {
                m_contacts[touching[i].second].grip =
                    touching[i].second == grip ? Contact::Grip::Stick : Contact::Grip::Slip;
            }
            // Held: no tangential motion relative to the gripping obstacle over the step.
            const Contact& c = m_contacts[grip];
            if (h > 0 && c.staticFriction > 0) {
                const int p = c.vertex[0];
                const Vec3 slip = (row(xe, p) - row(xs, p)) - h * c.obstacleVelocity;
                xe.row(p) -= (slip - slip.dot(c.normal) * c.normal).transpose();
            }
        }
        a = b;
    }
}

void CollisionStage::pairCrossings(int ta, int tb, const MatX3& xs, const MatX3& xe,
                                   std::vector<int>& hits) const {
    if (!selfPair(ta, tb)) {
        return;
    }
    for (int dir = 0; dir < 2; ++dir) {
        const int a = dir == 0 ? ta : tb;
        const int b = dir == 0 ? tb : ta;
        const int f0 = m_triangles(b, 0), f1 = m_triangles(b, 1), f2 = m_triangles(b, 2);
        for (int p : m_ownedVertices[static_cast<std::size_t>(a)]) {
            if (same(p, f0) || same(p, f1) || same(p, f2)) {
                continue;
            }
            const Vec3 p0 = row(xs, p), p1 = row(xe, p), a0 = row(xs, f0), a1 = row(xe, f0),
                       b0 = row(xs, f1), b1 = row(xe, f1), c0 = row(xs, f2), c1 = row(xe, f2);
            if (vertexCrosses(p0, p1, a0, a1, b0, b1, c0, c1)) {
                hits.insert(hits.end(), {p, f0, f1, f2});
            }
        }
    }
    for (int e : m_ownedEdges[static_cast<std::size_t>(ta)]) {
        const int e0 = m_edges(e, 0), e1 = m_edges(e, 1);
        for (int g : m_ownedEdges[static_cast<std::size_t>(tb)]) {
            const int g0 = m_edges(g, 0), g1 = m_edges(g, 1);
            if (same(e0, g0) || same(e0, g1) || same(e1, g0) || same(e1, g1)) {
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

void CollisionStage::markCrossings(const MatX3& xs, const MatX3& xe, const VecX* invMass,
                                   std::vector<int>& marked) {
    std::vector<char>& back = m_putBack;
    back.resize(static_cast<std::size_t>(xe.rows()), 0);
    m_clothBvh.refit(xs, &xe, 0.0);
    m_pairs.clear();
    SelfQueryOptions noCulling;
    noCulling.cullingAngle = 4.0; // exact: the cone test is only a heuristic (see README)
    m_clothBvh.selfOverlaps(m_pairs, noCulling);
    const std::size_t used = detectInChunks([&](DetectionChunk& out, const std::pair<int, int>& pair) {
        pairCrossings(pair.first, pair.second, xs, xe, out.hits);
    });
    for (std::size_t c = 0; c < used; ++c) {
        for (int v : m_chunks[c].hits) {
            if (!back[static_cast<std::size_t>(v)] && (invMass == nullptr || (*invMass)[v] > 0)) {
                back[static_cast<std::size_t>(v)] = 1;
                marked.push_back(v);
            }
        }
    }
}

void CollisionStage::rollBackCrossings(const MatX3& xs, MatX3& xe, MatX3& ve,
                                       const VecX& invMass) {
    std::vector<int>& marked = m_putBackList;
    std::vector<int> all; // every vertex put back this step, to clear the flags at the end
    std::vector<int> changed;
    for (int round = 0; round < 32; ++round) {
        marked.clear();
        if (round == 0) {
            markCrossings(xs, xe, &invMass, marked);
        } else {
            // Only the vertices put back last round moved since: a feature pair without one
            // crosses now exactly as it did then, and then its vertices were marked already.
            markCrossingsAround(xs, xe, changed, &invMass, marked);
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
        m_figures.rolledBack += static_cast<long>(marked.size());
    }
    for (int v : all) {
        m_putBack[static_cast<std::size_t>(v)] = 0;
    }
}

std::vector<int> CollisionStage::crossingVertices(const MatX3& xs, const MatX3& xe,
                                                  const std::vector<int>& moved) {
    std::vector<int> marked;
    if (!m_anySelf || moved.empty()) {
        return marked;
    }
    m_putBack.resize(static_cast<std::size_t>(xe.rows()), 0);
    markCrossingsAround(xs, xe, moved, nullptr, marked);
    for (int v : marked) {
        m_putBack[static_cast<std::size_t>(v)] = 0;
    }
    return marked;
}

void CollisionStage::markCrossingsAround(const MatX3& xs, const MatX3& xe,
                                         const std::vector<int>& moved, const VecX* invMass,
                                         std::vector<int>& marked) {
    const std::size_t nv = static_cast<std::size_t>(xe.rows());
    if (m_clothVertexTriangles.size() != nv) {
        m_clothVertexTriangles.assign(nv, {});
        for (int f = 0; f < m_triangles.rows(); ++f) {
            for (int k = 0; k < 3; ++k) {
                m_clothVertexTriangles[static_cast<std::size_t>(m_triangles(f, k))].push_back(f);
            }
        }
    }
    // Only triangles with a moved corner can cross anything: each is tested against the
    // triangles its swept box overlaps.
    m_clothBvh.refit(xs, &xe, 0.0);
    std::vector<int> triangles;
    for (int v : moved) {
        const auto& incident = m_clothVertexTriangles[static_cast<std::size_t>(v)];
        triangles.insert(triangles.end(), incident.begin(), incident.end());
    }
    std::sort(triangles.begin(), triangles.end());
    triangles.erase(std::unique(triangles.begin(), triangles.end()), triangles.end());
    std::vector<char>& flagged = m_putBack;
    std::vector<int>& hits = m_crossingHits;
    std::vector<int> candidates;
    for (int t : triangles) {
        Aabb box;
        for (int k = 0; k < 3; ++k) {
            box.add(row(xs, m_triangles(t, k)));
            box.add(row(xe, m_triangles(t, k)));
        }
        candidates.clear();
        m_clothBvh.query(box, candidates);
        for (int u : candidates) {
            if (u == t) {
                continue;
            }
            hits.clear();
            pairCrossings(t, u, xs, xe, hits);
            for (int v : hits) {
                if (!flagged[static_cast<std::size_t>(v)] && (invMass == nullptr || (*invMass)[v] > 0)) {
                    flagged[static_cast<std::size_t>(v)] = 1;
                    marked.push_back(v);
                }
            }
        }
    }
}

void CollisionStage::obstacleMotionChanged(std::size_t k) {
    ObstacleData& o = m_obstacles[k];
    o.moves = true;
    o.fittedMargin = -1.0;
    o.hullFitted = false;
}

void CollisionStage::update(double t0, double t1, const MatX3& xs, MatX3& xe, MatX3& ve,
                            const VecX& invMass) {
    const double h = t1 - t0;
    const double factor = 1.0 + m_scene.collision.proximityFactor;
    m_contacts.clear();
    m_contactKey.clear();
    m_contactSide.clear();
    m_contactReliable.clear();
    const bool swept = &xs != &xe && h > 0;
    m_clothBvh.refit(xs, swept ? &xe : nullptr, m_maxThickness * factor);
    const bool insideCheck = t1 - m_lastInsideCheck >= 1.0 / 30.0 - 1e-12;
    for (std::size_t k = 0; k < m_obstacles.size(); ++k) {
        ObstacleData& o = m_obstacles[k];
        if (o.moves) {
            obstaclePositionsAt(*o.spec, t0, o.x0);
            obstaclePositionsAt(*o.spec, t1, o.x1);
        }
        // A static obstacle's hierarchy is refitted once (its boxes do not change).
        const double margin = o.spec->thickness * factor;
        if (o.moves || o.fittedMargin != margin) {
            o.bvh.refit(o.x0, o.moves && h > 0 ? &o.x1 : nullptr, margin);
            o.fittedMargin = o.moves ? -1.0 : margin;
        }
        if (insideCheck && !(h > 0)) {
            findTrapped(k, xe); // the start: trapped vertices must not get ordinary contacts
        }
        extractTrapped(k, h, xe, ve);
        detectObstacle(k, h, xs, xe, Detection::First);
    }
    if (m_anySelf) {
        detectSelf(xs, xe);
        voteRegions(xe);
    }
    project(xs, xe, ve, invMass, h);
    if (m_anySelf && !m_obstacles.empty()) {
        // Cloth–cloth corrections may have carried vertices toward an obstacle from farther
        // than its proximity margin: detect against obstacles again where the cloth is now and
        // correct with those contacts (obstacles win).
        const std::size_t first = m_contacts.size();
        for (std::size_t k = 0; k < m_obstacles.size(); ++k) {
            detectObstacle(k, h, xe, xe, Detection::Again);
        }
        m_contactKey.resize(m_contacts.size(), 0);
        m_contactSide.resize(m_contacts.size(), 0);
        m_contactReliable.resize(m_contacts.size(), 1);
        for (std::size_t i = first; i < m_contacts.size(); ++i) {
            Contact& c = m_contacts[i];
            const double w = effectiveInverseMass(c, invMass);
            const double violation = c.distance - c.normal.dot(combination(c, xe) - c.obstaclePoint);
            if (w > 0 && violation > 0) {
                distribute(c, invMass, w, violation * c.normal, xe);
            }
            c.active = c.distance - c.normal.dot(combination(c, xe) - c.obstaclePoint) >=
                       -c.distance * TOUCH - TINY;
            if (c.active) {
                velocityCorrection(c, invMass, ve, 0.0, true);
                ++m_figures.contacts;
            }
        }
    }
    // Last: nothing after the fail-safe may move the cloth (the start was free of crossings,
    // and so is every vertex put back there).
    if (m_anySelf && swept && m_scene.collision.failSafe) {
        rollBackCrossings(xs, xe, ve, invMass);
    }
    if (insideCheck) {
        // After the corrections: a vertex that crossed during the step is back outside by now;
        // one still deep inside is trapped and is carried out from the next step on.
        if (h > 0) {
            for (std::size_t k = 0; k < m_obstacles.size(); ++k) {
                findTrapped(k, xe);
            }
        }
        m_lastInsideCheck = t1;
    }
    long trapped = 0;
    for (int v : m_trapped) {
        trapped += v >= 0 ? 1 : 0;
    }
    m_figures.trappedVertices = trapped;
}

double CollisionStage::correctAccelerations(const MatX3& vs, MatX3& a, const VecX& mass,
                                            const VecX& invMass, double h) const {
    double power = 0;
    for (const Contact& c : m_contacts) {
        if (!c.active) {
            continue;
        }
        const double w = effectiveInverseMass(c, invMass);
        if (!(w > 0)) {
            continue;
        }
        const Vec3 arel = combination(c, a);
        const double an = c.normal.dot(arel);
        if (an >= 0) {
            continue; // separating: the contact does not pull
        }
        const double pressure = -an; // normal acceleration the contact must supply [m/s²]
        Vec3 delta = pressure * c.normal;
        const Vec3 u = combination(c, vs) - c.obstacleVelocity;
        const Vec3 ut = u - c.normal.dot(u) * c.normal;
        const double utn = ut.norm();
        if (utn > c.kineticFriction * pressure * h && utn > 0) {
            // Sliding: kinetic friction against the relative tangential velocity.
            delta -= (c.kineticFriction * pressure / utn) * ut;
        } else {
            // At rest (or stopping within this step): cancel the tangential acceleration and the
            // remaining slip if the static cone allows, else kinetic friction against it.
            const Vec3 at = arel - an * c.normal;
            const Vec3 need = -(at + (h > 0 ? Vec3(ut / h) : Vec3::Zero()));
            const double needN = need.norm();
            if (needN <= c.staticFriction * pressure) {
                delta += need;
            } else if (needN > 0) {
                delta += (c.kineticFriction * pressure / needN) * need;
            }
        }
        for (int k = 0; k < 4; ++k) {
            const int i = c.vertex[k];
            if (i >= 0 && invMass[i] > 0) {
                const Vec3 dai = c.weight[k] * invMass[i] / w * delta;
                a.row(i) += dai.transpose();
                power += mass[i] * dai.dot(row(vs, i));
            }
        }
    }
    return power;
}

void CollisionStage::predictObstacleVelocities(double t, double h) {
    if (!(h > 0)) {
        return;
    }
    bool any = false;
    for (ObstacleData& o : m_obstacles) {
        if (o.moves) {
            obstaclePositionsAt(*o.spec, t + h, o.xNext);
            any = true;
        }
    }
    if (!any) {
        return;
    }
    for (Contact& c : m_contacts) {
        if (c.obstacle < 0 || !m_obstacles[static_cast<std::size_t>(c.obstacle)].moves) {
            continue;
        }
        const ObstacleData& o = m_obstacles[static_cast<std::size_t>(c.obstacle)];
        Vec3 velocity = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
            const int q = c.obstacleVertex[k];
            if (q >= 0) {
                velocity += c.obstacleWeight[k] * (row(o.xNext, q) - row(o.x1, q)) / h;
            }
        }
        c.obstacleVelocity = velocity;
    }
}

void CollisionStage::correctVelocities(MatX3& v, const VecX& invMass) const {
    for (int pass = 0; pass < 2; ++pass) {
        for (const Contact& c : m_contacts) {
            if (c.active) {
                velocityCorrection(c, invMass, v, 0.0, true);
            }
        }
    }
}

double CollisionStage::penetration(const MatX3& x) {
    double worst = 0;
    const std::size_t n = static_cast<std::size_t>(x.rows());
    for (std::size_t k = 0; k < m_obstacles.size(); ++k) {
        ObstacleData& o = m_obstacles[k];
        const double th = o.spec->thickness;
        if (o.fittedMargin < 0 && !o.moves) {
            o.bvh.refit(o.x1, nullptr, th); // the boxes of the last update hold x1 otherwise
            o.fittedMargin = th;
        }
        const Aabb& box = o.bvh.nodes()[static_cast<std::size_t>(o.bvh.root())].box;
        // Each vertex on its own (its own slot of the distance cache); the largest depth is
        // then taken serially (a maximum: the same for any order).
        std::vector<double>& depth = m_depthScratch;
        depth.assign(n, 0.0);
        const std::int64_t nv = x.rows();
        parallelFor(nv, [&](std::int64_t pp) {
            const int p = static_cast<int>(pp);
            const Vec3 xp = row(x, p);
            if (box.squaredDistance(xp) > 0) {
                return;
            }
            double sd;
            if (o.spec->closed) {
                sd = vertexSignedDistance(k, p, xp, th);
            } else {
                const auto [tri, cp] = o.bvh.closestTriangle(o.x1, xp, th);
                if (tri < 0) {
                    return;
                }
                const MatX3i& f = o.spec->triangles;
                const Vec3 nf = triangleNormal(row(o.x1, f(tri, 0)), row(o.x1, f(tri, 1)), row(o.x1, f(tri, 2)));
                const signed char side = m_openSide[k * n + static_cast<std::size_t>(p)];
                const double along = nf.dot(xp - cp.point);
                sd = side == 0 ? cp.distance : (along * side >= 0 ? cp.distance : -cp.distance);
            }
            depth[static_cast<std::size_t>(p)] = th - sd;
        });
        for (double d : depth) {
            worst = std::max(worst, d);
        }
    }
    return worst;
}

long CollisionStage::intersectingTrianglePairs(const MatX3& x, long* clothObstacle) {
    long count = 0;
    m_clothBvh.refit(x, nullptr, 0.0);
    m_pairs.clear();
    SelfQueryOptions all;
    all.cullingAngle = 4.0; // no culling: the count must be exact
    m_clothBvh.selfOverlaps(m_pairs, all);
    for (const auto& [a, b] : m_pairs) {
        bool shared = false;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                shared = shared || same(m_triangles(a, i), m_triangles(b, j));
            }
        }
        if (!shared && trianglesIntersect(row(x, m_triangles(a, 0)), row(x, m_triangles(a, 1)),
                                          row(x, m_triangles(a, 2)), row(x, m_triangles(b, 0)),
                                          row(x, m_triangles(b, 1)), row(x, m_triangles(b, 2)))) {
            ++count;
        }
    }
    long obstacleCount = 0;
    for (ObstacleData& o : m_obstacles) {
        o.bvh.refit(o.x1, nullptr, 0.0);
        o.fittedMargin = o.moves ? -1.0 : 0.0;
        m_pairs.clear();
        m_clothBvh.overlaps(o.bvh, m_pairs);
        const MatX3i& f = o.spec->triangles;
        for (const auto& [a, b] : m_pairs) {
            if (trianglesIntersect(row(x, m_triangles(a, 0)), row(x, m_triangles(a, 1)),
                                   row(x, m_triangles(a, 2)), row(o.x1, f(b, 0)), row(o.x1, f(b, 1)),
                                   row(o.x1, f(b, 2)))) {
                ++count;
                ++obstacleCount;
            }
        }
    }
    if (clothObstacle != nullptr) {
        *clothObstacle = obstacleCount;
    }
    return count;
}

} // namespace atelier::sim
