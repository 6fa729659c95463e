#include "patterns/drape_session.h"

#include "patterns/placement.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace atelier::patterns {

namespace {

using Clock = std::chrono::steady_clock;

Error sessionError(std::string message) {
    return Error{"", "", std::move(message)};
}

} // namespace

double interactiveStep(const DrapeSettings& settings) {
    const double frame = 1.0 / sim::SceneSpec().frameRate; // the assembled scene's frames
    const double limit = std::min(settings.particleDistance * 1.0 /* s/m */, MAX_INTERACTIVE_STEP);
    if (!(limit > settings.dt)) {
        return settings.dt;
    }
    const double step = frame / std::ceil(frame / limit - 1e-9);
    return std::max(step, settings.dt);
}

std::string_view phaseName(DrapePhase phase) {
    switch (phase) {
    case DrapePhase::Empty:
        return "empty";
    case DrapePhase::Placing:
        return "placing";
    case DrapePhase::Sewing:
        return "sewing";
    case DrapePhase::Settling:
        return "settling";
    case DrapePhase::AtRest:
        return "at rest";
    case DrapePhase::Failed:
        return "failed";
    }
    return "?";
}

std::string_view eventName(DrapeEvent::Kind kind) {
    switch (kind) {
    case DrapeEvent::Kind::Placed:
        return "placed";
    case DrapeEvent::Kind::SeamsSewn:
        return "seams sewn";
    case DrapeEvent::Kind::ForcedWelds:
        return "forced welds";
    case DrapeEvent::Kind::GravityOn:
        return "gravity on";
    case DrapeEvent::Kind::AtRest:
        return "at rest";
    case DrapeEvent::Kind::TimeLimit:
        return "time limit";
    case DrapeEvent::Kind::Failed:
        return "failed";
    case DrapeEvent::Kind::Restarted:
        return "restarted";
    }
    return "?";
}

/// How a (re)built simulation starts.
struct DrapeSession::Start {
    /// Per panel: positions to start from (|V_p|×3), or empty to place the panel on its slot.
    std::vector<sim::MatX3> positions;
    /// Sewing already done: the simulation starts with gravity on and every pair welded at
    /// its first step (pairs of a finished drape are closed, so nothing is forced).
    bool sewn = false;
    /// Sewing under way for this long [s]: the new simulation sews for what remains.
    double sewingElapsed = 0;
};

DrapeSession::DrapeSession(BodyProvider bodies) : m_bodies(std::move(bodies)) {}
DrapeSession::~DrapeSession() = default;

void DrapeSession::setProject(Project project) {
    m_project = std::move(project);
    m_meshValid = false; // the cache keeps what did not change
    m_simulation.reset();
    m_phase = DrapePhase::Empty;
}

Result<void> DrapeSession::ensureBody() {
    if (m_haveBodySource && m_bodySource == m_project.body) {
        return {};
    }
    if (!m_bodies) {
        return sessionError("no body provider");
    }
    auto body = m_bodies(m_project.body);
    if (!body.ok()) {
        return body.error();
    }
    m_body = std::move(body).value();
    m_bodySource = m_project.body;
    m_haveBodySource = true;
    return {};
}

Result<void> DrapeSession::ensureMesh() {
    if (m_meshValid) {
        return {};
    }
    MeshOptions options;
    options.particleDistance = m_project.drape.particleDistance;
    options.cache = &m_triangulations;
    GarmentMesh mesh;
    if (auto err = meshGarment(m_project.garment, options, mesh)) {
        return sessionError(*err);
    }
    m_mesh = std::move(mesh);
    m_meshValid = true;
    return {};
}

