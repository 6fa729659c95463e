// Pin markers: a pinhead drawn where a pinned point projects, over everything, and nowhere when
// there are no pins or they are turned off.
#include "ui/render/pin_markers.h"

#include "render_fixture.h"

#include <gtest/gtest.h>

#include <cmath>

namespace atelier::render::test {
namespace {

/// The pinhead's red: saturated, unlike any panel tone, the body or the background.
bool pinRed(const std::uint8_t* p) {
    return p[0] > 170 && p[1] < 60 && p[2] < 70;
}

int pinRedPixels(const io::RgbaImage& image) {
    int n = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            n += pinRed(image.at(x, y)) ? 1 : 0;
        }
    }
    return n;
}

TEST(PinMarkers, ProjectionPutsTheFramedCentreInTheMiddle) {
    Eigen::AlignedBox3d box(Eigen::Vector3d(-0.3, 0.7, -0.1), Eigen::Vector3d(0.3, 1.3, 0.1));
    const Camera camera = frameView(View::Front, box, 1.0);
    const auto centre = projectToPixel(camera, box.center(), 200, 100);
    ASSERT_TRUE(centre.has_value());
    EXPECT_NEAR(centre->x(), 100, 1e-3);
    EXPECT_NEAR(centre->y(), 50, 1e-3);
    // Up in the world is up in the picture (smaller y); behind the camera is nothing.
    EXPECT_LT(projectToPixel(camera, box.center() + Eigen::Vector3d(0, 0.1, 0), 200, 100)->y(), 50);
    EXPECT_FALSE(
        projectToPixel(camera, camera.eye.cast<double>() + Eigen::Vector3d(0, 0, 1), 200, 100));
    EXPECT_EQ(pinRadiusPx(256), 4.0f);
    EXPECT_EQ(pinRadiusPx(1024), 10.24f);
}

TEST_F(RenderTest, APinheadIsDrawnWhereThePinProjectsAndNowhereWithoutPins) {
    Scene scene;
    scene.meshes.push_back(sheet());
    RenderOptions options;
    options.width = 160;
    options.height = 160;
    options.view = View::Front;
    const io::RgbaImage plain = draw(scene, options);
    EXPECT_EQ(pinRedPixels(plain), 0) << "no pins, no pinheads";

    // A pin at the sheet's upper left quarter, and one behind the sheet (still drawn).
    scene.pins.resize(2, 3);
    scene.pins.row(0) << -0.125, 1.125, 0;
    scene.pins.row(1) << 0.1, 0.9, -0.05;
    const io::RgbaImage pinned = draw(scene, options);
    const Camera camera = frameView(View::Front, renderer().bounds(), 1.0);
    const float r = pinRadiusPx(options.height);
    for (Eigen::Index k = 0; k < scene.pins.rows(); ++k) {
        SCOPED_TRACE(k);
        const auto at =
            projectToPixel(camera, scene.pins.row(k).transpose(), options.width, options.height);
        ASSERT_TRUE(at.has_value());
        const int cx = static_cast<int>(at->x());
        const int cy = static_cast<int>(at->y());
        // The head's red is within its radius of the projection (the shine sits up and left).
        int red = 0;
        for (int y = 0; y < options.height; ++y) {
            for (int x = 0; x < options.width; ++x) {
                const double d = std::hypot(x + 0.5 - at->x(), y + 0.5 - at->y());
                red += pinRed(pinned.at(x, y)) && d <= r ? 1 : 0;
            }
        }
        EXPECT_GE(red, 10) << "the pinhead's red around (" << cx << ", " << cy << ")";
        EXPECT_TRUE(pinRed(pinned.at(cx, cy))) << "the head covers the pinned point";
        EXPECT_FALSE(pinRed(plain.at(cx, cy)));
    }
    // Only pinheads: the red is all within the two heads.
    EXPECT_LE(pinRedPixels(pinned), static_cast<int>(2 * 3.1416 * (r + 1) * (r + 1)));

    options.pins = false;
    EXPECT_EQ(pinRedPixels(draw(scene, options)), 0) << "turned off";

    // setPins replaces them without a new scene.
    options.pins = true;
    ASSERT_TRUE(renderer().setScene(scene).ok());
    renderer().setPins(sim::MatX3());
    auto none = renderer().render(options);
    ASSERT_TRUE(none.ok());
    EXPECT_EQ(pinRedPixels(none.value()), 0);
}

} // namespace
} // namespace atelier::render::test
