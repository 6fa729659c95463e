#include "sim/constraints/seam_welds.h"
#include "sim/forces/force_check.h"
#include "sim/forces/seam_bending.h"
#include "sim/simulation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace atelier::sim {
namespace {

constexpr double SIDE = 0.2; ///< each sheet's side [m]
constexpr int CELLS = 4;     ///< cells along each side

/// A `width` × SIDE sheet of `cellsX` × CELLS cells at x ∈ [x0, x0 + width], in the plane z = 0.
ClothSpec sheet(const std::string& name, double x0, double width, int cellsX) {
    ClothSpec c;
    c.name = name;
    c.mesh = test::makeTestMesh(Triangulation::Regular, cellsX, CELLS, width, SIDE);
    const MatX2& rest = c.mesh.rest;
    c.position.resize(rest.rows(), 3);
    for (int i = 0; i < rest.rows(); ++i) {
        c.position.row(i) << x0 + rest(i, 0), rest(i, 1), 0.0;
    }
    c.material.bending = 2e-4;
    c.material.damping = 0.01;
    // The figures below are discrete shells' (k = bending per hinge), whatever the default.
    c.bendingModel = BendingModel::Hinge;
    return c;
}

/// Sheets A (x ∈ [0, SIDE]) and B (x ∈ [SIDE, 2·SIDE]), A's right border sewn to B's left one.
SceneSpec sewnSheets() {
    SceneSpec scene;
    scene.cloths = {sheet("a", 0, SIDE, CELLS), sheet("b", SIDE, SIDE, CELLS)};
    const int nA = scene.cloths[0].mesh.vertexCount();
    for (int j = 0; j <= CELLS; ++j) {
        scene.seams.push_back({j * (CELLS + 1) + CELLS, nA + j * (CELLS + 1), 0.0});
    }
    return scene;
}

std::vector<int> offsetsOf(const SceneSpec& scene) {
    std::vector<int> offsets{0};
    for (const ClothSpec& c : scene.cloths) {
        offsets.push_back(offsets.back() + c.mesh.vertexCount());
    }
    return offsets;
}

/// The scene's positions with everything beyond x = SIDE turned about the line x = SIDE, z = 0
/// by `phi` [rad] (towards +z for phi > 0).
MatX3 folded(const SceneSpec& scene, double phi) {
    MatX3 x(offsetsOf(scene).back(), 3);
    int row = 0;
    for (const ClothSpec& c : scene.cloths) {
        x.middleRows(row, c.position.rows()) = c.position;
        row += static_cast<int>(c.position.rows());
    }
    for (int i = 0; i < x.rows(); ++i) {
        const double d = x(i, 0) - SIDE;
        if (d > 1e-12) {
            x(i, 0) = SIDE + d * std::cos(phi);
            x(i, 2) = d * std::sin(phi);
        }
    }
    return x;
}

SeamWelds allWelded(const SceneSpec& scene, const MatX3& x) {
    SeamWelds welds(scene.seams, static_cast<int>(x.rows()));
    WeldFigures figures;
    welds.weldClosed(x, 0.0, true, figures);
    return welds;
}

TEST(SeamBending, HingesJoinTheTrianglesOnEitherSideOfASeam) {
    const SceneSpec scene = sewnSheets();
    const auto model = SeamBending::build(scene, offsetsOf(scene));
    ASSERT_NE(model, nullptr);
    ASSERT_EQ(model->hingeCount(), CELLS); // one per seam edge
    const int nA = scene.cloths[0].mesh.vertexCount();
    for (int h = 0; h < model->hingeCount(); ++h) {
        const auto corners = model->hinges().row(h);
        // Wing 0 is A (the pairs' `a` side), its seam edge running counter-clockwise.
        EXPECT_LT(corners(0), nA);
        EXPECT_LT(corners(1), nA);
        EXPECT_LT(corners(2), nA);
        EXPECT_GE(corners(3), nA);
        EXPECT_EQ(corners(0) % (CELLS + 1), CELLS);
        EXPECT_GT(corners(1), corners(0));            // up the seam: counter-clockwise in A
        EXPECT_NEAR(model->weights()[h], 3.0, 1e-12); // 3|ē|²/(Ā₀+Ā₁) on half-cell wings
    }
    const auto [p0, p1] = model->pairs()[0];
    EXPECT_EQ(scene.seams[p0].a, model->hinges()(0, 0));
    EXPECT_EQ(scene.seams[p1].a, model->hinges()(0, 1));

    // Off, no seam: nothing joins the sheets.
    SceneSpec plain = scene;
    plain.seams.clear();
    EXPECT_EQ(SeamBending::build(plain, offsetsOf(plain)), nullptr);
}

TEST(SeamBending, ActsOnlyOnceBothPairsOfAnEdgeAreWelded) {
    const SceneSpec scene = sewnSheets();
    auto model = SeamBending::build(scene, offsetsOf(scene));
    ASSERT_NE(model, nullptr);
    const MatX3 x = folded(scene, 0.6);
    const MatX3 v = MatX3::Zero(x.rows(), 3);
    EXPECT_EQ(model->energy(x), 0.0);
    EXPECT_EQ(test::forces(*model, x, v).cwiseAbs().maxCoeff(), 0.0);

    // The two lowest pairs welded: the lowest seam edge acts, the others do not.
    SeamWelds welds(scene.seams, static_cast<int>(x.rows()));
    WeldFigures figures;
    MatX3 closing = x;
    for (std::size_t k = 2; k < scene.seams.size(); ++k) { // the upper pairs held apart
        closing.row(scene.seams[k].b) += Vec3(0.1, 0, 0).transpose();
    }
    welds.weldClosed(closing, 1e-6, false, figures);
    EXPECT_TRUE(model->followWelds(welds));
    EXPECT_FALSE(model->followWelds(welds)); // nothing new
    const double k = scene.cloths[0].material.bending;
    EXPECT_NEAR(model->energy(x), k * 3.0 * (1.0 - std::cos(0.6)), 1e-15);
}

TEST(SeamBending, AWeldedSeamBendsAsTheClothRunningOn) {
    // Folding two sewn sheets about their seam stores what folding one sheet of both widths
    // about the same line does: the same hinges, weights and stiffness (the discrete-shells
    // model's k), so the seam is as stiff as the cloth beside it.
    const SceneSpec scene = sewnSheets();
    auto model = SeamBending::build(scene, offsetsOf(scene));
    ASSERT_NE(model, nullptr);
    SceneSpec whole;
    whole.cloths = {sheet("whole", 0, 2 * SIDE, 2 * CELLS)};
    const DihedralBending wholeBending(whole.cloths[0].mesh, 0, whole.cloths[0].material, {},
                                       false);
    for (double phi : {0.1, 0.7, 2.0}) {
        const MatX3 x = folded(scene, phi);
        model->followWelds(allWelded(scene, x));
        EXPECT_NEAR(model->energy(x), wholeBending.energy(folded(whole, phi)),
                    1e-12 * wholeBending.energy(folded(whole, phi)))
            << phi;
    }

    // The seam's bending scale multiplies it; a fold angle is where it rests.
    SceneSpec stiff = scene;
    for (SeamPair& p : stiff.seams) {
        p.bendingScale = 3.0;
        p.foldAngle = 0.7;
    }
    auto stiffModel = SeamBending::build(stiff, offsetsOf(stiff));
    const MatX3 x = folded(stiff, 0.3);
    stiffModel->followWelds(allWelded(stiff, x));
    model->followWelds(allWelded(scene, x));
    for (int h = 0; h < stiffModel->hingeCount(); ++h) {
        EXPECT_DOUBLE_EQ(stiffModel->restAngles()[h], 0.7);
    }
    // At rest where the hinge's angle is the fold angle (the sign: dihedralAngle's, from A's
    // front), and 3× as stiff about it.
    const double theta = stiffModel->angle(folded(stiff, 0.7), 0);
    const double restPhi = theta > 0 ? 0.7 : -0.7;
    EXPECT_NEAR(stiffModel->energy(folded(stiff, restPhi)), 0.0, 1e-15);
    EXPECT_NEAR(stiffModel->energy(folded(stiff, restPhi + 0.2)),
                3.0 * model->energy(folded(scene, 0.2)), 1e-12);
}

TEST(SeamBending, ForcesAndJacobiansAreTheEnergysDerivatives) {
    const SceneSpec scene = sewnSheets();
    auto model = SeamBending::build(scene, offsetsOf(scene));
    ASSERT_NE(model, nullptr);
    MatX3 x = folded(scene, 0.5);
    model->followWelds(allWelded(scene, x));
    std::mt19937 random(3);
    std::uniform_real_distribution<double> noise(-0.01, 0.01);
    MatX3 v(x.rows(), 3);
    for (int i = 0; i < x.rows(); ++i) {
        x.row(i) += Vec3(noise(random), noise(random), noise(random)).transpose();
        v.row(i) = Vec3(noise(random), noise(random), noise(random)).transpose() * 10;
    }
    test::expectForcesAreEnergyGradient(*model, x, 1e-6, 1e-5);
    test::expectExactJacobianMatchesFiniteDifferences(*model, x, v, 1e-6, 1e-5);
    test::expectDefiniteJacobian(*model, x, v);
    test::expectMomentumConserved(*model, x, v, 1e-9);
}

/// A horizontal strip SIDE wide, 2·SIDE long, clamped along its first cells and hanging
/// under gravity: one cloth, or two sewn end to end; its tip's height [m] after `duration`.
double tipHeight(bool sewn, bool seamBending) {
    SceneSpec scene;
    if (sewn) {
        scene = sewnSheets();
    } else {
        scene.cloths = {sheet("whole", 0, 2 * SIDE, 2 * CELLS)};
    }
    const int columns = sewn ? CELLS + 1 : 2 * CELLS + 1;
    for (ClothSpec& c : scene.cloths) { // horizontal: pattern y → world −z
        c.position.col(2) = -c.position.col(1);
        c.position.col(1).setZero();
        c.material.bending = 1e-2; // ρgL³/k ≈ 6 over its 0.35 m overhang
        c.material.density = 0.15;
    }
    for (int j = 0; j <= CELLS; ++j) { // two columns: a clamp, not a pivot
        scene.pins.push_back(j * columns);
        scene.pins.push_back(j * columns + 1);
    }
    scene.seamMode = SeamMode::Imposed;
    scene.seamWeldDistance = 1e-3;
    scene.seamBending = seamBending;
    scene.highDampingTimeConstant = 0.05;
    scene.integrator.kind = IntegratorKind::ImplicitEuler;
    scene.integrator.dt = 5e-3;
    Simulation simulation(scene);
    EXPECT_TRUE(simulation.error().empty()) << simulation.error();
    EXPECT_EQ(simulation.advance(1.5), RunStatus::Finished) << simulation.error();
    return simulation.positions().col(1).minCoeff();
}

TEST(SeamBending, AStripSewnEndToEndHangsAsTheWholeStrip) {
    const double whole = tipHeight(false, true);
    const double sewn = tipHeight(true, true);
    const double freeHinge = tipHeight(true, false);
    EXPECT_LT(whole, -0.01); // it bends
    EXPECT_NEAR(sewn, whole, 0.02 * std::abs(whole));
    // Without the seam's hinges B folds down at the seam as if on a door hinge.
    EXPECT_LT(freeHinge, 1.5 * whole);
}

} // namespace
} // namespace atelier::sim