Result<void> DrapeSession::prepare() {
    if (auto r = ensureBody(); !r.ok()) {
        return r;
    }
    if (auto r = ensureMesh(); !r.ok()) {
        return r;
    }
    m_simulation.reset(); // a new drape: time starts at 0
    m_pause = false;
    m_cancel = false;
    m_timeOffset = 0;
    m_limitStart = 0;
    m_stepSecondsBefore = 0;
    m_sewnAt = -1;
    m_sewingStart = 0;
    m_frameSteps = 0;
    m_shifts.clear();
    m_placementLifts.clear();
    m_placedCrossings = 0;
    if (auto r = build(Start{}); !r.ok()) {
        return r;
    }
    // Cloth through cloth as the simulation starts, seam partners about to weld taken as one
    // vertex: panels sewn edge to edge touch there (GarmentCode places them so), which the
    // engine's count, welding nothing yet, takes for crossings. A panel's own pairs count too.
    auto pairsIn = [](const std::vector<PanelCrossing>& crossings) {
        long n = 0;
        for (const PanelCrossing& c : crossings) {
            n += c.pairs;
        }
        return n;
    };
    std::vector<PanelCrossing> crossings =
        startCrossings(m_assembled, m_simulation->positions(), true);
    m_startIntersecting = pairsIn(crossings);
    // Panels placed through each other (pairs of different panels): moved apart on their
    // slots where that clears them.
    std::erase_if(crossings, [](const PanelCrossing& c) { return c.a == c.b; });
    m_placedCrossings = pairsIn(crossings);
    if (!crossings.empty()) {
        std::vector<SlotShift> shifts = liftCrossedPanels(m_project.garment, m_mesh, m_body,
                                                          m_assembled, crossings, m_placementLifts);
        if (!m_placementLifts.empty()) {
            m_shifts = std::move(shifts);
            m_simulation.reset();
            if (auto r = build(Start{}); !r.ok()) {
                return r;
            }
            m_startIntersecting =
                pairsIn(startCrossings(m_assembled, m_simulation->positions(), true));
        }
    }
    m_startPenetration = m_simulation->penetration();
    char placed[160];
    std::snprintf(placed, sizeof placed,
                  "%zu panels, %ld triangles, %zu seam pairs placed on the body",
                  m_mesh.panels.size(), m_mesh.triangleCount, m_assembled.scene.seams.size());
    std::string message = placed;
    for (std::size_t k = 0; k < m_placementLifts.size(); ++k) {
        message += (k == 0 ? "; placed through each other, moved apart on their slots: " : "; ") +
                   liftText(m_placementLifts[k]);
    }
    raise(DrapeEvent::Kind::Placed, message);
    return {};
}

Result<void> DrapeSession::build(const Start& start) {
    AssembledGarment assembled;
    DrapeSettings settings = m_project.drape;
    if (m_interactive) {
        DrapeSettings finest = settings; // the step suits the finest panel
        for (const Panel& p : m_project.garment.panels) {
            finest.particleDistance = std::min(finest.particleDistance,
                                               panelParticleDistance(p, settings.particleDistance));
        }
        settings.dt = interactiveStep(finest);
        m_stepDistance = finest.particleDistance;
    }
    const std::vector<SlotShift> noShifts;
    const bool shifted = m_shifts.size() == m_project.garment.panels.size();
    if (auto err = assembleGarment(m_project.garment, m_mesh, m_body, settings, assembled,
                                   shifted ? m_shifts : noShifts)) {
        return sessionError(*err);
    }
    sim::SceneSpec& scene = assembled.scene;
    for (std::size_t p = 0; p < start.positions.size() && p < scene.cloths.size(); ++p) {
        if (start.positions[p].rows() == scene.cloths[p].position.rows()) {
            scene.cloths[p].position = start.positions[p];
        }
    }
    if (!start.positions.empty()) {
        // The pins hold from where the cloth is now, their paths and releases in drape time.
        pinGarment(m_project.garment, m_mesh, m_project.drape, time(), assembled);
    }
    auto simulation = std::make_unique<sim::Simulation>(scene);
    if (!simulation->error().empty()) {
        return sessionError(simulation->error());
    }
    if (m_simulation) {
        m_timeOffset += m_simulation->time();
        m_stepSecondsBefore += m_simulation->stats().wallTime;
    }
    m_assembled = std::move(assembled);
    m_simulation = std::move(simulation);
    m_sewing.begin(*m_simulation, m_project.drape, start.sewingElapsed, start.sewn);
    if (!m_sewing.active()) {
        settle();
    }
    if (m_publishing) {
        m_simulation->publishTo(&m_snapshots);
    }
    m_restSince = -1;
    m_restTime = -1;
    m_timeLimit = false;
    m_gravityRaised = false;
    m_error.clear();
    m_kineticEnergyPerVertex = 0;
    if (start.sewn) {
        m_sewnAt = m_sewnAt >= 0 ? m_sewnAt : m_timeOffset;
    } else {
        m_sewnAt = -1;
        // The new simulation sews for what remains of the sewing that began then.
        m_sewingStart = m_timeOffset - start.sewingElapsed;
    }
    m_phase = DrapePhase::Placing;
    return {};
}

