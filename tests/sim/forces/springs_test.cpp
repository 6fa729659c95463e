#include "sim/forces/force_check.h"
#include "sim/forces/springs.h"

#include <gtest/gtest.h>

namespace atelier::sim {
namespace {

using test::PlacedCloth;

Material springMaterial() {
    Material m;
    m.stretchWeft = 3000;
    m.stretchWarp = 1200;
    m.shear = 400;
    m.damping = 0.01;
    return m;
}

struct SpringCase {
    Triangulation triangulation;
    bool crossSprings;
};

class SpringStretchTest : public ::testing::TestWithParam<SpringCase> {};

TEST_P(SpringStretchTest, PassesForceChecks) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(GetParam().triangulation));
    const SpringStretch model(c.mesh, c.offset, springMaterial(), GetParam().crossSprings);
    EXPECT_EQ(model.springCount(),
              c.mesh.edges.rows() + (GetParam().crossSprings ? c.mesh.hinges.rows() : 0));
    for (std::uint32_t seed : {1u, 2u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        const auto [x, v] = test::randomState(c, 0.02, 0.5, seed);
        test::checkForceModel(model, c, x, v);
    }
}

INSTANTIATE_TEST_SUITE_P(Meshes, SpringStretchTest,
                         ::testing::Values(SpringCase{Triangulation::Regular, false},
                                           SpringCase{Triangulation::Irregular, false},
                                           SpringCase{Triangulation::Regular, true},
                                           SpringCase{Triangulation::Irregular, true}));

TEST(SpringStretch, DegenerateStatesStayFinite) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Irregular));
    const SpringStretch model(c.mesh, c.offset, springMaterial(), true);
    const MatX3 x = MatX3::Zero(c.totalVertices, 3);
    const MatX3 v = MatX3::Ones(x.rows(), 3);
    EXPECT_TRUE(test::forces(model, x, v).allFinite());
    EXPECT_TRUE(std::isfinite(model.energy(x)));
    for (auto mode : {JacobianMode::Exact, JacobianMode::Definite}) {
        EXPECT_TRUE(test::denseJacobian(model, x, v, 1, 1, mode).allFinite());
    }
}

} // namespace
} // namespace atelier::sim
