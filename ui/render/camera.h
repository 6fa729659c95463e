#pragma once
/// Named views and the camera that frames a scene's bounding box in them.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <optional>
#include <string_view>

namespace atelier::render {

/// A named view of the content. The body faces +z with y up: `front` looks at its front from
/// +z, `left` at its left side (from +x), `three-quarter` from the front-left and a little
/// above, `top` from above with the front at the bottom of the picture.
enum class View { Front, Back, Left, Right, ThreeQuarter, Top };

inline constexpr std::array<View, 6> ALL_VIEWS = {View::Front, View::Back,         View::Left,
                                                  View::Right, View::ThreeQuarter, View::Top};

/// "front", "back", "left", "right", "three-quarter", "top".
std::string_view viewName(View view);
/// The view of a name viewName gives, or nullopt.
std::optional<View> viewFromName(std::string_view name);

/// A perspective camera: world → view space (the camera looks down −z, y up) and view space →
/// clip space (OpenGL conventions).
struct Camera {
    Eigen::Matrix4f view = Eigen::Matrix4f::Identity();
    Eigen::Matrix4f projection = Eigen::Matrix4f::Identity();
    Eigen::Vector3f eye = Eigen::Vector3f::Zero(); ///< camera position, world [m]
};

/// Options of frameView.
struct FramingOptions {
    double fovYDeg = 30.0; ///< vertical field of view [deg]
    /// Share of the picture's half-width and half-height the content's box may fill at most.
    double fill = 0.9;
};

/// The camera of `view` looking at the centre of `bounds`, as close as it can be with every
/// corner of the box inside the picture (of width/height `aspect`). An empty box frames a
/// unit box at the origin.
Camera frameView(View view, const Eigen::AlignedBox3d& bounds, double aspect,
                 const FramingOptions& options = {});

} // namespace atelier::render
