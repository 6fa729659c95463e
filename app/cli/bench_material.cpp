#include "app/cli/bench_material.h"

#include "app/cli/commands.h"
#include "io/atomic_file.h"
#include "sim/forces/fem.h"
#include "sim/forces/springs.h"
#include "sim/forces/volino.h"
#include "sim/simulation.h"

#include <Eigen/SparseLU>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <vector>

namespace atelier::app {

namespace {

constexpr double NaN = std::numeric_limits<double>::quiet_NaN();

std::unique_ptr<sim::ForceModel> makeStretchModel(const TensionTestOptions& o,
                                                  const sim::ClothMesh& mesh) {
    switch (o.model) {
    case sim::StretchModel::Springs:
        return std::make_unique<sim::SpringStretch>(mesh, 0, o.material, o.crossSprings);
    case sim::StretchModel::Volino:
        return std::make_unique<sim::VolinoStretch>(mesh, 0, o.material,
                                                    sim::lumpedMasses(mesh, o.material.density));
    case sim::StretchModel::Fem:
        return std::make_unique<sim::FemStretch>(mesh, 0, o.material);
    }
    return nullptr;
}

/// Index of the vertex among `candidates` whose rest coordinate along `axis` is nearest `value`.
int nearestAlong(const sim::MatX2& rest, const std::vector<int>& candidates, int axis,
                 double value) {
    int best = candidates.front();
    for (int i : candidates) {
        if (std::abs(rest(i, axis) - value) < std::abs(rest(best, axis) - value)) {
            best = i;
        }
    }
    return best;
}

const char* directionName(PullDirection d) {
    return d == PullDirection::Weft ? "weft" : "warp";
}

const char* triangulationName(sim::Triangulation t) {
    return t == sim::Triangulation::Regular ? "regular" : "irregular";
}

} // namespace

/// Boundary conditions (frictionless grips, in-plane test):
/// - every vertex is held in z: the strip stays in its plane (no wrinkling or buckling modes);
/// - the vertices of the fixed edge (pull coordinate 0) are held along the pull at 0, those of
///   the pulled edge at length·(1 + strain); both edges slide freely across the pull, so the
///   strip is in uniaxial stress (no grip constraint on the lateral contraction);
/// - the fixed edge's corner vertex on the lateral boundary 0 is also held across the pull, to
///   remove the rigid translation.
/// Static equilibrium f(x) = 0 on the free degrees of freedom is solved by Newton's method with
/// the model's `Exact` Jacobian (sparse LU) and a backtracking line search on |f_free|, starting
/// from the uniform stretch x_a = X_a(1 + strain) with no lateral contraction.
/// Stiffness = (force the pulled grip applies along the pull) / (width × strain); Poisson ratio
/// = −(lateral strain at mid-length) / strain, the lateral strain being the change of distance
/// between the two lateral-boundary vertices nearest mid-length over the rest width.
TensionTestResult runTensionTest(const TensionTestOptions& o) {
    TensionTestResult result;
    const bool weft = o.direction == PullDirection::Weft;
    const int pull = weft ? 0 : 1; // axis of the pull
    const int side = 1 - pull;     // lateral axis
    const sim::Material& m = o.material;
    result.requestedStretch = weft ? m.stretchWeft : m.stretchWarp;
    result.requestedPoisson = weft ? m.poisson : m.poisson * m.stretchWarp / m.stretchWeft;

    sim::RectangleOptions rect;
    rect.width = weft ? o.length : o.width;
    rect.height = weft ? o.width : o.length;
    rect.cellsX = weft ? o.cellsLong : o.cellsWide;
    rect.cellsY = weft ? o.cellsWide : o.cellsLong;
    rect.triangulation = o.triangulation;
    rect.seed = o.seed;
    sim::MatX2 rest;
    sim::MatX3i triangles;
    sim::makeRectangle(rect, rest, triangles);
    sim::ClothMesh mesh;
    if (auto e = sim::buildClothMesh(rest, triangles, mesh)) {
        result.error = "mesh: " + *e;
        return result;
    }
    const int n = mesh.vertexCount();
    result.vertices = n;
    result.triangles = mesh.triangleCount();
    const std::unique_ptr<sim::ForceModel> model = makeStretchModel(o, mesh);

    // Boundary sets, by rest coordinate (makeRectangle keeps boundary vertices on the border).
    const double eps = 1e-9 * std::max(o.length, o.width);
    std::vector<int> fixedEdge, pulledEdge, lowSide, highSide;
    for (int i = 0; i < n; ++i) {
        if (rest(i, pull) < eps) {
            fixedEdge.push_back(i);
        }
        if (rest(i, pull) > o.length - eps) {
            pulledEdge.push_back(i);
        }
        if (rest(i, side) < eps) {
            lowSide.push_back(i);
        }
        if (rest(i, side) > o.width - eps) {
            highSide.push_back(i);
        }
    }
    const int anchor = nearestAlong(rest, lowSide, pull, 0.0);
    const int midLow = nearestAlong(rest, lowSide, pull, 0.5 * o.length);
    const int midHigh = nearestAlong(rest, highSide, pull, 0.5 * o.length);

    // DOF d = 3·vertex + axis; free DOFs get consecutive indices, held ones -1.
    std::vector<int> freeIndex(static_cast<std::size_t>(3 * n), 0);
    for (int i = 0; i < n; ++i) {
        freeIndex[static_cast<std::size_t>(3 * i + 2)] = -1;
    }
    for (int i : fixedEdge) {
        freeIndex[static_cast<std::size_t>(3 * i + pull)] = -1;
    }
    for (int i : pulledEdge) {
        freeIndex[static_cast<std::size_t>(3 * i + pull)] = -1;
    }
    freeIndex[static_cast<std::size_t>(3 * anchor + side)] = -1;
    int freeCount = 0;
    for (int& f : freeIndex) {
        if (f == 0) {
            f = freeCount++;
        }
    }

    sim::MatX3 x = sim::MatX3::Zero(n, 3);
    for (int i = 0; i < n; ++i) {
        x(i, pull) = rest(i, pull) * (1.0 + o.strain);
        x(i, side) = rest(i, side);
    }
    const sim::MatX3 v = sim::MatX3::Zero(n, 3);
    sim::MatX3 f;

    // Forces, the free residual and the pulled grip's reaction at x.
    Eigen::VectorXd r(freeCount);
    const auto evaluate = [&](const sim::MatX3& xs, Eigen::VectorXd& res, double& reaction) {
        f.setZero(n, 3);
        model->addForces(xs, v, f);
        for (int i = 0; i < n; ++i) {
            for (int a = 0; a < 3; ++a) {
                const int k = freeIndex[static_cast<std::size_t>(3 * i + a)];
                if (k >= 0) {
                    res[k] = f(i, a);
                }
            }
        }
        reaction = 0;
        for (int i : pulledEdge) {
            reaction -= f(i, pull); // the grip balances the internal force
        }
    };

    std::vector<std::pair<int, int>> pairs;
    model->jacobianPattern(pairs);
    sim::BlockSparseMatrix jacobian(n, pairs);
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
    std::vector<Eigen::Triplet<double>> triplets;

    double reaction = 0;
    evaluate(x, r, reaction);
    const auto converged = [&](double norm) {
        return norm <= o.tolerance * std::max(std::abs(reaction), 1e-300);
    };
    double norm = r.norm();
    int it = 0;
    for (; it < o.maxIterations && !converged(norm); ++it) {
        jacobian.setZero();
        model->addJacobian(x, v, 1.0, 0.0, sim::JacobianMode::Exact, jacobian);
        triplets.clear();
        const std::vector<int>& rowStart = jacobian.rowStart();
        const std::vector<int>& cols = jacobian.columns();
        for (int bi = 0; bi < n; ++bi) {
            for (int s = rowStart[static_cast<std::size_t>(bi)];
                 s < rowStart[static_cast<std::size_t>(bi) + 1]; ++s) {
                const int bj = cols[static_cast<std::size_t>(s)];
                const sim::Mat3& b = jacobian.block(s);
                for (int p = 0; p < 3; ++p) {
                    const int row = freeIndex[static_cast<std::size_t>(3 * bi + p)];
                    if (row < 0) {
                        continue;
                    }
                    for (int q = 0; q < 3; ++q) {
                        const int col = freeIndex[static_cast<std::size_t>(3 * bj + q)];
                        if (col >= 0 && b(p, q) != 0.0) {
                            triplets.emplace_back(row, col, b(p, q));
                        }
                    }
                }
            }
        }
        Eigen::SparseMatrix<double> K(freeCount, freeCount);
        K.setFromTriplets(triplets.begin(), triplets.end());
        K.makeCompressed();
        lu.compute(K);
        if (lu.info() != Eigen::Success) {
            result.error = "Newton: the Jacobian on the free degrees of freedom is singular";
            break;
        }
        // f(x + Δ) ≈ f + K Δ = 0.
        const Eigen::VectorXd step = lu.solve(-r);
        if (!step.allFinite()) {
            result.error = "Newton: non-finite step";
            break;
        }
        // Backtracking on |r|: accept the first step length that decreases it.
        double alpha = 1.0;
        sim::MatX3 trial = x;
        Eigen::VectorXd trialR(freeCount);
        double trialReaction = 0;
        double trialNorm = norm;
        for (int ls = 0; ls < 30; ++ls) {
            trial = x;
            for (int i = 0; i < n; ++i) {
                for (int a = 0; a < 3; ++a) {
                    const int k = freeIndex[static_cast<std::size_t>(3 * i + a)];
                    if (k >= 0) {
                        trial(i, a) += alpha * step[k];
                    }
                }
            }
            evaluate(trial, trialR, trialReaction);
            trialNorm = trialR.norm();
            if (std::isfinite(trialNorm) && trialNorm < (1.0 - 1e-4 * alpha) * norm) {
                break;
            }
            alpha *= 0.5;
        }
        if (!(std::isfinite(trialNorm) && trialNorm < norm)) {
            // No decrease along the Newton direction: at the rounding floor, or stuck.
            break;
        }
        x = trial;
        r = trialR;
        reaction = trialReaction;
        norm = trialNorm;
    }

    result.iterations = it;
    result.reactionForce = reaction;
    result.residual = norm / std::max(std::abs(reaction), 1e-300);
    result.converged = converged(norm) && result.error.empty();
    if (!result.converged && result.error.empty()) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "Newton did not converge: relative residual %.3g after %d iterations",
                      result.residual, it);
        result.error = buf;
    }
    result.measuredStretch = reaction / (o.width * o.strain);
    const double widthNow = x(midHigh, side) - x(midLow, side);
    const double restWidth = rest(midHigh, side) - rest(midLow, side);
    result.lateralStrain = widthNow / restWidth - 1.0;
    result.measuredPoisson = -result.lateralStrain / o.strain;
    return result;
}

