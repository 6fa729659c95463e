// Contacts inside the implicit solve (sim/collision/contact_forces.h): forces and Jacobians
// against finite differences, the kept blocks negative semi-definite, and what they are for:
// cloth resting on a body comes to rest, and cloth carried by a moving body is not flung out.

#include "sim/collision/contact_forces.h"
#include "sim/collision/obstacle.h"
#include "sim/simulation.h"
#include "sim/test_scenes.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>

namespace atelier {
namespace {

using sim::Contact;
using sim::MatX3;
using sim::Vec3;

constexpr int N = 8;
constexpr double H = 0.01;

/// Three contacts on eight vertices: a vertex on an obstacle face (0), a cloth face (1, 2, 3)
/// on an obstacle vertex, and a cloth–cloth edge pair (4, 5 against 6, 7), each with its gap
/// inside the layer [d, 1.25 d].
struct ThreeContacts {
    std::vector<Contact> contacts;
    MatX3 x = MatX3::Zero(N, 3);
    sim::VecX invMass = sim::VecX::Constant(N, 1.0 / 0.002);
    sim::ContactSolveOptions options;

    ThreeContacts() {
        options.selfContacts = true;
        for (int i = 0; i < N; ++i) {
            x.row(i) << 0.1 * i, 0.0, 0.05 * (i % 3);
        }
        Contact a;
        a.kind = Contact::Kind::VertexFace;
        a.vertex[0] = 0;
        a.weight[0] = 1;
        a.normal = Vec3(0, 1, 0);
        a.distance = 0.004;
        a.obstaclePoint = x.row(0).transpose() - Vec3(0, 0.0045, 0);
        a.obstacle = 0;
        a.staticFriction = 0.5;
        a.kineticFriction = 0.4;
        Contact b;
        b.kind = Contact::Kind::FaceVertex;
        const double bary[3] = {0.2, 0.3, 0.5};
        Vec3 p = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
            b.vertex[k] = 1 + k;
            b.weight[k] = bary[k];
            p += bary[k] * x.row(1 + k).transpose();
        }
        b.normal = Vec3(1, 2, 2) / 3.0;
        b.distance = 0.004;
        b.obstaclePoint = p - 0.0042 * b.normal;
        b.obstacle = 0;
        b.staticFriction = 0.5;
        b.kineticFriction = 0.4;
        Contact c;
        c.kind = Contact::Kind::SelfEdgeEdge;
        const double w[4] = {0.6, 0.4, -0.7, -0.3};
        Vec3 r = Vec3::Zero();
        for (int k = 0; k < 4; ++k) {
            c.vertex[k] = 4 + k;
            c.weight[k] = w[k];
            r += w[k] * x.row(4 + k).transpose();
        }
        c.normal = Vec3(0, 0, 1);
        c.distance = 0.004;
        // Move vertex 4 so the pair's gap is 4.6 mm.
        x(4, 2) += (0.0046 - c.normal.dot(r)) / w[0];
        c.staticFriction = 0.3;
        c.kineticFriction = 0.3;
        contacts = {a, b, c};
    }

    sim::BlockSparseMatrix pattern() const {
        // Each side's blocks, and one pair across the cloth–cloth contact (4, 6) whose block
        // must stay empty.
        return sim::BlockSparseMatrix(N, {{1, 2}, {1, 3}, {2, 3}, {4, 5}, {6, 7}, {4, 6}});
    }

