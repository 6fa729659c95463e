#pragma once
/// A garment project: the body, the garment and how to drape it. What a `.atelier` file holds
/// (io/project_file reads and writes it).

#include "patterns/document.h"
#include "patterns/garment.h"

#include "sim/scene.h"

#include <string>
#include <utility>
#include <vector>

namespace atelier::patterns {

/// Where the body comes from: the parametric mannequin (a base and measurements), or a mesh.
struct BodySource {
    std::string base = "female"; ///< mannequin base: "female" or "male"
    /// Measurements overriding the base's defaults, by field name (`waist`, `hip`, ...) in
    /// file order [m].
    std::vector<std::pair<std::string, double>> measurements;
    /// A body mesh (OBJ, FBX, glTF, COLLADA, PLY or STL; facing +z once Y up), relative to the
    /// project file; when set, the mannequin is not used and the slots are computed from the
    /// mesh.
    std::string meshPath;
    /// The mesh file's unit ("mm", "cm", "m") and up axis ("y", "z"); empty = detected.
    std::string meshUnits;
    std::string meshUp;

    bool operator==(const BodySource&) const = default;
};

/// How a garment is meshed, assembled and draped.
struct DrapeSettings {
    double particleDistance = 0.01; ///< target mesh edge length [m]
    sim::StretchModel model = sim::StretchModel::Fem;
    /// Bending: the per-hinge coefficient (discrete shells, the default until the hard cases
    /// pass with the continuum, decisions/020) or the continuum plate's rigidity on any mesh.
    sim::BendingModel bendingModel = sim::BendingModel::Hinge;
    sim::IntegratorKind integrator = sim::IntegratorKind::ImplicitEuler;
    double dt = 1.0 / 300; ///< step (fixed, or first of rk45) [s]
    /// Implicit Euler: relative tolerance of the conjugate-gradient solve. Draping needs the
    /// shape at rest, not the path to it: on the 10 mm skirt, 1e-3 closed the seams nearly as
    /// fast as 1e-6 (gap 0.176 against 0.156 m after 0.3 s) with ~200 instead of 500 iterations.
    double cgTolerance = 1e-3;
    /// Implicit Euler: the solve's preconditioner. Block-Jacobi: the drapes' sewing and rest
    /// figures were tuned with its inexact solves; block IC(0) closes the 10 mm tshirt's seams
    /// later (docs/decisions/019-linear-solver.md).
    sim::LinearSolver linearSolver = sim::LinearSolver::BlockJacobi;
    double clothThickness = 0.002; ///< collision thickness of the cloth [m]
    bool selfCollision = true;     ///< garment against itself (layers, front vs back)
    double bodyThickness = 0.002;  ///< collision thickness of the body surface [m]
    double bodyStaticFriction = 0.5;
    double bodyKineticFriction = 0.4;
    /// Seams close like (1 + t/τ)e^{−t/τ} when nothing resists [s]. The elastic's stiffness is
    /// μ/τ² (μ: the pair's reduced mass), tiny against fabric stiffness at garment masses: at
    /// 4 ms half the tshirt's pairs close by themselves (docs/decisions/009).
    double seamTimeConstant = 0.004;
    /// The seams' strength: stiffness per metre of seam added to the μ/τ² law
    /// (sim::SceneSpec::seamStiffnessPerLength), so that a seam holds against the fabric's
    /// tension at any mesh resolution [N/m²]; 0 = the mass-proportional law only. 16000 closes
    /// every pair of the 10 mm tshirt by 0.74 s; the sweep that chose it is in
    /// docs/decisions/008.
    double seamStiffness = 16000.0;
    double seamWeldDistance = 0.001; ///< a closed seam pair welds below this gap [m]
    /// Welded seams bend like the cloth beside them (times each seam's bending scale, about its
    /// fold angle: sim::SceneSpec::seamBending); off, every seam is a free hinge.
    bool seamBending = true;
    /// Beyond this gap a seam pulls with a constant force (sim::SceneSpec::seamReach): gaps
    /// close at about seamReach/(2τ) [m].
    double seamReach = 0.01;
    /// Sewing leads a seam around the body where its chord crosses it, via a point this far
    /// outside the body (sim::SceneSpec::seamRouteClearance) [m]; 0 = straight chords only.
    double seamRouteClearance = 0.01;
    /// Sewing phase: gravity starts after this time [s], so that the seams close around the
    /// body before the garment can fall off it.
    double sewingTime = 0.3;
    /// Friction against the body and between layers is multiplied by this while sewing
    /// (sim::Simulation::setFrictionScale): panels pressed onto the body by their own
    /// tension slide along it to meet their seams instead of sticking where they land [-].
    double sewingFrictionScale = 0.0;
    /// Over the last this-many seconds of sewing the pull of open seams grows tenfold
    /// (patterns/sewing.h), so they close before sewing ends rather than
    /// being welded across their gap [s]; 0 = a constant pull.
    double closingTime = 0.3;
    /// At rest when the mean kinetic energy per vertex stays below this [J] ...
    double restKineticEnergy = 1e-8;
    double restDuration = 0.2; ///< ... for this long [s] of simulated time
    double timeLimit = 5.0;    ///< simulated time after which the drape stops anyway [s]
};

/// The design (name, body, garment document) and the drape settings. The document is the
/// source of truth: editing works on it and saving writes it. `garment` is the index-based
/// form the mesher and the drape session take, `toGarment(document)`: loading fills both, and
/// whoever edits `document` refreshes `garment` with `syncGarment`. What the drape session
/// changes on its copy (a material's values, a redrawn panel, a placement) stays in `garment`.
struct Project {
    int version = 2; ///< the file version it was read from (saving writes the newest)
    std::string name;
    BodySource body;
    GarmentDocument document;
    Garment garment;
    DrapeSettings drape;
};

/// `project.garment = toGarment(project.document)`.
inline void syncGarment(Project& project) {
    project.garment = toGarment(project.document);
}

} // namespace atelier::patterns