void DrapeSession::raise(DrapeEvent::Kind kind, std::string message) {
    m_events.push_back({kind, time(), std::move(message)});
}

std::vector<DrapeEvent> DrapeSession::takeEvents() {
    std::vector<DrapeEvent> out;
    out.swap(m_events);
    return out;
}

double DrapeSession::time() const {
    return m_timeOffset + (m_simulation ? m_simulation->time() : 0.0);
}

const sim::MatX3& DrapeSession::positions() const {
    static const sim::MatX3 none;
    return m_simulation ? m_simulation->positions() : none;
}

void DrapeSession::wake() {
    if (!m_simulation || m_phase.load() == DrapePhase::Failed) {
        return;
    }
    if (m_phase.load() == DrapePhase::AtRest) {
        m_phase = DrapePhase::Settling;
    }
    m_restSince = -1;
    m_restTime = -1;
    m_timeLimit = false;
    m_limitStart = time();
    // A touch moves the cloth: the next step is the sewing one (chooseStep() decides again at
    // the next frame).
    if (const double base = m_simulation->scene().integrator.dt;
        m_simulation->nominalStep() != base) {
        m_simulation->setStep(base);
    }
}

bool DrapeSession::finished() const {
    const DrapePhase p = m_phase.load();
    return p == DrapePhase::AtRest || p == DrapePhase::Failed || m_timeLimit;
}

void DrapeSession::setPublishing(bool on) {
    m_publishing = on;
    if (m_simulation) {
        m_simulation->publishTo(on ? &m_snapshots : nullptr);
    }
}

DrapeStatus DrapeSession::finalStatus() const {
    switch (m_phase.load()) {
    case DrapePhase::AtRest:
        return DrapeStatus::AtRest;
    case DrapePhase::Failed:
        return DrapeStatus::Failed;
    default:
        return m_timeLimit ? DrapeStatus::TimeLimit : DrapeStatus::Running;
    }
}

void DrapeSession::settle() {
    if (m_interactive && m_settlingSolver) {
        m_simulation->setLinearSolver(*m_settlingSolver);
    }
}

void DrapeSession::chooseStep() {
    sim::Simulation& s = *m_simulation;
    const double base = s.scene().integrator.dt;
    const double frame = 1.0 / s.scene().frameRate;
    double step = base;
    // Implicit Euler only: the explicit integrators' steps are bound by their stability.
    if (m_interactive && m_settlingStep && !m_sewing.active() && s.grabCount() == 0 &&
        s.scene().integrator.kind == sim::IntegratorKind::ImplicitEuler && frame > base &&
        m_stepDistance > 0 && s.positions().rows() > 0) {
        // The fastest vertex, in particle distances per frame.
        const double moves = s.velocities().rowwise().norm().maxCoeff() * frame / m_stepDistance;
        const bool large = s.nominalStep() > base;
        // At most twice the sewing step, dividing a frame evenly: 1/30 s at 20 mm, 1/60 s at
        // 15 mm (1/90 s sewing).
        const double longer = frame / std::ceil(frame / (2 * base) - 1e-9);
        step = moves < (large ? 2.0 : 1.0) * INTERACTIVE_SETTLING_SPEED ? longer : base;
    }
    if (step != s.nominalStep()) {
        s.setStep(step);
    }
}

