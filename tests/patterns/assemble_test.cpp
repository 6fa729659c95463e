// Assembly and sewing of a minimal garment: a band of two rectangular panels sewn at both sides
// around a capsule "body" (gravity held off, as in the sewing phase of a drape). Hand-built meshes
// keep this independent of the mesher: what is tested is placement, sewing (imposed seams that
// weld), the body obstacle and the figures.

#include "patterns/assemble.h"
#include "patterns/sewing.h"

#include "sim/collision/obstacle.h"
#include "sim/mesh/cloth_mesh.h"
#include "sim/simulation.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace atelier::patterns {
namespace {

/// A w × h rectangle panel mesh of cx × cy cells; vertex (i, j) has index j·(cx+1) + i.
PanelMesh rectanglePanel(double w, double h, int cx, int cy) {
    PanelMesh m;
    sim::RectangleOptions r;
    r.width = w;
    r.height = h;
    r.cellsX = cx;
    r.cellsY = cy;
    sim::makeRectangle(r, m.pattern, m.triangles);
    m.rest = m.pattern;
    return m;
}

struct Tube {
    Garment garment;
    GarmentMesh mesh;
    Body body;
};

/// Front and back panels 0.34 × 0.1 m around a capsule of radius 0.1 (0.63 m around; the band
/// is 0.68 m), sewn at both sides.
Tube tube(int cx, int cy) {
    Tube t;
    const double w = 0.34, h = 0.1;
    for (const char* name : {"front", "back"}) {
        Panel p;
        p.name = name;
        p.material = "cotton";
        p.placement.slot = name == std::string("front") ? "front" : "back";
        p.placement.clearance = 0.02;
        t.garment.panels.push_back(p);
        t.mesh.panels.push_back(rectanglePanel(w, h, cx, cy));
    }
    GarmentMaterial m;
    m.name = "cotton";
    m.material.density = 0.15;
    t.garment.materials.push_back(m);
    // Front's right edge (i = cx) meets back's left edge (i = 0) and vice versa.
    for (const char* name : {"right", "left"}) {
        Seam s;
        s.name = name;
        t.garment.seams.push_back(s);
    }
    for (int j = 0; j <= cy; ++j) {
        t.mesh.seamPairs.push_back({VertexRef{0, j * (cx + 1) + cx}, VertexRef{1, j * (cx + 1)}});
        t.mesh.seamOfPair.push_back(0);
        t.mesh.seamPairs.push_back({VertexRef{0, j * (cx + 1)}, VertexRef{1, j * (cx + 1) + cx}});
        t.mesh.seamOfPair.push_back(1);
    }
    t.mesh.triangleCount = 2L * cx * cy * 2;
    sim::makeCapsuleMesh(0.1, 0.4, 32, t.body.vertices, t.body.triangles);
    for (const auto& [name, facing] :
         {std::pair{"front", sim::Vec3(0, 0, 1)}, std::pair{"back", sim::Vec3(0, 0, -1)}}) {
        ArrangementSlot s;
        s.name = name;
        s.origin = sim::Vec3(0, 0.05, 0);
        s.axis = sim::Vec3::UnitY();
        s.facing = facing;
        s.radius = 0.1;
        t.body.slots.push_back(s);
    }
    return t;
}

TEST(Assemble, OneClothPerPanelSeamsAndTheBody) {
    const Tube t = tube(6, 4);
    AssembledGarment a;
    DrapeSettings settings;
    ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, settings, a).has_value());
    ASSERT_EQ(a.scene.cloths.size(), 2u);
    EXPECT_EQ(a.panelOffsets, (std::vector<int>{0, 35, 70}));
    EXPECT_EQ(a.scene.seams.size(), 10u);
    // Implicit Euler (the default): seams as elastics inside the solve.
    EXPECT_EQ(a.scene.seamMode, sim::SeamMode::Elastic);
    ASSERT_EQ(a.scene.obstacles.size(), 1u);
    EXPECT_TRUE(a.scene.obstacles[0].closed);
    // Placed at radius + clearance: outside the body, the front panel in front.
    sim::Simulation simulation(a.scene);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    EXPECT_EQ(simulation.penetration(), 0.0);
    EXPECT_GT(a.scene.cloths[0].position.col(2).minCoeff(), 0.0);
    EXPECT_LT(a.scene.cloths[1].position.col(2).maxCoeff(), 0.0);
}

