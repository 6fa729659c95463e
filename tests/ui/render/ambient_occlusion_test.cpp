/// The ambient-occlusion approximation: open where nothing is near, darker in a fold, and
/// darker in the picture.

#include "ui/render/ambient_occlusion.h"

#include "render_fixture.h"

#include <gtest/gtest.h>

namespace atelier::render::test {
namespace {

/// An L of two sheets meeting at a concave corner: a floor (the plane y = 0.75, facing up)
/// and a wall behind it (the plane z = −0.25, facing +z).
Scene fold() {
    DrawMesh floor = sheet(0.5, 10);
    DrawMesh wall = sheet(0.5, 10);
    for (Eigen::Index i = 0; i < floor.positions.rows(); ++i) {
        const double x = floor.positions(i, 0);
        const double v = floor.positions(i, 1) - 0.75; // 0 .. 0.5
        floor.positions.row(i) << x, 0.75, 0.25 - v;   // z from 0.25 back to -0.25
    }
    for (Eigen::Index i = 0; i < wall.positions.rows(); ++i) {
        wall.positions(i, 2) = -0.25;
    }
    Scene scene;
    scene.meshes = {floor, wall};
    return scene;
}

TEST(AmbientOcclusion, OpenOnAFlatSheetDarkerInAFold) {
    Scene flat;
    flat.meshes.push_back(sheet(0.5, 10));
    const auto open = ambientOcclusion(flat);
    ASSERT_EQ(open.size(), 1u);
    for (const float v : open[0]) {
        EXPECT_NEAR(v, 1.0f, 1e-6f);
    }
    const Scene scene = fold();
    const auto v = ambientOcclusion(scene);
    ASSERT_EQ(v.size(), 2u);
    // On the floor, visibility grows away from the wall: nil in the corner (the normal runs
    // up the wall), 0.906 a row (5 cm) out ((0.08 − 0.05)/0.08 at the farthest of 4 samples),
    // 1 at the far edge.
    const DrawMesh& floor = scene.meshes[0];
    const auto rowMean = [&](double z) {
        double sum = 0;
        int n = 0;
        for (Eigen::Index i = 0; i < floor.positions.rows(); ++i) {
            if (std::abs(floor.positions(i, 2) - z) < 1e-9 &&
                std::abs(floor.positions(i, 0)) < 0.2) {
                sum += v[0][static_cast<std::size_t>(i)];
                ++n;
            }
        }
        return n > 0 ? sum / n : -1.0;
    };
    EXPECT_NEAR(rowMean(-0.25), 0.0, 1e-6);
    EXPECT_NEAR(rowMean(-0.20), 1 - 0.375 / 4, 1e-6);
    EXPECT_NEAR(rowMean(0.25), 1.0, 1e-6);
}

TEST_F(RenderTest, OcclusionDarkensTheFoldInThePicture) {
    Scene scene = fold();
    RenderOptions o;
    o.width = 96;
    o.height = 96;
    o.view = View::ThreeQuarter;
    o.groundShadow = false;
    const io::RgbaImage plain = draw(scene, o);
    const auto v = ambientOcclusion(scene);
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        scene.meshes[m].ambientOcclusion = v[m];
    }
    const io::RgbaImage occluded = draw(scene, o);
    long darker = 0;
    long lighter = 0;
    for (std::size_t i = 0; i < plain.pixels.size(); i += 4) {
        const int d = (plain.pixels[i] + plain.pixels[i + 1] + plain.pixels[i + 2]) -
                      (occluded.pixels[i] + occluded.pixels[i + 1] + occluded.pixels[i + 2]);
        darker += d > 6 ? 1 : 0;
        lighter += d < -3 ? 1 : 0;
    }
    EXPECT_GT(darker, 100);
    EXPECT_EQ(lighter, 0);
    scene.meshes[0].ambientOcclusion.pop_back();
    EXPECT_FALSE(renderer().setScene(scene).ok()) << "one value per vertex";
}

} // namespace
} // namespace atelier::render::test
