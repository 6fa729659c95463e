/// Renderer::updatePositions: a mesh moved in place draws as the same mesh uploaded anew.

#include "render_fixture.h"

namespace atelier::render::test {
namespace {

TEST_F(RenderTest, UpdatedPositionsDrawAsAFreshUpload) {
    RenderOptions o;
    o.width = 96;
    o.height = 80;
    Scene scene = skirtOnBody();
    Scene moved = scene;
    // The skirt flares and shifts: new positions (and normals), the same triangles.
    sim::MatX3& p = moved.meshes[0].positions;
    for (Eigen::Index i = 0; i < p.rows(); ++i) {
        const double flare = 1.0 + 0.6 * (1.0 - p(i, 1));
        p(i, 0) *= flare;
        p(i, 2) *= flare;
    }
    p.col(0).array() += 0.05;
    const io::RgbaImage fresh = draw(moved, o);

    ASSERT_TRUE(renderer().setScene(scene).ok());
    const io::RgbaImage before = renderer().render(o).value();
    const auto updated = renderer().updatePositions(0, p);
    ASSERT_TRUE(updated.ok()) << updated.error().toString();
    EXPECT_TRUE(renderer().bounds().isApprox(sceneBounds(moved)));
    const io::RgbaImage after = renderer().render(o).value();
    EXPECT_EQ(after.pixels, fresh.pixels);
    EXPECT_NE(after.pixels, before.pixels);
}

TEST_F(RenderTest, PositionUpdatesOfTheWrongShapeAreRefused) {
    ASSERT_TRUE(renderer().setScene(skirtOnBody()).ok());
    const sim::MatX3 few = sim::MatX3::Zero(3, 3);
    EXPECT_FALSE(renderer().updatePositions(0, few).ok());
    EXPECT_FALSE(renderer().updatePositions(2, few).ok());
    EXPECT_FALSE(renderer().updatePositions(-1, few).ok());
    sim::MatX3 bad = skirtOnBody().meshes[0].positions;
    bad(0, 0) = std::nan("");
    EXPECT_FALSE(renderer().updatePositions(0, bad).ok());
    const sim::MatX3 good = skirtOnBody().meshes[0].positions;
    EXPECT_FALSE(renderer().updatePositions(0, good, sim::MatX3::Zero(2, 3)).ok());
    EXPECT_TRUE(renderer().updatePositions(0, good).ok());
}

} // namespace
} // namespace atelier::render::test
