#include "patterns/placement.h"

#include <cmath>

namespace atelier::patterns {

sim::MatX2 placementCoordinates(const Panel& panel, const PanelMesh& mesh) {
    sim::MatX2 p = mesh.pattern;
    if (panel.side == PanelSide::Back) {
        p.col(0) = -p.col(0);
    }
    if (p.rows() == 0) {
        return p;
    }
    const Vec2 centre = 0.5 * (p.colwise().minCoeff() + p.colwise().maxCoeff()).transpose();
    const double c = std::cos(panel.placement.rotation), s = std::sin(panel.placement.rotation);
    for (int i = 0; i < p.rows(); ++i) {
        const Vec2 q = p.row(i).transpose() - centre;
        p.row(i) = (Vec2(c * q.x() - s * q.y(), s * q.x() + c * q.y()) + panel.placement.offset)
                       .transpose();
    }
    return p;
}

sim::MatX3 wrapOnSlot(const sim::MatX2& coordinates, const ArrangementSlot& slot,
                      double clearance) {
    const double r = slot.radius + clearance;
    const Vec3 right = slot.right();
    sim::MatX3 x(coordinates.rows(), 3);
    for (int i = 0; i < coordinates.rows(); ++i) {
        const double angle = coordinates(i, 0) / r;
        const double along = coordinates(i, 1);
        x.row(i) = (slot.origin + along * slot.axis +
                    r * (std::cos(angle) * slot.facing + std::sin(angle) * right))
                       .transpose();
    }
    return x;
}

} // namespace atelier::patterns
