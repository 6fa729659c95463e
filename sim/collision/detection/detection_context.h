#pragma once
/// What every detection pass reads: the scene (options, materials), the cloths' collision mesh
/// and hierarchy, and the friction scale of the current phase.

#include "sim/collision/bvh.h"
#include "sim/collision/collision_mesh.h"
#include "sim/scene.h"

#include <algorithm>
#include <cmath>

namespace atelier::sim {

/// The side of a signed distance: +1, −1, or 0 on the surface (a contact's orientation).
inline signed char signOf(double v) {
    return v > 0 ? 1 : (v < 0 ? -1 : 0);
}

struct DetectionContext {
    const SceneSpec& scene;
    const CollisionMesh& mesh;
    const SurfaceBvh& clothBvh;
    double frictionScale = 1.0; ///< multiplies the friction of contacts found (sewing phase)

    /// The friction coefficient of a contact between two materials' coefficients a and b
    /// (their geometric mean), times the current scale.
    double scaledFriction(double a, double b) const {
        return frictionScale * std::sqrt(std::max(0.0, a) * std::max(0.0, b));
    }
};

} // namespace atelier::sim
