#include "ui/render/camera.h"
#include "ui/render/scene.h"

#include <gtest/gtest.h>

namespace atelier::render {
namespace {

/// The corner's position in normalised device coordinates.
Eigen::Vector3f project(const Camera& camera, const Eigen::Vector3d& p) {
    const Eigen::Vector4f clip = camera.projection * camera.view * p.cast<float>().homogeneous();
    return clip.head<3>() / clip.w();
}

TEST(Camera, EveryViewFramesTheBoxTightly) {
    // A body-like box: 0.5 m wide, 1.8 m tall, 0.3 m deep, feet at y = 0.
    const Eigen::AlignedBox3d box(Eigen::Vector3d(-0.25, 0, -0.15),
                                  Eigen::Vector3d(0.25, 1.8, 0.15));
    for (const double aspect : {1.0, 0.5, 2.0}) {
        for (const View view : ALL_VIEWS) {
            const Camera camera = frameView(view, box, aspect);
            double extent = 0;
            for (int k = 0; k < 8; ++k) {
                const Eigen::Vector3f ndc =
                    project(camera, box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)));
                EXPECT_LE(std::abs(ndc.x()), 0.9001) << viewName(view);
                EXPECT_LE(std::abs(ndc.y()), 0.9001) << viewName(view);
                EXPECT_GT(ndc.z(), -1) << viewName(view) << ": corner in front of the near plane";
                EXPECT_LT(ndc.z(), 1) << viewName(view) << ": corner beyond the far plane";
                extent = std::max({extent, double(std::abs(ndc.x())), double(std::abs(ndc.y()))});
            }
            // Tight: some corner reaches the allowed fill on one axis.
            EXPECT_GT(extent, 0.85) << viewName(view) << " aspect " << aspect;
        }
    }
}

TEST(Camera, ViewsLookFromWhereTheirNamesSay) {
    const Eigen::AlignedBox3d box(Eigen::Vector3d(-1, 0, -1), Eigen::Vector3d(1, 2, 1));
    EXPECT_GT(frameView(View::Front, box, 1).eye.z(), 1);
    EXPECT_LT(frameView(View::Back, box, 1).eye.z(), -1);
    EXPECT_GT(frameView(View::Left, box, 1).eye.x(), 1);
    EXPECT_LT(frameView(View::Right, box, 1).eye.x(), -1);
    EXPECT_GT(frameView(View::Top, box, 1).eye.y(), 2);
    const Eigen::Vector3f q = frameView(View::ThreeQuarter, box, 1).eye;
    EXPECT_GT(q.x(), 0);
    EXPECT_GT(q.z(), q.x());
    EXPECT_GT(q.y(), 1);
    // Top: the front of the body (+z) is at the bottom of the picture.
    EXPECT_LT(project(frameView(View::Top, box, 1), {0, 2, 1}).y(), 0);
}

TEST(Camera, ViewNamesRoundTrip) {
    for (const View view : ALL_VIEWS) {
        EXPECT_EQ(viewFromName(viewName(view)), view);
    }
    EXPECT_FALSE(viewFromName("side").has_value());
}

TEST(Scene, ColoursParse) {
    Colour c;
    ASSERT_TRUE(parseColour("#ff8000", c));
    EXPECT_FLOAT_EQ(c.r, 1);
    EXPECT_NEAR(c.g, 128 / 255.0, 1e-6);
    EXPECT_FLOAT_EQ(c.a, 1);
    ASSERT_TRUE(parseColour("transparent", c));
    EXPECT_FLOAT_EQ(c.a, 0);
    ASSERT_TRUE(parseColour("00000080", c));
    EXPECT_NEAR(c.a, 128 / 255.0, 1e-6);
    EXPECT_FALSE(parseColour("#12345", c));
    EXPECT_FALSE(parseColour("blue-ish", c));
}

TEST(Scene, PanelColoursDifferAndScalarsRamp) {
    for (int i = 0; i < 8; ++i) {
        for (int j = 0; j < i; ++j) {
            const Colour a = panelColour(i);
            const Colour b = panelColour(j);
            EXPECT_GT(std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b), 0.15f);
        }
    }
    const std::vector<Colour> ramp = scalarColours(Eigen::Vector3d(0, 0.5, 1), 0, 1);
    EXPECT_GT(ramp[0].b, ramp[0].r);
    EXPECT_FLOAT_EQ(ramp[1].g, 1);
    EXPECT_GT(ramp[2].r, ramp[2].b);
}

} // namespace
} // namespace atelier::render
