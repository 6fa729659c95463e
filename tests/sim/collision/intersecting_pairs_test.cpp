/// The intersecting-pairs figure of the reports: seam partners not welded are two vertices.

#include "sim/collision/collision_stage.h"
#include "sim/simulation.h"

#include <gtest/gtest.h>

namespace atelier {
namespace {

/// A one-triangle cloth at `position` (3×3, rows = corners), a right triangle at rest.
sim::ClothSpec triangleCloth(const std::string& name, const sim::MatX3& position) {
    sim::ClothSpec c;
    c.name = name;
    sim::MatX2 rest(3, 2);
    rest << 0, 0, 1, 0, 0, 1;
    sim::MatX3i tris(1, 3);
    tris << 0, 1, 2;
    EXPECT_FALSE(sim::buildClothMesh(rest, tris, c.mesh).has_value());
    c.position = position;
    c.selfCollision = true;
    return c;
}

/// Two triangles crossing each other, their first corners a seam pair 0.1 m apart (open).
sim::SceneSpec openSeamThroughCloth() {
    sim::SceneSpec s;
    sim::MatX3 a(3, 3);
    a << 0, 0, 0, 1, 0, 0, 0, 1, 0;
    sim::MatX3 b(3, 3);
    b << 0.1, 0.1, -0.5, 0.1, 0.1, 0.5, 0.3, 0.3, 0.5;
    s.cloths = {triangleCloth("a", a), triangleCloth("b", b)};
    s.seams = {sim::SeamPair{0, 3, 0.0}};
    return s;
}

TEST(IntersectingPairs, AnOpenSeamsCrossingTrianglesCount) {
    const sim::Simulation simulation(openSeamThroughCloth());
    ASSERT_NE(simulation.collision(), nullptr);
    ASSERT_FALSE(simulation.seamPairWelded(0));
    // Before: every pair with seam partners was skipped, welded or not, and this read 0.
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 1);
}

TEST(IntersectingPairs, WeldedPartnersAreOneVertex) {
    const sim::Simulation simulation(openSeamThroughCloth());
    auto* stage = const_cast<sim::CollisionStage*>(simulation.collision());
    const sim::MatX3 x = simulation.positions();
    EXPECT_EQ(stage->intersectingTrianglePairs(x, {}), 1);
    EXPECT_EQ(stage->intersectingTrianglePairs(x, {{0, 3}}), 0);
}

} // namespace
} // namespace atelier
