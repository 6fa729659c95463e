#include "sim/forces/air.h"
#include "sim/forces/force_check.h"

#include <gtest/gtest.h>

namespace atelier::sim {
namespace {

using test::PlacedCloth;

AirOptions airOptions(const Vec3& wind = Vec3::Zero()) {
    AirOptions a;
    a.enabled = true;
    a.dragCoefficient = 0.8;
    a.wind = wind;
    return a;
}

class AirDragTest : public ::testing::TestWithParam<Triangulation> {};

TEST_P(AirDragTest, PassesForceChecksWithoutWind) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(GetParam()));
    const AirDrag model(c.mesh, c.offset, airOptions());
    test::ForceCheckOptions o;
    o.internal = false;            // the drag is an external force
    o.rigidVelocityAtRest = false; // a moving cloth feels drag
    o.restTolerance = 0.0;
    for (std::uint32_t seed : {1u, 2u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        const auto [x, v] = test::randomState(c, 0.03, 1.0, seed);
        test::checkForceModel(model, c, x, v, o);
    }
}

TEST_P(AirDragTest, JacobianMatchesWithWind) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(GetParam()));
    const AirDrag model(c.mesh, c.offset, airOptions(Vec3(2.0, -1.0, 3.0)));
    const auto [x, v] = test::randomState(c, 0.03, 1.0, 3);
    test::expectExactJacobianMatchesFiniteDifferences(model, x, v, 1e-6, 1e-6);
    test::expectDefiniteJacobian(model, x, v);
    test::expectOnlyClothRows(model, c, x, v);
}

INSTANTIATE_TEST_SUITE_P(Meshes, AirDragTest,
                         ::testing::Values(Triangulation::Regular, Triangulation::Irregular));

TEST(AirDrag, DragsOnlyTheNormalRelativeVelocity) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Irregular));
    const MatX3 x = test::restPositions(c); // in the plane z = 0, area 0.4 × 0.3
    const double area = 0.4 * 0.3;
    const auto clothVelocity = [&](const Vec3& u) {
        MatX3 v = MatX3::Zero(x.rows(), 3);
        for (int i = 0; i < c.mesh.vertexCount(); ++i) {
            v.row(c.offset + i) = u.transpose();
        }
        return v;
    };
    const AirDrag still(c.mesh, c.offset, airOptions());
    // Falling flat at 2 m/s: total drag c·A·2 upwards.
    Vec3 total = test::forces(still, x, clothVelocity(Vec3(0, 0, -2))).colwise().sum();
    EXPECT_NEAR(total.z(), 0.8 * area * 2, 1e-12);
    EXPECT_NEAR(total.head<2>().norm(), 0.0, 1e-12);
    // Sliding in its plane: no drag.
    total = test::forces(still, x, clothVelocity(Vec3(3, -1, 0))).colwise().sum();
    EXPECT_NEAR(total.norm(), 0.0, 1e-12);
    // Moving with the wind: no drag; still in the wind: pushed along the wind's normal part.
    const AirDrag windy(c.mesh, c.offset, airOptions(Vec3(1, 2, 0.5)));
    test::expectZeroForce(windy, x, clothVelocity(Vec3(1, 2, 0.5)), 1e-15);
    total = test::forces(windy, x, MatX3::Zero(x.rows(), 3)).colwise().sum();
    EXPECT_NEAR(total.z(), 0.8 * area * 0.5, 1e-12);
}

TEST(AirDrag, DegenerateTrianglesContributeNothing) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Regular));
    const AirDrag model(c.mesh, c.offset, airOptions(Vec3(1, 1, 1)));
    const MatX3 x = MatX3::Zero(c.totalVertices, 3);
    const MatX3 v = MatX3::Ones(x.rows(), 3);
    EXPECT_TRUE(test::forces(model, x, v).isZero(0.0));
    EXPECT_TRUE(test::denseJacobian(model, x, v, 1, 1, JacobianMode::Exact).isZero(0.0));
}

} // namespace
} // namespace atelier::sim
