#pragma once
/// Index helpers of the collision stage's files: a vertex's row of a position matrix, and the
/// key of an ordered pair of indices.

#include "sim/core/types.h"

#include <cstdint>

namespace atelier::sim {

/// Row i of positions x (|V|×3) as a vector [m].
inline Vec3 row(const MatX3& x, int i) {
    return x.row(i).transpose();
}

/// A 64-bit key of the ordered pair of non-negative indices (a, b).
inline std::uint64_t pairKey(int a, int b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
           static_cast<std::uint32_t>(b);
}

} // namespace atelier::sim
