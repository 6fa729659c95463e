// A cloth face pierced from both sides of a crease of one obstacle (sim/collision/response/
// pinch.h, dropSqueezedFaces): its two opposed face–vertex contacts cannot both hold, and
// projected one after the other they rock the face and push a vertex far; they are dropped, and
// only they.

#include "sim/collision/response/pinch.h"
#include "sim/collision/response/position_projection.h"
#include "sim/scene.h"

#include <gtest/gtest.h>

namespace atelier {
namespace {

using sim::Contact;
using sim::MatX3;
using sim::Vec3;

/// A 20 mm cloth face (vertices 0, 1, 2) in the plane x = 0, and vertex 3 beside it.
MatX3 clothFace() {
    MatX3 x(4, 3);
    x << 0, 0, 0, 0, 0.02, 0, 0, 0, 0.02, 0.05, 0, 0;
    return x;
}

/// A face–vertex contact of the face with an obstacle vertex at q, pushing along `normal`, at
/// barycentric weights w.
Contact faceVertex(const Vec3& q, const Vec3& normal, const std::array<double, 3>& w) {
    Contact c;
    c.kind = Contact::Kind::FaceVertex;
    c.obstacle = 0;
    for (int k = 0; k < 3; ++k) {
        c.vertex[k] = k;
        c.weight[k] = w[static_cast<std::size_t>(k)];
    }
    c.normal = normal;
    c.distance = 0.004;
    c.obstaclePoint = q;
    return c;
}

/// The arm's wall (its point 3 mm on the −x side, through the face, pushing the face to −x) and
/// the torso's (3 mm on the +x side, pushing to +x), at different points of the face, as at the
/// armpit of the large dress; a vertex–face contact of vertex 3 that nothing should disturb.
std::vector<Contact> creaseContacts() {
    std::vector<Contact> contacts = {
        faceVertex(Vec3(-0.003, 0.004, 0.001), -Vec3::UnitX(), {0.74, 0.26, 0.0}),
        faceVertex(Vec3(0.003, 0.008, 0.004), Vec3::UnitX(), {0.53, 0.2, 0.27}),
    };
    Contact v;
    v.kind = Contact::Kind::VertexFace;
    v.obstacle = 0;
    v.vertex[0] = 3;
    v.weight[0] = 1;
    v.normal = Vec3::UnitY();
    v.distance = 0.004;
    v.obstaclePoint = Vec3(0.05, -0.002, 0);
    contacts.push_back(v);
    return contacts;
}

TEST(SqueezedFace, ItsOpposedContactsRockItAndAreDropped) {
    const sim::VecX invMass = sim::VecX::Constant(4, 1.0 / 0.002);
    sim::SceneSpec scene; // four projection passes, as a drape's
    // Projected as they are, the two contacts push the face back and forth, and it walks.
    std::vector<Contact> kept = creaseContacts();
    MatX3 x = clothFace();
    sim::projectPositions(kept, scene, x, invMass);
    double walked = 0;
    for (int i = 0; i < 3; ++i) {
        walked = std::max(walked, (x.row(i) - clothFace().row(i)).norm());
    }
    EXPECT_GT(walked, 0.01);

    std::vector<Contact> contacts = creaseContacts();
    EXPECT_EQ(sim::dropSqueezedFaces(contacts, 0, clothFace()), 2u);
    ASSERT_EQ(contacts.size(), 1u);
    EXPECT_EQ(contacts[0].kind, Contact::Kind::VertexFace);
    x = clothFace();
    sim::projectPositions(contacts, scene, x, invMass);
    EXPECT_EQ(x.topRows(3), clothFace().topRows(3));
    EXPECT_NEAR(x(3, 1), 0.002, 1e-12); // vertex 3 pushed out of its layer as before
}

TEST(SqueezedFace, ContactsThatCanHoldAreKept) {
    // One wall only through the face: the other is on its own side, and the face can keep
    // both.
    std::vector<Contact> contacts = creaseContacts();
    contacts[1].obstaclePoint.x() = -0.009;
    EXPECT_EQ(sim::dropSqueezedFaces(contacts, 0, clothFace()), 0u);
    EXPECT_EQ(contacts.size(), 3u);
    // Opposed walls of different faces: each face keeps its own.
    contacts = creaseContacts();
    contacts[1].vertex[2] = 3;
    EXPECT_EQ(sim::dropSqueezedFaces(contacts, 0, clothFace()), 0u);
    // Contacts before `first` are not looked at.
    contacts = creaseContacts();
    EXPECT_EQ(sim::dropSqueezedFaces(contacts, 1, clothFace()), 0u);
}

} // namespace
} // namespace atelier
