#pragma once
/// What a continuous (swept) test reports: when in the step the primitives first come within
/// the distance, and where on them.

#include <array>

namespace atelier::sim {

/// A hit of a continuous test: the first time in [0, 1] (fraction of the step, positions
/// moving linearly from start to end) at which the primitives are within the distance.
struct SweptHit {
    double time = 0; ///< fraction of the step in [0, 1]
    /// Vertex–triangle: barycentric weights of the triangle's vertices at `time`.
    /// Edge–edge: (s, t, unused) segment parameters at `time`.
    std::array<double, 3> coords{};
};

} // namespace atelier::sim
