#include "patterns/fabric_fit.h"

#include "sim/analysis/heavy_elastica.h"
#include "sim/core/types.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace atelier::patterns {
namespace {

sim::Material base() {
    sim::Material m;
    m.density = 0.12;
    m.stretchWeft = 5000;
    m.stretchWarp = 8000;
    m.shear = 100;
    m.poisson = 0.25;
    m.bending = 8e-6;
    return m;
}

TEST(FabricFit, TheBendingLengthIsHalfTheOverhangWhoseTipLineFalls41Point5Degrees) {
    // Peirce: at rho g L^3 / B = 8 the tip line of the heavy elastica is 41.5 deg below the
    // horizontal, and c = L / 2.
    const double density = 0.12;
    const double c = 0.021;
    const double b = rigidityOfBendingLength(c, density);
    EXPECT_NEAR(b, density * sim::STANDARD_GRAVITY * c * c * c, 1e-18);
    EXPECT_NEAR(bendingLengthOf(b, density), c, 1e-12);
    const double overhang = 2 * c;
    const double lambda = density * sim::STANDARD_GRAVITY * std::pow(overhang, 3) / b;
    EXPECT_NEAR(lambda, 8.0, 1e-9);
    EXPECT_NEAR(sim::solveHeavyElastica(lambda).tipLineAngle * 180 / std::numbers::pi, 41.5, 0.1);
}

TEST(FabricFit, LabValuesBecomeTheMaterial) {
    LabFabric lab;
    lab.density = 0.2;
    lab.bendingLengthWeft = 0.025;
    lab.bendingLengthWarp = 0.03;
    lab.tensileWeft = 6000;
    lab.tensileWarp = 9000;
    lab.poisson = 0.3;
    // A bias stiffness from a known shear modulus comes back as that shear modulus.
    sim::Material expected = base();
    expected.stretchWeft = 6000;
    expected.stretchWarp = 9000;
    expected.poisson = 0.3;
    expected.shear = 150;
    lab.tensileBias = biasTensile(expected).stretch;
    const auto fitted = fitFabric(lab, base());
    ASSERT_TRUE(fitted.ok()) << fitted.error().toString();
    const sim::Material& m = fitted.value();
    EXPECT_DOUBLE_EQ(m.density, 0.2);
    EXPECT_NEAR(m.bendingWeft, rigidityOfBendingLength(0.025, 0.2), 1e-15);
    EXPECT_NEAR(m.bendingWarp, rigidityOfBendingLength(0.03, 0.2), 1e-15);
    EXPECT_NEAR(m.bending, std::sqrt(m.bendingWeft * m.bendingWarp), 1e-15);
    EXPECT_DOUBLE_EQ(m.stretchWeft, 6000);
    EXPECT_DOUBLE_EQ(m.stretchWarp, 9000);
    EXPECT_DOUBLE_EQ(m.poisson, 0.3);
    EXPECT_NEAR(m.shear, 150, 1e-9);
    // And the figures it shows are the lab's.
    const auto figures = fabricFigures(m);
    ASSERT_TRUE(figures.ok()) << figures.error().toString();
    EXPECT_NEAR(figures.value().bendingLengthWeft, 0.025, 1e-12);
    EXPECT_NEAR(figures.value().bendingLengthWarp, 0.03, 1e-12);
    EXPECT_NEAR(figures.value().tensileBias, *lab.tensileBias, 1e-9);
    // The bias strip lies between the two threads' (no bias rigidity given: Huber's plate).
    EXPECT_GT(figures.value().bendingLengthBias, 0.02);
    EXPECT_LT(figures.value().bendingLengthBias, 0.03);
}

TEST(FabricFit, OneBendingDirectionIsTakenForBothAndUnmeasuredValuesStay) {
    LabFabric lab;
    lab.density = 0.12;
    lab.bendingWeft = 2e-5;
    const auto fitted = fitFabric(lab, base());
    ASSERT_TRUE(fitted.ok()) << fitted.error().toString();
    EXPECT_DOUBLE_EQ(fitted.value().bending, 2e-5);
    EXPECT_EQ(fitted.value().bendingWeft, 0); // isotropic
    EXPECT_EQ(fitted.value().bendingWarp, 0);
    EXPECT_DOUBLE_EQ(fitted.value().stretchWeft, 5000);
    EXPECT_DOUBLE_EQ(fitted.value().shear, 100);
}

TEST(FabricFit, ImpossibleMeasurementsAreNamed) {
    const auto errorAt = [](const LabFabric& lab) {
        const auto r = fitFabric(lab, base());
        return r.ok() ? std::string("(accepted)") : r.error().where;
    };
    LabFabric lab;
    EXPECT_EQ(errorAt(lab), "density"); // not given
    lab.density = 0.12;
    lab.tensileWarp = -5;
    EXPECT_EQ(errorAt(lab), "tensile_warp");
    lab.tensileWarp.reset();
    lab.bendingLengthWeft = 0.02;
    lab.bendingWeft = 1e-5;
    EXPECT_EQ(errorAt(lab), "bending_weft"); // both a length and a rigidity
    lab.bendingWeft.reset();
    // A bias strip stiffer than the threads allow (G would be negative).
    lab.tensileBias = 1e5;
    EXPECT_EQ(errorAt(lab), "tensile_bias");
    lab.tensileBias.reset();
    lab.poisson = 1.5;
    EXPECT_EQ(errorAt(lab), "poisson");
}

} // namespace
} // namespace atelier::patterns
