// Landmarks and slots found from a body mesh's shape: plausible heights and girths on the
// MakeHuman body of ../shared/data, the same slots on a turned, rescaled copy of it, and the
// mannequin's slots found again from its mesh alone.
#include "io/mesh_import.h"

#include "patterns/body_landmarks.h"
#include "patterns/mannequin.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <variant>

namespace atelier::patterns {
namespace {

using sim::Vec3;

std::filesystem::path makeHumanPath() {
    return std::filesystem::path(ATELIER_SOURCE_DIR) / ".." / "shared" / "data" / "bodies" /
           "makehuman-base-body.obj";
}

/// The MakeHuman body, imported once for the suite; nullopt when ../shared/data is absent.
const std::optional<io::ImportedBody>& makeHuman() {
    static const std::optional<io::ImportedBody> body = []() -> std::optional<io::ImportedBody> {
        if (!std::filesystem::exists(makeHumanPath())) {
            return std::nullopt;
        }
        auto imported = io::importBody(makeHumanPath());
        if (!imported.ok()) {
            ADD_FAILURE() << imported.error().toString();
            return std::nullopt;
        }
        return imported.value();
    }();
    return body;
}

#define REQUIRE_MAKEHUMAN()                                                                        \
    if (!makeHuman()) {                                                                            \
        GTEST_SKIP() << "test data absent: " << makeHumanPath()                                    \
                     << " (../shared/data beside the checkout)";                                   \
    }

TEST(BodyLandmarks, MakeHumanLandmarksAreWhereABodyHasThem) {
    REQUIRE_MAKEHUMAN();
    auto found = findLandmarks(makeHuman()->vertices, makeHuman()->triangles);
    ASSERT_TRUE(std::holds_alternative<FoundLandmarks>(found)) << std::get<std::string>(found);
    const BodyLandmarks& L = std::get<FoundLandmarks>(found).landmarks;
    const double H = L.height;
    EXPECT_NEAR(H, 1.666, 0.001); // the data's README
    // The file's body faces +z, its left at +x.
    EXPECT_GT(L.facing.z(), 0.99);
    EXPECT_GT(L.left.x(), 0.99);
    // Heights as fractions of the stature, within the ranges of adult proportions
    // (crotch 0.42–0.50, waist 0.57–0.66, armpits 0.70–0.78, shoulders 0.78–0.84,
    // neck 0.82–0.88).
    const auto at = [&](double y) { return (y - L.floorY) / H; };
    EXPECT_GT(at(L.crotchY), 0.42);
    EXPECT_LT(at(L.crotchY), 0.50);
    EXPECT_GT(at(L.hipY), at(L.crotchY));
    EXPECT_LT(at(L.hipY), at(L.waistY));
    EXPECT_GT(at(L.waistY), 0.57);
    EXPECT_LT(at(L.waistY), 0.66);
    EXPECT_GT(at(L.bustY), at(L.waistY));
    for (std::size_t s = 0; s < 2; ++s) {
        EXPECT_GT(at(L.armpitY[s]), 0.70) << s;
        EXPECT_LT(at(L.armpitY[s]), 0.78) << s;
        EXPECT_GT(L.bustY, L.waistY);
        EXPECT_LT(L.bustY, L.armpitY[s]);
        // Each arm on its own side, pointing down and out from the shoulder (A-pose).
        const double sx = s == 0 ? 1.0 : -1.0;
        EXPECT_GT(sx * L.shoulderJoint[s].x(), 0.1) << s;
        EXPECT_GT(L.armAxis[s].y(), 0.5) << s;
        EXPECT_LT(sx * L.armAxis[s].x(), -0.3) << s;
        EXPECT_GT(sx * L.hipJoint[s].x(), 0.03) << s;
        EXPECT_LT(L.ankle[s].y(), L.thighPoint[s].y());
        // Girths: thigh and upper arm of an adult [m].
        EXPECT_GT(L.thigh[s], 0.40) << s;
        EXPECT_LT(L.thigh[s], 0.70) << s;
        EXPECT_GT(L.upperArm[s], 0.20) << s;
        EXPECT_LT(L.upperArm[s], 0.40) << s;
    }
    EXPECT_GT(at(L.shoulderY), 0.78);
    EXPECT_LT(at(L.shoulderY), 0.84);
    EXPECT_GT(at(L.neckY), 0.82);
    EXPECT_LT(at(L.neckY), 0.88);
    EXPECT_LE(L.neckBaseY, L.neckY);
    EXPECT_GE(L.neckBaseY, L.shoulderY);
    EXPECT_LT(L.waist, L.hip);
    EXPECT_LT(L.waist, L.bust);
    EXPECT_GT(L.neck, 0.25);
    EXPECT_LT(L.neck, 0.50);
    // Left and right agree on a symmetric body.
    EXPECT_NEAR(L.armpitY[0], L.armpitY[1], 0.01);
    EXPECT_NEAR(L.thigh[0], L.thigh[1], 0.01);
}

TEST(BodyLandmarks, SlotsAgreeOnATurnedRescaledCopy) {
    REQUIRE_MAKEHUMAN();
    Body original;
    original.vertices = makeHuman()->vertices;
    original.triangles = makeHuman()->triangles;
    ASSERT_FALSE(estimateSlots(original).has_value());

    // Turned 90° about the vertical, moved aside and written in centimetres; imported with the
    // unit given.
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()).toRotationMatrix();
    const Vec3 aside(0.4, 0, -0.7);
    io::RawMesh raw;
    raw.format = "test";
    raw.triangles = original.triangles;
    raw.positions.resize(original.vertices.rows(), 3);
    for (Eigen::Index v = 0; v < raw.positions.rows(); ++v) {
        raw.positions.row(v) = 100.0 * (turn * Vec3(original.vertices.row(v)) + aside).transpose();
    }
    io::BodyImportOptions cm;
    cm.units = io::LengthUnit::Centimetre;
    cm.up = io::UpAxis::Y;
    auto imported = io::normaliseBody(raw, "turned.obj", cm);
    ASSERT_TRUE(imported.ok()) << imported.error().toString();
    Body copy;
    copy.vertices = imported.value().vertices;
    copy.triangles = imported.value().triangles;
    ASSERT_FALSE(estimateSlots(copy).has_value());
    // The import keeps x and z, and moves the floor to y = 0 (as the original's).
    ASSERT_EQ(copy.slots.size(), original.slots.size());
    for (const ArrangementSlot& s : original.slots) {
        const ArrangementSlot* c = copy.slot(s.name);
        ASSERT_NE(c, nullptr) << s.name;
        EXPECT_LT((c->origin - (turn * s.origin + aside)).norm(), 0.003) << s.name;
        EXPECT_LT(std::acos(std::min(1.0, c->axis.dot(turn * s.axis))), 0.02) << s.name;
        EXPECT_LT(std::acos(std::min(1.0, c->facing.dot(turn * s.facing))), 0.02) << s.name;
        EXPECT_NEAR(c->radius, s.radius, 0.003) << s.name;
        EXPECT_NEAR(c->alongMin, s.alongMin, 0.003) << s.name;
        EXPECT_NEAR(c->alongMax, s.alongMax, 0.003) << s.name;
        ASSERT_EQ(c->profileCentre.size(), s.profileCentre.size()) << s.name;
        for (std::size_t k = 0; k < s.profileCentre.size(); ++k) {
            EXPECT_LT((c->profileCentre[k] - turn * s.profileCentre[k]).norm(), 0.003) << s.name;
        }
    }
}

TEST(BodyLandmarks, ALegsOnlyMeshSaysWhatIsMissing) {
    REQUIRE_MAKEHUMAN();
    // Only the triangles below 0.9 m: no pelvis, no torso, no arms.
    const sim::MatX3& v = makeHuman()->vertices;
    const sim::MatX3i& f = makeHuman()->triangles;
    std::vector<int> keep;
    for (Eigen::Index t = 0; t < f.rows(); ++t) {
        if (v(f(t, 0), 1) < 0.9 && v(f(t, 1), 1) < 0.9 && v(f(t, 2), 1) < 0.9) {
            keep.push_back(static_cast<int>(t));
        }
    }
    sim::MatX3i legs(static_cast<Eigen::Index>(keep.size()), 3);
    for (std::size_t i = 0; i < keep.size(); ++i) {
        legs.row(static_cast<Eigen::Index>(i)) = f.row(keep[i]);
    }
    auto found = findLandmarks(v, legs);
    ASSERT_TRUE(std::holds_alternative<std::string>(found));
    EXPECT_NE(std::get<std::string>(found).find("expected a standing figure"), std::string::npos)
        << std::get<std::string>(found);
}

} // namespace
} // namespace atelier::patterns
