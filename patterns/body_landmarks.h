#pragma once
/// Landmarks of a standing body mesh found from its shape: horizontal sections give the
/// crotch (where the legs' two loops join into one), the armpits (where an arm's loop joins
/// the torso's), the waist, hip, bust and neck (narrowest and fullest torso girths); the
/// limbs' vertices give their axes. Independent of the body's turn about the vertical and of
/// its scale; the arms may be anywhere from A-pose to T-pose.

#include "sim/core/types.h"

#include <array>
#include <string>
#include <variant>
#include <vector>

namespace atelier::patterns {

/// What `findLandmarks` found, in the mesh's coordinates (Y up) [m]. Arrays are left (the
/// body's own left) then right.
struct BodyLandmarks {
    double floorY = 0;                     ///< lowest vertex
    double height = 0;                     ///< floor to crown
    sim::Vec3 facing = sim::Vec3::UnitZ(); ///< horizontal unit: where the toes point (+z if not)
    sim::Vec3 left = sim::Vec3::UnitX();   ///< horizontal unit: the body's left, Y × facing
    /// A point on the torso's vertical axis (the centroid of its section above the crotch).
    sim::Vec3 centre = sim::Vec3::Zero();
    double crotchY = 0;              ///< where the legs' sections join
    double hipY = 0;                 ///< fullest torso girth above the crotch
    double waistY = 0;               ///< narrowest torso girth between hip and bust
    double bustY = 0;                ///< fullest torso girth between waist and armpits
    std::array<double, 2> armpitY{}; ///< where each arm's section joins the torso's
    double shoulderY = 0;            ///< top of the shoulders above the armpits
    double neckY = 0;                ///< narrowest girth between shoulders and head
    double neckBaseY = 0;            ///< below the neck, where its girth has grown by a fifth
    double shoulderHalfWidth = 0;    ///< torso half-width where the arms join [m]
    std::array<sim::Vec3, 2> shoulderJoint{}; ///< top of each (upper) arm's axis
    std::array<sim::Vec3, 2> wrist{};      ///< the arm's length (to the fingertips) down that axis
    std::array<sim::Vec3, 2> armAxis{};    ///< unit, from the wrist toward the shoulder
    std::array<sim::Vec3, 2> hipJoint{};   ///< above the thigh's centre, at the crotch
    std::array<sim::Vec3, 2> thighPoint{}; ///< centre of each thigh's section
    std::array<sim::Vec3, 2> ankle{};      ///< centre of each leg's section near the floor
    // Tape girths [m].
    double bust = 0, waist = 0, hip = 0, neck = 0;
    std::array<double, 2> thigh{}, upperArm{};

    /// The body's own frame: x its left, y up (as the mesh's), z where it faces, the torso's
    /// axis at x = z = 0.
    sim::Vec3 toLocal(const sim::Vec3& p) const {
        const sim::Vec3 d(p.x() - centre.x(), 0, p.z() - centre.z());
        return {d.dot(left), p.y(), d.dot(facing)};
    }
    sim::Vec3 toWorld(const sim::Vec3& q) const {
        return sim::Vec3(centre.x(), q.y(), centre.z()) + q.x() * left + q.z() * facing;
    }
    /// A direction (or offset) of the body's frame in the mesh's.
    sim::Vec3 directionToWorld(const sim::Vec3& v) const {
        return v.x() * left + v.y() * sim::Vec3::UnitY() + v.z() * facing;
    }
};

/// The landmarks of a body mesh, with each vertex's part (0 torso with head and neck, 1–2
/// arms left and right, 3–4 legs, as the mannequin labels them).
struct FoundLandmarks {
    BodyLandmarks landmarks;
    std::vector<int> part; ///< (|V|)
};

/// Finds the landmarks of a standing body (Y up, any turn about Y, arms away from the torso),
/// or says what it could not find.
std::variant<FoundLandmarks, std::string> findLandmarks(const sim::MatX3& vertices,
                                                        const sim::MatX3i& triangles);

} // namespace atelier::patterns
