#pragma once
/// A contact of the collision stage: a one-sided constraint on a combination of cloth vertices
/// and an obstacle point, with its friction.

#include "sim/core/types.h"

#include <cstdint>

namespace atelier::sim {

/// One contact: the constraint n · r ≥ distance on the relative position
/// \f$ r = \sum_k w_k x_k - q \f$ of cloth vertices (up to four, weights w) and an obstacle
/// point q (zero for cloth–cloth).
struct Contact {
    enum class Kind : std::uint8_t {
        VertexFace,
        FaceVertex,
        EdgeEdge,
        SelfVertexFace,
        SelfEdgeEdge
    };
    Kind kind = Kind::VertexFace;
    int vertex[4] = {-1, -1, -1, -1}; ///< global cloth vertices (-1 unused)
    double weight[4] = {0, 0, 0, 0};
    Vec3 obstaclePoint = Vec3::Zero();    ///< q at the end of the step [m]
    Vec3 obstacleVelocity = Vec3::Zero(); ///< dq/dt over the step [m/s]
    Vec3 normal = Vec3::UnitY();          ///< unit direction in which r must stay
    double distance = 0;                  ///< contact distance (sum of thicknesses) [m]
    double staticFriction = 0;
    double kineticFriction = 0;
    /// Friction of a touching contact: Coulomb's law, or, for a vertex pinched between two
    /// obstacles (markPinches, response/pinch.h), stuck to the one that grips harder and sliding
    /// freely on the other.
    enum class Grip : std::uint8_t { Coulomb, Stick, Slip };
    Grip grip = Grip::Coulomb;
    bool active = false; ///< touching after the position correction (B acts on it)
    bool swept = false;  ///< found by a swept test only (the pair ended apart)
    int obstacle = -1;   ///< obstacle index, or -1 for cloth–cloth
    /// q as a combination of the obstacle's vertices (up to three: a face point, an edge
    /// point or a vertex), so its velocity can be taken over another step.
    int obstacleVertex[3] = {-1, -1, -1};
    double obstacleWeight[3] = {0, 0, 0};

    void setObstaclePoint(const int* vertices, const double* weights, int count) {
        for (int k = 0; k < count; ++k) {
            obstacleVertex[k] = vertices[k];
            obstacleWeight[k] = weights[k];
        }
    }
};

} // namespace atelier::sim