TEST(Assemble, MissingSlotOrMaterialIsNamed) {
    Tube t = tube(2, 2);
    t.garment.panels[1].placement.slot = "sleeve";
    AssembledGarment a;
    auto err = assembleGarment(t.garment, t.mesh, t.body, {}, a);
    ASSERT_TRUE(err.has_value());
    EXPECT_NE(err->find("panel \"back\": the body has no slot \"sleeve\""), std::string::npos)
        << *err;
    t = tube(2, 2);
    t.garment.panels[0].material = "silk";
    err = assembleGarment(t.garment, t.mesh, t.body, {}, a);
    ASSERT_TRUE(err.has_value());
    EXPECT_NE(err->find("no material \"silk\""), std::string::npos) << *err;
}

/// The tube with a third panel, "patch" (0.16 × 0.1 m), on a slot of the body whose axis is
/// `axis` (through the front slot's origin, facing front), at the front panel's clearance.
Tube tubeWithPatch(const sim::Vec3& axis) {
    Tube t = tube(24, 6);
    Panel patch = t.garment.panels[0];
    patch.name = "patch";
    patch.placement.slot = "patch";
    t.garment.panels.push_back(patch);
    t.mesh.panels.push_back(rectanglePanel(0.16, 0.1, 12, 7));
    ArrangementSlot s = t.body.slots[0];
    s.name = "patch";
    s.axis = axis.normalized();
    t.body.slots.push_back(s);
    return t;
}

/// The crossings a simulation of `a` starts with.
std::vector<PanelCrossing> crossingsAtStart(const AssembledGarment& a) {
    const sim::Simulation simulation(a.scene);
    return startCrossings(a, simulation.positions());
}

// A panel placed through another is lifted off its slot until the two clear each other: a patch
// on a slot tilted 25° from the front panel's crosses it (both at 20 mm from the body); lifted
// by a few 5 mm steps it lies outside the front panel everywhere.
TEST(Assemble, APanelPlacedThroughAnotherIsLiftedUntilItClears) {
    const double tilt = 25 * std::numbers::pi / 180;
    const Tube t = tubeWithPatch(sim::Vec3(std::sin(tilt), std::cos(tilt), 0));
    AssembledGarment a;
    ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, {}, a).has_value());
    const std::vector<PanelCrossing> placed = crossingsAtStart(a);
    ASSERT_EQ(placed.size(), 1u);
    EXPECT_EQ(placed[0].a, 0);
    EXPECT_EQ(placed[0].b, 2);
    EXPECT_GT(placed[0].pairs, 0);
    std::vector<PlacementLift> lifted;
    const std::vector<SlotShift> shifts =
        liftCrossedPanels(t.garment, t.mesh, t.body, a, placed, lifted);
    ASSERT_EQ(shifts.size(), 3u);
    ASSERT_EQ(lifted.size(), 1u);
    EXPECT_EQ(lifted[0].crossed,
              std::vector<std::string>{lifted[0].panel == "patch" ? "front" : "patch"});
    EXPECT_EQ(shifts[1], SlotShift{}); // the back panel crossed nothing
    EXPECT_GT(lifted[0].lift, 0.0);
    EXPECT_LE(lifted[0].lift, 0.03 + 1e-12);
    ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, {}, a, shifts).has_value());
    EXPECT_TRUE(crossingsAtStart(a).empty());
    const sim::Simulation simulation(a.scene);
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
}

TEST(Drape, BandSewsShutAroundTheBody) {
    const Tube t = tube(24, 6);
    AssembledGarment a;
    DrapeSettings settings;
    settings.timeLimit = 0.5;
    settings.sewingTime = settings.timeLimit; // no gravity: the band would slide off
    ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, settings, a).has_value());
    sim::Simulation simulation(a.scene);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    Sewing sewing;
    sewing.begin(simulation, settings, 0.0, false);
    double sewnAt = -1;
    while (simulation.time() < settings.timeLimit - 1e-12) {
        sewing.beforeStep(simulation);
        ASSERT_EQ(simulation.step(settings.timeLimit), sim::RunStatus::Finished)
            << simulation.stats().error;
        if (sewing.afterStep(simulation) == Sewing::End::Sewn) {
            sewnAt = simulation.time();
            EXPECT_FALSE(sewing.holdsGravity());
        }
    }
    EXPECT_EQ(seamGapMax(a, simulation.positions()), 0.0);
    EXPECT_EQ(simulation.stats().weldedSeamPairs, static_cast<long>(a.scene.seams.size()));
    // Sewing ended when the last pair closed, not at its set end (gravity started then).
    EXPECT_GT(sewnAt, 0.0);
    EXPECT_LT(sewnAt, settings.sewingTime);
    for (const sim::SeamPair& p : a.scene.seams) {
        EXPECT_GT(p.length, 0.0); // the length of seam each pair stands for, for its pull
    }
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    EXPECT_LT(simulation.stats().maxPenetration, 0.001);
    // Closed into a ring of 0.68 m around: radius 0.108 about the capsule's axis.
    const sim::MatX3& x = simulation.positions();
    for (int i = 0; i < x.rows(); ++i) {
        const double r = std::hypot(x(i, 0), x(i, 2));
        EXPECT_GT(r, 0.1 + 0.002) << "vertex " << i;
        EXPECT_LT(r, 0.125) << "vertex " << i;
    }
    const double ratio = areaRatio(a.scene, simulation.positions());
    EXPECT_GT(ratio, 0.95);
    EXPECT_LT(ratio, 1.05);
}

