#include "sim/collision/distance/obstacle_distance.h"

#include "sim/collision/indexing.h"
#include "sim/collision/triangle_normal.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace atelier::sim {

namespace {

constexpr double INFINITE_DISTANCE = std::numeric_limits<double>::infinity();

/// Angle of triangle (a, b, c) at a [rad].
double cornerAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 u = b - a, w = c - a;
    return std::atan2(u.cross(w).norm(), u.dot(w));
}

} // namespace

double signedDistance(const CollisionObstacle& o, const MatX3& xo, const Vec3& p,
                      double maxDistance, Vec3* closest, Vec3* outward) {
    const auto [tri, cp] = o.bvh.closestTriangle(xo, p, maxDistance);
    if (tri < 0) {
        return INFINITE_DISTANCE;
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
        *outward =
            cp.distance > TINY_LENGTH ? Vec3(sign * d / cp.distance) : Vec3(pseudo.normalized());
    }
    return sign * cp.distance;
}

double vertexSignedDistance(CollisionObstacle& o, int p, const Vec3& xp, double enough) {
    const auto i = static_cast<std::size_t>(p);
    if (!o.moves && std::isfinite(o.distanceValue[i])) {
        const double bound =
            o.distanceValue[i] -
            (xp - o.distancePoint.row(static_cast<Eigen::Index>(i)).transpose()).norm();
        if (bound >= enough) {
            return bound;
        }
    }
    const double sd = signedDistance(o, o.x1, xp, INFINITE_DISTANCE);
    if (!o.moves) {
        o.distanceValue[i] = sd;
        o.distancePoint.row(static_cast<Eigen::Index>(i)) = xp.transpose();
    }
    return sd;
}

} // namespace atelier::sim
