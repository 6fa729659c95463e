#include "sim/collision/response/pinch.h"

#include "sim/collision/indexing.h"
#include "sim/collision/response/contact_correction.h"

#include <algorithm>
#include <array>

namespace atelier::sim {

void markPinches(std::vector<Contact>& contacts, std::size_t obstacleCount, const MatX3& xs,
                 MatX3& xe, double h, std::vector<std::pair<int, std::size_t>>& scratch) {
    // A vertex squeezed between two obstacles (touching vertex–face contacts with opposing
    // normals, closer together than the two contact distances) is pressed by both with the same
    // force, as large as the squeeze makes it: by Coulomb's law it slides on the surface that
    // grips less and is held by the one that grips more, positions included (held by velocities
    // alone, the cloth's pull moved it back a little at every step). Taken one contact at a time,
    // each with the friction of its own small normal impulse, the last contact applied won: a
    // sheet squeezed under a sweeping press stayed with the floor and was torn apart.
    if (obstacleCount < 2) {
        return; // every contact keeps Coulomb's law (Contact::grip's default)
    }
    std::vector<std::pair<int, std::size_t>>& touching = scratch;
    touching.clear();
    for (std::size_t i = 0; i < contacts.size(); ++i) {
        const Contact& c = contacts[i];
        if (c.active && c.obstacle >= 0 && c.kind == Contact::Kind::VertexFace) {
            touching.emplace_back(c.vertex[0], i);
        }
    }
    std::sort(touching.begin(), touching.end());
    for (std::size_t a = 0; a < touching.size();) {
        std::size_t b = a + 1;
        while (b < touching.size() && touching[b].first == touching[a].first) {
            ++b;
        }
        bool squeezed = false;
        for (std::size_t i = a; i < b && !squeezed; ++i) {
            for (std::size_t j = i + 1; j < b; ++j) {
                const Contact& ci = contacts[touching[i].second];
                const Contact& cj = contacts[touching[j].second];
                if (ci.obstacle != cj.obstacle && ci.normal.dot(cj.normal) < -0.5 &&
                    (ci.obstaclePoint - cj.obstaclePoint).dot(cj.normal) <
                        ci.distance + cj.distance) {
                    squeezed = true;
                    break;
                }
            }
        }
        if (squeezed) {
            std::size_t grip = touching[a].second;
            for (std::size_t i = a; i < b; ++i) {
                if (contacts[touching[i].second].staticFriction > contacts[grip].staticFriction) {
                    grip = touching[i].second;
                }
            }
            for (std::size_t i = a; i < b; ++i) {
                contacts[touching[i].second].grip =
                    touching[i].second == grip ? Contact::Grip::Stick : Contact::Grip::Slip;
            }
            // Held: no tangential motion relative to the gripping obstacle over the step.
            const Contact& c = contacts[grip];
            if (h > 0 && c.staticFriction > 0) {
                const int p = c.vertex[0];
                const Vec3 slip = (row(xe, p) - row(xs, p)) - h * c.obstacleVelocity;
                xe.row(p) -= (slip - slip.dot(c.normal) * c.normal).transpose();
            }
        }
        a = b;
    }
}

std::size_t dropSqueezedFaces(std::vector<Contact>& contacts, std::size_t first, const MatX3& x) {
    // A face (obstacle and cloth vertices, as the detection lists them for every contact of
    // one face) is squeezed when two of its face–vertex contacts are pierced and push it apart.
    // Only pierced contacts can make a pair, and they are rare: only they are gathered (a step
    // without any allocates nothing), grouped by face so that the pair test stays linear in
    // their number (a sheet dragged through the body pierces thousands at once).
    using Key = std::array<int, 4>;
    auto key = [&](std::size_t i) {
        const Contact& c = contacts[i];
        return Key{c.obstacle, c.vertex[0], c.vertex[1], c.vertex[2]};
    };
    std::vector<std::size_t> pierced;
    for (std::size_t i = first; i < contacts.size(); ++i) {
        const Contact& c = contacts[i];
        if (c.obstacle >= 0 && c.kind == Contact::Kind::FaceVertex &&
            c.normal.dot(combination(c, x) - c.obstaclePoint) < 0) {
            pierced.push_back(i);
        }
    }
    std::sort(pierced.begin(), pierced.end(), [&](std::size_t l, std::size_t r) {
        return key(l) < key(r) || (key(l) == key(r) && l < r);
    });
    std::vector<Key> squeezed;
    for (std::size_t a = 0; a < pierced.size();) {
        std::size_t b = a + 1;
        while (b < pierced.size() && key(pierced[b]) == key(pierced[a])) {
            ++b;
        }
        bool found = false;
        for (std::size_t i = a; i < b && !found; ++i) {
            for (std::size_t j = i + 1; j < b && !found; ++j) {
                const Contact& ci = contacts[pierced[i]];
                const Contact& cj = contacts[pierced[j]];
                found = ci.normal.dot(cj.normal) < -0.5 &&
                        (ci.obstaclePoint - cj.obstaclePoint).dot(cj.normal) <
                            ci.distance + cj.distance;
            }
        }
        if (found) {
            squeezed.push_back(key(pierced[a])); // sorted, as the groups are
        }
        a = b;
    }
    if (squeezed.empty()) {
        return 0;
    }
    // Every face–vertex contact of a squeezed face goes.
    const std::size_t before = contacts.size();
    const auto kept = std::remove_if(
        contacts.begin() + static_cast<std::ptrdiff_t>(first), contacts.end(),
        [&](const Contact& c) {
            return c.obstacle >= 0 && c.kind == Contact::Kind::FaceVertex &&
                   std::binary_search(squeezed.begin(), squeezed.end(),
                                      Key{c.obstacle, c.vertex[0], c.vertex[1], c.vertex[2]});
        });
    contacts.erase(kept, contacts.end());
    return before - contacts.size();
}

} // namespace atelier::sim
