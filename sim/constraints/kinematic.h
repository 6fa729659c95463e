#pragma once
/// Kinematic corrections (Volino & Magnenat-Thalmann 1997, §6.2): paths of driven vertices and
/// the purely dissipative high damping (A).

#include "sim/core/types.h"
#include "sim/scene.h"

#include <array>
#include <vector>

namespace atelier::sim {

/// Position [m] and velocity [m/s] of a drive's path at time t (piecewise linear; the
/// velocity is the one of the segment after t, so a step starting on a key moves toward the
/// next key).
struct PathSample {
    Vec3 position;
    Vec3 velocity;
};
PathSample samplePath(const Drive& drive, double t);

/// Whether the drive still holds its vertex at time t.
inline bool driveActive(const Drive& d, double t) {
    return t < d.releaseTime;
}

/// Next time after t at which a drive's path has a kink or releases (so steps can stop there),
/// or +inf.
double nextPathEvent(const Drive& drive, double t);

/// High damping (A): for each edge (i, j) in turn, the relative velocity is multiplied by
/// \f$ e^{-h/\tau} \f$ with a momentum-conserving split by mass. Each pair update lowers the
/// kinetic energy by \f$ \tfrac12\mu|r|^2(1-e^{-2h/\tau}) \ge 0 \f$ whatever τ and h, so the
/// correction is purely dissipative. Vertices with zero inverse mass are not changed.
void applyHighDamping(const std::vector<std::array<int, 2>>& edges, const VecX& invMass, double h,
                      double timeConstant, MatX3& v);

} // namespace atelier::sim