/// The band of tube(24, 6) sewn shut around the body (as BandSewsShutAroundTheBody), with or
/// without hinges across its welded seams: its fold figures 0.2 s after the last pair welds.
FoldFigures sewnBandFolds(bool seamBending) {
    const Tube t = tube(24, 6);
    AssembledGarment a;
    DrapeSettings settings;
    settings.timeLimit = 0.5;
    settings.sewingTime = settings.timeLimit;
    settings.seamBending = seamBending;
    EXPECT_FALSE(assembleGarment(t.garment, t.mesh, t.body, settings, a).has_value());
    sim::Simulation simulation(a.scene);
    Sewing sewing;
    sewing.begin(simulation, settings, 0.0, false);
    double end = settings.timeLimit;
    while (simulation.time() < end - 1e-12) {
        sewing.beforeStep(simulation);
        EXPECT_EQ(simulation.step(end), sim::RunStatus::Finished);
        if (sewing.afterStep(simulation) == Sewing::End::Sewn) {
            end = std::min(end, simulation.time() + 0.2);
        }
    }
    EXPECT_EQ(seamGapMax(a, simulation.positions()), 0.0);
    return foldFigures(a, simulation.positions());
}

TEST(Drape, ASewnBandIsAsRoundAcrossItsSeamsAsBetween) {
    // 48 columns around a ring: about 7.5° between neighbouring columns. With hinges across
    // the welded seams the ring stays round there too (measured: seam folds 6.3° median, 9.6°
    // at most); without them each side seam is a free hinge, and the band folds there (19.0°).
    const FoldFigures bending = sewnBandFolds(true);
    const FoldFigures free = sewnBandFolds(false);
    EXPECT_EQ(bending.seamEdges, 12); // two seams of 6 edges
    EXPECT_EQ(free.seamEdges, 12);
    const double deg = std::numbers::pi / 180;
    EXPECT_LT(bending.seamMax, 12 * deg);
    EXPECT_GT(free.seamMedian, 2 * bending.seamMedian);
    EXPECT_LT(bending.clothMedian, 10 * deg);
}

TEST(Drape, ForcedWeldsNameTheSeamsWidestFirst) {
    // Sewing stops before the band can close: every pair is welded by force, and the report
    // names both seams with their widest gap as the engine measured it.
    const Tube t = tube(24, 6);
    AssembledGarment a;
    DrapeSettings settings;
    settings.timeLimit = 0.02;
    settings.sewingTime = 0.01;
    settings.seamStiffness = 0; // the slow mass-proportional pull: nothing closes in 0.01 s
    ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, settings, a).has_value());
    ASSERT_EQ(a.pairSeam.size(), a.scene.seams.size());
    const sim::MatX3 start = [&] {
        sim::Simulation s(a.scene);
        return s.positions();
    }();
    sim::Simulation simulation(a.scene);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    Sewing sewing;
    sewing.begin(simulation, settings, 0.0, false);
    double endedAt = -1;
    while (simulation.time() < settings.timeLimit - 1e-12) {
        EXPECT_EQ(sewing.holdsGravity(), endedAt < 0);
        sewing.beforeStep(simulation);
        ASSERT_EQ(simulation.step(settings.timeLimit), sim::RunStatus::Finished);
        if (sewing.afterStep(simulation) == Sewing::End::Timeup) {
            endedAt = simulation.time();
        }
    }
    EXPECT_NEAR(endedAt, settings.sewingTime, 1e-12); // steps stopped at the deadline
    const std::vector<double>& gaps = simulation.stats().forcedWeldGaps;
    ASSERT_EQ(gaps.size(), a.scene.seams.size());
    double widest[2] = {0, 0};
    for (std::size_t k = 0; k < gaps.size(); ++k) {
        // 0.01 s of sewing closes little of gaps that start centimetres wide.
        const sim::SeamPair& p = a.scene.seams[k];
        const double startGap = (start.row(p.a) - start.row(p.b)).norm();
        EXPECT_GT(gaps[k], 0.5 * startGap) << "pair " << k;
        widest[a.pairSeam[k]] = std::max(widest[a.pairSeam[k]], gaps[k]);
    }
    const std::vector<ForcedWeld> forced = forcedWelds(t.garment, a, gaps);
    ASSERT_EQ(forced.size(), 2u);
    EXPECT_GE(forced[0].widest, forced[1].widest);
    for (const ForcedWeld& w : forced) {
        EXPECT_EQ(w.pairs, 7);
        EXPECT_EQ(w.widest, widest[w.seam == "right" ? 0 : 1]) << w.seam;
    }
    EXPECT_EQ(simulation.stats().largestForcedWeld, forced[0].widest);
}

