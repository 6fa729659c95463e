#pragma once
/// Reusable checks of a ForceModel against finite differences and physical invariants
/// (ipc-toolkit's test_barrier.cpp style). Each check reports through GoogleTest
/// EXPECT macros, so call them inside a TEST; wrap a group in SCOPED_TRACE to name the case.

#include "sim/core/block_sparse.h"
#include "sim/forces/force_model.h"
#include "sim/mesh/cloth_mesh.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace atelier::test {

// The engine's types and force models, unqualified as in the engine's own code.
using namespace atelier::sim;

/// A cloth embedded in a global state with other vertices before and after it, so that
/// checks also catch a model that ignores its `offset`.
struct PlacedCloth {
    ClothMesh mesh;
    int offset = 0;        ///< global index of the mesh's vertex 0
    int totalVertices = 0; ///< rows of the global x, v, f
};

/// Builds a rectangle mesh with makeRectangle + buildClothMesh (fails the test if refused).
inline ClothMesh makeTestMesh(Triangulation triangulation, int cellsX = 4, int cellsY = 3,
                              double width = 0.4, double height = 0.3, std::uint32_t seed = 7) {
    RectangleOptions o;
    o.width = width;
    o.height = height;
    o.cellsX = cellsX;
    o.cellsY = cellsY;
    o.triangulation = triangulation;
    o.seed = seed;
    MatX2 rest;
    MatX3i triangles;
    makeRectangle(o, rest, triangles);
    ClothMesh mesh;
    const auto error = buildClothMesh(rest, triangles, mesh);
    EXPECT_FALSE(error.has_value()) << *error;
    return mesh;
}

inline PlacedCloth placeCloth(ClothMesh mesh, int before = 2, int after = 1) {
    PlacedCloth p;
    p.totalVertices = mesh.vertexCount() + before + after;
    p.offset = before;
    p.mesh = std::move(mesh);
    return p;
}

/// Rotation about a random axis by a random angle (fixed seed).
inline Mat3 randomRotation(std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
    q.normalize();
    return q.toRotationMatrix();
}

/// Global positions with the flat pattern placed by x = R·(X, Y, 0) + t; the vertices that are
/// not the cloth's get arbitrary positions. (|V_global|×3).
inline MatX3 restPositions(const PlacedCloth& c, const Mat3& R = Mat3::Identity(),
                           const Vec3& t = Vec3::Zero()) {
    MatX3 x(c.totalVertices, 3);
    for (int i = 0; i < c.totalVertices; ++i) {
        x.row(i) << 0.3 + i, -0.2 * i, 0.1;
    }
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        const Vec3 p(c.mesh.rest(i, 0), c.mesh.rest(i, 1), 0.0);
        x.row(c.offset + i) = (R * p + t).transpose();
    }
    return x;
}

/// `base` plus uniform noise of the given amplitude on the cloth's rows only (fixed seed).
inline MatX3 perturbed(const PlacedCloth& c, const MatX3& base, double amplitude,
                       std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-amplitude, amplitude);
    MatX3 x = base;
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        for (int k = 0; k < 3; ++k) {
            x(c.offset + i, k) += u(rng);
        }
    }
    return x;
}

/// A random test state: the rest shape rotated and moved, positions perturbed by up to
/// `positionNoise` [m], velocities uniform in ±`velocityNoise` [m/s] (fixed seed).
inline std::pair<MatX3, MatX3> randomState(const PlacedCloth& c, double positionNoise,
                                           double velocityNoise, std::uint32_t seed) {
    const MatX3 base = restPositions(c, randomRotation(seed + 100), Vec3(0.1, 0.2, 0.3));
    MatX3 x = perturbed(c, base, positionNoise, seed);
    MatX3 v = perturbed(c, MatX3::Zero(base.rows(), 3), velocityNoise, seed + 1);
    return {std::move(x), std::move(v)};
}

inline MatX3 forces(const ForceModel& model, const MatX3& x, const MatX3& v) {
    MatX3 f = MatX3::Zero(x.rows(), 3);
    model.addForces(x, v, f);
    return f;
}

/// Dense kx·∂f/∂x + kv·∂f/∂v assembled through the model's own pattern.
inline Eigen::MatrixXd denseJacobian(const ForceModel& model, const MatX3& x, const MatX3& v,
                                     double kx, double kv, JacobianMode mode) {
    std::vector<std::pair<int, int>> pairs;
    model.jacobianPattern(pairs);
    BlockSparseMatrix J(static_cast<int>(x.rows()), pairs);
    J.setZero();
    model.addJacobian(x, v, kx, kv, mode, J);
    return J.toDense();
}

