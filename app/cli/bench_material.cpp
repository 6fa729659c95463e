#include "app/cli/bench_material.h"

#include "app/cli/commands.h"

#include "io/atomic_file.h"
#include "io/json_text.h"

#include "patterns/fabric_fit.h"

#include "sim/forces/fem.h"
#include "sim/forces/springs.h"
#include "sim/forces/volino.h"
#include "sim/simulation.h"

#include <Eigen/SparseLU>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
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
    switch (d) {
    case PullDirection::Weft:
        return "weft";
    case PullDirection::Warp:
        return "warp";
    case PullDirection::Bias:
        break;
    }
    return "bias";
}

const char* triangulationName(sim::Triangulation t) {
    return t == sim::Triangulation::Regular ? "regular" : "irregular";
}

/// The strip's boundary sets, by rest coordinate (makeRectangle keeps boundary vertices on the
/// border), and the vertices the test holds or measures.
struct StripBoundary {
    std::vector<int> fixedEdge, pulledEdge, lowSide, highSide;
    int anchor = 0;  ///< the fixed edge's corner on lateral boundary 0, also held across the pull
    int midLow = 0;  ///< lateral boundary 0's vertex nearest mid-length
    int midHigh = 0; ///< the other lateral boundary's
};

StripBoundary stripBoundary(const sim::MatX2& rest, int n, int pull, int side,
                            const TensionTestOptions& o) {
    StripBoundary b;
    const double eps = 1e-9 * std::max(o.length, o.width);
    for (int i = 0; i < n; ++i) {
        if (rest(i, pull) < eps) {
            b.fixedEdge.push_back(i);
        }
        if (rest(i, pull) > o.length - eps) {
            b.pulledEdge.push_back(i);
        }
        if (rest(i, side) < eps) {
            b.lowSide.push_back(i);
        }
        if (rest(i, side) > o.width - eps) {
            b.highSide.push_back(i);
        }
    }
    b.anchor = nearestAlong(rest, b.lowSide, pull, 0.0);
    b.midLow = nearestAlong(rest, b.lowSide, pull, 0.5 * o.length);
    b.midHigh = nearestAlong(rest, b.highSide, pull, 0.5 * o.length);
    return b;
}

/// DOF d = 3·vertex + axis; free DOFs get consecutive indices, held ones -1 (every z, the
/// grips along the pull, the anchor across it).
std::vector<int> freeIndices(int n, const StripBoundary& b, int pull, int side, int& freeCount) {
    std::vector<int> freeIndex(static_cast<std::size_t>(3 * n), 0);
    for (int i = 0; i < n; ++i) {
        freeIndex[static_cast<std::size_t>(3 * i + 2)] = -1;
    }
    for (int i : b.fixedEdge) {
        freeIndex[static_cast<std::size_t>(3 * i + pull)] = -1;
    }
    for (int i : b.pulledEdge) {
        freeIndex[static_cast<std::size_t>(3 * i + pull)] = -1;
    }
    freeIndex[static_cast<std::size_t>(3 * b.anchor + side)] = -1;
    freeCount = 0;
    for (int& f : freeIndex) {
        if (f == 0) {
            f = freeCount++;
        }
    }
    return freeIndex;
}

/// The strip's static equilibrium on its free degrees of freedom: forces, residual and the
/// pulled grip's reaction, and Newton steps with the model's exact Jacobian (sparse LU).
class StripEquilibrium {
  public:
    StripEquilibrium(sim::ForceModel& model, int n, int pull, std::vector<int> freeIndex,
                     int freeCount, const std::vector<int>& pulledEdge)
        : m_model(model), m_n(n), m_pull(pull), m_freeIndex(std::move(freeIndex)),
          m_freeCount(freeCount), m_pulledEdge(pulledEdge), m_v(sim::MatX3::Zero(n, 3)),
          m_jacobian(n, pattern(model)) {}

    int freeCount() const { return m_freeCount; }

    /// Forces, the free residual and the pulled grip's reaction at xs.
    void evaluate(const sim::MatX3& xs, Eigen::VectorXd& res, double& reaction) {
        m_f.setZero(m_n, 3);
        m_model.addForces(xs, m_v, m_f);
        for (int i = 0; i < m_n; ++i) {
            for (int a = 0; a < 3; ++a) {
                const int k = m_freeIndex[static_cast<std::size_t>(3 * i + a)];
                if (k >= 0) {
                    res[k] = m_f(i, a);
                }
            }
        }
        reaction = 0;
        for (int i : m_pulledEdge) {
            reaction -= m_f(i, m_pull); // the grip balances the internal force
        }
    }

