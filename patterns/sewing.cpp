#include "patterns/sewing.h"

#include <algorithm>

namespace atelier::patterns {

namespace {

/// How much stronger the pull of an open seam is at the end of the closing time
/// (DrapeSettings::closingTime).
constexpr double CLOSING_PULL_GROWTH = 10.0;

} // namespace

void Sewing::begin(sim::Simulation& simulation, const DrapeSettings& settings, double elapsed,
                   bool sewn) {
    double deadline = settings.sewingTime;
    m_growthStart =
        settings.closingTime > 0 ? std::max(0.0, settings.sewingTime - settings.closingTime) : -1.0;
    m_growth = settings.closingTime > 0 ? CLOSING_PULL_GROWTH : 1.0;
    if (sewn) {
        deadline = 0;
        m_growthStart = -1;
    } else if (elapsed > 0) {
        deadline = std::max(0.0, deadline - elapsed);
        if (m_growthStart >= 0) {
            m_growthStart = std::max(0.0, m_growthStart - elapsed);
        }
    }
    m_deadline = deadline;
    m_active = !sewn;
    simulation.setSewingDeadline(deadline);
    simulation.setGravity(!holdsGravity());
    simulation.setSeamBending(!m_active);
    if (holdsGravity()) {
        simulation.setFrictionScale(settings.sewingFrictionScale);
    } else {
        simulation.setSeamRouting(false); // nothing left to route
    }
}

void Sewing::beforeStep(sim::Simulation& simulation) const {
    const double reach = simulation.scene().seamReach;
    if (m_growthStart < 0 || !(reach > 0) || m_deadline <= m_growthStart) {
        return;
    }
    const double s =
        std::clamp((simulation.time() - m_growthStart) / (m_deadline - m_growthStart), 0.0, 1.0);
    simulation.setSeamReach(reach * (1.0 + (m_growth - 1.0) * s));
}

Sewing::End Sewing::afterStep(sim::Simulation& simulation) {
    if (!m_active) {
        return End::None;
    }
    const double t = simulation.time();
    if (t >= m_deadline - 1e-12) {
        end(simulation); // the engine welded every open pair at this step's end
        return End::Timeup;
    }
    if (simulation.seamsWelded()) {
        // What the rest of the phase waited for has happened: drape now. (The pull stays
        // as grown by now: it acts on open pairs only, and there are none.)
        m_deadline = t;
        simulation.weldAllSeams();
        end(simulation);
        return End::Sewn;
    }
    return End::None;
}

void Sewing::end(sim::Simulation& simulation) {
    m_active = false;
    simulation.setSewingDeadline(-1);
    simulation.setGravity(true);
    simulation.setSeamBending(true);
    simulation.setFrictionScale(1.0);
    simulation.setSeamRouting(false);
}

} // namespace atelier::patterns
