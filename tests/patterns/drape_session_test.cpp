// The drape session on a small garment (a band of two panels sewn around a capsule, and a
// loose patch): events and phases, pause and cancel from another thread, and the edits that
// keep the drape.

#include "patterns/drape_session.h"
#include "patterns/loops.h"

#include "sim/collision/obstacle.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <thread>

namespace atelier::patterns {
namespace {

using test::rectangle;

/// Front and back 0.34 × 0.1 m around a capsule of radius 0.1 (0.63 m round; the band is
/// 0.68 m), sewn at both sides; a 0.1 m patch on its own higher up, sewn to nothing.
Project bandProject() {
    Project p;
    for (const char* name : {"front", "back"}) {
        Panel panel;
        panel.name = name;
        panel.outline = rectangle(0.34, 0.1);
        panel.material = "cotton";
        panel.placement.slot = name;
        panel.placement.clearance = 0.02;
        p.garment.panels.push_back(panel);
    }
    Panel patch;
    patch.name = "patch";
    patch.outline = rectangle(0.1, 0.1);
    patch.material = "cotton";
    patch.placement.slot = "front";
    patch.placement.offset = Vec2(0, 0.25);
    p.garment.panels.push_back(patch);
    // Front's right edge to back's left edge, and the other way round, bottom to bottom.
    p.garment.seams.push_back({"right", {{"front", 1, 0, 1}}, {{"back", 3, 1, 0}}});
    p.garment.seams.push_back({"left", {{"front", 3, 1, 0}}, {{"back", 1, 0, 1}}});
    GarmentMaterial cotton;
    cotton.name = "cotton";
    cotton.material.density = 0.15;
    p.garment.materials.push_back(cotton);
    p.drape.particleDistance = 0.02;
    p.drape.timeLimit = 0.5;
    p.drape.sewingTime = 0.3;
    p.drape.closingTime = 0.2;
    return p;
}

Body capsuleBody() {
    Body body;
    sim::makeCapsuleMesh(0.1, 0.6, 32, body.vertices, body.triangles);
    for (const auto& [name, facing] :
         {std::pair{"front", sim::Vec3(0, 0, 1)}, std::pair{"back", sim::Vec3(0, 0, -1)}}) {
        ArrangementSlot s;
        s.name = name;
        s.origin = sim::Vec3(0, 0.0, 0);
        s.facing = facing;
        s.radius = 0.1;
        body.slots.push_back(s);
    }
    // A slot tilted 45° from the front's (a panel on it at the band's height crosses the
    // front panel).
    ArrangementSlot tilted = body.slots.front();
    tilted.name = "tilted";
    const double tilt = 45 * std::numbers::pi / 180;
    tilted.axis = sim::Vec3(std::sin(tilt), std::cos(tilt), 0);
    body.slots.push_back(tilted);
    return body;
}

struct Fixture {
    int bodiesMade = 0;
    DrapeSession session{[this](const BodySource&) -> Result<Body> {
        ++bodiesMade;
        return capsuleBody();
    }};
    Fixture() { session.setProject(bandProject()); }
};

bool sameBits(const sim::MatX3& a, const sim::MatX3& b) {
    return a.rows() == b.rows() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

/// Whether a kept panel is where it was: to rounding, as the rebuilt simulation resolves the
/// contacts it starts in (a vertex at the contact distance may move by 1e-13 m).
bool samePlace(const sim::MatX3& a, const sim::MatX3& b) {
    return a.rows() == b.rows() && (a - b).cwiseAbs().maxCoeff() < 1e-9;
}

/// Rows of panel p in the session's global positions.
sim::MatX3 panelRows(const DrapeSession& s, std::size_t p) {
    const std::vector<int>& o = s.assembled().panelOffsets;
    return s.positions().middleRows(o[p], o[p + 1] - o[p]);
}

TEST(InteractiveStep, EnlargedOnCoarseMeshesInWholeStepsPerFrame) {
    DrapeSettings s;
    s.dt = 0.01;
    s.particleDistance = 0.02; // up to 20 ms: two steps per 1/30 s frame
    EXPECT_DOUBLE_EQ(interactiveStep(s), 1.0 / 60);
    s.particleDistance = 0.015; // up to 15 ms: three
    EXPECT_DOUBLE_EQ(interactiveStep(s), 1.0 / 90);
    s.particleDistance = 0.05; // never above MAX_INTERACTIVE_STEP
    EXPECT_DOUBLE_EQ(interactiveStep(s), 1.0 / 60);
    s.particleDistance = 0.01; // the project's step is at the limit already
    EXPECT_EQ(interactiveStep(s), 0.01);
    s.particleDistance = 0.011; // 11 ms would take four steps of 8.3 ms: keep 10 ms
    EXPECT_EQ(interactiveStep(s), 0.01);
    s.particleDistance = 0.02;
    s.dt = 0.025; // a step larger than the rule's is the project's choice
    EXPECT_EQ(interactiveStep(s), 0.025);
}

TEST(DrapeSession, InteractiveStepsTheSceneAndLeavesTheProject) {
    Fixture f;
    const double projectStep = f.session.project().drape.dt;
    f.session.setInteractive(true);
    ASSERT_TRUE(f.session.prepare().ok());
    const double step = interactiveStep(f.session.project().drape);
    EXPECT_GT(step, projectStep);
    EXPECT_EQ(f.session.simulation()->scene().integrator.dt, step);
    EXPECT_EQ(f.session.project().drape.dt, projectStep);
    EXPECT_EQ(f.session.step(), DrapeStatus::Running);
    EXPECT_NEAR(f.session.time(), step, 1e-12) << "one step of the interactive size";
}

TEST(DrapeSession, InteractiveSewsWithTheProjectsSolverAndSettlesWithItsOwn) {
    Fixture f;
    f.session.setInteractive(true);
    ASSERT_TRUE(f.session.prepare().ok());
    ASSERT_EQ(f.session.project().drape.linearSolver, sim::LinearSolver::BlockJacobi);
    while (f.session.step() == DrapeStatus::Running && f.session.phase() != DrapePhase::Settling) {
        ASSERT_EQ(f.session.simulation()->linearSolver(), sim::LinearSolver::BlockJacobi)
            << "sewing at t = " << f.session.time();
    }
    ASSERT_EQ(f.session.phase(), DrapePhase::Settling);
    EXPECT_EQ(f.session.simulation()->linearSolver(), INTERACTIVE_SETTLING_SOLVER);
    // A rebuild after sewing (an edit) settles with it from its first step.
    sim::Material stiffer = f.session.project().garment.materials[0].material;
    stiffer.density *= 1.1;
    ASSERT_TRUE(f.session.setMaterial("cotton", stiffer).ok());
    EXPECT_EQ(f.session.simulation()->linearSolver(), INTERACTIVE_SETTLING_SOLVER);

    // Not interactive, or without a settling solver: the project's throughout.
    for (const bool interactive : {false, true}) {
        Fixture g;
        g.session.setInteractive(interactive);
        g.session.setSettlingSolver(std::nullopt);
        ASSERT_TRUE(g.session.prepare().ok());
        while (g.session.step() == DrapeStatus::Running &&
               g.session.phase() != DrapePhase::Settling) {
        }
        EXPECT_EQ(g.session.phase(), DrapePhase::Settling);
        EXPECT_EQ(g.session.simulation()->linearSolver(), sim::LinearSolver::BlockJacobi);
    }
}

/// The fastest garment vertex, in interactive particle distances per output frame.
double distancesPerFrame(const DrapeSession& s) {
    const sim::Simulation& sim = *s.simulation();
    const double frame = 1.0 / sim.scene().frameRate;
    const double d = s.project().drape.particleDistance; // every band panel has the project's
    return sim.velocities().rowwise().norm().maxCoeff() * frame / d;
}

/// Steps an interactive drape once, checking the settling step's rule; returns whether the
/// step taken was one frame long.
bool stepCheckingTheSettlingStep(DrapeSession& s) {
    sim::Simulation& sim = *s.simulation();
    const double base = sim.scene().integrator.dt;
    const double frame = 1.0 / sim.scene().frameRate;
    const bool sewing = s.phase() != DrapePhase::Settling;
    const bool large = sim.nominalStep() > base;
    const double before = s.time();
    EXPECT_EQ(s.step(), DrapeStatus::Running);
    const double taken = s.time() - before;
    if (large) {
        EXPECT_NEAR(taken, frame, 1e-12) << "at t = " << s.time();
    } else {
        EXPECT_LE(taken, base + 1e-12) << "at t = " << s.time();
    }
    EXPECT_FALSE(sewing && large) << "sewing keeps its step, t = " << s.time();
    if (sim.atFrame() && s.phase() == DrapePhase::Settling && sim.grabCount() == 0) {
        const double moves = distancesPerFrame(s);
        const bool next = sim.nominalStep() > base;
        if (moves < INTERACTIVE_SETTLING_SPEED) {
            EXPECT_TRUE(next) << "slow at t = " << s.time() << ": " << moves;
        } else if (moves > 2 * INTERACTIVE_SETTLING_SPEED) {
            EXPECT_FALSE(next) << "fast at t = " << s.time() << ": " << moves;
        }
    }
    return large;
}

TEST(DrapeSession, InteractiveSettlesOneStepAFrameWhileTheGarmentIsSlow) {
    // The band alone: sewn, it hangs still for a while and then slides off the capsule.
    Project band = bandProject();
    band.garment.panels.pop_back();
    band.drape.timeLimit = 1.5;
    Fixture f;
    f.session.setProject(band);
    f.session.setInteractive(true);
    ASSERT_TRUE(f.session.prepare().ok());
    sim::Simulation* sim = f.session.simulation();
    const double base = sim->scene().integrator.dt;
    ASSERT_LT(base, 1.0 / sim->scene().frameRate);
    while (sim->nominalStep() == base && f.session.time() < 0.5) {
        ASSERT_FALSE(stepCheckingTheSettlingStep(f.session));
    }
    ASSERT_GT(sim->nominalStep(), base) << "slow once sewn";
    EXPECT_EQ(f.session.phase(), DrapePhase::Settling);
    EXPECT_TRUE(stepCheckingTheSettlingStep(f.session));
    EXPECT_EQ(f.session.frameSteps(), 1);

    // A grab wakes the drape at its sewing step and holds it there while it is held.
    const sim::MatX3i& tri = sim->scene().cloths[0].mesh.triangles;
    const sim::Vec3 at =
        (f.session.positions().row(tri(0, 0)) + f.session.positions().row(tri(0, 1)) +
         f.session.positions().row(tri(0, 2))) /
        3;
    const int handle = sim->grab(sim::ClothPoint{0, sim::Vec3::Constant(1.0 / 3)}, at);
    ASSERT_GT(handle, 0);
    f.session.wake();
    EXPECT_EQ(sim->nominalStep(), base);
    for (int k = 0; k < 12; ++k) {
        EXPECT_FALSE(stepCheckingTheSettlingStep(f.session)) << "held, step " << k;
    }
    ASSERT_TRUE(sim->release(handle));
    // Let go, it settles by the same rule.
    while (f.session.time() < 1.4) {
        stepCheckingTheSettlingStep(f.session);
    }
    EXPECT_EQ(sim->stats().maxDt, 1.0 / sim->scene().frameRate);

    // Not grabbed, the band slides off the capsule: fast again, it steps the sewing step.
    Fixture h;
    h.session.setProject(band);
    h.session.setInteractive(true);
    ASSERT_TRUE(h.session.prepare().ok());
    int back = 0;
    bool was = false;
    while (h.session.time() < 1.4) {
        stepCheckingTheSettlingStep(h.session);
        const bool large = h.session.simulation()->nominalStep() > base;
        back += was && !large ? 1 : 0;
        was = large;
    }
    EXPECT_GT(h.session.frameSteps(), 0);
    EXPECT_GT(back, 0);

    // Off: the sewing step throughout.
    Fixture g;
    g.session.setProject(band);
    g.session.setInteractive(true);
    g.session.setSettlingStep(false);
    ASSERT_TRUE(g.session.prepare().ok());
    g.session.runUntil();
    EXPECT_EQ(g.session.frameSteps(), 0);
    EXPECT_EQ(g.session.simulation()->stats().maxDt, base);
}

TEST(DrapeSession, PhasesAndEventsOfASewnBand) {
    Fixture f;
    EXPECT_EQ(f.session.phase(), DrapePhase::Empty);
    ASSERT_TRUE(f.session.prepare().ok());
    EXPECT_EQ(f.session.phase(), DrapePhase::Placing);
    EXPECT_EQ(f.session.figures().seamPairs,
              static_cast<long>(f.session.simulation()->scene().seams.size()));
    EXPECT_GT(f.session.figures().seamPairs, 0);
    EXPECT_EQ(f.session.step(), DrapeStatus::Running);
    EXPECT_EQ(f.session.phase(), DrapePhase::Sewing);
    const DrapeStatus end = f.session.runUntil();
    EXPECT_TRUE(end == DrapeStatus::AtRest || end == DrapeStatus::TimeLimit);
    EXPECT_TRUE(f.session.finished());
    std::vector<DrapeEvent::Kind> kinds;
    double sewnAt = -1, gravityAt = -1;
    for (const DrapeEvent& e : f.session.takeEvents()) {
        kinds.push_back(e.kind);
        if (e.kind == DrapeEvent::Kind::SeamsSewn || e.kind == DrapeEvent::Kind::ForcedWelds) {
            sewnAt = e.time;
        }
        if (e.kind == DrapeEvent::Kind::GravityOn) {
            gravityAt = e.time;
        }
    }
    ASSERT_GE(kinds.size(), 4u);
    EXPECT_EQ(kinds.front(), DrapeEvent::Kind::Placed);
    EXPECT_TRUE(kinds.back() == DrapeEvent::Kind::AtRest ||
                kinds.back() == DrapeEvent::Kind::TimeLimit);
    // The band closes by itself before the sewing time is up, and gravity starts then.
    EXPECT_GT(sewnAt, 0.0);
    EXPECT_LT(sewnAt, 0.3);
    EXPECT_NEAR(gravityAt, sewnAt, 0.02);
    EXPECT_TRUE(f.session.takeEvents().empty());
    const DrapeFigures fig = f.session.figures();
    EXPECT_EQ(fig.seamGapMax, 0.0);
    EXPECT_NEAR(fig.sewnAt, sewnAt, 1e-12);
    EXPECT_EQ(fig.panelsMeshed, 2) << "front and back are one drawing, triangulated once";
    EXPECT_EQ(f.bodiesMade, 1);
}

TEST(DrapeSession, AGrabWakesAFinishedDrapeWhichSettlesAgain) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    const DrapeStatus end = f.session.runUntil();
    ASSERT_TRUE(end == DrapeStatus::AtRest || end == DrapeStatus::TimeLimit);
    ASSERT_TRUE(f.session.finished());
    const double stoppedAt = f.session.time();
    EXPECT_EQ(f.session.step(), end) << "a finished drape does not step";
    EXPECT_EQ(f.session.time(), stoppedAt);

    // Pull a triangle of the front panel 3 cm outwards, then let go.
    sim::Simulation& sim = *f.session.simulation();
    const sim::MatX3i& tri = sim.scene().cloths[0].mesh.triangles;
    const sim::Vec3 at =
        (f.session.positions().row(tri(0, 0)) + f.session.positions().row(tri(0, 1)) +
         f.session.positions().row(tri(0, 2))) /
        3;
    const int handle =
        sim.grab(sim::ClothPoint{0, sim::Vec3::Constant(1.0 / 3)}, at + sim::Vec3(0, 0, 0.03));
    ASSERT_GT(handle, 0);
    f.session.wake();
    EXPECT_FALSE(f.session.finished());
    EXPECT_EQ(f.session.phase(), DrapePhase::Settling);
    for (int k = 0; k < 20; ++k) {
        ASSERT_EQ(f.session.step(), DrapeStatus::Running);
    }
    EXPECT_GT(f.session.time(), stoppedAt);
    const sim::Vec3 moved =
        (f.session.positions().row(tri(0, 0)) + f.session.positions().row(tri(0, 1)) +
         f.session.positions().row(tri(0, 2))) /
        3;
    EXPECT_GT((moved - at).z(), 0.01) << "the grabbed point followed the target";
    ASSERT_TRUE(sim.release(handle));
    const DrapeStatus again = f.session.runUntil();
    EXPECT_TRUE(again == DrapeStatus::AtRest || again == DrapeStatus::TimeLimit);
    EXPECT_TRUE(f.session.positions().allFinite());
}

TEST(DrapeSession, PauseFromAnotherThreadAndResumeGivesTheSameBits) {
    Fixture whole;
    ASSERT_TRUE(whole.session.prepare().ok());
    const DrapeStatus end = whole.session.runUntil();

    Fixture paused;
    ASSERT_TRUE(paused.session.prepare().ok());
    std::atomic<bool> done{false};
    std::thread presser([&] {
        while (!done.load()) {
            paused.session.pause();
            std::this_thread::sleep_for(std::chrono::milliseconds(3));
        }
    });
    int pauses = 0;
    DrapeStatus status;
    while ((status = paused.session.runUntil()) == DrapeStatus::Paused) {
        ++pauses;
    }
    done = true;
    presser.join();
    EXPECT_GT(pauses, 0);
    EXPECT_EQ(status, end);
    EXPECT_EQ(paused.session.time(), whole.session.time());
    EXPECT_TRUE(sameBits(paused.session.positions(), whole.session.positions()));
}

TEST(DrapeSession, CancelKeepsTheDrapeSoFarAndItCanGoOn) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    ASSERT_EQ(f.session.advance(0.1), DrapeStatus::Running);
    const double t = f.session.time();
    EXPECT_GE(t, 0.1 - 1e-12);
    f.session.cancel();
    EXPECT_EQ(f.session.runUntil(), DrapeStatus::Cancelled);
    EXPECT_EQ(f.session.time(), t);
    EXPECT_TRUE(f.session.positions().allFinite());
    EXPECT_EQ(f.session.advance(0.05), DrapeStatus::Running);
    EXPECT_GT(f.session.time(), t);
}

TEST(DrapeSession, BodyIsMadeOncePerBodySource) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    ASSERT_TRUE(f.session.prepare().ok());
    EXPECT_EQ(f.bodiesMade, 1);
    Project p = bandProject();
    p.body.measurements.push_back({"waist", 0.7});
    f.session.setProject(p);
    ASSERT_TRUE(f.session.prepare().ok());
    EXPECT_EQ(f.bodiesMade, 2);
    EXPECT_EQ(f.session.figures().panelsMeshed, 0) << "the panels did not change";
}

