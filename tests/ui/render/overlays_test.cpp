/// Overlay measures (strain against the rest shape, seam edges, body distances) and what the
/// overlays look like in pictures: the strain colours and legend, seam lines.

#include "ui/render/overlays.h"

#include "render_fixture.h"

#include <gtest/gtest.h>

#include <cmath>

namespace atelier::render::test {
namespace {

/// Rest coordinates of a sheet (its x, y) scaled by `sx`, `sy`.
sim::MatX2 restOf(const DrawMesh& m, double sx = 1, double sy = 1) {
    sim::MatX2 uv(m.positions.rows(), 2);
    uv.col(0) = sx * m.positions.col(0);
    uv.col(1) = sy * m.positions.col(1);
    return uv;
}

TEST(TriangleStrain, ZeroAtRestThePrincipalStretchOtherwise) {
    const DrawMesh m = sheet(0.5, 4);
    const sim::VecX rest = triangleStrain(m.positions, m.triangles, restOf(m));
    EXPECT_LT(rest.cwiseAbs().maxCoeff(), 1e-12);
    // Cut 10% shorter along x than drawn: stretched by 1/0.9 along x.
    const sim::VecX stretched = triangleStrain(m.positions, m.triangles, restOf(m, 0.9, 1));
    for (Eigen::Index t = 0; t < stretched.size(); ++t) {
        EXPECT_NEAR(stretched[t], 1 / 0.9 - 1, 1e-12);
    }
    // Cut 20% longer along y (and 1% shorter along x): compressed wins.
    const sim::VecX squeezed = triangleStrain(m.positions, m.triangles, restOf(m, 0.99, 1.25));
    EXPECT_NEAR(squeezed[0], 1 / 1.25 - 1, 1e-12);
    // A rigid rotation and a mirror of the rest shape (a Back panel) change nothing.
    sim::MatX2 turned = restOf(m);
    turned.col(0) = -restOf(m).col(1);
    turned.col(1) = restOf(m).col(0);
    EXPECT_LT(triangleStrain(m.positions, m.triangles, turned).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT(triangleStrain(m.positions, m.triangles, restOf(m, -1, 1)).cwiseAbs().maxCoeff(),
              1e-12);
    // A rest triangle of no area has no strain.
    sim::MatX2 flat = restOf(m);
    flat.col(1).setZero();
    EXPECT_TRUE(std::isnan(triangleStrain(m.positions, m.triangles, flat)[0]));
}

TEST(StrainColours, WhiteAtZeroRedStretchedBlueCompressed) {
    sim::VecX s(4);
    s << 0, 0.2, -0.2, std::nan("");
    const auto c = strainColours(s, 0.1);
    EXPECT_FLOAT_EQ(c[0].r + c[0].g + c[0].b, 3.0f);
    EXPECT_GT(c[1].r, 0.5f);
    EXPECT_LT(c[1].b, 0.3f);
    EXPECT_GT(c[2].b, 0.5f);
    EXPECT_LT(c[2].r, 0.3f);
    EXPECT_FLOAT_EQ(c[3].r, c[3].b);
}

TEST(SeamEdges, BoundaryEdgesSharedInPositionWithAnotherPanel) {
    // Two panels side by side, each its own vertices: x in [0, 1] and [1, 2], sharing x = 1.
    DrawMesh a = sheet(1.0, 2);
    DrawMesh b = a;
    b.positions.col(0).array() += 1.0;
    sim::MatX3 positions(a.positions.rows() * 2, 3);
    positions << a.positions, b.positions;
    sim::MatX3i triangles(a.triangles.rows() * 2, 3);
    triangles << a.triangles, b.triangles.array() + static_cast<int>(a.positions.rows());
    std::vector<int> panel(static_cast<std::size_t>(triangles.rows()), 0);
    std::fill(panel.begin() + a.triangles.rows(), panel.end(), 1);
    const sim::MatX2i seams = seamEdgesByPosition(positions, triangles, panel, 1e-3);
    ASSERT_EQ(seams.rows(), 4); // two edges on each side of x = 0.5 (the sheet is centred)
    for (Eigen::Index k = 0; k < seams.rows(); ++k) {
        for (int e = 0; e < 2; ++e) {
            EXPECT_NEAR(positions(seams(k, e), 0), 0.5, 1e-12);
        }
    }
    // Apart by more than the tolerance: no seam.
    positions.bottomRows(a.positions.rows()).col(2).array() += 0.01;
    EXPECT_EQ(seamEdgesByPosition(positions, triangles, panel, 1e-3).rows(), 0);
}

TEST(BodyDistances, SignedInsideNegativeFarInfinite) {
    // A unit cube centred at the origin, outward-facing triangles.
    sim::MatX3 v(8, 3);
    v << -0.5, -0.5, -0.5, 0.5, -0.5, -0.5, 0.5, 0.5, -0.5, -0.5, 0.5, -0.5, -0.5, -0.5, 0.5, 0.5,
        -0.5, 0.5, 0.5, 0.5, 0.5, -0.5, 0.5, 0.5;
    sim::MatX3i f(12, 3);
    f << 4, 5, 6, 4, 6, 7, 1, 0, 3, 1, 3, 2, 0, 4, 7, 0, 7, 3, 5, 1, 2, 5, 2, 6, 7, 6, 2, 7, 2, 3,
        0, 1, 5, 0, 5, 4;
    sim::MatX3 p(3, 3);
    p << 0, 0, 0.45, 0, 0, 0.502, 0, 0, 3;
    const sim::VecX d = bodyDistances(p, v, f, 0.5);
    EXPECT_NEAR(d[0], -0.05, 1e-12);
    EXPECT_NEAR(d[1], 0.002, 1e-12);
    EXPECT_TRUE(std::isinf(d[2]) && d[2] > 0);
}

TEST(StrainLegend, ABarOfTheRampWithLabels) {
    io::RgbaImage image(256, 256);
    for (std::uint8_t& b : image.pixels) {
        b = 255;
    }
    drawStrainLegend(image, 0.1);
    int red = 0;
    int blue = 0;
    int ink = 0;
    for (int y = 0; y < 256; ++y) {
        for (int x = 0; x < 256; ++x) {
            const std::uint8_t* p = image.at(x, y);
            red += p[0] > 150 && p[1] < 60 && p[2] < 80 ? 1 : 0;
            blue += p[2] > 150 && p[0] < 90 && p[1] < 110 ? 1 : 0;
            ink += p[0] < 60 && p[1] < 60 && p[2] < 60 ? 1 : 0;
            if (x < 160) {
                ASSERT_EQ(p[0] + p[1] + p[2], 3 * 255) << "the legend keeps to the right edge";
            }
        }
    }
    EXPECT_GT(red, 40);
    EXPECT_GT(blue, 40);
    EXPECT_GT(ink, 60); // "strain" and the five tick labels
}

RenderOptions front() {
    RenderOptions o;
    o.width = 96;
    o.height = 96;
    o.view = View::Front;
    o.groundShadow = false;
    return o;
}

long differingPixels(const io::RgbaImage& a, const io::RgbaImage& b) {
    long n = 0;
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            n += samePixel(a.at(x, y), b.at(x, y), 2) ? 0 : 1;
        }
    }
    return n;
}

TEST_F(RenderTest, StrainColoursChangeAStretchedSheetAndNotOneAtRest) {
    DrawMesh neutral = sheet(0.5, 8);
    neutral.colour = {1, 1, 1, 1};
    Scene scene;
    scene.meshes.push_back(neutral);
    const io::RgbaImage white = draw(scene, front());

    for (const auto& [scale, changes] : {std::pair{1.0, false}, std::pair{0.9, true}}) {
        DrawMesh m = sheet(0.5, 8);
        m.triangleColours =
            strainColours(triangleStrain(m.positions, m.triangles, restOf(m, scale, 1)), 0.1);
        scene.meshes = {m};
        const io::RgbaImage strained = draw(scene, front());
        const long n = differingPixels(white, strained);
        if (changes) {
            EXPECT_GT(n, long(0.2 * coverage(white) * 96 * 96)) << "stretched by 1/" << scale;
        } else {
            EXPECT_EQ(n, 0) << "at rest";
        }
    }
}

TEST_F(RenderTest, SeamLinesAreDrawnOverTheCloth) {
    Scene scene;
    scene.meshes.push_back(sheet(0.5, 8));
    const io::RgbaImage plain = draw(scene, front());
    DrawLines seam;
    seam.positions.resize(2, 3);
    seam.positions << 0, 0.8, 0, 0, 1.2, 0; // down the middle of the sheet, on it
    seam.segments.resize(1, 2);
    seam.segments << 0, 1;
    seam.colour = {0, 0, 0, 1};
    seam.widthPx = 3;
    scene.lines.push_back(seam);
    const io::RgbaImage lined = draw(scene, front());
    int dark = 0;
    for (int y = 0; y < 96; ++y) {
        const std::uint8_t* p = lined.at(48, y);
        dark += p[0] + p[1] + p[2] < 60 ? 1 : 0;
    }
    EXPECT_GT(dark, 20) << "the line is visible down the sheet's middle";
    const long n = differingPixels(plain, lined);
    EXPECT_GT(n, 40);
    EXPECT_LT(n, 96 * 8) << "only the line changed";

    scene.lines.front().segments << 0, 2;
    EXPECT_FALSE(renderer().setScene(scene).ok()) << "index out of range";
}

double meanLuminance(const io::RgbaImage& image, int x0, int y0, int x1, int y1) {
    double sum = 0;
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            const std::uint8_t* p = image.at(x, y);
            sum += 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        }
    }
    return sum / (double(x1 - x0) * double(y1 - y0));
}

