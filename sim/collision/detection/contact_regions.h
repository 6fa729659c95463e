#pragma once
/// Contact regions of self contacts (Volino & Magnenat-Thalmann 1997 §5.2): vertex–face
/// contacts of one smooth layer pair are grouped, and each group takes the side most of its
/// members hold, so that a vertex pushed through the other layer is put back on the right side.

#include "sim/collision/collision_mesh.h"
#include "sim/collision/contact.h"
#include "sim/core/types.h"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace atelier::sim {

/// The side of each self (vertex, face) pair in contact, by pairKey(vertex, face).
using ContactMemory = std::unordered_map<std::uint64_t, signed char>;

class ContactRegions {
  public:
    /// The vote over the step's contacts (positions xe) with, per contact, its memory key, its
    /// side and whether that side is certain (keys, sides, reliable: 0 / 0 / 1 for contacts
    /// other than self vertex–face): flips the sides (and normals) of the uncertain members
    /// that disagree with their region, drops the self edge–edge contacts touching a flipped
    /// region (all four arrays), and remembers the sides for the next step. Returns the number
    /// of contacts flipped.
    long vote(const CollisionMesh& mesh, const MatX3& xe, std::vector<Contact>& contacts,
              std::vector<std::uint64_t>& keys, std::vector<signed char>& sides,
              std::vector<char>& reliable);

    /// The sides of the pairs in contact after the last vote.
    const ContactMemory& memory() const { return m_memory; }

  private:
    ContactMemory m_memory;
    std::vector<signed char> m_flippedFrom; ///< sides before the vote
};

} // namespace atelier::sim