/// Flattens (|V|×3) row-major to a 3|V| vector (vertex-major, as the dense Jacobian).
inline VecX flat(const MatX3& m) {
    return Eigen::Map<const VecX>(m.data(), m.size());
}

/// Largest |entry| of a, at least `floor`.
inline double scaleOf(const Eigen::MatrixXd& a, double floor = 1e-300) {
    return std::max(a.cwiseAbs().maxCoeff(), floor);
}

/// (a) forces = −∇energy by central differences, at velocity 0 (the conservative part).
inline void expectForcesAreEnergyGradient(const ForceModel& model, const MatX3& x, double h,
                                          double tolerance) {
    ASSERT_TRUE(model.hasEnergy());
    const MatX3 zero = MatX3::Zero(x.rows(), 3);
    const VecX f = flat(forces(model, x, zero));
    VecX fd(f.size());
    MatX3 xp = x;
    for (int i = 0; i < x.rows(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const double x0 = xp(i, k);
            xp(i, k) = x0 + h;
            const double ep = model.energy(xp);
            xp(i, k) = x0 - h;
            const double em = model.energy(xp);
            xp(i, k) = x0;
            fd[3 * i + k] = -(ep - em) / (2 * h);
        }
    }
    const double err = (f - fd).cwiseAbs().maxCoeff();
    EXPECT_LE(err, tolerance * scaleOf(f))
        << model.name() << ": max |f + ∇E| = " << err << ", max |f| = " << f.cwiseAbs().maxCoeff();
    EXPECT_GT(f.cwiseAbs().maxCoeff(), 0.0) << model.name() << ": the test state has no force";
}

/// Central-difference ∂f/∂x (wrtVelocity = false) or ∂f/∂v, dense (3|V| × 3|V|).
inline Eigen::MatrixXd finiteDifferenceJacobian(const ForceModel& model, const MatX3& x,
                                                const MatX3& v, double h, bool wrtVelocity) {
    const auto n = static_cast<int>(x.size());
    Eigen::MatrixXd J(n, n);
    MatX3 xp = x;
    MatX3 vp = v;
    MatX3& p = wrtVelocity ? vp : xp;
    for (int i = 0; i < x.rows(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const double p0 = p(i, k);
            p(i, k) = p0 + h;
            const VecX fp = flat(forces(model, xp, vp));
            p(i, k) = p0 - h;
            const VecX fm = flat(forces(model, xp, vp));
            p(i, k) = p0;
            J.col(3 * i + k) = (fp - fm) / (2 * h);
        }
    }
    return J;
}

/// (b) Exact ∂f/∂x and ∂f/∂v against central differences of addForces (dense), plus: the
/// model adds (two calls give twice), and kx, kv combine linearly.
inline void expectExactJacobianMatchesFiniteDifferences(const ForceModel& model, const MatX3& x,
                                                        const MatX3& v, double h,
                                                        double tolerance) {
    const Eigen::MatrixXd jx = denseJacobian(model, x, v, 1.0, 0.0, JacobianMode::Exact);
    const Eigen::MatrixXd jv = denseJacobian(model, x, v, 0.0, 1.0, JacobianMode::Exact);
    const Eigen::MatrixXd fdx = finiteDifferenceJacobian(model, x, v, h, false);
    const Eigen::MatrixXd fdv = finiteDifferenceJacobian(model, x, v, h, true);
    const double ex = (jx - fdx).cwiseAbs().maxCoeff();
    const double ev = (jv - fdv).cwiseAbs().maxCoeff();
    EXPECT_LE(ex, tolerance * scaleOf(fdx)) << model.name() << ": ∂f/∂x max error " << ex
                                            << " of max entry " << fdx.cwiseAbs().maxCoeff();
    EXPECT_LE(ev, tolerance * scaleOf(fdv, 1e-12 * scaleOf(fdx)))
        << model.name() << ": ∂f/∂v max error " << ev << " of max entry "
        << fdv.cwiseAbs().maxCoeff();
    EXPECT_GT(fdx.cwiseAbs().maxCoeff(), 0.0) << model.name();

    // Linear in (kx, kv), and accumulating.
    const Eigen::MatrixXd mixed = denseJacobian(model, x, v, 2.0, -3.0, JacobianMode::Exact);
    const double em = (mixed - (2.0 * jx - 3.0 * jv)).cwiseAbs().maxCoeff();
    EXPECT_LE(em, 1e-10 * (scaleOf(jx) + scaleOf(jv, 0.0))) << model.name();
    std::vector<std::pair<int, int>> pairs;
    model.jacobianPattern(pairs);
    BlockSparseMatrix J(static_cast<int>(x.rows()), pairs);
    J.setZero();
    model.addJacobian(x, v, 1.0, 0.0, JacobianMode::Exact, J);
    model.addJacobian(x, v, 1.0, 0.0, JacobianMode::Exact, J);
    EXPECT_LE((J.toDense() - 2.0 * jx).cwiseAbs().maxCoeff(), 1e-10 * scaleOf(jx))
        << model.name() << ": addJacobian must add";
}