TEST(DrapeSession, NewMaterialContinuesFromTheCurrentDrape) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    ASSERT_EQ(f.session.advance(0.35), DrapeStatus::Running);
    const double t = f.session.time();
    const sim::MatX3 x = f.session.positions();
    f.session.takeEvents();
    sim::Material heavier = f.session.project().garment.materials[0].material;
    heavier.density = 0.3;
    ASSERT_TRUE(f.session.setMaterial("cotton", heavier).ok());
    EXPECT_FALSE(f.session.setMaterial("silk", heavier).ok());
    const std::vector<DrapeEvent> events = f.session.takeEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, DrapeEvent::Kind::Restarted);
    EXPECT_EQ(f.session.time(), t) << "drape time goes on";
    EXPECT_LT((f.session.positions() - x).cwiseAbs().maxCoeff(), 1e-9) << "where it was";
    EXPECT_EQ(f.session.simulation()->scene().cloths[0].material.density, 0.3);
    ASSERT_EQ(f.session.advance(0.05), DrapeStatus::Running);
    EXPECT_EQ(f.session.figures().seamGapMax, 0.0) << "sewn seams stay sewn";
}

TEST(DrapeSession, AnAddedMaterialGivenToAPanelContinuesTheDrape) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    ASSERT_EQ(f.session.advance(0.1), DrapeStatus::Running);
    const double t = f.session.time();
    const sim::MatX3 x = f.session.positions();
    GarmentMaterial silk;
    silk.name = "silk";
    silk.material.density = 0.06;
    ASSERT_TRUE(f.session.addMaterial(silk).ok());
    EXPECT_FALSE(f.session.addMaterial(silk).ok()) << "the name is taken";
    EXPECT_FALSE(f.session.addMaterial(GarmentMaterial{}).ok()) << "no name";
    EXPECT_TRUE(sameBits(f.session.positions(), x)) << "nothing uses it yet";
    Panel patch = f.session.project().garment.panels[2];
    patch.material = "silk";
    ASSERT_TRUE(f.session.setPanel(2, patch).ok());
    EXPECT_EQ(f.session.figures().panelsMeshed, 0) << "the same mesh";
    EXPECT_TRUE(sameBits(f.session.positions(), x)) << "every panel where it was";
    EXPECT_EQ(f.session.time(), t);
    EXPECT_EQ(f.session.simulation()->scene().cloths[2].material.density, 0.06);
    EXPECT_EQ(f.session.advance(0.02), DrapeStatus::Running);
}