TEST(Drape, ForcedWeldsOfDartsNameTheirPanel) {
    Garment g;
    Panel p;
    p.name = "bodice";
    g.panels.push_back(p);
    AssembledGarment a;
    a.pairSeam = {-1, -1, -1};
    const std::vector<ForcedWeld> forced = forcedWelds(g, a, {0.0, 0.02, 0.01});
    ASSERT_EQ(forced.size(), 1u);
    EXPECT_EQ(forced[0].seam, "dart of bodice");
    EXPECT_EQ(forced[0].pairs, 2);
    EXPECT_EQ(forced[0].widest, 0.02);
}

/// Two panels of `width` × 0.1 m on the backs of two capsules of radius 0.1 m side by side,
/// 20 mm apart (legs): wrapped on their own capsules, their inner edges reach round into each
/// other between the two, as the trousers' backs do on a body whose legs are spread.
Tube twoLegs(double width) {
    Tube t;
    for (const char* name : {"left", "right"}) {
        Panel p;
        p.name = name;
        p.material = "cotton";
        p.placement.slot = name;
        p.placement.clearance = 0.02;
        t.garment.panels.push_back(p);
        t.mesh.panels.push_back(rectanglePanel(width, 0.1, 24, 6));
    }
    GarmentMaterial m;
    m.name = "cotton";
    m.material.density = 0.15;
    t.garment.materials.push_back(m);
    for (const double x : {0.11, -0.11}) {
        sim::MatX3 v;
        sim::MatX3i f;
        sim::makeCapsuleMesh(0.1, 0.4, 32, v, f);
        v.col(0).array() += x;
        const auto base = static_cast<int>(t.body.vertices.rows());
        t.body.vertices.conservativeResize(base + v.rows(), 3);
        t.body.vertices.bottomRows(v.rows()) = v;
        t.body.triangles.conservativeResize(t.body.triangles.rows() + f.rows(), 3);
        t.body.triangles.bottomRows(f.rows()) = f.array() + base;
        ArrangementSlot s;
        s.name = x > 0 ? "left" : "right";
        s.origin = sim::Vec3(x, 0.05, 0);
        s.axis = sim::Vec3::UnitY();
        s.facing = sim::Vec3(0, 0, -1);
        s.radius = 0.1;
        t.body.slots.push_back(s);
    }
    return t;
}

// Panels that reach round into each other between two slots are turned apart round their slots
// when that clears them sooner than a lift (which wraps a panel wider, reaching further round):
// here a 5 mm turn clears what a 5 mm lift does not.
TEST(Assemble, PanelsReachingRoundIntoEachOtherAreTurnedApart) {
    const Tube t = twoLegs(0.3);
    AssembledGarment a;
    ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, {}, a).has_value());
    const std::vector<PanelCrossing> placed = crossingsAtStart(a);
    ASSERT_EQ(placed.size(), 1u);
    EXPECT_GT(placed[0].pairs, 0);
    for (std::size_t p = 0; p < 2; ++p) {
        std::vector<SlotShift> out(2);
        out[p].lift = 0.005;
        ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, {}, a, out).has_value());
        EXPECT_FALSE(crossingsAtStart(a).empty()) << t.garment.panels[p].name;
    }
    ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, {}, a).has_value());
    std::vector<PlacementLift> lifted;
    const std::vector<SlotShift> shifts =
        liftCrossedPanels(t.garment, t.mesh, t.body, a, placed, lifted);
    ASSERT_EQ(lifted.size(), 1u);
    EXPECT_EQ(lifted[0].lift, 0.0);
    EXPECT_NE(lifted[0].around, 0.0);
    EXPECT_NEAR(std::abs(lifted[0].around), 0.005, 1e-12);
    EXPECT_EQ(liftText(lifted[0]),
              lifted[0].panel + " " + std::to_string(std::lround(lifted[0].around * 1000)) +
                  " mm around (crossed " + (lifted[0].panel == "left" ? "right" : "left") + ")");
    ASSERT_FALSE(assembleGarment(t.garment, t.mesh, t.body, {}, a, shifts).has_value());
    EXPECT_TRUE(crossingsAtStart(a).empty());
}

} // namespace
} // namespace atelier::patterns
