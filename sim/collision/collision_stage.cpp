#include "sim/collision/collision_stage.h"

#include "sim/collision/detection/detection_context.h"
#include "sim/collision/detection/self_detection.h"
#include "sim/collision/intersection/triangle_triangle.h"
#include "sim/collision/measures/intersecting_pairs.h"
#include "sim/collision/measures/penetration.h"
#include "sim/collision/obstacle.h"
#include "sim/collision/response/acceleration_correction.h"
#include "sim/collision/response/obstacle_velocity.h"
#include "sim/collision/response/pinch.h"
#include "sim/collision/response/position_projection.h"
#include "sim/collision/response/velocity_correction.h"
#include "sim/collision/seam_routing.h"

#include <algorithm>
#include <limits>

namespace atelier::sim {

bool CollisionStage::needed(const SceneSpec& scene) {
    if (!scene.obstacles.empty()) {
        return true;
    }
    return std::any_of(scene.cloths.begin(), scene.cloths.end(),
                       [](const ClothSpec& c) { return c.selfCollision; });
}

CollisionStage::CollisionStage(const SceneSpec& scene, const std::vector<int>& offsets,
                               const MatX3& x)
    : m_scene(scene), m_mesh(scene, offsets), m_clothBvh(m_mesh.triangles, x),
      m_trapped(offsets.back()) {
    for (const ObstacleSpec& spec : scene.obstacles) {
        m_obstacles.emplace_back(spec, offsets.back());
    }
}

void CollisionStage::gather(const DetectionResult& result) {
    m_figures.candidatePairs += result.candidatePairs;
    // Self contacts carry keys, sides and reliability; obstacle contacts none (0, 0, 1).
    m_contactKey.resize(m_contacts.size(), 0);
    m_contactSide.resize(m_contacts.size(), 0);
    m_contactReliable.resize(m_contacts.size(), 1);
    for (std::size_t c = 0; c < result.pieces; ++c) {
        const DetectionChunk& chunk = m_scratch.chunks[c];
        m_contacts.insert(m_contacts.end(), chunk.contacts.begin(), chunk.contacts.end());
        if (chunk.keys.size() == chunk.contacts.size()) {
            m_contactKey.insert(m_contactKey.end(), chunk.keys.begin(), chunk.keys.end());
            m_contactSide.insert(m_contactSide.end(), chunk.sides.begin(), chunk.sides.end());
            m_contactReliable.insert(m_contactReliable.end(), chunk.reliable.begin(),
                                     chunk.reliable.end());
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
    const DetectionContext ctx{m_scene, m_mesh, m_clothBvh, m_frictionScale};
    gather(detectObstacleContacts(ctx, k, m_obstacles[k], m_trapped.obstacleOf(), h, xs, xe, which,
                                  m_scratch));
}

void CollisionStage::obstacleMotionChanged(std::size_t k) {
    ObstacleData& o = m_obstacles[k];
    o.moves = obstacleMoves(*o.spec);
    o.fittedMargin = -1.0;
    o.hullFitted = false;
    // Distances kept for a static obstacle belong to where it was.
    std::fill(o.distanceValue.begin(), o.distanceValue.end(),
              std::numeric_limits<double>::quiet_NaN());
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
    m_clothBvh.refit(xs, swept ? &xe : nullptr, m_mesh.maxThickness * factor);
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
            // The start: trapped vertices must not get ordinary contacts.
            m_trapped.find(k, o, m_mesh, m_scene.collision, xe);
        }
        m_trapped.extract(k, o, m_mesh, m_scene.collision.extractionSpeed, h, xe, ve);
        detectObstacle(k, h, xs, xe, Detection::First);
    }
    if (dropSqueezedFaces(m_contacts, 0, xe) > 0) {
        m_contactKey.resize(m_contacts.size());
        m_contactSide.resize(m_contacts.size());
        m_contactReliable.resize(m_contacts.size());
    }
    if (m_mesh.anySelf) {
        const DetectionContext ctx{m_scene, m_mesh, m_clothBvh, m_frictionScale};
        gather(detectSelfContacts(ctx, m_regions.memory(), xs, xe, m_scratch,
                                  m_failSafe.watchedPairs()));
        m_figures.regionFlips +=
            m_regions.vote(m_mesh, xe, m_contacts, m_contactKey, m_contactSide, m_contactReliable);
    }
    m_figures.contacts = projectPositions(m_contacts, m_scene, xe, invMass);
    markPinches(m_contacts, m_obstacles.size(), xs, xe, h, m_pinchScratch);
    correctContactVelocities(m_contacts, xe, ve, invMass, h);
    if (m_mesh.anySelf && !m_obstacles.empty()) {
        // Cloth–cloth corrections may have carried vertices toward an obstacle from farther
        // than its proximity margin: detect against obstacles again where the cloth is now and
        // correct with those contacts (obstacles win).
        const std::size_t first = m_contacts.size();
        for (std::size_t k = 0; k < m_obstacles.size(); ++k) {
            detectObstacle(k, h, xe, xe, Detection::Again);
        }
        dropSqueezedFaces(m_contacts, first, xe);
        m_contactKey.resize(m_contacts.size(), 0);
        m_contactSide.resize(m_contacts.size(), 0);
        m_contactReliable.resize(m_contacts.size(), 1);
        m_figures.contacts += correctRedetected(m_contacts, first, xe, ve, invMass);
    }
    // Last: nothing after the fail-safe may move the cloth (the start was free of crossings,
    // and so is every vertex put back there).
    if (m_mesh.anySelf && swept && m_scene.collision.failSafe) {
        m_figures.rolledBack +=
            m_failSafe.rollBack(m_mesh, m_clothBvh, m_scratch, xs, xe, ve, invMass);
    }
    if (insideCheck) {
        // After the corrections: a vertex that crossed during the step is back outside by now;
        // one still deep inside is trapped and is carried out from the next step on.
        if (h > 0) {
            for (std::size_t k = 0; k < m_obstacles.size(); ++k) {
                m_trapped.find(k, m_obstacles[k], m_mesh, m_scene.collision, xe);
            }
        }
        m_lastInsideCheck = t1;
    }
    m_figures.trappedVertices = m_trapped.count();
}

double CollisionStage::correctAccelerations(const MatX3& vs, MatX3& a, const VecX& mass,
                                            const VecX& invMass, double h) const {
    return correctContactAccelerations(m_contacts, vs, a, mass, invMass, h);
}

void CollisionStage::predictObstacleVelocities(double t, double h) {
    sim::predictObstacleVelocities(m_obstacles, m_contacts, t, h);
}

void CollisionStage::correctVelocities(MatX3& v, const VecX& invMass) const {
    correctActiveVelocities(m_contacts, v, invMass);
}

double CollisionStage::penetration(const MatX3& x) {
    return penetrationDepth(m_obstacles, x, m_depthScratch);
}

double CollisionStage::contactLayerCrush(const MatX3& x) {
    return penetrationDepth(m_obstacles, x, m_depthScratch, &m_mesh.thickness);
}

long CollisionStage::intersectingTrianglePairs(const MatX3& x,
                                               const std::vector<std::vector<int>>& welded,
                                               long* clothObstacle) {
    return countIntersectingTrianglePairs(m_mesh, m_clothBvh, m_obstacles, x, welded,
                                          m_scratch.pairs, clothObstacle);
}

bool CollisionStage::routeAround(const Vec3& p, const Vec3& q, double clearance, Vec3& via) const {
    return routeChordAround(m_obstacles, p, q, clearance, via);
}

std::vector<int> CollisionStage::crossingVertices(const MatX3& xs, const MatX3& xe,
                                                  const std::vector<int>& moved) {
    std::vector<int> marked = m_failSafe.crossingVertices(m_mesh, m_clothBvh, xs, xe, moved);
    // And the moved vertices of triangles the move brings into an obstacle (intersecting one
    // of its triangles at xe, not at xs): a weld across a too-small garment's side seam at the
    // armpit carried the cloth's triangles into the torso.
    const std::size_t before = marked.size();
    const MatX3i& t = m_mesh.triangles;
    const std::vector<int> triangles = m_mesh.trianglesAround(moved);
    std::vector<int> candidates;
    auto enters = [&](const ObstacleData& o, int k) {
        const MatX3i& f = o.spec->triangles;
        Aabb box;
        for (int i = 0; i < 3; ++i) {
            box.add(row(xs, t(k, i)));
            box.add(row(xe, t(k, i)));
        }
        candidates.clear();
        o.bvh.query(box, candidates);
        auto meets = [&](const MatX3& x) {
            return std::any_of(candidates.begin(), candidates.end(), [&](int q) {
                return trianglesIntersect(row(x, t(k, 0)), row(x, t(k, 1)), row(x, t(k, 2)),
                                          row(o.x1, f(q, 0)), row(o.x1, f(q, 1)),
                                          row(o.x1, f(q, 2)));
            });
        };
        return meets(xe) && !meets(xs);
    };
    for (int k : triangles) {
        for (const ObstacleData& o : m_obstacles) {
            if (enters(o, k)) {
                for (int i = 0; i < 3; ++i) {
                    if (row(xs, t(k, i)) != row(xe, t(k, i))) {
                        marked.push_back(t(k, i));
                    }
                }
                break;
            }
        }
    }
    if (marked.size() > before) {
        std::sort(marked.begin(), marked.end());
        marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    }
    return marked;
}

} // namespace atelier::sim
