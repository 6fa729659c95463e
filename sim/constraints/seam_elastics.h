#pragma once
/// Seam elastics as an acceleration contribution (C) with one time constant
/// (Volino & Magnenat-Thalmann 1997, §6.2.2).

#include "sim/forces/force_model.h"
#include "sim/scene.h"

namespace atelier::sim {

/// Each pair (a, b) is pulled together as a critically damped oscillator of time constant τ
/// in its relative coordinate r = x_a − x_b:
/// \f$ \ddot r = -r/\tau^2 - 2\dot r/\tau \f$, shared so momentum is conserved:
/// \f$ a_a \mathrel{+}= \frac{m_b}{m_a+m_b}\ddot r \f$, \f$ a_b \mathrel{-}=
/// \frac{m_a}{m_a+m_b}\ddot r \f$. As a force on the pair this is \f$ f_a = \mu\,\ddot r \f$ with
/// the reduced mass μ, which is how it enters implicit solves. The law is independent of the
/// masses: a gap shrinks like \f$ (1 + t/\tau)e^{-t/\tau} \f$ when nothing resists. Against the
/// cloth's own forces the stiffness μ/τ² is weak unless τ is small (garments sew at 4 ms; at 30 ms
/// their seams held centimetres open under the fabric's tension).
///
/// Routing: a pair whose straight chord is blocked by an obstacle (a shoulder between the
/// front and back of a shirt) can be given a via point clear of it; each of its two vertices
/// is then pulled towards the via point with the same law (stiffness μ/τ², damping 2μ/τ on its
/// own velocity), so the cloth is led around the obstacle instead of being pressed into it.
class SeamElastics : public ForceModel {
  public:
    /// `reach` > 0 saturates the pull: beyond a gap of `reach` the spring pulls with the
    /// constant force it has at `reach`, so a wide gap closes at about reach/(2τ) instead of
    /// snapping shut at gap/τ (which crumples the panels).
    ///
    /// `stiffnessPerLength` > 0 adds to each pair's stiffness μ/τ² that many N/m per metre of
    /// seam the pair stands for (SeamPair::length), with damping 2τ times the stiffness, so
    /// the law's closing speed (gap/2τ, at most reach/2τ) is unchanged and only its strength
    /// grows: a pull per length of seam, the same at every mesh resolution (μ/τ² alone, per
    /// pair ∝ the vertex mass, halves per metre of seam when the spacing halves, and loses
    /// against the fabric's tension). The pair is then no longer critically damped but
    /// overdamped: it closes like e^{−t/2τ}, and a routed vertex (damped on its own velocity)
    /// barely moves except along its pull.
    SeamElastics(const std::vector<SeamPair>& pairs, const VecX& masses, double timeConstant,
                 double reach = 0.0, double stiffnessPerLength = 0.0);

    std::string_view name() const override { return "seams"; }
    void addForces(const MatX3& x, const MatX3& v, MatX3& f) const override;
    bool hasEnergy() const override { return true; }
    double energy(const MatX3& x) const override;
    void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const override;
    void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                     BlockSparseMatrix& J) const override;

    /// Changes the reach (a sewing phase that pulls harder towards its end) [m].
    void setReach(double reach) { m_reach = reach; }
    double reach() const { return m_reach; }

    /// Routes pair s through `via` (world point), or back to its straight chord (nullptr).
    void setVia(std::size_t s, const Vec3* via);
    bool routed(std::size_t s) const { return m_routed[s] != 0; }

  private:
    std::vector<SeamPair> m_pairs;
    std::vector<Vec3> m_via;         ///< per pair: via point when routed [m]
    std::vector<char> m_routed;      ///< per pair
    std::vector<double> m_stiffness; ///< per pair: k [N/m]; damping is 2τk [N·s/m]
    double m_tau;
    double m_reach; ///< [m], 0 = linear
};

} // namespace atelier::sim