TEST(DrapeSession, EditsDuringSewingKeepItsClock) {
    // A slider dragged while the seams close: many edits, and sewing still ends (by itself or
    // at its set time, 0.3 s after the start), with gravity on after it.
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    sim::Material m = f.session.project().garment.materials[0].material;
    for (int k = 0; k < 8; ++k) {
        ASSERT_EQ(f.session.advance(0.05), DrapeStatus::Running);
        m.density = 0.15 + 0.01 * k;
        ASSERT_TRUE(f.session.setMaterial("cotton", m).ok());
    }
    EXPECT_GE(f.session.time(), 0.4 - 1e-9);
    EXPECT_GE(f.session.figures().sewnAt, 0.0) << "sewing ended";
    EXPECT_LE(f.session.figures().sewnAt, 0.3 + 0.02);
    EXPECT_EQ(f.session.phase(), DrapePhase::Placing);
    EXPECT_EQ(f.session.step(), DrapeStatus::Running);
    EXPECT_EQ(f.session.phase(), DrapePhase::Settling);
}

TEST(DrapeSession, NewSettingsContinueANewParticleDistanceStartsAgain) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    ASSERT_EQ(f.session.advance(0.2), DrapeStatus::Running);
    DrapeSettings settings = f.session.project().drape;
    settings.bodyStaticFriction = 0.7;
    ASSERT_TRUE(f.session.setDrapeSettings(settings).ok());
    EXPECT_NEAR(f.session.time(), 0.2, 0.02) << "went on";
    const long triangles = f.session.figures().triangles;
    settings.particleDistance = 0.03;
    ASSERT_TRUE(f.session.setDrapeSettings(settings).ok());
    EXPECT_EQ(f.session.time(), 0.0) << "placed again";
    EXPECT_LT(f.session.figures().triangles, triangles);
    settings.particleDistance = -1; // a mesh that cannot be made: nothing changes
    EXPECT_FALSE(f.session.setDrapeSettings(settings).ok());
    EXPECT_EQ(f.session.project().drape.particleDistance, 0.03);
    EXPECT_EQ(f.session.advance(0.02), DrapeStatus::Running);
}

