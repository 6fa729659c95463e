// Assembly and sewing of a minimal garment: a band of two rectangular panels sewn at both sides
// around a capsule "body" (gravity held off, as in the sewing phase of a drape). Hand-built meshes keep this independent of the
// mesher: what is tested is placement, sewing (imposed seams that weld), the body obstacle and
// the figures.

#include "patterns/assemble.h"
#include "patterns/drape.h"

#include "sim/collision/obstacle.h"
#include "sim/mesh/cloth_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

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
    for (int j = 0; j <= cy; ++j) {
        t.mesh.seamPairs.push_back({VertexRef{0, j * (cx + 1) + cx}, VertexRef{1, j * (cx + 1)}});
        t.mesh.seamPairs.push_back({VertexRef{0, j * (cx + 1)}, VertexRef{1, j * (cx + 1) + cx}});
    }
    t.mesh.triangleCount = 2L * cx * cy * 2;
    sim::makeCapsuleMesh(0.1, 0.4, 32, t.body.vertices, t.body.triangles);
    for (const auto& [name, facing] : {std::pair{"front", sim::Vec3(0, 0, 1)},
                                       std::pair{"back", sim::Vec3(0, 0, -1)}}) {
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
    EXPECT_NE(err->find("panel \"back\": the body has no slot \"sleeve\""), std::string::npos) << *err;
    t = tube(2, 2);
    t.garment.panels[0].material = "silk";
    err = assembleGarment(t.garment, t.mesh, t.body, {}, a);
    ASSERT_TRUE(err.has_value());
    EXPECT_NE(err->find("no material \"silk\""), std::string::npos) << *err;
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
    const DrapeOutcome outcome = drapeUntilRest(simulation, settings);
    ASSERT_EQ(outcome.status, sim::RunStatus::Finished) << simulation.stats().error;
    EXPECT_EQ(seamGapMax(a, simulation.positions()), 0.0);
    EXPECT_EQ(simulation.stats().weldedSeamPairs, static_cast<long>(a.scene.seams.size()));
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

} // namespace
} // namespace atelier::patterns
