// Pins: a point of a panel held while the garment drapes. The document's pin edits undo
// exactly, the garment's check names a pin off its panel, and in a drape a pinned vertex does
// not move by a single bit (its displacement is exactly 0) while the cloth around it does.

#include "patterns/document_edit.h"
#include "patterns/drape_session.h"
#include "patterns/loops.h"
#include "patterns/mesh.h"

#include "sim/collision/obstacle.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>

namespace atelier::patterns {
namespace {

using test::rectangle;

/// A 0.2 × 0.2 m cotton patch in front of a capsule, sewn to nothing: it falls unless pinned.
Project patchProject() {
    Project p;
    Panel patch;
    patch.name = "patch";
    patch.outline = rectangle(0.2, 0.2);
    patch.material = "cotton";
    patch.placement.slot = "front";
    patch.placement.clearance = 0.05;
    patch.notches.push_back({2, 0.5}); // the middle of the top edge
    p.garment.panels.push_back(patch);
    GarmentMaterial cotton;
    cotton.name = "cotton";
    cotton.material.density = 0.15;
    p.garment.materials.push_back(cotton);
    p.drape.particleDistance = 0.02;
    p.drape.timeLimit = 0.6;
    p.drape.sewingTime = 0.05;
    p.drape.closingTime = 0;
    p.document = fromGarment(p.garment);
    return p;
}

Body frontCapsuleBody() {
    Body body;
    sim::makeCapsuleMesh(0.1, 0.6, 32, body.vertices, body.triangles);
    ArrangementSlot s;
    s.name = "front";
    s.facing = sim::Vec3(0, 0, 1);
    s.radius = 0.1;
    body.slots.push_back(s);
    return body;
}

std::unique_ptr<DrapeSession> makeSession(const Project& project) {
    auto session = std::make_unique<DrapeSession>(
        [](const BodySource&) -> Result<Body> { return frontCapsuleBody(); });
    session->setProject(project);
    return session;
}

bool samePointBits(const sim::Vec3& a, const sim::Vec3& b) {
    return std::memcmp(a.data(), b.data(), sizeof(double) * 3) == 0;
}

Pin pinAt(double x, double y) {
    Pin pin;
    pin.point = Vec2(x, y);
    return pin;
}

TEST(Pins, APinnedVertexDoesNotMoveWhileTheClothFalls) {
    Project project = patchProject();
    project.garment.panels[0].pins = {pinAt(0, 0.2), pinAt(0.2, 0.2)};
    auto session = makeSession(project);
    ASSERT_TRUE(session->prepare().ok());
    const AssembledGarment& assembled = session->assembled();
    ASSERT_EQ(assembled.pins.size(), 2U);
    EXPECT_EQ(assembled.scene.pins.size(), 2U) << "still pins for good are engine pins";
    const sim::MatX3 start = session->positions();
    const PanelMesh& mesh = session->mesh().panels[0];
    for (const HeldPin& h : assembled.pins) {
        // Snapped to the mesh vertex at the corner.
        const Vec2 uv = mesh.pattern.row(h.hold.vertex).transpose();
        EXPECT_LT(
            (uv - project.garment.panels[0].pins[static_cast<std::size_t>(h.pin)].point).norm(),
            1e-9);
    }
    session->runUntil();
    const sim::MatX3& end = session->positions();
    ASSERT_TRUE(end.allFinite());
    for (const HeldPin& h : assembled.pins) {
        EXPECT_TRUE(samePointBits(end.row(h.hold.vertex).transpose(),
                                  start.row(h.hold.vertex).transpose()));
    }
    const DrapeFigures f = session->figures();
    EXPECT_EQ(f.pins, 2);
    EXPECT_EQ(f.pinDisplacementMax, 0.0);
    // The cloth around the pins moves as it hangs from them.
    EXPECT_GT((end - start).rowwise().norm().maxCoeff(), 0.01);

    // Without pins the whole patch falls: the top corners drop too.
    Project free = patchProject();
    auto loose = makeSession(free);
    ASSERT_TRUE(loose->prepare().ok());
    loose->runUntil();
    EXPECT_EQ(loose->figures().pins, 0);
    EXPECT_LT(loose->positions().col(1).maxCoeff(), start.col(1).maxCoeff() - 0.05);
}

TEST(Pins, APinMovesToItsPositionAndLetsGoAtItsReleaseTime) {
    Project project = patchProject();
    Pin toPosition;
    toPosition.notch = 0;
    project.garment.panels[0].pins = {toPosition, pinAt(0, 0.2)};
    project.garment.panels[0].pins[1].releaseTime = 0.3;
    auto probe = makeSession(project);
    ASSERT_TRUE(probe->prepare().ok());
    const int notchVertex =
        probe->assembled().panelOffsets[0] + probe->mesh().panels[0].notchVertices[0];
    const sim::Vec3 placed = probe->positions().row(notchVertex).transpose();
    const sim::Vec3 target = placed + sim::Vec3(0, 0.03, 0.02);
    project.garment.panels[0].pins[0].position = target;

    auto session = makeSession(project);
    ASSERT_TRUE(session->prepare().ok());
    EXPECT_EQ(session->assembled().scene.drives.size(), 2U)
        << "a pin that moves or lets go is a drive";
    const int released = session->assembled().pins[1].hold.vertex;
    const sim::Vec3 releasedStart = session->positions().row(released).transpose();
    EXPECT_EQ(session->figures().pins, 2);
    session->runUntil();
    const DrapeFigures f = session->figures();
    EXPECT_EQ(f.pins, 1) << "the second pin let go at 0.3 s";
    EXPECT_EQ(f.pinDisplacementMax, 0.0);
    EXPECT_TRUE(samePointBits(session->positions().row(notchVertex).transpose(), target));
    EXPECT_GT((session->positions().row(released).transpose() - releasedStart).norm(), 0.01)
        << "the released corner falls";
}

TEST(Pins, PinningAndUnpinningAVertexOfARunningDrape) {
    auto session = makeSession(patchProject());
    ASSERT_TRUE(session->prepare().ok());
    EXPECT_FALSE(session->pinVertex(-1).ok());
    session->advance(0.1);
    const int vertex = 0;
    const sim::Vec3 held = session->positions().row(vertex).transpose();
    const auto pinned = session->pinVertex(vertex);
    ASSERT_TRUE(pinned.ok()) << pinned.error().toString();
    EXPECT_FALSE(session->pinVertex(vertex).ok()) << "already pinned";
    ASSERT_EQ(session->project().garment.panels[0].pins.size(), 1U);
    const Pin& pin = session->project().garment.panels[0].pins[0];
    EXPECT_EQ(pin.point, Vec2(session->mesh().panels[0].pattern.row(vertex).transpose()));
    ASSERT_TRUE(pin.position.has_value());
    EXPECT_TRUE(samePointBits(*pin.position, held));
    session->advance(0.2);
    EXPECT_TRUE(samePointBits(session->positions().row(vertex).transpose(), held));
    EXPECT_EQ(session->figures().pins, 1);
    EXPECT_EQ(session->figures().pinDisplacementMax, 0.0);

    // A rebuild (a material edit) keeps the pin, now a drive at the position it was pinned at.
    ASSERT_TRUE(
        session->setMaterial("cotton", session->project().garment.materials[0].material).ok());
    session->advance(0.05);
    EXPECT_TRUE(samePointBits(session->positions().row(vertex).transpose(), held));

    const auto unpinned = session->unpinVertex(vertex);
    ASSERT_TRUE(unpinned.ok()) << unpinned.error().toString();
    EXPECT_TRUE(session->project().garment.panels[0].pins.empty());
    EXPECT_FALSE(session->unpinVertex(vertex).ok());
    session->advance(0.1);
    EXPECT_EQ(session->figures().pins, 0);
    EXPECT_GT((session->positions().row(vertex).transpose() - held).norm(), 1e-3)
        << "let go, the corner falls";
}

TEST(Pins, APinOffItsPanelIsAnIssueAtItsPointer) {
    Garment g = patchProject().garment;
    g.panels[0].pins = {pinAt(0.1, 0.1), pinAt(0.2, 0.2), pinAt(0.2005, 0.1)};
    EXPECT_TRUE(validateGarment(g).empty()) << "inside, on a corner, within 1 mm of an edge";
    g.panels[0].pins.push_back(pinAt(0.3, 0.1));
    auto issues = validateGarment(g);
    ASSERT_EQ(issues.size(), 1U);
    EXPECT_EQ(issues[0].where, "/panels/0/pins/3/at");
    EXPECT_NE(issues[0].message.find("not inside panel \"patch\""), std::string::npos)
        << issues[0].message;
    g.panels[0].pins.back() = Pin{};
    g.panels[0].pins.back().notch = 4;
    issues = validateGarment(g);
    ASSERT_EQ(issues.size(), 1U);
    EXPECT_EQ(issues[0].where, "/panels/0/pins/3/notch");
}

TEST(Pins, DocumentEditsAddRemoveAndMirrorPinsAndUndoExactly) {
    GarmentDocument d = patchProject().document;
    const PanelId panel = d.panels[0].id;
    const std::string before = dumpDocument(d);
    doc::Pin pin;
    pin.point = Vec2(0.05, 0.15);
    auto added = addPin(d, panel, pin);
    ASSERT_TRUE(added.ok()) << added.error().toString();
    ASSERT_EQ(d.panels[0].pins.size(), 1U);
    EXPECT_EQ(d.panels[0].pins[0].id.value, added.value().created);
    EXPECT_TRUE(checkDocument(d).ok());
    const std::string withPin = dumpDocument(d);
    EXPECT_NE(withPin, before);

    // The drawing keeps the pin, and a notch pin keeps its notch through it.
    doc::Pin onNotch;
    onNotch.notch = d.panels[0].notches[0].id;
    ASSERT_TRUE(addPin(d, panel, onNotch).ok());
    const Garment g = toGarment(d);
    ASSERT_EQ(g.panels[0].pins.size(), 2U);
    EXPECT_EQ(g.panels[0].pins[0].point, pin.point);
    EXPECT_EQ(g.panels[0].pins[1].notch, 0);
    const GarmentDocument again = fromGarment(g);
    ASSERT_EQ(again.panels[0].pins.size(), 2U);
    EXPECT_EQ(again.panels[0].pins[1].notch, again.panels[0].notches[0].id);

    auto mirrored = mirrorPanel(d, panel);
    ASSERT_TRUE(mirrored.ok());
    EXPECT_DOUBLE_EQ(d.panels[0].pins[0].point.x(), 0.15) << "mirrored about x = 0.1";
    undo(d, mirrored.value());

    const PinId id = d.panels[0].pins[0].id;
    auto removed = removePin(d, panel, id);
    ASSERT_TRUE(removed.ok());
    EXPECT_EQ(d.panels[0].pins.size(), 1U);
    EXPECT_FALSE(removePin(d, panel, id).ok());
    undo(d, removed.value());
    EXPECT_EQ(d.panels[0].pins.size(), 2U);

    doc::Pin outside;
    outside.point = Vec2(0.5, 0.1);
    const std::string beforeRefused = dumpDocument(d);
    const auto refused = addPin(d, panel, outside);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("not inside the panel"), std::string::npos);
    EXPECT_EQ(dumpDocument(d), beforeRefused) << "a refused edit changes nothing";
    doc::Pin badNotch;
    badNotch.notch = NotchId{9999};
    EXPECT_FALSE(addPin(d, panel, badNotch).ok());
}

} // namespace
} // namespace atelier::patterns