void DrapeSession::afterStep() {
    sim::Simulation& s = *m_simulation;
    const sim::SceneSpec& scene = s.scene();
    if (const Sewing::End end = m_sewing.afterStep(s); end != Sewing::End::None) {
        m_sewnAt = time();
        settle();
        const sim::RunStats& stats = s.stats();
        if (stats.largestForcedWeld > 0) {
            std::string seams;
            for (const ForcedWeld& w :
                 forcedWelds(m_project.garment, m_assembled, stats.forcedWeldGaps)) {
                char part[160];
                std::snprintf(part, sizeof part, "%s%s %.1f mm (%d pairs)",
                              seams.empty() ? "" : ", ", w.seam.c_str(), 1000 * w.widest, w.pairs);
                seams += part;
            }
            raise(DrapeEvent::Kind::ForcedWelds,
                  "sewing time is up; welded where they were, widest pair per seam: " + seams);
        } else {
            raise(DrapeEvent::Kind::SeamsSewn, "every seam pair closed");
        }
    }
    if (!m_gravityRaised && scene.gravity && !m_sewing.holdsGravity()) {
        m_gravityRaised = true;
        raise(DrapeEvent::Kind::GravityOn, "gravity acts");
    }
    if (m_phase != DrapePhase::AtRest) {
        m_phase =
            (m_sewnAt < 0 && !scene.seams.empty()) ? DrapePhase::Sewing : DrapePhase::Settling;
    }
    if (!s.atFrame()) {
        return;
    }
    chooseStep();
    const double vertices = std::max(1.0, static_cast<double>(s.positions().rows()));
    const double ke = s.kineticEnergy() / vertices;
    m_kineticEnergyPerVertex = ke;
    // Rest counts after sewing: at its set end, or earlier once every seam is sewn.
    const double t = s.time();
    const DrapeSettings& settings = m_project.drape;
    if (!m_sewing.active() && ke < settings.restKineticEnergy) {
        if (m_restSince < 0) {
            m_restSince = t;
        }
        if (t - m_restSince >= settings.restDuration - 1e-12) {
            m_restTime = time();
            m_phase = DrapePhase::AtRest;
            char message[96];
            std::snprintf(message, sizeof message, "kinetic energy %.2e J per vertex", ke);
            raise(DrapeEvent::Kind::AtRest, message);
        }
    } else {
        m_restSince = -1;
    }
    if (m_onFrame) {
        m_onFrame(s.frameIndex(), time(), ke);
    }
}

DrapeStatus DrapeSession::stepOnce() {
    if (m_cancel.exchange(false)) {
        return DrapeStatus::Cancelled;
    }
    if (m_pause.exchange(false)) {
        return DrapeStatus::Paused;
    }
    if (finished()) {
        return finalStatus();
    }
    const double until = m_limitStart + m_project.drape.timeLimit - m_timeOffset;
    m_sewing.beforeStep(*m_simulation);
    const bool frameStep = m_simulation->nominalStep() > m_simulation->scene().integrator.dt;
    if (m_simulation->step(until) != sim::RunStatus::Finished) {
        const sim::RunStats& stats = m_simulation->stats();
        m_error = !m_simulation->error().empty() ? m_simulation->error() : stats.error;
        m_phase = DrapePhase::Failed;
        raise(DrapeEvent::Kind::Failed, m_error);
        return DrapeStatus::Failed;
    }
    m_frameSteps += frameStep ? 1 : 0;
    afterStep();
    if (m_phase == DrapePhase::AtRest) {
        return DrapeStatus::AtRest;
    }
    if (!(m_simulation->time() < until - 1e-12)) {
        m_timeLimit = true;
        char message[96];
        std::snprintf(message, sizeof message, "not at rest after %.2f s", time());
        raise(DrapeEvent::Kind::TimeLimit, message);
        return DrapeStatus::TimeLimit;
    }
    return DrapeStatus::Running;
}

bool DrapeSession::ensurePrepared() {
    if (m_simulation) {
        return true;
    }
    if (auto r = prepare(); !r.ok()) {
        m_error = r.error().toString();
        m_phase = DrapePhase::Failed;
        return false;
    }
    return true;
}

DrapeStatus DrapeSession::step() {
    return ensurePrepared() ? stepOnce() : DrapeStatus::Failed;
}

DrapeStatus DrapeSession::runUntil(const std::function<bool(const DrapeSession&)>& stop) {
    if (!ensurePrepared()) {
        return DrapeStatus::Failed;
    }
    for (;;) {
        const DrapeStatus status = stepOnce();
        if (status != DrapeStatus::Running) {
            return status;
        }
        if (stop && stop(*this)) {
            return DrapeStatus::Stopped;
        }
    }
}

DrapeStatus DrapeSession::advance(double dt) {
    if (!ensurePrepared()) {
        return DrapeStatus::Failed;
    }
    const double target = time() + dt;
    const DrapeStatus status =
        runUntil([target](const DrapeSession& s) { return s.time() >= target - 1e-12; });
    return status == DrapeStatus::Stopped ? DrapeStatus::Running : status;
}