int runMaterialBench(const MaterialBenchOptions& options) {
    const TensionTestOptions& o = options.test;
    if (!(o.strain > 0) || !std::isfinite(o.strain) || o.cellsLong < 1 || o.cellsWide < 1 ||
        !(o.length > 0) || !(o.width > 0)) {
        std::cerr << "error: bench material: need strain > 0, positive size and cell counts\n";
        return EXIT_BAD_INPUT;
    }
    const sim::Material& m = o.material;
    if (!(m.stretchWeft > 0) || !(m.stretchWarp > 0) || !(m.shear > 0) || !(m.poisson >= 0) ||
        !(m.poisson * m.poisson * m.stretchWarp / m.stretchWeft < 1.0) ||
        (o.model == sim::StretchModel::Volino && m.poisson >= 0.5)) {
        std::cerr << "error: bench material: need positive weft, warp and shear stiffness and "
                     "0 <= poisson with nu12*nu21 < 1 (volino: < 0.5)\n";
        return EXIT_BAD_INPUT;
    }
    const TensionTestResult r = runTensionTest(o);

    const auto relative = [](double measured, double requested) {
        return requested != 0 ? measured / requested - 1.0 : NaN;
    };
    nlohmann::json j;
    j["format"] = "atelier-bench-material";
    j["version"] = 1;
    j["model"] = std::string(sim::stretchModelName(o.model)) +
                 (o.model == sim::StretchModel::Springs && o.crossSprings ? "+cross" : "");
    j["mesh"] = triangulationName(o.triangulation);
    j["direction"] = directionName(o.direction);
    j["strain"] = o.strain;
    j["geometry"] = {{"length_m", o.length},
                     {"width_m", o.width},
                     {"cells_long", o.cellsLong},
                     {"cells_wide", o.cellsWide},
                     {"vertices", r.vertices},
                     {"triangles", r.triangles},
                     {"seed", o.seed}};
    j["boundary_conditions"] =
        "in-plane (z held); fixed edge held along the pull, pulled edge displaced to "
        "length*(1+strain); both grips frictionless across the pull (uniaxial stress); one "
        "fixed-edge corner held across the pull";
    j["material"] = {{"weft_n_per_m", m.stretchWeft},
                     {"warp_n_per_m", m.stretchWarp},
                     {"shear_n_per_m", m.shear},
                     {"poisson", m.poisson}};
    j["requested"] = {{"stretch_n_per_m", r.requestedStretch}, {"poisson", r.requestedPoisson}};
    j["measured"] = {{"stretch_n_per_m", r.measuredStretch},
                     {"poisson", r.measuredPoisson},
                     {"reaction_force_n", r.reactionForce},
                     {"lateral_strain", r.lateralStrain}};
    j["relative_error"] = {{"stretch", relative(r.measuredStretch, r.requestedStretch)},
                           {"poisson", relative(r.measuredPoisson, r.requestedPoisson)}};
    j["poisson_difference"] = r.measuredPoisson - r.requestedPoisson;
    j["iterations"] = r.iterations;
    j["residual"] = r.residual;
    j["converged"] = r.converged;
    j["error"] = r.error.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.error);
    const std::string text = j.dump(2) + "\n";

    char line[256];
    std::snprintf(line, sizeof line,
                  "bench material: %s %s %s: stretch %.6g N/m (requested %.6g), poisson %.4f "
                  "(requested %.4f), %d Newton iterations, residual %.2g",
                  j["model"].get<std::string>().c_str(), triangulationName(o.triangulation),
                  directionName(o.direction), r.measuredStretch, r.requestedStretch,
                  r.measuredPoisson, r.requestedPoisson, r.iterations, r.residual);
    std::cerr << line << "\n";
    if (options.out.empty()) {
        std::cout << text;
    } else if (auto written = io::writeFileAtomically(options.out, text); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    if (!r.converged) {
        std::cerr << "error: bench material: " << r.error << "\n";
        return EXIT_RUN_FAILED;
    }
    return EXIT_OK;
}

} // namespace atelier::app