    /// The Newton step at x with residual r: f(x + Δ) ≈ f + K Δ = 0 on the free DOFs. Returns
    /// why there is none (a singular Jacobian, a non-finite step).
    std::optional<std::string> newtonStep(const sim::MatX3& x, const Eigen::VectorXd& r,
                                          Eigen::VectorXd& step) {
        m_jacobian.setZero();
        m_model.addJacobian(x, m_v, 1.0, 0.0, sim::JacobianMode::Exact, m_jacobian);
        freeTriplets();
        Eigen::SparseMatrix<double> K(m_freeCount, m_freeCount);
        K.setFromTriplets(m_triplets.begin(), m_triplets.end());
        K.makeCompressed();
        m_lu.compute(K);
        if (m_lu.info() != Eigen::Success) {
            return "Newton: the Jacobian on the free degrees of freedom is singular";
        }
        step = m_lu.solve(-r);
        if (!step.allFinite()) {
            return "Newton: non-finite step";
        }
        return std::nullopt;
    }

    /// trial = x + alpha·step on the free DOFs.
    void advance(const sim::MatX3& x, const Eigen::VectorXd& step, double alpha,
                 sim::MatX3& trial) const {
        trial = x;
        for (int i = 0; i < m_n; ++i) {
            for (int a = 0; a < 3; ++a) {
                const int k = m_freeIndex[static_cast<std::size_t>(3 * i + a)];
                if (k >= 0) {
                    trial(i, a) += alpha * step[k];
                }
            }
        }
    }

  private:
    static std::vector<std::pair<int, int>> pattern(sim::ForceModel& model) {
        std::vector<std::pair<int, int>> pairs;
        model.jacobianPattern(pairs);
        return pairs;
    }
    /// The Jacobian's entries on the free DOFs (nonzero ones) into m_triplets.
    void freeTriplets() {
        m_triplets.clear();
        const std::vector<int>& rowStart = m_jacobian.rowStart();
        const std::vector<int>& cols = m_jacobian.columns();
        for (int bi = 0; bi < m_n; ++bi) {
            for (int s = rowStart[static_cast<std::size_t>(bi)];
                 s < rowStart[static_cast<std::size_t>(bi) + 1]; ++s) {
                const int bj = cols[static_cast<std::size_t>(s)];
                const sim::Mat3& b = m_jacobian.block(s);
                for (int p = 0; p < 3; ++p) {
                    const int row = m_freeIndex[static_cast<std::size_t>(3 * bi + p)];
                    if (row < 0) {
                        continue;
                    }
                    for (int q = 0; q < 3; ++q) {
                        const int col = m_freeIndex[static_cast<std::size_t>(3 * bj + q)];
                        if (col >= 0 && b(p, q) != 0.0) {
                            m_triplets.emplace_back(row, col, b(p, q));
                        }
                    }
                }
            }
        }
    }

    sim::ForceModel& m_model;
    int m_n;
    int m_pull;
    std::vector<int> m_freeIndex;
    int m_freeCount;
    const std::vector<int>& m_pulledEdge;
    const sim::MatX3 m_v; ///< velocities: zero (the test is static)
    sim::MatX3 m_f;
    sim::BlockSparseMatrix m_jacobian;
    Eigen::SparseLU<Eigen::SparseMatrix<double>> m_lu;
    std::vector<Eigen::Triplet<double>> m_triplets;
};

/// Where Newton's method on the strip stopped.
struct NewtonState {
    sim::MatX3 x;        ///< positions [m]
    Eigen::VectorXd r;   ///< free residual [N]
    double reaction = 0; ///< the pulled grip's reaction [N]
    double norm = 0;     ///< |r|
    int iterations = 0;
    std::string error;
};

/// Backtracking on |r| from state s along `step`: the first step length that decreases it
/// enough, into the trial state. False when the Newton direction does not decrease it (at the
/// rounding floor, or stuck).
bool lineSearch(StripEquilibrium& eq, const NewtonState& s, const Eigen::VectorXd& step,
                NewtonState& trial) {
    double alpha = 1.0;
    trial.x = s.x;
    trial.r.resize(eq.freeCount());
    trial.reaction = 0;
    trial.norm = s.norm;
    for (int ls = 0; ls < 30; ++ls) {
        eq.advance(s.x, step, alpha, trial.x);
        eq.evaluate(trial.x, trial.r, trial.reaction);
        trial.norm = trial.r.norm();
        if (std::isfinite(trial.norm) && trial.norm < (1.0 - 1e-4 * alpha) * s.norm) {
            break;
        }
        alpha *= 0.5;
    }
    return std::isfinite(trial.norm) && trial.norm < s.norm;
}

