// The parametric mannequin: closed and manifold, about 20k triangles, its tape girths within
// 1 cm of the requested ones (measured here by an independent ray-casting tape), slots in place.
#include "patterns/body_measure.h"
#include "patterns/mannequin.h"

#include "sim/core/parallel.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>

namespace atelier::patterns {
namespace {

using sim::Vec2;
using sim::Vec3;

/// Independent tape: in the plane through `c` with normal `n`, rays from c in 720 directions
/// each hit the first mesh edge of the section; the convex hull of the hits is the tape.
double rayTape(const Mannequin& m, const Vec3& c, const Vec3& normal) {
    const Vec3 n = normal.normalized();
    const Vec3 e1 = n.cross(std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).normalized();
    const Vec3 e2 = n.cross(e1);
    const sim::MatX3& x = m.body.vertices;
    const sim::MatX3i& f = m.body.triangles;
    // Section segments in plane coordinates.
    std::vector<std::pair<Vec2, Vec2>> segments;
    for (Eigen::Index t = 0; t < f.rows(); ++t) {
        std::vector<Vec2> cut;
        for (int e = 0; e < 3; ++e) {
            const Vec3 a = x.row(f(t, e));
            const Vec3 b = x.row(f(t, (e + 1) % 3));
            const double da = (a - c).dot(n);
            const double db = (b - c).dot(n);
            if ((da < 0) != (db < 0)) {
                const Vec3 p = a + da / (da - db) * (b - a);
                cut.emplace_back((p - c).dot(e1), (p - c).dot(e2));
            }
        }
        if (cut.size() == 2) {
            segments.emplace_back(cut[0], cut[1]);
        }
    }
    std::vector<Vec2> hits;
    for (int k = 0; k < 720; ++k) {
        const Vec2 d(std::cos(2 * std::numbers::pi * k / 720),
                     std::sin(2 * std::numbers::pi * k / 720));
        double best = 1e9;
        for (const auto& [a, b] : segments) {
            // Solve a + s (b − a) = t d.
            const Vec2 ab = b - a;
            const double det = d.x() * (-ab.y()) + ab.x() * d.y();
            if (std::abs(det) < 1e-15) {
                continue;
            }
            const double t = (a.x() * (-ab.y()) + ab.x() * a.y()) / det;
            const double s = (d.x() * a.y() - d.y() * a.x()) / det;
            if (s >= 0 && s <= 1 && t > 0) {
                best = std::min(best, t);
            }
        }
        if (best < 1e9) {
            hits.push_back(best * d);
        }
    }
    // Gift wrapping.
    std::size_t start = 0;
    for (std::size_t i = 1; i < hits.size(); ++i) {
        if (hits[i].x() < hits[start].x()) {
            start = i;
        }
    }
    double perimeter = 0;
    std::size_t at = start;
    do {
        std::size_t next = (at + 1) % hits.size();
        for (std::size_t i = 0; i < hits.size(); ++i) {
            const Vec2 u = hits[next] - hits[at];
            const Vec2 v = hits[i] - hits[at];
            if (u.x() * v.y() - u.y() * v.x() < 0) {
                next = i;
            }
        }
        perimeter += (hits[next] - hits[at]).norm();
        at = next;
    } while (at != start && perimeter < 100);
    return perimeter;
}

void expectMannequin(std::string_view base, const BodyMeasurements& want) {
    const Mannequin m = makeMannequin(base, want);
    SCOPED_TRACE(std::string(base));
    const MeshTopology topo = meshTopology(m.body.vertices, m.body.triangles);
    EXPECT_TRUE(topo.watertight())
        << "boundary " << topo.boundaryEdges << " non-manifold edges " << topo.nonManifoldEdges
        << " vertices " << topo.nonManifoldVertices << " misoriented " << topo.misorientedEdges
        << " degenerate " << topo.degenerateTriangles;
    EXPECT_EQ(topo.components, 1);
    EXPECT_EQ(topo.eulerCharacteristic, 2); // a sphere's topology: no handles, no holes
    EXPECT_GT(enclosedVolume(m.body.vertices, m.body.triangles), 0.03); // outward, body-sized
    EXPECT_GT(m.body.triangles.rows(), 14000);
    EXPECT_LT(m.body.triangles.rows(), 28000);

    // Lengths on the mesh.
    EXPECT_NEAR(m.body.vertices.col(1).minCoeff(), 0.0, 0.005); // feet on the floor
    EXPECT_NEAR(m.body.vertices.col(1).maxCoeff(), want.height, 0.01);
    EXPECT_NEAR(m.measured.inseam, want.inseam, 0.01);
    // Girths by the independent tape, at the landmarks.
    const MannequinLandmarks& L = m.landmarks;
    const Vec3 up = Vec3::UnitY();
    EXPECT_NEAR(rayTape(m, Vec3(0, L.bustY, L.torsoZ), up), want.bust, 0.01);
    EXPECT_NEAR(rayTape(m, Vec3(0, L.underBustY, L.torsoZ), up), want.underBust, 0.01);
    EXPECT_NEAR(rayTape(m, Vec3(0, L.waistY, L.torsoZ), up), want.waist, 0.01);
    EXPECT_NEAR(rayTape(m, Vec3(0, L.hipY, L.torsoZ), up), want.hip, 0.01);
    EXPECT_NEAR(rayTape(m, Vec3(0, L.neckY, L.torsoZ), up), want.neck, 0.01);
    EXPECT_NEAR(rayTape(m, L.thighPoint[0], up), want.thigh, 0.01);
    EXPECT_NEAR(rayTape(m, L.thighPoint[1], up), want.thigh, 0.01);
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_NEAR(rayTape(m, L.upperArmPoint[i], L.elbow[i] - L.shoulderJoint[i]), want.upperArm,
                    0.01);
        EXPECT_NEAR((L.wrist[i] - L.shoulderPoint[i]).norm(), want.armLength, 1e-9);
    }
    EXPECT_NEAR((L.shoulderPoint[0] - L.shoulderPoint[1]).norm(), want.shoulderWidth, 1e-9);
    // The shoulder points lie on the surface.
    for (const Vec3& s : L.shoulderPoint) {
        double nearest = 1e9;
        for (Eigen::Index v = 0; v < m.body.vertices.rows(); ++v) {
            nearest = std::min(nearest, (Vec3(m.body.vertices.row(v)) - s).norm());
        }
        EXPECT_LT(nearest, 0.03); // within one mesh edge (cell 27 mm)
    }
    // Left is +x: the body faces +z.
    EXPECT_GT(L.shoulderPoint[0].x(), 0);
    EXPECT_GT(L.wrist[0].x(), L.shoulderPoint[0].x()); // A-pose: arms away from the torso

