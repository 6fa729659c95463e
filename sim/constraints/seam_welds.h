#pragma once
/// Seam welding: a seam pair whose gap has closed is welded for good, its vertices moving as
/// one from then on (Volino & Magnenat-Thalmann 1997 §6.2's kinematic corrections applied to
/// sewing): positions and velocities merged by mass (A), accelerations shared (B). At the end
/// of a sewing phase every pair is welded, whatever its gap (a forced weld).

#include "sim/core/types.h"
#include "sim/scene.h"

#include <cstddef>
#include <functional>
#include <vector>

namespace atelier::sim {

/// What welding did, for the run's figures (sim::RunStats).
struct WeldFigures {
    long weldedPairs = 0; ///< pairs welded so far
    /// Largest gap of a pair welded by force, beyond the weld distance [m].
    double largestForced = 0;
    /// Welds put off because the merge would carry cloth through cloth, per pair and step.
    long deferred = 0;
    /// Per seam pair: its gap when welded by force, 0 otherwise [m] (empty until one is).
    std::vector<double> forcedGaps;
};

/// The welded state of a scene's seam pairs: union–find over the welded pairs and the groups
/// of two or more vertices they join.
class SeamWelds {
  public:
    SeamWelds() = default;
    SeamWelds(const std::vector<SeamPair>& seams, int vertexCount);

    /// Welds the open pairs closer than `distance` [m], or every open pair when `all` (the
    /// forced welds at the end of sewing, whose gaps are recorded). Returns whether a group
    /// changed. The pairs welded here are this step's new welds (see unweldCrossing).
    bool weldClosed(const MatX3& x, double distance, bool all, WeldFigures& figures);

    /// A: each group takes its mass-weighted mean position (when `x` is given) and velocity;
    /// a held member (invMass 0) imposes its own. Momentum-conserving and dissipative.
    void merge(MatX3* x, MatX3& v, const VecX& mass, const VecX& invMass) const;
    /// B: each group shares its mass-weighted mean acceleration (a held member imposes its own).
    void shareAccelerations(MatX3& a, const VecX& mass, const VecX& invMass) const;

    /// Vertices that cross cloth when the merge moves the cloth from `before` to `after`
    /// (given the vertices it moved); see CollisionStage::crossingVertices.
    using CrossingTest = std::function<std::vector<int>(const MatX3& before, const MatX3& after,
                                                        const std::vector<int>& moved)>;
    /// After merge(&x, v) from (xBefore, vBefore): where the merge carries cloth through cloth,
    /// un-welds this step's new pairs involved (they are tried again later: figures.deferred)
    /// and merges again without them; members of older groups involved stay where they were
    /// before the merge.
    void unweldCrossing(const MatX3& xBefore, const MatX3& vBefore, MatX3& x, MatX3& v,
                        const VecX& mass, const VecX& invMass, const CrossingTest& crossing,
                        WeldFigures& figures);

    /// merge(&x, v) at a step's start, where a group's members may have been left apart (see
    /// unweldCrossing): members whose move onto their group's point would carry cloth through
    /// cloth stay where they are (apart, one velocity). Groups whose members all lie within
    /// `unchecked` [m] of their first member are merged without the test.
    void mergeWithoutCrossing(MatX3& x, MatX3& v, const VecX& mass, const VecX& invMass,
                              const CrossingTest& crossing, double unchecked);

    bool welded(std::size_t pair) const { return !m_pairWelded.empty() && m_pairWelded[pair]; }
    /// Groups of two or more welded vertices, each sorted.
    const std::vector<std::vector<int>>& groups() const { return m_groups; }
    bool empty() const { return m_groups.empty(); }

  private:
    int root(int v);
    bool join(const SeamPair& p);
    void rebuildGroups();
    std::vector<int> crossings(const MatX3& xBefore, const MatX3& x, const CrossingTest& test);
    /// Puts the crossing vertices back at `xBefore` until nothing crosses (or rounds run out:
    /// then every vertex still crossing goes back).
    void putBackCrossing(const MatX3& xBefore, MatX3& x, const std::vector<int>& candidates,
                         const CrossingTest& test);

    const std::vector<SeamPair>* m_seams = nullptr;
    int m_vertexCount = 0;
    std::vector<int> m_parent;
    std::vector<char> m_pairWelded;
    std::vector<std::vector<int>> m_groups;
    std::vector<std::size_t> m_new; ///< pairs welded by the last weldClosed
    std::vector<int> m_moved;       ///< scratch: vertices a merge moved
    MatX3 m_xBefore;                ///< scratch: positions before the start's merge
};

} // namespace atelier::sim
