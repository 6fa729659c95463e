#include "sim/forces/force_check.h"
#include "sim/forces/volino.h"

#include <gtest/gtest.h>

namespace atelier::sim {
namespace {

using test::PlacedCloth;

Material volinoMaterial() {
    Material m;
    m.stretchWeft = 3000;
    m.stretchWarp = 1200;
    m.poisson = 0.3;
    m.damping = 0.01;
    return m;
}

class VolinoStretchTest : public ::testing::TestWithParam<Triangulation> {};

TEST_P(VolinoStretchTest, PassesForceChecks) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(GetParam()));
    const Material m = volinoMaterial();
    const VolinoStretch model(c.mesh, c.offset, m, lumpedMasses(c.mesh, m.density));
    EXPECT_FALSE(model.hasEnergy()); // the corrected-elongation model is not conservative
    for (std::uint32_t seed : {1u, 2u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        const auto [x, v] = test::randomState(c, 0.02, 0.5, seed);
        test::checkForceModel(model, c, x, v);
    }
}

INSTANTIATE_TEST_SUITE_P(Meshes, VolinoStretchTest,
                         ::testing::Values(Triangulation::Regular, Triangulation::Irregular));

TEST(VolinoStretch, DegenerateStatesStayFinite) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Irregular));
    const Material m = volinoMaterial();
    const VolinoStretch model(c.mesh, c.offset, m, lumpedMasses(c.mesh, m.density));
    const MatX3 x = MatX3::Zero(c.totalVertices, 3);
    const MatX3 v = MatX3::Ones(x.rows(), 3);
    EXPECT_TRUE(test::forces(model, x, v).allFinite());
    for (auto mode : {JacobianMode::Exact, JacobianMode::Definite}) {
        EXPECT_TRUE(test::denseJacobian(model, x, v, 1, 1, mode).allFinite());
    }
}

} // namespace
} // namespace atelier::sim