DrapeFigures DrapeSession::figures() const {
    DrapeFigures f;
    f.phase = m_phase.load();
    f.triangles = m_mesh.triangleCount;
    f.meshSeconds = m_mesh.seconds;
    f.minAngleDeg = m_mesh.minAngleDeg;
    f.panelsMeshed = m_mesh.panelsTriangulated;
    f.error = m_error;
    if (!m_simulation) {
        return f;
    }
    const sim::Simulation& s = *m_simulation;
    f.rested = f.phase == DrapePhase::AtRest;
    f.timeLimitReached = m_timeLimit;
    f.time = time();
    f.restTime = m_restTime;
    f.sewnAt = m_sewnAt;
    f.stepSeconds = m_stepSecondsBefore + s.stats().wallTime;
    f.kineticEnergyPerVertex =
        s.kineticEnergy() / std::max(1.0, static_cast<double>(s.positions().rows()));
    f.seamGapMax = seamGapMax(m_assembled, s.positions());
    f.areaRatio = areaRatio(m_assembled.scene, s.positions());
    f.startPenetration = m_startPenetration;
    f.startIntersectingPairs = m_startIntersecting;
    f.placedCrossings = m_placedCrossings;
    f.placementLifts = m_placementLifts;
    f.forcedWelds = forcedWelds(m_project.garment, m_assembled, s.stats().forcedWeldGaps);
    f.seamPairs = static_cast<long>(m_assembled.scene.seams.size());
    const PinFigures pins = pinFigures(m_assembled, s.positions(), s.time());
    f.pins = pins.holding;
    f.pinDisplacementMax = pins.largestDisplacement;
    return f;
}

std::vector<ForcedWeld> DrapeSession::openSeams() const {
    if (!m_simulation || m_sewnAt < 0) {
        return {};
    }
    const sim::Simulation& s = *m_simulation;
    const sim::MatX3& x = s.positions();
    const auto& pairs = m_assembled.scene.seams;
    std::vector<double> open(pairs.size(), 0.0);
    for (std::size_t k = 0; k < pairs.size(); ++k) {
        if (!s.seamPairWelded(k)) {
            open[k] = std::max((x.row(pairs[k].a) - x.row(pairs[k].b)).norm(), 1e-12);
        }
    }
    return forcedWelds(m_project.garment, m_assembled, open);
}

GarmentFit DrapeSession::fit() const {
    GarmentFit out;
    if (!m_simulation) {
        return out;
    }
    const sim::Simulation& s = *m_simulation;
    out.panels = panelStrains(m_assembled, s.positions());
    const bool finite = s.stats().finite && s.positions().allFinite();
    long withBody = 0;
    const long pairs = finite ? s.intersectingTrianglePairs(&withBody) : 0;
    out.verdict =
        fitVerdict(out.panels, openSeams(), static_cast<int>(pairs), static_cast<int>(withBody));
    return out;
}

Result<PinnedVertex> DrapeSession::pinVertex(int vertex) {
    if (!m_simulation || m_phase.load() == DrapePhase::Failed) {
        return sessionError("nothing is draped to pin");
    }
    const std::vector<int>& offsets = m_assembled.panelOffsets;
    if (vertex < 0 || offsets.empty() || vertex >= offsets.back()) {
        return sessionError("no garment vertex " + std::to_string(vertex));
    }
    if (m_simulation->pinned(vertex) ||
        std::any_of(m_assembled.pins.begin(), m_assembled.pins.end(),
                    [&](const HeldPin& h) { return h.hold.vertex == vertex; })) {
        return sessionError("vertex " + std::to_string(vertex) + " is already pinned");
    }
    const auto panel = static_cast<std::size_t>(
        std::upper_bound(offsets.begin(), offsets.end(), vertex) - offsets.begin() - 1);
    const int local = vertex - offsets[panel];
    if (!m_simulation->pin(vertex)) {
        return sessionError("the engine could not pin vertex " + std::to_string(vertex));
    }
    Pin pin;
    pin.point = m_mesh.panels[panel].pattern.row(local).transpose();
    pin.position = m_simulation->positions().row(vertex).transpose();
    std::vector<Pin>& pins = m_project.garment.panels[panel].pins;
    pins.push_back(pin);
    HeldPin held;
    held.panel = static_cast<int>(panel);
    held.pin = static_cast<int>(pins.size()) - 1;
    held.hold.vertex = vertex;
    held.hold.times = {0.0};
    held.hold.positions = {*pin.position};
    m_assembled.pins.push_back(held);
    return PinnedVertex{held.panel, held.pin, pin};
}

