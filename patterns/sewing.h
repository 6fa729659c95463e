#pragma once
/// The sewing phase of a drape, as the drape session runs it: the seams close around the body
/// with gravity held and friction lowered, the pull of open seams growing over the closing
/// time; the phase ends once every pair is welded, or at its deadline, where the pairs still
/// open are welded where they are; then gravity acts, and the welded seams bend like their
/// cloth (held off while sewing: a closed part of a seam pushed flat would hold the rest open).
/// The engine only obeys the calls (sim::Simulation::setGravity, setSeamBending,
/// setFrictionScale, setSeamReach, setSeamRouting, setSewingDeadline, weldAllSeams); when they
/// happen is decided here.

#include "patterns/project.h"

#include "sim/simulation.h"

namespace atelier::patterns {

class Sewing {
  public:
    /// How a step ended the phase.
    enum class End {
        None,   ///< still sewing (or not sewing at all)
        Sewn,   ///< every pair closed by itself before the deadline
        Timeup, ///< the deadline: pairs still open were welded where they were
    };

    /// Starts the phase on a fresh simulation. `elapsed` [s]: sewing time already spent on the
    /// same garment (a simulation rebuilt by an edit sews for what remains); `sewn`: the
    /// garment was sewn already (it drapes at once, every pair welded at the first step).
    void begin(sim::Simulation& simulation, const DrapeSettings& settings, double elapsed,
               bool sewn);
    /// Before each step: the growing pull of the open seams (it stays grown after the phase,
    /// for pairs whose weld is deferred).
    void beforeStep(sim::Simulation& simulation) const;
    /// After each step: ends the phase when the step did (gravity on, friction back, routing
    /// and the deadline off).
    End afterStep(sim::Simulation& simulation);
    /// The phase lasts (it began and has not ended).
    bool active() const { return m_active; }
    /// Gravity is held: the phase lasts with a deadline still ahead.
    bool holdsGravity() const { return m_active && m_deadline > 0; }

  private:
    void end(sim::Simulation& simulation);

    bool m_active = false;
    double m_deadline = -1;    ///< simulation time at which the phase ends (or ended) [s]
    double m_growthStart = -1; ///< simulation time at which the pull starts growing [s]
    double m_growth = 1;       ///< the pull's growth at the deadline [-]
};

} // namespace atelier::patterns
