#include "ui/render/pin_markers.h"

#include <algorithm>
#include <cmath>

namespace atelier::render {

namespace {

/// Blends `colour` over pixel (x, y) with coverage `cover` ∈ [0, 1] (straight sRGB).
void blend(io::RgbaImage& image, int x, int y, const Colour& colour, float cover) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height || !(cover > 0)) {
        return;
    }
    cover = std::min(cover, 1.0f);
    std::uint8_t* p = image.at(x, y);
    const float rgb[3] = {colour.r, colour.g, colour.b};
    for (int k = 0; k < 3; ++k) {
        const float v = rgb[k] * 255.0f * cover + static_cast<float>(p[k]) * (1.0f - cover);
        p[k] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
    p[3] = static_cast<std::uint8_t>(
        std::max<long>(p[3], std::lround(255.0f * cover))); // markers are opaque
}

/// A filled disc of radius r around c, its edge anti-aliased over one pixel.
void disc(io::RgbaImage& image, const Eigen::Vector2f& c, float r, const Colour& colour) {
    const int x0 = static_cast<int>(std::floor(c.x() - r - 1));
    const int x1 = static_cast<int>(std::ceil(c.x() + r + 1));
    const int y0 = static_cast<int>(std::floor(c.y() - r - 1));
    const int y1 = static_cast<int>(std::ceil(c.y() + r + 1));
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            const float d =
                (Eigen::Vector2f(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f) - c)
                    .norm();
            blend(image, x, y, colour, r + 0.5f - d);
        }
    }
}

/// A segment from a to b, `width` pixels wide, anti-aliased.
void segment(io::RgbaImage& image, const Eigen::Vector2f& a, const Eigen::Vector2f& b, float width,
             const Colour& colour) {
    const Eigen::Vector2f d = b - a;
    const float length2 = std::max(d.squaredNorm(), 1e-12f);
    const float half = 0.5f * width;
    const int x0 = static_cast<int>(std::floor(std::min(a.x(), b.x()) - half - 1));
    const int x1 = static_cast<int>(std::ceil(std::max(a.x(), b.x()) + half + 1));
    const int y0 = static_cast<int>(std::floor(std::min(a.y(), b.y()) - half - 1));
    const int y1 = static_cast<int>(std::ceil(std::max(a.y(), b.y()) + half + 1));
    for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
            const Eigen::Vector2f p(static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f);
            const float t = std::clamp((p - a).dot(d) / length2, 0.0f, 1.0f);
            blend(image, x, y, colour, half + 0.5f - (a + t * d - p).norm());
        }
    }
}

} // namespace

float pinRadiusPx(int heightPx) {
    return std::max(4.0f, 0.01f * static_cast<float>(heightPx));
}

std::optional<Eigen::Vector2f> projectToPixel(const Camera& camera, const Eigen::Vector3d& world,
                                              int width, int height) {
    const Eigen::Vector4f clip =
        camera.projection * camera.view * Eigen::Vector4f(world.cast<float>().homogeneous());
    if (!(clip.w() > 1e-6f)) {
        return std::nullopt;
    }
    const float x = clip.x() / clip.w();
    const float y = clip.y() / clip.w();
    return Eigen::Vector2f(0.5f * (x + 1.0f) * static_cast<float>(width),
                           0.5f * (1.0f - y) * static_cast<float>(height));
}

void drawPinMarkers(io::RgbaImage& image, const Camera& camera, const sim::MatX3& pins,
                    float radiusPx) {
    const float r = radiusPx > 0 ? radiusPx : pinRadiusPx(image.height);
    const Colour needle{0.30f, 0.30f, 0.32f, 1.0f};
    const Colour outline{0.15f, 0.05f, 0.05f, 1.0f};
    const Colour ring{1.0f, 1.0f, 1.0f, 1.0f};
    const Colour shine{1.0f, 0.72f, 0.72f, 1.0f};
    for (Eigen::Index i = 0; i < pins.rows(); ++i) {
        if (!pins.row(i).allFinite()) {
            continue;
        }
        const auto c = projectToPixel(camera, pins.row(i).transpose(), image.width, image.height);
        if (!c) {
            continue;
        }
        const Eigen::Vector2f tip = *c + 2.4f * r * Eigen::Vector2f(0.6f, 0.8f);
        segment(image, *c, tip, std::max(1.5f, 0.3f * r), needle);
        disc(image, *c, r + 1.0f, outline);
        disc(image, *c, r, ring);
        disc(image, *c, std::max(1.0f, r - 1.5f), PIN_HEAD_COLOUR);
        disc(image, *c - Eigen::Vector2f(0.45f, 0.45f) * r, 0.2f * r, shine);
    }
}

} // namespace atelier::render