TEST(DrapeSession, EditedPanelIsTheOnlyOneMeshedAndPlacedAgain) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    ASSERT_EQ(f.session.advance(0.2), DrapeStatus::Running);
    const sim::MatX3 front = panelRows(f.session, 0);
    const sim::MatX3 back = panelRows(f.session, 1);
    Panel patch = f.session.project().garment.panels[2];
    patch.outline = rectangle(0.12, 0.08);
    ASSERT_TRUE(f.session.setPanel(2, patch).ok());
    EXPECT_EQ(f.session.figures().panelsMeshed, 1);
    EXPECT_TRUE(samePlace(panelRows(f.session, 0), front));
    EXPECT_TRUE(samePlace(panelRows(f.session, 1), back));
    EXPECT_NEAR(panelRows(f.session, 2).col(0).maxCoeff() -
                    panelRows(f.session, 2).col(0).minCoeff(),
                0.12, 0.02)
        << "the new patch is placed, flat on its slot";
    EXPECT_EQ(f.session.advance(0.05), DrapeStatus::Running);
}

TEST(DrapeSession, PlacingOnePanelAgainLeavesTheOthers) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    const sim::MatX3 placedBack = panelRows(f.session, 1);
    ASSERT_EQ(f.session.advance(0.2), DrapeStatus::Running);
    const sim::MatX3 front = panelRows(f.session, 0);
    EXPECT_FALSE(sameBits(panelRows(f.session, 1), placedBack)) << "the back has moved";
    ASSERT_TRUE(f.session.placePanel(1, f.session.project().garment.panels[1].placement).ok());
    EXPECT_TRUE(samePlace(panelRows(f.session, 0), front));
    EXPECT_LT((panelRows(f.session, 1) - placedBack).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_EQ(f.session.phase(), DrapePhase::Placing);
    EXPECT_EQ(f.session.step(), DrapeStatus::Running);
    EXPECT_EQ(f.session.phase(), DrapePhase::Sewing) << "sewing again";
}