/// Newton's method with a backtracking line search from x until |r_free| <= tolerance·|reaction|,
/// the iteration cap, or a failure (NewtonState::error).
NewtonState solveEquilibrium(StripEquilibrium& eq, sim::MatX3 x, const TensionTestOptions& o) {
    NewtonState s;
    s.x = std::move(x);
    s.r.resize(eq.freeCount());
    eq.evaluate(s.x, s.r, s.reaction);
    const auto converged = [&](double norm) {
        return norm <= o.tolerance * std::max(std::abs(s.reaction), 1e-300);
    };
    s.norm = s.r.norm();
    NewtonState trial;
    Eigen::VectorXd step;
    int it = 0;
    for (; it < o.maxIterations && !converged(s.norm); ++it) {
        if (auto error = eq.newtonStep(s.x, s.r, step)) {
            s.error = *error;
            break;
        }
        if (!lineSearch(eq, s, step, trial)) {
            break;
        }
        s.x = trial.x;
        s.r = trial.r;
        s.reaction = trial.reaction;
        s.norm = trial.norm;
    }
    s.iterations = it;
    return s;
}

} // namespace

patterns::StripResponse orthotropicResponse(const sim::Material& m, PullDirection direction) {
    switch (direction) {
    case PullDirection::Weft:
        return {m.stretchWeft, m.poisson};
    case PullDirection::Warp:
        return {m.stretchWarp, m.poisson * m.stretchWarp / m.stretchWeft};
    case PullDirection::Bias:
        break;
    }
    return patterns::biasTensile(m);
}

double uniaxialLawStretch(const sim::Material& m, PullDirection direction, double strain) {
    const bool weft = direction == PullDirection::Weft;
    const double e = strain + 0.5 * strain * strain; // Green strain along the pull
    const double small = weft ? m.stretchWeft : m.stretchWarp;
    const double beyond = weft ? m.stretchWeftBeyond : m.stretchWarpBeyond;
    const double delta = m.stretchKnee > 0 ? std::max(beyond - small, 0.0) : 0.0;
    const double s = small * e + delta * std::max(e - m.stretchKnee, 0.0);
    return (1.0 + strain) * s / strain;
}

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
    // A bias strip is laid out as a weft one whose material frame is turned by 45°.
    const bool weft = o.direction != PullDirection::Warp;
    const int pull = weft ? 0 : 1; // axis of the pull
    const int side = 1 - pull;     // lateral axis
    const patterns::StripResponse requested = orthotropicResponse(o.material, o.direction);
    result.requestedStretch = requested.stretch;
    result.requestedPoisson = requested.poisson;

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
    sim::MatX2 materialRest = rest; // the pattern's coordinates: weft = x, warp = y
    if (o.direction == PullDirection::Bias) {
        const double c = std::sqrt(0.5);
        materialRest = rest * (sim::Mat2() << c, c, -c, c).finished(); // rows turned by +45°
    }
    sim::ClothMesh mesh;
    if (auto e = sim::buildClothMesh(materialRest, triangles, mesh)) {
        result.error = "mesh: " + *e;
        return result;
    }
    const int n = mesh.vertexCount();
    result.vertices = n;
    result.triangles = mesh.triangleCount();
    const std::unique_ptr<sim::ForceModel> model = makeStretchModel(o, mesh);

    const StripBoundary b = stripBoundary(rest, n, pull, side, o);
    int freeCount = 0;
    std::vector<int> freeIndex = freeIndices(n, b, pull, side, freeCount);
    sim::MatX3 x = sim::MatX3::Zero(n, 3);
    for (int i = 0; i < n; ++i) {
        x(i, pull) = rest(i, pull) * (1.0 + o.strain);
        x(i, side) = rest(i, side);
    }
    StripEquilibrium eq(*model, n, pull, std::move(freeIndex), freeCount, b.pulledEdge);
    const NewtonState s = solveEquilibrium(eq, std::move(x), o);

    result.iterations = s.iterations;
    result.reactionForce = s.reaction;
    result.error = s.error;
    result.residual = s.norm / std::max(std::abs(s.reaction), 1e-300);
    result.converged =
        s.norm <= o.tolerance * std::max(std::abs(s.reaction), 1e-300) && result.error.empty();
    if (!result.converged && result.error.empty()) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "Newton did not converge: relative residual %.3g after %d iterations",
                      result.residual, s.iterations);
        result.error = buf;
    }
    result.measuredStretch = s.reaction / (o.width * o.strain);
    const double widthNow = s.x(b.midHigh, side) - s.x(b.midLow, side);
    const double restWidth = rest(b.midHigh, side) - rest(b.midLow, side);
    result.lateralStrain = widthNow / restWidth - 1.0;
    result.measuredPoisson = -result.lateralStrain / o.strain;
    if (o.model == sim::StretchModel::Fem && o.direction != PullDirection::Bias &&
        o.material.stretchKnee > 0) {
        result.lawStretch = uniaxialLawStretch(o.material, o.direction, o.strain);
    }
    return result;
}

