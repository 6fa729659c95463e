#include "ui/render/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace atelier::render {

namespace {

struct ViewInfo {
    View view;
    std::string_view name;
    Eigen::Vector3d toCamera; ///< from the content's centre towards the camera (any length)
    Eigen::Vector3d up;       ///< the picture's up direction, world
};

/// Three-quarter: 35° round from the front towards the body's left, 15° above.
const ViewInfo& info(View view) {
    static const std::array<ViewInfo, 6> INFOS = {{
        {View::Front, "front", {0, 0, 1}, {0, 1, 0}},
        {View::Back, "back", {0, 0, -1}, {0, 1, 0}},
        {View::Left, "left", {1, 0, 0}, {0, 1, 0}},
        {View::Right, "right", {-1, 0, 0}, {0, 1, 0}},
        {View::ThreeQuarter,
         "three-quarter",
         {std::sin(35 * std::numbers::pi / 180) * std::cos(15 * std::numbers::pi / 180),
          std::sin(15 * std::numbers::pi / 180),
          std::cos(35 * std::numbers::pi / 180) * std::cos(15 * std::numbers::pi / 180)},
         {0, 1, 0}},
        {View::Top, "top", {0, 1, 0}, {0, 0, -1}},
    }};
    return INFOS[static_cast<std::size_t>(view)];
}

} // namespace

std::string_view viewName(View view) {
    return info(view).name;
}

std::optional<View> viewFromName(std::string_view name) {
    for (const View v : ALL_VIEWS) {
        if (info(v).name == name) {
            return v;
        }
    }
    return std::nullopt;
}

Camera frameView(View view, const Eigen::AlignedBox3d& bounds, double aspect,
                 const FramingOptions& options) {
    Eigen::AlignedBox3d box = bounds;
    if (box.isEmpty()) {
        box = Eigen::AlignedBox3d(Eigen::Vector3d::Constant(-0.5), Eigen::Vector3d::Constant(0.5));
    }
    const ViewInfo& v = info(view);
    const Eigen::Vector3d back = v.toCamera.normalized(); // the camera looks along −back
    const Eigen::Vector3d right = v.up.cross(back).normalized();
    const Eigen::Vector3d up = back.cross(right);
    const Eigen::Vector3d centre = box.center();

    // The camera sits at centre + d·back. A corner at (x, y, z) in (right, up, back) is in the
    // picture when |x| ≤ (d − z)·tanX and |y| ≤ (d − z)·tanY: d is the largest bound.
    const double tanY = std::tan(options.fovYDeg * std::numbers::pi / 360) * options.fill;
    const double tanX = tanY * aspect;
    const double size = std::max(box.sizes().norm(), 1e-6);
    double distance = 0;
    double zMin = 0;
    double zMax = 0;
    for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d p =
            box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k)) - centre;
        const double x = p.dot(right);
        const double y = p.dot(up);
        const double z = p.dot(back);
        distance = std::max({distance, z + std::abs(x) / tanX, z + std::abs(y) / tanY});
        zMin = std::min(zMin, z);
        zMax = std::max(zMax, z);
    }
    distance = std::max(distance, zMax + 0.01 * size);

    Camera camera;
    const Eigen::Vector3d eye = centre + distance * back;
    camera.eye = eye.cast<float>();
    Eigen::Matrix4d view4 = Eigen::Matrix4d::Identity();
    view4.block<1, 3>(0, 0) = right.transpose();
    view4.block<1, 3>(1, 0) = up.transpose();
    view4.block<1, 3>(2, 0) = back.transpose();
    view4.block<3, 1>(0, 3) = -view4.block<3, 3>(0, 0) * eye;
    camera.view = view4.cast<float>();

    // Near and far planes around the box (and the floor shadow just below it), with margins.
    const double nearPlane = std::max(distance - zMax - 0.05 * size, 1e-3 * size);
    const double farPlane = distance - zMin + 0.5 * size;
    const double f = 1.0 / std::tan(options.fovYDeg * std::numbers::pi / 360);
    Eigen::Matrix4d projection = Eigen::Matrix4d::Zero();
    projection(0, 0) = f / aspect;
    projection(1, 1) = f;
    projection(2, 2) = (farPlane + nearPlane) / (nearPlane - farPlane);
    projection(2, 3) = 2 * farPlane * nearPlane / (nearPlane - farPlane);
    projection(3, 2) = -1;
    camera.projection = projection.cast<float>();
    return camera;
}

} // namespace atelier::render