Result<PinnedVertex> DrapeSession::unpinVertex(int vertex) {
    const auto it = std::find_if(m_assembled.pins.begin(), m_assembled.pins.end(),
                                 [&](const HeldPin& h) { return h.hold.vertex == vertex; });
    if (!m_simulation || it == m_assembled.pins.end()) {
        return sessionError("vertex " + std::to_string(vertex) + " is not pinned");
    }
    const HeldPin held = *it;
    std::vector<Pin>& pins = m_project.garment.panels[static_cast<std::size_t>(held.panel)].pins;
    const Pin removed = pins[static_cast<std::size_t>(held.pin)];
    pins.erase(pins.begin() + held.pin);
    if (m_simulation->unpin(vertex)) {
        m_assembled.pins.erase(it);
        for (HeldPin& h : m_assembled.pins) {
            if (h.panel == held.panel && h.pin > held.pin) {
                --h.pin;
            }
        }
    } else if (auto r = continueDrape("unpinned"); !r.ok()) {
        // A drive (a pin that moves or lets go) is not an engine pin: the drape continues
        // from where it is without it.
        pins.insert(pins.begin() + held.pin, removed);
        return r.error();
    }
    return PinnedVertex{held.panel, held.pin, removed};
}

// ---- Edits ----

Result<void> DrapeSession::continueDrape(const std::string& why) {
    if (!m_simulation) {
        return {}; // nothing draped yet: the next prepare() uses the new values
    }
    Start start;
    const std::vector<int>& offsets = m_assembled.panelOffsets;
    for (std::size_t p = 0; p + 1 < offsets.size(); ++p) {
        start.positions.push_back(
            m_simulation->positions().middleRows(offsets[p], offsets[p + 1] - offsets[p]));
    }
    start.sewn = m_sewnAt >= 0;
    start.sewingElapsed = start.sewn ? 0.0 : time() - m_sewingStart;
    if (auto r = build(start); !r.ok()) {
        return r;
    }
    raise(DrapeEvent::Kind::Restarted, why + ": continuing from the current drape");
    return {};
}

Result<void> DrapeSession::setDrapeSettings(const DrapeSettings& settings) {
    const bool remesh = settings.particleDistance != m_project.drape.particleDistance;
    const DrapeSettings previous = m_project.drape;
    m_project.drape = settings;
    if (!remesh) {
        if (auto r = continueDrape("drape settings changed"); !r.ok()) {
            m_project.drape = previous;
            return r;
        }
        return {};
    }
    m_meshValid = false;
    if (!m_simulation) {
        return {};
    }
    GarmentMesh mesh = m_mesh;
    if (auto r = ensureMesh(); !r.ok()) {
        m_project.drape = previous;
        m_mesh = std::move(mesh);
        m_meshValid = true;
        return r; // the drape goes on as it was
    }
    if (auto r = prepare(); !r.ok()) {
        return r;
    }
    raise(DrapeEvent::Kind::Restarted, "particle distance changed: re-meshed and placed again");
    return {};
}

Result<void> DrapeSession::setMaterial(const std::string& name, const sim::Material& material) {
    for (GarmentMaterial& m : m_project.garment.materials) {
        if (m.name == name) {
            const sim::Material previous = m.material;
            m.material = material;
            auto r = continueDrape("material \"" + name + "\" changed");
            if (!r.ok()) {
                m.material = previous; // the drape goes on as it was
            }
            return r;
        }
    }
    return sessionError("no material \"" + name + "\"");
}

Result<void> DrapeSession::addMaterial(const GarmentMaterial& material) {
    if (material.name.empty()) {
        return sessionError("a material needs a name");
    }
    for (const GarmentMaterial& m : m_project.garment.materials) {
        if (m.name == material.name) {
            return sessionError("a material \"" + material.name + "\" exists");
        }
    }
    m_project.garment.materials.push_back(material);
    return {};
}