// A panel placed again through the others (the patch moved onto a tilted slot, across the
// front of the band) is moved on its slot until it clears them, the band left where it is;
// placed again clear of them, it is where its placement says.
TEST(DrapeSession, APanelPlacedAgainThroughTheOthersIsMovedOnItsSlotAlone) {
    Fixture f;
    ASSERT_TRUE(f.session.prepare().ok());
    EXPECT_TRUE(f.session.placementLifts().empty());
    const sim::MatX3 front = panelRows(f.session, 0);
    Placement across;
    across.slot = "tilted";
    across.clearance = 0.02;
    across.offset = Vec2(0, 0.03);
    // As placed, the patch crosses the front where it is now.
    {
        Project crossed = f.session.project();
        crossed.garment.panels[2].placement = across;
        DrapeSession check([](const BodySource&) -> Result<Body> { return capsuleBody(); });
        check.setProject(crossed);
        ASSERT_TRUE(check.prepare().ok());
        ASSERT_EQ(check.placementLifts().size(), 1u) << "crossed as placed";
    }
    ASSERT_TRUE(f.session.placePanel(2, across).ok());
    // The front stays where it was (not moved on its slot: a 5 mm move would shift all of it),
    // but for the vertices the start's contact resolution pushes out of the patch's layer.
    const sim::VecX moved = (panelRows(f.session, 0) - front).rowwise().norm();
    EXPECT_LT(moved.mean(), 0.001);
    EXPECT_LT(moved.maxCoeff(), 0.005);
    ASSERT_EQ(f.session.placementLifts().size(), 1u);
    const PlacementLift& lift = f.session.placementLifts().front();
    EXPECT_EQ(lift.panel, "patch");
    EXPECT_EQ(lift.crossed, std::vector<std::string>{"front"});
    EXPECT_GT(lift.lift + std::abs(lift.around), 0.0);
    EXPECT_TRUE(startCrossings(f.session.assembled(), f.session.positions()).empty());
    const std::vector<DrapeEvent> events = f.session.takeEvents();
    ASSERT_FALSE(events.empty());
    EXPECT_EQ(events.back().kind, DrapeEvent::Kind::Restarted);
    EXPECT_NE(events.back().message.find("moved on its slot: " + liftText(lift)), std::string::npos)
        << events.back().message;
    EXPECT_EQ(f.session.step(), DrapeStatus::Running);

    // Back on the front slot, high above the band: no move.
    ASSERT_TRUE(f.session.placePanel(2, bandProject().garment.panels[2].placement).ok());
    EXPECT_TRUE(f.session.placementLifts().empty());
    EXPECT_TRUE(startCrossings(f.session.assembled(), f.session.positions()).empty());
}

} // namespace
} // namespace atelier::patterns
