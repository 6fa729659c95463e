#pragma once
/// The renderer tests' shared pieces: one headless context and renderer per suite (each test
/// skips, saying why, when this machine cannot make an EGL context), small procedural scenes,
/// and pixel measures.

#include "ui/render/headless_context.h"
#include "ui/render/renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>

namespace atelier::render::test {

class RenderTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() {
        auto context = HeadlessContext::create();
        if (!context.ok()) {
            s_skipReason = "no headless OpenGL context: " + context.error().toString();
            return;
        }
        s_context = std::move(context).value();
        auto renderer = Renderer::create();
        if (!renderer.ok()) {
            s_skipReason = renderer.error().toString();
            return;
        }
        s_renderer = std::move(renderer).value();
    }
    static void TearDownTestSuite() {
        s_renderer.reset(); // before its context
        s_context.reset();
    }
    void SetUp() override {
        if (!s_renderer) {
            GTEST_SKIP() << s_skipReason;
        }
    }
    Renderer& renderer() { return *s_renderer; }

    /// Draws `scene` with `options`; fails the test on an error.
    io::RgbaImage draw(const Scene& scene, const RenderOptions& options) {
        const auto set = s_renderer->setScene(scene);
        EXPECT_TRUE(set.ok()) << set.error().toString();
        auto image = s_renderer->render(options);
        EXPECT_TRUE(image.ok()) << image.error().toString();
        return image.ok() ? std::move(image).value() : io::RgbaImage();
    }

    static inline std::unique_ptr<HeadlessContext> s_context;
    static inline std::unique_ptr<Renderer> s_renderer;
    static inline std::string s_skipReason;
};

/// A square sheet of side `side` [m] centred at (0, 1, 0) in the z = 0 plane, its front
/// (counter-clockwise) facing +z, `n`×`n` cells.
inline DrawMesh sheet(double side = 0.5, int n = 8) {
    DrawMesh m;
    m.positions.resize((n + 1) * (n + 1), 3);
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            m.positions.row(j * (n + 1) + i) << side * (double(i) / n - 0.5),
                1 + side * (double(j) / n - 0.5), 0;
        }
    }
    m.triangles.resize(2 * n * n, 3);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i;
            m.triangles.row(2 * (j * n + i)) << a, a + 1, a + n + 2;
            m.triangles.row(2 * (j * n + i) + 1) << a, a + n + 2, a + n + 1;
        }
    }
    m.colour = panelColour(1);
    return m;
}

/// A surface of revolution about the y axis, radius r(y) from y0 to y1, outward facing,
/// `panels` panels (each its own colour, as groups of a draped OBJ would be).
template <class Radius>
DrawMesh revolution(double y0, double y1, Radius radius, int segments, int rings, int panels,
                    MeshKind kind = MeshKind::Garment) {
    DrawMesh m;
    m.kind = kind;
    m.positions.resize((rings + 1) * segments, 3);
    for (int j = 0; j <= rings; ++j) {
        const double y = y0 + (y1 - y0) * j / rings;
        for (int i = 0; i < segments; ++i) {
            const double a = 2 * std::numbers::pi * i / segments;
            m.positions.row(j * segments + i) << radius(y) * std::sin(a), y,
                radius(y) * std::cos(a);
        }
    }
    m.triangles.resize(2 * rings * segments, 3);
    for (int j = 0; j < rings; ++j) {
        for (int i = 0; i < segments; ++i) {
            const int a = j * segments + i;
            const int b = j * segments + (i + 1) % segments;
            m.triangles.row(2 * (j * segments + i)) << a, b, b + segments;
            m.triangles.row(2 * (j * segments + i) + 1) << a, b + segments, a + segments;
            for (int k = 0; k < 2; ++k) {
                m.triangleColours.push_back(
                    kind == MeshKind::Body ? bodyColour() : panelColour(i * panels / segments));
            }
        }
    }
    return m;
}

/// A skirt (four panels, open at both ends) on a body-like ellipsoid: the sample garment of
/// the renderer's tests.
inline Scene skirtOnBody() {
    Scene scene;
    scene.meshes.push_back(revolution(
        0.55, 1.0, [](double y) { return 0.14 + 0.18 * (1.0 - y) / 0.45; }, 48, 12, 4));
    scene.meshes.push_back(revolution(
        0.25, 1.55,
        [](double y) {
            const double t = (y - 0.9) / 0.65;
            return 0.16 * std::sqrt(std::max(1 - t * t, 0.0)) + 1e-3;
        },
        40, 24, 1, MeshKind::Body));
    return scene;
}

inline bool samePixel(const std::uint8_t* p, const std::uint8_t* q, int tolerance = 1) {
    for (int k = 0; k < 4; ++k) {
        if (std::abs(int(p[k]) - int(q[k])) > tolerance) {
            return false;
        }
    }
    return true;
}

/// Share of pixels that differ from the top-left corner's colour.
inline double coverage(const io::RgbaImage& image) {
    long covered = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            covered += samePixel(image.at(x, y), image.at(0, 0)) ? 0 : 1;
        }
    }
    return double(covered) / (double(image.width) * image.height);
}

} // namespace atelier::render::test
