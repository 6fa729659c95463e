/// Renderer::updatePositions, updateTriangleColours and updateLinePositions: a mesh or lines
/// changed in place draw as the same scene uploaded anew.

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

/// The skirt with its triangles in two alternating colours and a line along its hem.
Scene colouredWithLines() {
    Scene scene = skirtOnBody();
    DrawMesh& skirt = scene.meshes[0];
    skirt.triangleColours.clear();
    for (Eigen::Index t = 0; t < skirt.triangles.rows(); ++t) {
        skirt.triangleColours.push_back(t % 2 == 0 ? Colour{0.9f, 0.2f, 0.2f, 1}
                                                   : Colour{0.2f, 0.3f, 0.9f, 1});
    }
    DrawLines lines;
    lines.positions = skirt.positions.topRows(40);
    lines.segments.resize(39, 2);
    for (Eigen::Index i = 0; i < 39; ++i) {
        lines.segments.row(i) << static_cast<int>(i), static_cast<int>(i + 1);
    }
    lines.colour = {0.1f, 0.8f, 0.1f, 1};
    lines.widthPx = 3;
    scene.lines.push_back(std::move(lines));
    return scene;
}

TEST_F(RenderTest, UpdatedTriangleColoursAndLinePositionsDrawAsAFreshUpload) {
    RenderOptions o;
    o.width = 96;
    o.height = 80;
    const Scene scene = colouredWithLines();
    Scene changed = scene;
    for (Colour& c : changed.meshes[0].triangleColours) {
        std::swap(c.r, c.b);
    }
    changed.lines[0].positions.col(1).array() -= 0.1; // 10 cm lower
    const io::RgbaImage fresh = draw(changed, o);

    ASSERT_TRUE(renderer().setScene(scene).ok());
    const io::RgbaImage before = renderer().render(o).value();
    const auto colours = renderer().updateTriangleColours(0, changed.meshes[0].triangleColours);
    ASSERT_TRUE(colours.ok()) << colours.error().toString();
    const auto lines = renderer().updateLinePositions(0, changed.lines[0].positions);
    ASSERT_TRUE(lines.ok()) << lines.error().toString();
    const io::RgbaImage after = renderer().render(o).value();
    EXPECT_EQ(after.pixels, fresh.pixels);
    EXPECT_NE(after.pixels, before.pixels);
}

TEST_F(RenderTest, ColourAndLineUpdatesOfTheWrongShapeAreRefused) {
    const Scene scene = colouredWithLines();
    ASSERT_TRUE(renderer().setScene(scene).ok());
    const auto& colours = scene.meshes[0].triangleColours;
    EXPECT_FALSE(renderer().updateTriangleColours(0, {colours.begin(), colours.end() - 1}).ok());
    EXPECT_FALSE(renderer().updateTriangleColours(1, {}).ok())
        << "no colour for the body's triangles";
    EXPECT_FALSE(renderer().updateTriangleColours(2, colours).ok());
    EXPECT_TRUE(renderer().updateTriangleColours(0, colours).ok());
    sim::MatX3 p = scene.lines[0].positions;
    EXPECT_FALSE(renderer().updateLinePositions(0, p.topRows(3)).ok());
    EXPECT_FALSE(renderer().updateLinePositions(1, p).ok());
    p(2, 1) = std::nan("");
    const auto bad = renderer().updateLinePositions(0, p);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("not finite"), std::string::npos);
    EXPECT_TRUE(renderer().updateLinePositions(0, scene.lines[0].positions).ok());
}

} // namespace
} // namespace atelier::render::test
