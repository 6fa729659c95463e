/// Sanity checks on real pictures: what a black, empty or mis-framed picture would fail.

#include "sim/collision/obstacle.h"

#include "render_fixture.h"

namespace atelier::render::test {
namespace {

RenderOptions small(View view = View::ThreeQuarter) {
    RenderOptions o;
    o.width = 160;
    o.height = 120;
    o.view = view;
    return o;
}

double luminance(const std::uint8_t* p) {
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

TEST_F(RenderTest, SkirtFillsAPlausibleShareOfEveryViewOnItsBackground) {
    const Scene scene = skirtOnBody();
    for (const View view : ALL_VIEWS) {
        const io::RgbaImage image = draw(scene, small(view));
        ASSERT_EQ(image.width, 160);
        ASSERT_EQ(image.height, 120);
        const std::uint8_t white[4] = {255, 255, 255, 255};
        for (const auto& [x, y] : {std::pair{0, 0}, {159, 0}, {0, 119}, {159, 119}}) {
            EXPECT_TRUE(samePixel(image.at(x, y), white)) << viewName(view) << " corner " << x;
        }
        const double share = coverage(image);
        EXPECT_GT(share, 0.04) << viewName(view) << ": (nearly) empty picture";
        EXPECT_LT(share, 0.8) << viewName(view);
        // Framed: the content's pixels are centred, not cut by the picture's edges, and fill
        // a good part of it along one axis (the box's corners frame it, so a tall skirt seen
        // from above fills less than its box would).
        int x0 = image.width;
        int x1 = -1;
        int y0 = image.height;
        int y1 = -1;
        double light = 0;
        long count = 0;
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x) {
                if (luminance(image.at(x, y)) < 250) {
                    x0 = std::min(x0, x);
                    x1 = std::max(x1, x);
                    y0 = std::min(y0, y);
                    y1 = std::max(y1, y);
                    light += luminance(image.at(x, y));
                    ++count;
                }
            }
        }
        ASSERT_GT(count, 0);
        EXPECT_GT(std::max(double(x1 - x0) / image.width, double(y1 - y0) / image.height), 0.45)
            << viewName(view) << ": content too small in the frame";
        EXPECT_TRUE(x0 > 0 && y0 > 0 && x1 < image.width - 1 && y1 < image.height - 1)
            << viewName(view) << ": content cut by the picture's edge";
        EXPECT_LT(std::abs((x0 + x1) / 2.0 - image.width / 2.0), 0.15 * image.width)
            << viewName(view);
        EXPECT_LT(std::abs((y0 + y1) / 2.0 - image.height / 2.0), 0.15 * image.height)
            << viewName(view);
        EXPECT_GT(light / double(count), 60) << viewName(view) << ": too dark";
    }
}

TEST_F(RenderTest, BackOfTheClothDiffersFromItsFront) {
    Scene scene;
    scene.meshes.push_back(sheet());
    RenderOptions o = small(View::Front);
    o.groundShadow = false;
    const io::RgbaImage front = draw(scene, o);
    o.view = View::Back;
    const io::RgbaImage back = draw(scene, o);
    const std::uint8_t* f = front.at(80, 60);
    const std::uint8_t* b = back.at(80, 60);
    const std::uint8_t white[4] = {255, 255, 255, 255};
    EXPECT_FALSE(samePixel(f, white, 10));
    EXPECT_FALSE(samePixel(b, white, 10));
    // The back is paler and darker than the front.
    EXPECT_GT(std::abs(f[0] - b[0]) + std::abs(f[1] - b[1]) + std::abs(f[2] - b[2]), 60)
        << "front " << int(f[0]) << "," << int(f[1]) << "," << int(f[2]) << " back " << int(b[0])
        << "," << int(b[1]) << "," << int(b[2]);
    EXPECT_LT(luminance(b) + 10, luminance(f));
}

TEST_F(RenderTest, TransparentBackgroundHasAlphaZeroOutside) {
    RenderOptions o = small(View::Front);
    o.background = {0, 0, 0, 0};
    const io::RgbaImage image = draw(skirtOnBody(), o);
    for (const auto& [x, y] : {std::pair{0, 0}, {159, 0}, {0, 119}, {159, 119}}) {
        EXPECT_EQ(image.at(x, y)[3], 0) << x << "," << y;
    }
    EXPECT_EQ(image.at(80, 60)[3], 255);
}

TEST_F(RenderTest, PanelsKeepTheirColours) {
    Scene scene;
    scene.meshes.push_back(sheet());
    DrawMesh& m = scene.meshes.back();
    for (Eigen::Index t = 0; t < m.triangles.rows(); ++t) {
        const bool left =
            m.positions(m.triangles(t, 0), 0) < -1e-9 || m.positions(m.triangles(t, 1), 0) < -1e-9;
        m.triangleColours.push_back(left ? Colour{0.9f, 0.1f, 0.1f, 1}
                                         : Colour{0.1f, 0.2f, 0.9f, 1});
    }
    RenderOptions o = small(View::Front);
    o.groundShadow = false;
    const io::RgbaImage image = draw(scene, o);
    const std::uint8_t* left = image.at(60, 60);
    const std::uint8_t* right = image.at(100, 60);
    EXPECT_GT(left[0], left[2]);
    EXPECT_GT(right[2], right[0]);
}

TEST_F(RenderTest, WireframeOverlayDrawsEdges) {
    RenderOptions o = small(View::Front);
    const io::RgbaImage plain = draw(skirtOnBody(), o);
    o.wireframe = true;
    const io::RgbaImage wired = draw(skirtOnBody(), o);
    long darker = 0;
    for (int y = 0; y < o.height; ++y) {
        for (int x = 0; x < o.width; ++x) {
            darker += luminance(wired.at(x, y)) + 8 < luminance(plain.at(x, y)) ? 1 : 0;
        }
    }
    EXPECT_GT(darker, 200);
}

TEST_F(RenderTest, PerVertexColoursAreInterpolated) {
    Scene scene;
    scene.meshes.push_back(sheet());
    DrawMesh& m = scene.meshes.back();
    sim::VecX height = m.positions.col(1);
    m.vertexColours = scalarColours(height, 0.75, 1.25);
    RenderOptions o = small(View::Front);
    o.groundShadow = false;
    const io::RgbaImage image = draw(scene, o);
    const std::uint8_t* low = image.at(80, 100);
    const std::uint8_t* high = image.at(80, 20);
    EXPECT_GT(low[2], low[0]);   // blue at the bottom
    EXPECT_GT(high[0], high[2]); // red at the top
}

// A closed body's back faces are culled (never shaded): the picture must be the one drawn
// without culling, which the same body with its triangles turned inside out gets (its volume
// is negative, so nothing of it is culled; the shader turns its normals to the viewer). Only
// outline pixels may differ: there the far side's faces, at the near side's depth, can win the
// depth test where nothing is culled (67 of the 19,200 pixels of the top view).
TEST_F(RenderTest, AClosedBodyLooksTheSameWhicheverWayItsTrianglesTurn) {
    Scene outwards;
    DrawMesh body;
    body.kind = MeshKind::Body;
    sim::makeCapsuleMesh(0.15, 0.5, 32, body.positions, body.triangles);
    body.positions.col(1).array() += 1.0;
    body.colour = bodyColour();
    outwards.meshes.push_back(sheet(0.6)); // in front of half of the body, behind the rest
    outwards.meshes.back().positions.col(2).array() += 0.05;
    outwards.meshes.back().positions.col(0).array() += 0.3;
    outwards.meshes.push_back(body);
    Scene inwards = outwards;
    inwards.meshes.back().triangles.col(1).swap(inwards.meshes.back().triangles.col(2));
    for (const View view : {View::Front, View::ThreeQuarter, View::Top}) {
        RenderOptions o = small(view);
        const io::RgbaImage a = draw(outwards, o);
        const io::RgbaImage b = draw(inwards, o);
        long differing = 0;
        for (int y = 0; y < a.height; ++y) {
            for (int x = 0; x < a.width; ++x) {
                differing += samePixel(a.at(x, y), b.at(x, y), 8) ? 0 : 1;
            }
        }
        EXPECT_GT(coverage(a), 0.1) << viewName(view);
        EXPECT_LT(double(differing) / (double(a.width) * a.height), 0.01)
            << viewName(view) << ": " << differing << " pixels differ";
    }
}

// An open body (a scan with holes, a single sheet) is not culled: seen from behind it is there.
TEST_F(RenderTest, AnOpenBodyIsDrawnFromBehind) {
    Scene scene;
    scene.meshes.push_back(sheet());
    scene.meshes.back().kind = MeshKind::Body;
    RenderOptions o = small(View::Back);
    o.groundShadow = false;
    const io::RgbaImage back = draw(scene, o);
    const std::uint8_t white[4] = {255, 255, 255, 255};
    EXPECT_FALSE(samePixel(back.at(80, 60), white, 10));
}

TEST_F(RenderTest, BadArraysAreRefused) {
    Scene scene;
    scene.meshes.push_back(sheet());
    scene.meshes.back().triangles(3, 1) = 1000;
    const auto set = renderer().setScene(scene);
    ASSERT_FALSE(set.ok());
    EXPECT_NE(set.error().message.find("out of range"), std::string::npos);
    scene.meshes.back() = sheet();
    scene.meshes.back().triangleColours.resize(3);
    EXPECT_FALSE(renderer().setScene(scene).ok());
    RenderOptions o = small();
    o.width = 0;
    ASSERT_TRUE(renderer().setScene(skirtOnBody()).ok());
    EXPECT_FALSE(renderer().render(o).ok());
}

TEST_F(RenderTest, SaysWhatDrawsIt) {
    EXPECT_EQ(renderer().description().rfind("OpenGL ", 0), 0u) << renderer().description();
}

} // namespace
} // namespace atelier::render::test
