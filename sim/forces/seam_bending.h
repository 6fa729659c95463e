#pragma once
/// Bending across welded seams: a seam joins two cloths (or two borders of one) by welded
/// vertices only, and without hinges across it every seam would be a free hinge.

#include "sim/forces/bending.h"
#include "sim/scene.h"

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

namespace atelier::sim {

class SeamWelds;

/// A hinge across a seam: two border edges of the scene's cloths whose ends are sewn, (u, u')
/// and (v, v') being seam pairs, with the triangle on each side as its wings.
struct SeamHinge {
    /// Global vertices in `dihedralAngle`'s order: the edge (u, v) of wing 0, counter-clockwise
    /// in its triangle, that triangle's third corner, then the other wing's third corner.
    /// Wing 0 is the side holding the pairs' `a` vertices.
    std::array<int, 4> corners{};
    std::array<std::size_t, 2> pairs{}; ///< indices into SceneSpec::seams: at u, at v
    double edgeLength = 0;              ///< mean rest length of the two edges [m]
    std::array<double, 2> areas{};      ///< rest areas of the two wings [m²]
    /// k of the cloth on either side, averaged (see SeamBending), before the pairs' scale.
    double stiffness = 0;
    double damping = 0; ///< mean τ of both sides [s]
};

/// Every hinge across the seams of `scene`, whose cloth c starts at global vertex `offsets[c]`.
std::vector<SeamHinge> seamHinges(const SceneSpec& scene, const std::vector<int>& offsets);

/// Discrete-shells hinges (`DihedralBending`) across the seams of a scene (`seamHinges`). A hinge
/// acts once both of its pairs are welded (before that the sides are apart and there is no fold to
/// speak of); `followWelds` switches it on.
///
/// Its stiffness is that of the cloth beside it, so that a welded seam bends as the cloth would
/// if it ran on uninterrupted, times the pairs' SeamPair::bendingScale: the mean over both sides
/// of the side's k, where k is `material.bending` for the discrete-shells model (each of the
/// cloth's own hinges has this k) and B(φ)/3 for the continuum plate, B(φ) the rigidity of a
/// strip bent across the seam (`stripRigidity` at the edge's angle to the weft plus 90°): a lone
/// hinge of the plate stores ½·B·θ²·|ē|²/(Ā₀ + Ā₁), which is ½·(B/3)·w·θ² with the hinge weight
/// w = 3|ē|²/(Ā₀ + Ā₁). |ē| is the mean of both sides' rest lengths, τ the mean damping. The rest
/// angle is the pairs' SeamPair::foldAngle, measured from the front of the pair's `a` side (the
/// hinge's wing 0 is that side, its edge running counter-clockwise in its triangle).
class SeamBending : public DihedralBending {
  public:
    /// The hinges across the seams of `scene`, whose cloth c starts at global vertex
    /// `offsets[c]`; null when there are none (no seam joins two border edges, or no side
    /// bends).
    static std::unique_ptr<SeamBending> build(const SceneSpec& scene,
                                              const std::vector<int>& offsets);

    /// Switches on the hinges whose two pairs `welds` holds welded and off the others. Returns
    /// whether any hinge changed.
    bool followWelds(const SeamWelds& welds);
    /// Switches every hinge off. Returns whether any was on.
    bool switchOff();
    /// Scales every hinge's stiffness by `strength` ∈ [0, 1] (a hinge switched on is eased in
    /// over a few steps rather than at once).
    void setStrength(double strength);
    /// (|H|) indices into SceneSpec::seams of each hinge's two seam pairs (at v0 and at v1).
    const std::vector<std::array<std::size_t, 2>>& pairs() const { return m_pairs; }

  private:
    SeamBending(HingeSet hinges, std::vector<std::array<std::size_t, 2>> pairs);
    /// Sets which hinges act (DihedralBending::setActive); returns whether any changed.
    bool switchOn(const std::vector<char>& on);

    std::vector<std::array<std::size_t, 2>> m_pairs;
    VecX m_fullStiffness; ///< (|H|) k at strength 1 [N·m]
    double m_strength = 1;
};

} // namespace atelier::sim