    MatX3 forces(const MatX3& xs, const MatX3& vs) const {
        sim::ContactForces f;
        f.prepare(contacts, xs, vs, invMass, H, options);
        MatX3 out = MatX3::Zero(N, 3);
        f.addForces(out);
        return out;
    }
};

Eigen::MatrixXd finiteDifference(const ThreeContacts& s, const MatX3& x, const MatX3& v,
                                 bool wrtV) {
    Eigen::MatrixXd J(3 * N, 3 * N);
    const double eps = 1e-7;
    for (int j = 0; j < 3 * N; ++j) {
        MatX3 xp = x, xm = x, vp = v, vm = v;
        (wrtV ? vp : xp)(j / 3, j % 3) += eps;
        (wrtV ? vm : xm)(j / 3, j % 3) -= eps;
        const MatX3 d = (s.forces(xp, vp) - s.forces(xm, vm)) / (2 * eps);
        J.col(j) = Eigen::Map<const Eigen::VectorXd>(d.data(), 3 * N);
    }
    return J;
}

TEST(ContactForces, SpringForceIsTheLayerDepthTimesTheStiffness) {
    ThreeContacts s;
    const MatX3 f = s.forces(s.x, MatX3::Zero(N, 3));
    // Vertex 0: gap 4.5 mm in a layer up to 5 mm, stiffness κ m / h².
    const double k = s.options.stiffness * 0.002 / (H * H);
    EXPECT_NEAR(f(0, 1), k * 0.0005, 1e-9 * k);
    EXPECT_NEAR(f(0, 0), 0.0, 1e-12);
    // The cloth–cloth contact pushes its two sides apart with equal and opposite forces.
    EXPECT_NEAR(f.row(4).sum() + f.row(5).sum() + f.row(6).sum() + f.row(7).sum(), 0.0, 1e-9);
    EXPECT_GT(f(4, 2), 0.0);
    EXPECT_LT(f(6, 2), 0.0);
}

TEST(ContactForces, JacobiansMatchFiniteDifferencesOnEachSide) {
    ThreeContacts s;
    // Slow slips (below the 0.1 mm/s of the sticking regime) where friction is linear in v.
    MatX3 v = MatX3::Zero(N, 3);
    for (int i = 0; i < N; ++i) {
        v.row(i) << 1e-5 * (i % 2), -2e-6 * i, 3e-6;
    }
    for (bool wrtV : {false, true}) {
        sim::ContactForces f;
        f.prepare(s.contacts, s.x, wrtV ? v : MatX3::Zero(N, 3), s.invMass, H, s.options);
        sim::BlockSparseMatrix J = s.pattern();
        J.setZero();
        f.addJacobian(wrtV ? 0.0 : 1.0, wrtV ? 1.0 : 0.0, J);
        const Eigen::MatrixXd analytic = J.toDense();
        const Eigen::MatrixXd numeric =
            finiteDifference(s, s.x, wrtV ? v : MatX3::Zero(N, 3), wrtV);
        for (int a = 0; a < N; ++a) {
            for (int b = 0; b < N; ++b) {
                const bool across = (a >= 4 && a <= 5 && b >= 6) || (b >= 4 && b <= 5 && a >= 6);
                const Eigen::Matrix3d A = analytic.block<3, 3>(3 * a, 3 * b);
                if (across || J.slot(a, b) < 0) {
                    EXPECT_EQ(A.norm(), 0.0) << a << "," << b; // dropped: outside each side
                    continue;
                }
                const Eigen::Matrix3d D = numeric.block<3, 3>(3 * a, 3 * b);
                EXPECT_LT((A - D).norm(), 1e-5 * (1.0 + D.norm()))
                    << (wrtV ? "dv " : "dx ") << a << "," << b << "\n"
                    << A << "\n"
                    << D;
            }
        }
        // Symmetric and negative semi-definite: the solve's matrix stays positive definite.
        EXPECT_LT((analytic - analytic.transpose()).norm(), 1e-9 * analytic.norm());
        const Eigen::VectorXd eig =
            Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(analytic).eigenvalues();
        EXPECT_LE(eig.maxCoeff(), 1e-9 * analytic.norm());
    }
}

TEST(ContactForces, ProductIsTheAssembledJacobianTimesTheVector) {
    // The implicit step takes (∂f/∂v)·v of the contacts from this product instead of a second
    // assembly: it must be exactly what the matrix would give, across-side blocks left out.
    ThreeContacts s;
    MatX3 v = MatX3::Zero(N, 3);
    MatX3 p = MatX3::Zero(N, 3);
    for (int i = 0; i < N; ++i) {
        v.row(i) << 1e-3 * (i % 3), -2e-4 * i, 3e-4;
        p.row(i) << std::sin(1.0 + i), std::cos(2.0 * i), 0.5 - 0.1 * i;
    }
    sim::ContactForces f;
    f.prepare(s.contacts, s.x, v, s.invMass, H, s.options);
    for (const auto& [kx, kv] : {std::pair{1.0, 0.0}, {0.0, 1.0}, {-H * H, -H}}) {
        sim::BlockSparseMatrix J = s.pattern();
        J.setZero();
        f.addJacobian(kx, kv, J);
        const Eigen::VectorXd expected =
            J.toDense() * Eigen::Map<const Eigen::VectorXd>(p.data(), 3 * N);
        MatX3 out = MatX3::Zero(N, 3);
        f.addJacobianProduct(kx, kv, p, out);
        const Eigen::VectorXd got = Eigen::Map<const Eigen::VectorXd>(out.data(), 3 * N);
        EXPECT_GT(expected.norm(), 0.0);
        EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff())
            << "kx " << kx << " kv " << kv;
    }
}

TEST(ContactForces, NothingBeyondTheLayerOrWithoutAMovableVertex) {
    ThreeContacts s;
    s.contacts.resize(1);
    s.contacts[0].obstaclePoint.y() -= 0.001; // gap 5.5 mm: beyond 1.25 × 4 mm
    sim::ContactForces f;
    f.prepare(s.contacts, s.x, MatX3::Zero(N, 3), s.invMass, H, s.options);
    EXPECT_EQ(f.size(), 0u);
    s.contacts[0].obstaclePoint.y() += 0.001;
    s.invMass[0] = 0; // held
    f.prepare(s.contacts, s.x, MatX3::Zero(N, 3), s.invMass, H, s.options);
    EXPECT_EQ(f.size(), 0u);
}