TEST_F(RenderTest, AWeaveThroughTheUvsTexturesTheClothAndKeepsItsBrightness) {
    Scene scene;
    scene.meshes.push_back(sheet(0.5, 8));
    const io::RgbaImage plain = draw(scene, front());
    // 20 mm threads on a 0.5 m sheet: visible at 96 pixels (about 3 pixels a thread).
    scene.meshes.front().uvs = restOf(scene.meshes.front());
    scene.meshes.front().weavePeriodMm = 20;
    const io::RgbaImage woven = draw(scene, front());
    EXPECT_GT(differingPixels(plain, woven), 0.3 * coverage(plain) * 96 * 96);
    const double a = meanLuminance(plain, 30, 30, 66, 66);
    const double b = meanLuminance(woven, 30, 30, 66, 66);
    EXPECT_NEAR(b / a, 1.0, 0.06) << "the weave shades, it does not darken the cloth";
    // 0.05 mm threads are far below a pixel: they fade to the plain colour.
    scene.meshes.front().weavePeriodMm = 0.05;
    EXPECT_LT(differingPixels(plain, draw(scene, front())), 96 * 2);

    scene.meshes.front().uvs.resize(0, 2);
    EXPECT_FALSE(renderer().setScene(scene).ok()) << "a weave needs uvs";
}

} // namespace
} // namespace atelier::render::test