/// Whether the symmetric matrix is negative semi-definite up to a relative tolerance.
inline void expectSymmetricNegativeSemidefinite(const Eigen::MatrixXd& a, const std::string& what,
                                                double tolerance = 1e-9) {
    const double s = scaleOf(a, 1e-300);
    EXPECT_LE((a - a.transpose()).cwiseAbs().maxCoeff(), 1e-12 * s) << what << ": not symmetric";
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (a + a.transpose()));
    EXPECT_LE(eig.eigenvalues().maxCoeff(), tolerance * s)
        << what << ": positive eigenvalue " << eig.eigenvalues().maxCoeff() << " (scale " << s
        << ")";
}

/// (c) Definite-mode ∂f/∂x and ∂f/∂v are symmetric and negative semi-definite.
inline void expectDefiniteJacobian(const ForceModel& model, const MatX3& x, const MatX3& v) {
    const Eigen::MatrixXd jx = denseJacobian(model, x, v, 1.0, 0.0, JacobianMode::Definite);
    const Eigen::MatrixXd jv = denseJacobian(model, x, v, 0.0, 1.0, JacobianMode::Definite);
    expectSymmetricNegativeSemidefinite(jx, std::string(model.name()) + " Definite ∂f/∂x");
    expectSymmetricNegativeSemidefinite(jv, std::string(model.name()) + " Definite ∂f/∂v");
}

/// (d) No force at the given (rest) state: every |f_i| ≤ `absoluteTolerance` [N].
inline void expectZeroForce(const ForceModel& model, const MatX3& x, const MatX3& v,
                            double absoluteTolerance) {
    const MatX3 f = forces(model, x, v);
    EXPECT_TRUE(f.allFinite()) << model.name();
    EXPECT_LE(f.cwiseAbs().maxCoeff(), absoluteTolerance) << model.name();
}

/// Velocities of the rigid motion v = u + ω × (x − c) over the cloth's rows (0 elsewhere).
inline MatX3 rigidVelocity(const PlacedCloth& c, const MatX3& x, const Vec3& u, const Vec3& w) {
    MatX3 v = MatX3::Zero(x.rows(), 3);
    const Vec3 center = x.middleRows(c.offset, c.mesh.vertexCount()).colwise().mean().transpose();
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        const Vec3 r = x.row(c.offset + i).transpose() - center;
        v.row(c.offset + i) = (u + w.cross(r)).transpose();
    }
    return v;
}

/// (e) f(R x + t, R v) = R f(x, v) row by row.
inline void expectRigidInvariance(const ForceModel& model, const MatX3& x, const MatX3& v,
                                  std::uint32_t seed, double tolerance) {
    const Mat3 R = randomRotation(seed);
    const Vec3 t(0.7, -1.3, 2.1);
    MatX3 xr = x;
    MatX3 vr = v;
    for (int i = 0; i < x.rows(); ++i) {
        xr.row(i) = (R * x.row(i).transpose() + t).transpose();
        vr.row(i) = (R * v.row(i).transpose()).transpose();
    }
    const MatX3 f = forces(model, x, v);
    const MatX3 fr = forces(model, xr, vr);
    MatX3 expected = f * R.transpose(); // rows R·f_i
    const double err = (fr - expected).cwiseAbs().maxCoeff();
    EXPECT_LE(err, tolerance * scaleOf(f)) << model.name() << ": not rigid-motion invariant";
}