int runMaterialBench(const MaterialBenchOptions& options) {
    const TensionTestOptions& o = options.test;
    if (!(o.strain > 0) || !std::isfinite(o.strain) || o.cellsLong < 1 || o.cellsWide < 1 ||
        !(o.length > 0) || !(o.width > 0)) {
        std::cerr << "error: bench tensile: need strain > 0, positive size and cell counts\n";
        return EXIT_BAD_INPUT;
    }
    const sim::Material& m = o.material;
    if (!(m.stretchWeft > 0) || !(m.stretchWarp > 0) || !(m.shear > 0) || !(m.poisson >= 0) ||
        !(m.poisson * m.poisson * m.stretchWarp / m.stretchWeft < 1.0) ||
        (o.model == sim::StretchModel::Volino && m.poisson >= 0.5)) {
        std::cerr << "error: bench tensile: need positive weft, warp and shear stiffness and "
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
    if (m.stretchKnee > 0) {
        j["material"]["knee_strain"] = m.stretchKnee;
        j["material"]["weft_beyond_n_per_m"] = m.stretchWeftBeyond;
        j["material"]["warp_beyond_n_per_m"] = m.stretchWarpBeyond;
    }
    if (!options.fabric.empty()) {
        j["material"]["fabric"] = options.fabric;
    }
    j["requested"] = {{"stretch_n_per_m", r.requestedStretch}, {"poisson", r.requestedPoisson}};
    j["measured"] = {{"stretch_n_per_m", r.measuredStretch},
                     {"poisson", r.measuredPoisson},
                     {"reaction_force_n", r.reactionForce},
                     {"lateral_strain", r.lateralStrain}};
    j["relative_error"] = {{"stretch", relative(r.measuredStretch, r.requestedStretch)},
                           {"poisson", relative(r.measuredPoisson, r.requestedPoisson)}};
    j["poisson_difference"] = r.measuredPoisson - r.requestedPoisson;
    // The stiffening law's own figure: what the strip must give at this strain.
    if (std::isfinite(r.lawStretch)) {
        j["law"] = {{"stretch_n_per_m", r.lawStretch},
                    {"relative_error", relative(r.measuredStretch, r.lawStretch)}};
    }
    j["iterations"] = r.iterations;
    j["residual"] = r.residual;
    j["converged"] = r.converged;
    j["error"] = r.error.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.error);
    const std::string text = io::jsonText(j);

    char line[256];
    std::snprintf(line, sizeof line,
                  "bench tensile: %s %s %s: stretch %.6g N/m (requested %.6g), poisson %.4f "
                  "(requested %.4f), %d Newton iterations, residual %.2g",
                  j["model"].get<std::string>().c_str(), triangulationName(o.triangulation),
                  directionName(o.direction), r.measuredStretch, r.requestedStretch,
                  r.measuredPoisson, r.requestedPoisson, r.iterations, r.residual);
    std::cerr << line << "\n";
    if (std::isfinite(r.lawStretch)) {
        std::snprintf(line, sizeof line,
                      "bench tensile: the stiffening law gives %.6g N/m at this strain (measured "
                      "%+.2g relative)",
                      r.lawStretch, relative(r.measuredStretch, r.lawStretch));
        std::cerr << line << "\n";
    }
    if (options.out.empty()) {
        std::cout << text;
    } else if (auto written = io::writeFileAtomically(options.out, text); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    if (!r.converged) {
        std::cerr << "error: bench tensile: " << r.error << "\n";
        return EXIT_RUN_FAILED;
    }
    return EXIT_OK;
}

} // namespace atelier::app
