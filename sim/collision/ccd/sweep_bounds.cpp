#include "sim/collision/ccd/sweep_bounds.h"

namespace atelier::sim::ccd {

SweepBounds sweepBounds(const std::array<Vec3, 9>& offsets, double lipschitz, double distance) {
    double scale = 0;
    for (const Vec3& v : offsets) {
        scale = std::max(scale, v.norm());
    }
    SweepBounds b;
    b.lipschitz = lipschitz;
    b.tolerance = CCD_RELATIVE_TOLERANCE * scale;
    b.threshold = distance + b.tolerance;
    // With a distance below the resolution, resolve to the distance.
    const double resolution = CCD_RELATIVE_RESOLUTION * scale;
    b.resolution =
        std::max(b.tolerance, distance > 0 ? std::min(resolution, distance) : resolution);
    return b;
}

} // namespace atelier::sim::ccd
