#pragma once
/// The building blocks of every correction on a contact: its effective inverse mass, its
/// relative quantity (position, velocity or acceleration) and the distribution of a change of
/// that quantity over the contact's cloth vertices.

#include "sim/collision/contact.h"
#include "sim/collision/indexing.h"
#include "sim/core/types.h"

namespace atelier::sim {

/// Σ w_k invMass_k w_k over the contact's cloth vertices.
inline double effectiveInverseMass(const Contact& c, const VecX& invMass) {
    double w = 0;
    for (int k = 0; k < 4; ++k) {
        if (c.vertex[k] >= 0) {
            w += c.weight[k] * c.weight[k] * invMass[c.vertex[k]];
        }
    }
    return w;
}

/// Σ w_k x_k over the contact's cloth vertices (x: positions, velocities or accelerations).
inline Vec3 combination(const Contact& c, const MatX3& x) {
    Vec3 r = Vec3::Zero();
    for (int k = 0; k < 4; ++k) {
        if (c.vertex[k] >= 0) {
            r += c.weight[k] * row(x, c.vertex[k]);
        }
    }
    return r;
}

/// Adds `delta` to the contact's relative quantity, split by inverse mass (w: the effective
/// inverse mass): each vertex moves by w_k invMass_k / w · delta, so Σ w_k Δ_k = delta.
inline void distribute(const Contact& c, const VecX& invMass, double w, const Vec3& delta,
                       MatX3& y) {
    for (int k = 0; k < 4; ++k) {
        const int i = c.vertex[k];
        if (i >= 0 && invMass[i] > 0) {
            y.row(i) += (c.weight[k] * invMass[i] / w * delta).transpose();
        }
    }
}

} // namespace atelier::sim
