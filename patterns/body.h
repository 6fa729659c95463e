#pragma once
/// The body a garment is draped on: a closed triangle mesh and its arrangement slots.

#include "sim/core/types.h"

#include <string>
#include <vector>

namespace atelier::patterns {

/// A named surface around a part of the body on which panels are placed (like the
/// arrangement points of commercial garment tools): a cylinder around `axis` through
/// `origin`, enclosing the body part within [alongMin, alongMax] with `radius`; with a
/// profile, a surface of revolution following the part's radius; with section centres too
/// (leg slots), a tube whose centre follows the part.
///
/// A panel point (u, v) — u around, v along, both arc lengths [m] — maps to
/// origin + v·axis + c(v) + r·(cos(u/r)·facing + sin(u/r)·right), right = axis × facing,
/// r = radius (the profile's) + clearance, c the section centre's offset (zero but on leg
/// slots). A counter-clockwise panel drawn with +y "up" (toward +axis) then has its
/// front (normal +z of the pattern plane) facing away from the body.
struct ArrangementSlot {
    std::string name;
    sim::Vec3 origin = sim::Vec3::Zero();  ///< point on the axis where v = 0 [m]
    sim::Vec3 axis = sim::Vec3::UnitY();   ///< unit; pattern +y maps to +axis ("up" of the panel)
    sim::Vec3 facing = sim::Vec3::UnitZ(); ///< unit, ⟂ axis: where u = 0 looks from the axis
    /// Largest distance of the body part's vertices in range from the axis (from the section
    /// centres where there are some): the radius of the cylinder enclosing it [m].
    double radius = 0.2;
    double alongMin = -0.3; ///< extent of the body part along the axis from origin [m]
    double alongMax = 0.3;  ///< [m]
    /// The body part's radius along the axis: profile[k] encloses it at along = alongMin +
    /// k·profileStep (empty: `radius` everywhere) [m]. Panels are wrapped on this surface, so
    /// they start close to the body where it is narrow (a waist) and clear of it where it is
    /// wide (hips).
    std::vector<double> profile;
    /// Where the body part's sections are centred along the axis, as offsets ⟂ axis from it
    /// (profile[k]'s bin; empty: on the axis everywhere) [m]. A leg slot follows the leg,
    /// which is spread from the hip, and above the crotch the half of the pelvis on its side,
    /// so a trouser panel wrapped on it starts around its own leg.
    std::vector<sim::Vec3> profileCentre;
    double profileStep = 0.01; ///< [m]
    /// Largest angle a panel may span to either side of `facing` [rad]: a little under π/2
    /// where two panels share the circumference (front and back), under π where one panel
    /// wraps alone (a sleeve).
    double maxAngle = 3.1;

    sim::Vec3 right() const { return axis.cross(facing); }

    /// The profile's radius at `along` (linear, clamped to its ends) [m].
    double radiusAt(double along) const {
        return profile.empty() ? radius : interpolate(profile, along);
    }

    /// The section's centre offset from the axis at `along` (linear, clamped) [m].
    sim::Vec3 centreAt(double along) const {
        return profileCentre.empty() ? sim::Vec3(sim::Vec3::Zero())
                                     : interpolate(profileCentre, along);
    }

  private:
    template <class T> T interpolate(const std::vector<T>& values, double along) const {
        const double u = (along - alongMin) / profileStep;
        if (u <= 0) {
            return values.front();
        }
        const auto last = static_cast<double>(values.size() - 1);
        if (u >= last) {
            return values.back();
        }
        const auto k = static_cast<std::size_t>(u);
        const double f = u - static_cast<double>(k);
        return T((1 - f) * values[k] + f * values[k + 1]);
    }
};

/// A body mesh with its slots. Outward normals (counter-clockwise seen from outside), Y up,
/// feet at y = 0, facing +z, metres.
struct Body {
    sim::MatX3 vertices;   ///< (|V|×3) [m]
    sim::MatX3i triangles; ///< (|F|×3)
    std::vector<ArrangementSlot> slots;

    /// The slot with this name, or nullptr.
    const ArrangementSlot* slot(const std::string& name) const {
        for (const ArrangementSlot& s : slots) {
            if (s.name == name) {
                return &s;
            }
        }
        return nullptr;
    }
};

} // namespace atelier::patterns
