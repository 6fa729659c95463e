#pragma once
/// The Cusick drape test (BS 5058, ISO 9073-9): a circular specimen clamped between two discs
/// and left to hang under gravity; seen from above, its shadow gives the drape coefficient
/// DC = (A_shadow − A_disc) / (A_specimen − A_disc) (1: stiff as a board, 0: hangs straight)
/// and the number of nodes (the folds round its edge). Simulated here with a fabric on the
/// engine, so a designer can see the figure a textile lab would report beside a fabric.

#include "sim/core/types.h"
#include "sim/material.h"
#include "sim/scene.h"

#include <atomic>
#include <string>
#include <vector>

namespace atelier::patterns {

struct CusickOptions {
    sim::Material material;
    /// Continuum: `material.bending` is the rigidity a cantilever tester measures, on any mesh.
    sim::BendingModel bendingModel = sim::BendingModel::Hinge;
    double specimenDiameter = 0.30; ///< [m]
    double supportDiameter = 0.18;  ///< the clamping discs [m]
    double particleDistance = 0.01; ///< [m]
    double dt = 0.01;               ///< implicit Euler step [s]
    double maxTime = 8;             ///< settling gives up after this simulated time [s]
    /// At rest: no vertex moved more than this in 0.25 s of simulated time [m].
    double restMotion = 0.0005;
    /// Each start lifts or lowers the free vertices by a random amount up to this, so the folds
    /// can form where they will (a real specimen is never laid perfectly flat) [m]; seeded.
    double perturbation = 0.001;
    unsigned seed = 1;
    /// Set from another thread, stops the drape between steps (the result's error says so).
    const std::atomic<bool>* cancel = nullptr;
};

struct CusickResult {
    double drapeCoefficient = 0; ///< drape coefficient DC [-]
    int nodes = 0;               ///< folds round the edge
    double shadowArea = 0;       ///< [m²]
    std::vector<double> radius;  ///< the shadow's radius per degree (360 values) [m]
    sim::MatX3 positions;        ///< the draped specimen (y up, the disc at y = 0) [m]
    sim::MatX3i triangles;
    double settledTime = 0; ///< simulated time when at rest (or given up) [s]
    bool atRest = false;
    std::string error; ///< why the test could not run; empty otherwise
};

/// Meshes the specimen, clamps the disc's part, drapes it over the support and measures it.
CusickResult runCusick(const CusickOptions& options);

/// Area of the union of the triangles projected onto the horizontal (x, z) plane [m²], counted
/// on a grid of `cell`-sized squares (error ≲ perimeter × cell / 2).
double shadowArea(const sim::MatX3& positions, const sim::MatX3i& triangles, double cell);

/// The shadow's outer radius from the vertical axis per degree (360 bins, bin k covering
/// [k, k + 1)°, 0° along +x towards +z) [m], from the same grid; 0 where nothing lies.
std::vector<double> shadowRadius(const sim::MatX3& positions, const sim::MatX3i& triangles,
                                 double cell);

/// Folds in a closed radius profile: maxima that rise at least `prominence` above the minima
/// on both sides of them (hysteresis, so ripples smaller than that are not counted).
int countNodes(const std::vector<double>& radius, double prominence);

} // namespace atelier::patterns
