#pragma once
/// `atelier-cli bench cantilever`: Peirce's heavy cantilever (ASTM D1388), a strip clamped
/// horizontally along one short edge and settled under gravity with the implicit integrator,
/// against the exact heavy elastica (sim/analysis/heavy_elastica.h).
/// Plain C++ (no CLI11): the parsing is in bench_command.cpp.

#include "sim/material.h"
#include "sim/scene.h"

#include <string>
#include <vector>

namespace atelier::app {

/// How the strip is meshed.
enum class CantileverMesh {
    Regular,   ///< makeRectangle's criss-cross grid, aligned with the strip (weft along it)
    Irregular, ///< constrained Delaunay refinement of the strip (as garment panels are meshed)
    Rotated,   ///< the strip cut at 45° to the weft out of a weft-aligned square lattice
};

/// One cantilever scene.
struct CantileverOptions {
    CantileverMesh mesh = CantileverMesh::Regular;
    double particleDistance = 0.01; ///< target edge length [m]
    double ratio = 8;               ///< λ = ρgL³/B [-]; B follows from it
    double length = 0.08;           ///< overhang L [m]
    double width = 0.04;            ///< strip width [m]
    /// Fabric: density, stretch and damping are used; `bending` is set from `ratio`.
    sim::Material material;
    sim::BendingModel bendingModel = sim::BendingModel::Continuum;
    double dt = 0.01;            ///< implicit Euler step [s]
    double maxTime = 30;         ///< settling gives up after this simulated time [s]
    double restAngleDeg = 0.002; ///< at rest: tip-line angle moved less than this in 0.25 s
};

/// What one scene gave.
struct CantileverResult {
    double bending = 0; ///< B [N·m]
    int vertices = 0;
    double angleDeg = 0;        ///< simulated tip-line angle below the horizontal [deg]
    double exactAngleDeg = 0;   ///< the heavy elastica's [deg]
    double deflection = 0;      ///< simulated tip drop [m]
    double exactDeflection = 0; ///< [m]
    double settledTime = 0;     ///< simulated time to rest [s]
    bool atRest = false;
    std::string error; ///< why the scene could not run, empty otherwise
};

/// Builds and settles one cantilever.
CantileverResult runCantilever(const CantileverOptions& options);

/// `bench cantilever` as a whole: every ratio × particle distance × mesh.
struct CantileverBenchOptions {
    std::vector<double> ratios{1, 2, 4, 8, 16, 32, 50};
    std::vector<double> particleDistancesMm{10};
    std::vector<std::string> meshes{"regular", "irregular", "rotated"};
    std::string out; ///< output folder: cantilever.csv and cantilever.svg
    CantileverOptions scene;
};

/// Runs the sweep, prints a table, writes the CSV and SVG atomically. Returns an exit code
/// (app/cli/commands.h).
int runCantileverBench(const CantileverBenchOptions& options);

} // namespace atelier::app
