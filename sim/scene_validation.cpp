#include "sim/scene_validation.h"

#include "sim/collision/obstacle.h"
#include "sim/forces/continuum_bending.h"

#include <cmath>

namespace atelier::sim {

namespace {

/// The cloths: meshes, start state, materials.
std::optional<std::string> validateCloths(const SceneSpec& s) {
    for (std::size_t ci = 0; ci < s.cloths.size(); ++ci) {
        const ClothSpec& c = s.cloths[ci];
        const std::string who = "cloth " + std::to_string(ci) + " (" + c.name + ")";
        const int nv = c.mesh.vertexCount();
        if (c.mesh.triangleCount() == 0 || c.mesh.restArea.size() != c.mesh.triangleCount()) {
            return who + ": mesh has no triangles or was not built";
        }
        for (int t = 0; t < c.mesh.triangleCount(); ++t) {
            if (!(c.mesh.restArea[t] > 0)) {
                return who + ": triangle " + std::to_string(t) + ": zero or negative rest area";
            }
        }
        if (c.position.rows() != nv) {
            return who + ": " + std::to_string(c.position.rows()) + " positions for " +
                   std::to_string(nv) + " vertices";
        }
        if (c.velocity.rows() != 0 && c.velocity.rows() != nv) {
            return who + ": velocity count does not match the vertex count";
        }
        for (int i = 0; i < nv; ++i) {
            if (!c.position.row(i).allFinite()) {
                return who + ": vertex " + std::to_string(i) + ": position is not finite";
            }
        }
        const Material& m = c.material;
        if (!(m.density > 0) || !std::isfinite(m.density)) {
            return who + ": material density must be positive and finite";
        }
        if (!(m.stretchWeft > 0) || !(m.stretchWarp > 0) || !(m.shear > 0) ||
            !std::isfinite(m.stretchWeft + m.stretchWarp + m.shear)) {
            return who + ": stretch and shear stiffness must be positive and finite";
        }
        if (!(m.bending >= 0) || !(m.damping >= 0) || !std::isfinite(m.bending + m.damping)) {
            return who + ": bending and damping must be non-negative and finite";
        }
        if (BendingRigidity rigidity; const auto why = bendingRigidity(m, rigidity)) {
            return who + ": " + *why;
        }
        const double nu21 = m.poisson * m.stretchWarp / m.stretchWeft;
        if (!(m.poisson >= 0) || !(m.poisson * nu21 < 1.0) ||
            (c.model == StretchModel::Volino && m.poisson >= 0.5)) {
            return who + ": Poisson ratio out of range (need 0 <= nu and nu12*nu21 < 1; volino: nu "
                         "< 0.5)";
        }
        if (c.restAngles.size() != 0 && c.restAngles.size() != c.mesh.hinges.rows()) {
            return who + ": rest_angles has " + std::to_string(c.restAngles.size()) +
                   " values for " + std::to_string(c.mesh.hinges.rows()) + " interior edges";
        }
    }
    return std::nullopt;
}

/// Pins, drives and seams: vertices in range, paths and parameters valid.
std::optional<std::string> validateConstraints(const SceneSpec& s, int total) {
    for (int p : s.pins) {
        if (p < 0 || p >= total) {
            return "pin vertex " + std::to_string(p) + " out of range [0, " +
                   std::to_string(total) + ")";
        }
    }
    for (std::size_t d = 0; d < s.drives.size(); ++d) {
        const Drive& dr = s.drives[d];
        const std::string who = "drive " + std::to_string(d);
        if (dr.vertex < 0 || dr.vertex >= total) {
            return who + ": vertex " + std::to_string(dr.vertex) + " out of range";
        }
        if (dr.times.empty() || dr.times.size() != dr.positions.size()) {
            return who + ": needs as many key times as key positions, at least one";
        }
        for (std::size_t k = 1; k < dr.times.size(); ++k) {
            if (!(dr.times[k] > dr.times[k - 1])) {
                return who + ": key times must increase (key " + std::to_string(k) + ")";
            }
        }
        for (const Vec3& p : dr.positions) {
            if (!p.allFinite()) {
                return who + ": key positions must be finite";
            }
        }
        if (dr.followTimeConstant < 0) {
            return who + ": follow time constant must be >= 0";
        }
    }
    for (std::size_t k = 0; k < s.seams.size(); ++k) {
        const SeamPair& p = s.seams[k];
        if (p.a < 0 || p.a >= total || p.b < 0 || p.b >= total || p.a == p.b) {
            return "seam " + std::to_string(k) +
                   ": vertices must be two different vertices in range";
        }
    }
    if (!(s.seamWeldDistance >= 0)) {
        return std::string("seam weld distance must be zero or positive");
    }
    if (!(s.seamReach >= 0) || !std::isfinite(s.seamReach)) {
        return std::string("seam reach must be zero or positive");
    }
    if (!(s.seamRouteClearance >= 0) || !std::isfinite(s.seamRouteClearance)) {
        return std::string("seam route clearance must be zero or positive");
    }
    if (!(s.seamStiffnessPerLength >= 0) || !std::isfinite(s.seamStiffnessPerLength)) {
        return std::string("seam stiffness per length must be zero or positive");
    }
    for (std::size_t k = 0; k < s.seams.size(); ++k) {
        if (!(s.seams[k].length >= 0) || !std::isfinite(s.seams[k].length)) {
            return "seam pair " + std::to_string(k) + ": length must be zero or positive";
        }
    }
    if (!s.seams.empty() && !(s.seamTimeConstant > 0)) {
        return std::string("seam time constant must be positive");
    }
    return std::nullopt;
}

/// Obstacles: meshes, motion, thickness and friction.
std::optional<std::string> validateObstacles(const SceneSpec& s) {
    for (std::size_t k = 0; k < s.obstacles.size(); ++k) {
        const ObstacleSpec& ob = s.obstacles[k];
        const std::string who = "obstacle " + std::to_string(k) + " (" + ob.name + ")";
        const int nv = static_cast<int>(ob.vertices.rows());
        if (ob.triangles.rows() == 0 || nv == 0) {
            return who + ": mesh has no triangles";
        }
        if (!ob.vertices.allFinite()) {
            return who + ": vertex positions must be finite";
        }
        for (Eigen::Index t = 0; t < ob.triangles.rows(); ++t) {
            for (int c = 0; c < 3; ++c) {
                if (ob.triangles(t, c) < 0 || ob.triangles(t, c) >= nv) {
                    return who + ": triangle " + std::to_string(t) + " has a vertex out of range";
                }
            }
        }
        if (ob.closed && !isClosedOriented(ob.triangles, nv)) {
            return who + ": marked closed but not watertight with consistent orientation";
        }
        if (!(ob.thickness >= 0) || !(ob.staticFriction >= 0) || !(ob.kineticFriction >= 0) ||
            !std::isfinite(ob.thickness + ob.staticFriction + ob.kineticFriction)) {
            return who + ": thickness and friction must be non-negative and finite";
        }
        for (std::size_t i = 1; i < ob.keys.size(); ++i) {
            if (!(ob.keys[i].time > ob.keys[i - 1].time)) {
                return who + ": key times must increase (key " + std::to_string(i) + ")";
            }
        }
        for (const ObstacleKey& key : ob.keys) {
            if (!key.translation.allFinite() || !key.rotation.allFinite() ||
                !std::isfinite(key.time)) {
                return who + ": keys must be finite";
            }
        }
        if (ob.frames.size() != ob.frameTimes.size()) {
            return who + ": as many frame times as frames are needed";
        }
        for (std::size_t i = 0; i < ob.frames.size(); ++i) {
            if (ob.frames[i].rows() != nv || !ob.frames[i].allFinite()) {
                return who + ": frame " + std::to_string(i) + " must have " + std::to_string(nv) +
                       " finite positions";
            }
            if (i > 0 && !(ob.frameTimes[i] > ob.frameTimes[i - 1])) {
                return who + ": frame times must increase (frame " + std::to_string(i) + ")";
            }
        }
    }
    return std::nullopt;
}

/// Collision, integrator and run settings.
std::optional<std::string> validateSettings(const SceneSpec& s) {
    for (std::size_t ci = 0; ci < s.cloths.size(); ++ci) {
        if (!(s.cloths[ci].thickness >= 0) || !std::isfinite(s.cloths[ci].thickness)) {
            return "cloth " + std::to_string(ci) + ": thickness must be non-negative and finite";
        }
    }
    if (!(s.collision.iterations >= 1) || !(s.collision.proximityFactor >= 0) ||
        !(s.collision.extractionSpeed > 0)) {
        return std::string(
            "collision: need iterations >= 1, proximity factor >= 0, extraction speed > 0");
    }
    const IntegratorOptions& o = s.integrator;
    if (!(o.dt > 0) || !(o.minDt > 0) || !(o.maxDt >= o.minDt) || !(o.tolerance > 0) ||
        !(o.growth > 1.0)) {
        return std::string(
            "integrator: need dt > 0, tolerance > 0, 0 < min_dt <= max_dt, growth > 1");
    }
    if (!(s.duration >= 0) || !std::isfinite(s.duration) || !(s.frameRate > 0)) {
        return std::string("duration must be >= 0 and frame rate > 0");
    }
    if (!(s.highDampingTimeConstant >= 0)) {
        return std::string("high damping time constant must be >= 0");
    }
    return std::nullopt;
}

} // namespace

std::optional<std::string> validateScene(const SceneSpec& s) {
    if (s.cloths.empty()) {
        return std::string("the scene has no cloth");
    }
    int total = 0;
    for (const ClothSpec& c : s.cloths) {
        total += c.mesh.vertexCount();
    }
    if (auto e = validateCloths(s)) {
        return e;
    }
    if (auto e = validateConstraints(s, total)) {
        return e;
    }
    if (auto e = validateObstacles(s)) {
        return e;
    }
    return validateSettings(s);
}

} // namespace atelier::sim