Result<void> DrapeSession::setPanel(std::size_t index, Panel panel) {
    if (index >= m_project.garment.panels.size()) {
        return sessionError("no panel " + std::to_string(index));
    }
    const GarmentMesh before = m_mesh;
    const std::vector<int> offsets = m_assembled.panelOffsets;
    const Panel previous = m_project.garment.panels[index];
    m_project.garment.panels[index] = std::move(panel);
    m_meshValid = false;
    if (!m_simulation) {
        return {};
    }
    // On failure the drape stays as it was, with the panel it was made of.
    const auto rollback = [&](Result<void> r) {
        m_project.garment.panels[index] = previous;
        m_mesh = before;
        m_meshValid = true;
        return r;
    };
    if (auto r = ensureMesh(); !r.ok()) {
        return rollback(r);
    }
    // Panels whose mesh is the same keep their draped positions; the others are placed again.
    Start start;
    int kept = 0;
    for (std::size_t p = 0; p < m_mesh.panels.size(); ++p) {
        const auto equal = [](const auto& a, const auto& b) {
            return a.rows() == b.rows() && a.cols() == b.cols() && a == b;
        };
        const bool same = p < before.panels.size() && p + 1 < offsets.size() &&
                          equal(before.panels[p].rest, m_mesh.panels[p].rest) &&
                          equal(before.panels[p].triangles, m_mesh.panels[p].triangles);
        start.positions.push_back(same ? sim::MatX3(m_simulation->positions().middleRows(
                                             offsets[p], offsets[p + 1] - offsets[p]))
                                       : sim::MatX3());
        kept += same ? 1 : 0;
    }
    if (auto r = build(start); !r.ok()) {
        return rollback(r);
    }
    raise(DrapeEvent::Kind::Restarted,
          "panel \"" + m_project.garment.panels[index].name +
              "\" edited: " + std::to_string(m_mesh.panelsTriangulated) + " panel(s) re-meshed, " +
              std::to_string(kept) + " kept where they were");
    return {};
}

Result<void> DrapeSession::placePanel(std::size_t index, const Placement& placement) {
    if (index >= m_project.garment.panels.size()) {
        return sessionError("no panel " + std::to_string(index));
    }
    const Placement previous = m_project.garment.panels[index].placement;
    m_project.garment.panels[index].placement = placement;
    // Placed where its placement says: a move the garment's placement gave it goes, and it is
    // moved again only if it crosses the others where they are now.
    const std::vector<SlotShift> previousShifts = m_shifts;
    const std::vector<PlacementLift> previousLifts = m_placementLifts;
    const std::string& name = m_project.garment.panels[index].name;
    std::erase_if(m_placementLifts, [&](const PlacementLift& l) { return l.panel == name; });
    m_shifts.resize(m_project.garment.panels.size());
    m_shifts[index] = {};
    if (!m_simulation) {
        return {};
    }
    Start start;
    const std::vector<int>& offsets = m_assembled.panelOffsets;
    for (std::size_t p = 0; p + 1 < offsets.size(); ++p) {
        start.positions.push_back(p == index ? sim::MatX3()
                                             : sim::MatX3(m_simulation->positions().middleRows(
                                                   offsets[p], offsets[p + 1] - offsets[p])));
    }
    auto undo = [&] {
        m_project.garment.panels[index].placement = previous;
        m_shifts = previousShifts;
        m_placementLifts = previousLifts;
    };
    if (auto r = build(start); !r.ok()) {
        undo();
        return r;
    }
    std::vector<PanelCrossing> crossings = startCrossings(m_assembled, m_simulation->positions());
    std::erase_if(crossings, [&](const PanelCrossing& c) {
        return c.a != static_cast<int>(index) && c.b != static_cast<int>(index);
    });
    if (!crossings.empty()) {
        std::vector<char> movable(m_project.garment.panels.size(), 0);
        movable[index] = 1;
        std::vector<PlacementLift> lifted;
        const std::vector<SlotShift> shifts = liftCrossedPanels(
            m_project.garment, m_mesh, m_body, m_assembled, crossings, lifted, movable);
        if (!lifted.empty()) {
            m_shifts[index] = shifts[index];
            m_placementLifts.insert(m_placementLifts.end(), lifted.begin(), lifted.end());
            if (auto r = build(start); !r.ok()) {
                undo();
                return r;
            }
        }
    }
    std::string message =
        "panel \"" + m_project.garment.panels[index].name + "\" placed again; sewing it anew";
    for (const PlacementLift& l : m_placementLifts) {
        if (l.panel == m_project.garment.panels[index].name) {
            message += "; placed through other panels, moved on its slot: " + liftText(l);
        }
    }
    raise(DrapeEvent::Kind::Restarted, message);
    return {};
}

} // namespace atelier::patterns