/// A 0.6 m sheet dropped 2 cm onto a sphere's top with 10 ms implicit steps; the kinetic
/// energy per vertex after `seconds`.
double sheetOnSphereEnergy(bool solveContacts, double seconds) {
    sim::SceneSpec s = test::smallSheet(sim::StretchModel::Fem, 12, 0.6, false, true);
    for (int i = 0; i < s.cloths[0].position.rows(); ++i) {
        s.cloths[0].position.row(i) += Vec3(-0.3, 0.52, 0.3).transpose();
    }
    sim::ObstacleSpec o;
    sim::makeSphereMesh(0.25, 3, o.vertices, o.triangles);
    o.closed = true;
    o.keys.push_back(sim::ObstacleKey{0.0, Vec3(0, 0.25, 0), Vec3::Zero()});
    s.obstacles.push_back(o);
    s.integrator.kind = sim::IntegratorKind::ImplicitEuler;
    s.integrator.dt = 0.01;
    s.integrator.maxDt = 0.01;
    s.collision.solveContacts = solveContacts;
    sim::Simulation simulation(s);
    EXPECT_EQ(simulation.run(seconds), sim::RunStatus::Finished) << simulation.stats().error;
    long withObstacle = -1;
    test::intersections(simulation, &withObstacle);
    EXPECT_EQ(withObstacle, 0);
    return simulation.kineticEnergy() / static_cast<double>(simulation.positions().rows());
}

TEST(ContactForces, ClothHangingOnABodyComesToRest) {
    // The solve holds the cloth up and sticks it: the drape settles. With the contacts only
    // after the solve, every step lets the hanging cloth fall by g·h and puts back only the
    // vertices in contact, and it keeps moving.
    const double inSolve = sheetOnSphereEnergy(true, 2.0);
    const double after = sheetOnSphereEnergy(false, 2.0);
    EXPECT_LT(inSolve, 1e-9);
    EXPECT_LT(inSolve, 0.01 * after) << inSolve << " J against " << after << " J";
}

TEST(ContactForces, ClothCarriedByASpinningBodyKeepsItsShape) {
    // A sheet dropped on a sphere spinning at one turn per second, carried round by friction.
    // Taking the obstacle's velocity from the step before (detection's) instead of the step
    // being solved, cloth moved along the last step's chord each step, turned by ωh from the
    // surface's, and was flung outwards by rω²h² per step against friction.
    sim::SceneSpec s = test::smallSheet(sim::StretchModel::Fem, 12, 0.5, false, true);
    for (int i = 0; i < s.cloths[0].position.rows(); ++i) {
        s.cloths[0].position.row(i) += Vec3(-0.25, 0.41, 0.25).transpose();
    }
    s.cloths[0].material.staticFriction = s.cloths[0].material.kineticFriction = 0.6;
    sim::ObstacleSpec o;
    sim::makeSphereMesh(0.2, 3, o.vertices, o.triangles);
    o.closed = true;
    o.staticFriction = o.kineticFriction = 0.6;
    o.keys.push_back(sim::ObstacleKey{0.0, Vec3(0, 0.2, 0), Vec3::Zero()});
    o.keys.push_back(sim::ObstacleKey{2.0, Vec3(0, 0.2, 0), Vec3(0, 4 * M_PI, 0)});
    s.obstacles.push_back(o);
    s.integrator.kind = sim::IntegratorKind::ImplicitEuler;
    s.integrator.dt = 1.0 / 240;
    s.integrator.maxDt = 1.0 / 240;
    sim::Simulation simulation(s);
    double worst = 0;
    for (double t = 0.25; t < 2.01; t += 0.25) {
        ASSERT_EQ(simulation.run(t), sim::RunStatus::Finished) << simulation.stats().error;
        worst = std::max(worst, simulation.maxEdgeStrain());
    }
    // Measured: 0.8% at worst (3.8% with the last step's velocities, growing).
    EXPECT_LT(worst, 0.015);
    // Carried round: the sheet's angular velocity about the axis, L_y / I_y, near the table's
    // 2π rad/s (backward Euler damps rotation a little: 6.12 rad/s measured).
    const sim::MatX3& x = simulation.positions();
    const sim::MatX3& v = simulation.velocities();
    double angular = 0, inertia = 0;
    for (int i = 0; i < x.rows(); ++i) {
        angular += x(i, 2) * v(i, 0) - x(i, 0) * v(i, 2);
        inertia += x(i, 0) * x(i, 0) + x(i, 2) * x(i, 2);
    }
    EXPECT_GT(angular / inertia, 0.9 * 2 * M_PI);
}

} // namespace
} // namespace atelier