/// (f) Internal forces: zero net force and zero net torque (about the origin).
inline void expectMomentumConserved(const ForceModel& model, const MatX3& x, const MatX3& v,
                                    double tolerance) {
    const MatX3 f = forces(model, x, v);
    Vec3 sum = Vec3::Zero();
    Vec3 torque = Vec3::Zero();
    double torqueScale = 0;
    for (int i = 0; i < x.rows(); ++i) {
        const Vec3 fi = f.row(i).transpose();
        const Vec3 xi = x.row(i).transpose();
        sum += fi;
        torque += xi.cross(fi);
        torqueScale = std::max(torqueScale, xi.norm() * fi.norm());
    }
    EXPECT_LE(sum.norm(), tolerance * scaleOf(f)) << model.name() << ": net force " << sum;
    EXPECT_LE(torque.norm(), tolerance * std::max(torqueScale, 1e-300))
        << model.name() << ": net torque " << torque.transpose();
}

/// Forces only on the cloth's rows: the vertices before and after are untouched.
inline void expectOnlyClothRows(const ForceModel& model, const PlacedCloth& c, const MatX3& x,
                                const MatX3& v) {
    const MatX3 f = forces(model, x, v);
    for (int i = 0; i < x.rows(); ++i) {
        if (i < c.offset || i >= c.offset + c.mesh.vertexCount()) {
            EXPECT_EQ(f.row(i).cwiseAbs().maxCoeff(), 0.0)
                << model.name() << ": force on vertex " << i << " outside the cloth";
        }
    }
}

/// (g) `addDampingProduct` is (Definite ∂f/∂v)·v as assembled: the implicit step relies on it
/// to get (∂f/∂x)·v from its one assembly of M − h ∂f/∂v − h² ∂f/∂x.
inline void expectDampingProduct(const ForceModel& model, const MatX3& x, const MatX3& v,
                                 double tolerance) {
    MatX3 f = MatX3::Zero(x.rows(), 3);
    model.addDampingProduct(x, v, f);
    const VecX got = flat(f);
    const Eigen::MatrixXd jv = denseJacobian(model, x, v, 0.0, 1.0, JacobianMode::Definite);
    const VecX product = jv * flat(v);
    EXPECT_LE((got - product).cwiseAbs().maxCoeff(),
              tolerance * std::max(scaleOf(got), scaleOf(product)))
        << model.name() << ": addDampingProduct is not (Definite ∂f/∂v)·v";
}

/// What `checkForceModel` runs.
struct ForceCheckOptions {
    double stepSize = 1e-6;          ///< finite-difference step [m] or [m/s]
    double tolerance = 1e-5;         ///< relative tolerance of finite-difference comparisons
    double restTolerance = 1e-9;     ///< absolute force tolerance at rest [N]
    bool internal = true;            ///< check zero net force/torque
    bool rigidVelocityAtRest = true; ///< at rest, a rigid velocity also gives zero force
    bool rigidInvariance = true;     ///< check f(Rx+t, Rv) = R f(x, v)
    bool definite = true;            ///< check Definite mode is symmetric NSD
    double rigidTolerance = 1e-9;    ///< relative tolerance of invariance and momentum
};

/// Runs (a)–(g) on `model` for the cloth `c`: rest state placed with a rotation, and the
/// perturbed state (x, v).
inline void checkForceModel(const ForceModel& model, const PlacedCloth& c, const MatX3& x,
                            const MatX3& v, const ForceCheckOptions& o = {}) {
    SCOPED_TRACE(std::string(model.name()));
    // (d) rest, rotated and translated, with zero and with a rigid velocity.
    const MatX3 rest = restPositions(c, randomRotation(11), Vec3(0.2, 0.5, -0.3));
    expectZeroForce(model, rest, MatX3::Zero(rest.rows(), 3), o.restTolerance);
    if (o.rigidVelocityAtRest) {
        expectZeroForce(model, rest, rigidVelocity(c, rest, Vec3(0.3, -1, 2), Vec3(1, 2, -0.5)),
                        o.restTolerance);
    }
    expectOnlyClothRows(model, c, x, v);
    if (model.hasEnergy()) {
        expectForcesAreEnergyGradient(model, x, o.stepSize, o.tolerance); // (a)
    }
    expectExactJacobianMatchesFiniteDifferences(model, x, v, o.stepSize, o.tolerance); // (b)
    if (o.definite) {
        expectDefiniteJacobian(model, x, v); // (c)
    }
    if (o.rigidInvariance) {
        expectRigidInvariance(model, x, v, 5, o.rigidTolerance); // (e)
    }
    if (o.internal) {
        expectMomentumConserved(model, x, v, o.rigidTolerance); // (f)
    }
    expectDampingProduct(model, x, v, o.rigidTolerance); // (g)
}

} // namespace atelier::test
