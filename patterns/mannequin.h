#pragma once
/// The parametric mannequin: a smooth, closed body generated from tailoring measurements, in
/// A-pose, with its arrangement slots computed from the same parameters.

#include "patterns/body.h"

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace atelier::patterns {

/// Tailoring measurements [m]. Girths are tape measures (the convex hull of the section).
struct BodyMeasurements {
    double height = 1.68;        ///< floor to the top of the head
    double bust = 0.90;          ///< girth at the bust points (chest for the male base)
    double underBust = 0.76;     ///< girth just below the bust
    double waist = 0.70;         ///< girth at the natural waist
    double hip = 0.97;           ///< girth at the fullest part of the seat
    double neck = 0.34;          ///< girth of the neck at mid height
    double shoulderWidth = 0.39; ///< shoulder point to shoulder point (biacromial)
    double armLength = 0.57;     ///< shoulder point to wrist, along the arm
    double upperArm = 0.28;      ///< girth of the upper arm halfway to the elbow
    double inseam = 0.77;        ///< floor to crotch
    double thigh = 0.55;         ///< girth of the thigh just below the crotch
};

/// Every measurement by its file name (`height`, `bust`, `under_bust`, ...), in this order.
std::vector<std::pair<std::string_view, double BodyMeasurements::*>> measurementFields();

/// The defaults of a base ("female" or "male"); nullopt-like: false when the base is unknown.
bool baseMeasurements(std::string_view base, BodyMeasurements& out);

/// Problems with a set of measurements (out of range, or inconsistent with each other), each
/// naming the field. Empty when a mannequin can be built.
std::vector<std::pair<std::string, std::string>> checkMeasurements(const BodyMeasurements& m);

struct MannequinOptions {
    double cell = 0.027;         ///< grid spacing of the surface extraction [m] (≈ 20k triangles)
    int fitIterations = 8;       ///< girth-fitting rounds (each regenerates the surface)
    double fitTolerance = 0.001; ///< stop when every girth is this close [m]
};

/// Landmarks of a generated body [m]: where the measurements are taken and the joints are.
struct MannequinLandmarks {
    double crotchY = 0, hipY = 0, waistY = 0, underBustY = 0, bustY = 0, shoulderY = 0, neckY = 0,
           thighY = 0;
    std::array<sim::Vec3, 2> shoulderPoint; ///< acromion, left (+x) then right
    std::array<sim::Vec3, 2> shoulderJoint;
    std::array<sim::Vec3, 2> elbow;
    std::array<sim::Vec3, 2> wrist;
    std::array<sim::Vec3, 2> hipJoint;
    std::array<sim::Vec3, 2> upperArmPoint; ///< where the upper-arm girth is taken
    std::array<sim::Vec3, 2> thighPoint;    ///< where the thigh girth is taken
    double torsoZ = 0;                      ///< centre of the torso sections in z
    double armAngle = 0;                    ///< A-pose: the arms' angle from the vertical
};

struct Mannequin {
    Body body;          ///< mesh (outward, Y up, feet at y = 0, facing +z) and slots
    sim::MatX3 normals; ///< smooth vertex normals (gradients of the implicit surface)
    MannequinLandmarks landmarks;
    BodyMeasurements requested;
    /// The same measurements taken on the generated mesh (tape girths, floor-to-crotch, ...).
    BodyMeasurements measured;
    double seconds = 0; ///< wall time to generate [s]
};

/// Generates the mannequin of `base` with `m`. The surface is the zero set of a smooth union
/// of a swept torso (superellipse sections through the measured levels), neck, head, breasts
/// (female base), limbs as tapered round cones and hands and feet as ellipsoids, extracted as
/// a closed mesh; its section scales are then refitted until the tape girths measured on the
/// mesh match the requested ones. Precondition: checkMeasurements(m) is empty.
Mannequin makeMannequin(std::string_view base, const BodyMeasurements& m,
                        const MannequinOptions& options = {});

/// Arrangement slots for a body mesh that is not a mannequin (a scan, an export): a standing
/// figure, Y up, arms away from the torso (A-pose to T-pose), turned any way about Y. The
/// slots are the mannequin's, fitted to the landmarks found from the mesh's shape
/// (findLandmarks, patterns/body_landmarks.h) and turned with it. Returns what is wrong when
/// the mesh does not look like one.
std::optional<std::string> estimateSlots(Body& body);

/// Measurements of a mannequin's mesh, taken where its landmarks say.
BodyMeasurements measureMannequin(const sim::MatX3& vertices, const sim::MatX3i& triangles,
                                  const MannequinLandmarks& landmarks);

} // namespace atelier::patterns
