#pragma once
/// Pin markers: a pinhead (a red disc ringed in white and outlined in dark grey) on a short
/// needle, drawn into a finished picture at the projection of each pinned point. Drawn over
/// everything, so a pin behind the cloth or the body still shows; sized in pixels from the
/// picture's height, so it reads the same in a thumbnail and a poster.

#include "ui/render/camera.h"
#include "ui/render/scene.h"

#include "io/png.h"

#include "sim/core/types.h"

#include <Eigen/Core>

#include <optional>

namespace atelier::render {

/// The pinhead's colour (sRGB): a saturated red, unlike the soft panel palette.
inline constexpr Colour PIN_HEAD_COLOUR{0.86f, 0.10f, 0.14f, 1.0f};

/// The pinhead's radius in a picture `heightPx` tall [pixels]: 4 up to 400 pixels, then 1% of
/// the height (10 at 1024).
float pinRadiusPx(int heightPx);

/// Where the world point `world` [m] lands in a picture of `width`×`height` pixels taken with
/// `camera`: (x right, y down, pixel centres at +0.5); nullopt when it is behind the camera.
std::optional<Eigen::Vector2f> projectToPixel(const Camera& camera, const Eigen::Vector3d& world,
                                              int width, int height);

/// Draws a marker for each row of `pins` (|P|×3) [m] into `image` (taken with `camera`): the
/// head centred on the point's projection, of radius `radiusPx` (≤ 0: pinRadiusPx), the
/// needle leaning down to the right from it. Edges are anti-aliased; drawn pixels become
/// opaque.
void drawPinMarkers(io::RgbaImage& image, const Camera& camera, const sim::MatX3& pins,
                    float radiusPx = 0);

} // namespace atelier::render