    // Slots: every standard one, enclosing its part.
    for (const char* name :
         {"torso_front", "torso_back", "torso_left", "torso_right", "waist_front", "waist_back",
          "neck", "arm_left", "arm_right", "leg_left_front", "leg_left_back", "leg_right_front",
          "leg_right_back"}) {
        const ArrangementSlot* s = m.body.slot(name);
        ASSERT_NE(s, nullptr) << name;
        EXPECT_GT(s->radius, 0.03) << name;
        EXPECT_LT(s->radius, 0.45) << name;
        EXPECT_NEAR(s->axis.norm(), 1.0, 1e-12) << name;
        EXPECT_NEAR(s->axis.dot(s->facing), 0.0, 1e-12) << name;
    }
    // Leg slots follow their leg (spread from the hip) and, above the crotch, the pelvis on
    // their side: they enclose that side's vertices, and below the crotch, where the legs
    // stand apart, each stays on its own side of the body's mid-plane, so trouser panels
    // placed on them start round their own leg.
    for (const int sign : {1, -1}) {
        const ArrangementSlot& s = *m.body.slot(sign > 0 ? "leg_left_front" : "leg_right_front");
        const ArrangementSlot& back = *m.body.slot(sign > 0 ? "leg_left_back" : "leg_right_back");
        for (const double along : {-0.4, -0.25, -0.15, 0.05, 0.12}) {
            const Vec3 centre = s.origin + along * s.axis + s.centreAt(along);
            EXPECT_LT((back.centreAt(along) - s.centreAt(along)).norm(), 1e-12);
            int enclosed = 0;
            for (Eigen::Index v = 0; v < m.body.vertices.rows(); ++v) {
                const Vec3 p = m.body.vertices.row(v);
                if (std::abs(p.y() - centre.y()) > 0.004 || sign * p.x() <= 0 ||
                    std::abs(p.x()) > 0.3) { // not the hands, level with the hips
                    continue;
                }
                const Vec3 d = p - centre;
                EXPECT_LE((d - d.dot(s.axis) * s.axis).norm(), s.radiusAt(along) + 1e-9)
                    << s.name << " at " << along;
                ++enclosed;
            }
            EXPECT_GT(enclosed, 10) << s.name << " at " << along;
            if (along <= -0.15) {
                EXPECT_GT(sign * centre.x() - s.radiusAt(along), 0.0) << s.name << " at " << along;
            }
        }
    }
    // The sleeve convention: on the left arm, right() points to the back.
    EXPECT_LT(m.body.slot("arm_left")->right().z(), -0.99);
    EXPECT_GT(m.body.slot("arm_right")->right().z(), 0.99);
    EXPECT_GT(m.body.slot("arm_left")->axis.y(), 0.5); // +axis toward the shoulder
}

TEST(Mannequin, DefaultFemaleIsClosedWithItsMeasurements) {
    BodyMeasurements m;
    ASSERT_TRUE(baseMeasurements("female", m));
    EXPECT_TRUE(checkMeasurements(m).empty());
    expectMannequin("female", m);
}

TEST(Mannequin, TheSameMeshForAnyThreadCount) {
    // The surface is sampled, projected and relaxed in parallel: one thread and two must give
    // the same mesh, bit for bit (a coarse grid and one fitting round keep this quick).
    MannequinOptions coarse;
    coarse.cell = 0.05;
    coarse.fitIterations = 1;
    const int threads = sim::threadCount();
    sim::setThreadCount(1);
    const Mannequin one = makeMannequin("female", BodyMeasurements{}, coarse);
    sim::setThreadCount(2);
    const Mannequin two = makeMannequin("female", BodyMeasurements{}, coarse);
    sim::setThreadCount(threads);
    ASSERT_GT(one.body.triangles.rows(), 1000);
    ASSERT_EQ(two.body.vertices.rows(), one.body.vertices.rows());
    ASSERT_EQ(two.body.triangles.rows(), one.body.triangles.rows());
    EXPECT_TRUE((two.body.vertices.array() == one.body.vertices.array()).all());
    EXPECT_TRUE((two.body.triangles.array() == one.body.triangles.array()).all());
}

TEST(Mannequin, CheckMeasurementsNamesTheField) {
    BodyMeasurements m;
    m.waist = -0.7;
    auto issues = checkMeasurements(m);
    ASSERT_FALSE(issues.empty());
    EXPECT_EQ(issues.front().first, "waist");
    m = BodyMeasurements{};
    m.height = 17.0; // centimetres for decimetres: out of range
    issues = checkMeasurements(m);
    ASSERT_FALSE(issues.empty());
    EXPECT_EQ(issues.front().first, "height");
    m = BodyMeasurements{};
    m.underBust = 1.0; // above the bust
    issues = checkMeasurements(m);
    ASSERT_FALSE(issues.empty());
    EXPECT_EQ(issues.front().first, "under_bust");
    BodyMeasurements unused;
    EXPECT_FALSE(baseMeasurements("child", unused));
}

TEST(Mannequin, SlotsEstimatedForAMeshBodyMatchTheMannequins) {
    const Mannequin m = makeMannequin("female", BodyMeasurements{});
    Body copy;
    copy.vertices = m.body.vertices;
    copy.triangles = m.body.triangles;
    ASSERT_FALSE(estimateSlots(copy).has_value());
    for (const ArrangementSlot& s : m.body.slots) {
        const ArrangementSlot* e = copy.slot(s.name);
        ASSERT_NE(e, nullptr) << s.name;
        EXPECT_LT((e->axis - s.axis).norm(), 0.1) << s.name;
        EXPECT_NEAR(e->radius, s.radius, 0.06) << s.name;
        if (!s.profileCentre.empty()) {
            // Leg slots: the sections' centres, compared at the same heights on the thigh,
            // the knee and the hip.
            ASSERT_FALSE(e->profileCentre.empty()) << s.name;
            for (const double y : {0.35, 0.6, 0.9}) {
                const Vec3 cs =
                    s.origin + (y - s.origin.y()) * s.axis + s.centreAt(y - s.origin.y());
                const Vec3 ce =
                    e->origin + (y - e->origin.y()) * e->axis + e->centreAt(y - e->origin.y());
                EXPECT_LT((ce - cs).norm(), 0.03) << s.name << " at y = " << y;
            }
        }
    }
    Body flat;
    flat.vertices = sim::MatX3::Zero(3, 3);
    flat.triangles = sim::MatX3i::Zero(1, 3);
    EXPECT_TRUE(estimateSlots(flat).has_value());
}

TEST(IsosurfaceMeasure, CubeTopologyVolumeAndTape) {
    // A plane section of a closed mesh, and the convex-hull tape of the loop around a point.
    // Reuse the topology checks on a cube: 12 triangles, watertight, χ = 2.
    sim::MatX3 v(8, 3);
    for (int i = 0; i < 8; ++i) {
        v.row(i) << (i & 1), ((i >> 1) & 1), ((i >> 2) & 1);
    }
    sim::MatX3i f(12, 3);
    f << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6,
        1, 3, 5, 3, 7, 5;
    const MeshTopology topo = meshTopology(v, f);
    EXPECT_TRUE(topo.watertight());
    EXPECT_EQ(topo.eulerCharacteristic, 2);
    EXPECT_NEAR(enclosedVolume(v, f), 1.0, 1e-12);
    const auto tape = tapeGirth(v, f, Vec3(0.5, 0.5, 0.5), Vec3::UnitY());
    ASSERT_TRUE(tape.has_value());
    EXPECT_NEAR(*tape, 4.0, 1e-12);
    EXPECT_FALSE(tapeGirth(v, f, Vec3(3, 0.5, 3), Vec3::UnitY()).has_value());
    // A hole in the mesh is found.
    sim::MatX3i open = f.topRows(11);
    EXPECT_FALSE(meshTopology(v, open).watertight());
}

} // namespace
} // namespace atelier::patterns
