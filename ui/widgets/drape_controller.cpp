#include "ui/widgets/drape_controller.h"

#include "io/body_file.h"
#include "io/project_file.h"

#include "patterns/document_edit.h"

#include <QMetaObject>

#include <algorithm>
#include <map>
#include <set>

namespace atelier::ui {

namespace {

/// Each seam's sewn edges: the seam's pairs run along it in order, so consecutive pairs' vertices
/// on one side are neighbours along the outline; a step to another panel (a side of several
/// ranges) or between vertices that share no triangle edge (a pair merged away) is no segment.
std::vector<SeamLine> seamLines(const patterns::GarmentMesh& mesh, const std::vector<int>& offsets,
                                const sim::MatX3i& triangles) {
    std::set<std::pair<int, int>> edges;
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(t, k);
            const int b = triangles(t, (k + 1) % 3);
            edges.emplace(std::min(a, b), std::max(a, b));
        }
    }
    std::map<int, std::vector<std::array<int, 2>>> pairsOf; // seam -> global vertex pairs
    for (std::size_t k = 0; k < mesh.seamPairs.size() && k < mesh.seamOfPair.size(); ++k) {
        if (mesh.seamOfPair[k] < 0) {
            continue; // a dart's
        }
        const auto global = [&](const patterns::VertexRef& v) {
            return offsets[static_cast<std::size_t>(v.panel)] + v.vertex;
        };
        pairsOf[mesh.seamOfPair[k]].push_back(
            {global(mesh.seamPairs[k][0]), global(mesh.seamPairs[k][1])});
    }
    std::vector<SeamLine> lines;
    for (const auto& [seam, pairs] : pairsOf) {
        SeamLine line;
        line.seam = seam;
        std::map<int, int> index; // global vertex -> its place in line.vertices
        const auto local = [&](int v) {
            const auto [at, added] = index.emplace(v, static_cast<int>(line.vertices.size()));
            if (added) {
                line.vertices.push_back(v);
            }
            return at->second;
        };
        std::vector<std::array<int, 2>> segments;
        for (std::size_t k = 0; k + 1 < pairs.size(); ++k) {
            for (int side = 0; side < 2; ++side) {
                const int a = pairs[k][static_cast<std::size_t>(side)];
                const int b = pairs[k + 1][static_cast<std::size_t>(side)];
                if (edges.contains({std::min(a, b), std::max(a, b)})) {
                    segments.push_back({local(a), local(b)});
                }
            }
        }
        line.segments.resize(static_cast<Eigen::Index>(segments.size()), 2);
        for (std::size_t s = 0; s < segments.size(); ++s) {
            line.segments(static_cast<Eigen::Index>(s), 0) = segments[s][0];
            line.segments(static_cast<Eigen::Index>(s), 1) = segments[s][1];
        }
        lines.push_back(std::move(line));
    }
    return lines;
}

} // namespace

DrapeController::DrapeController(QObject* parent) : QObject(parent) {
    m_session = std::make_unique<patterns::DrapeSession>(
        [this](const patterns::BodySource& source) -> Result<patterns::Body> {
            {
                const std::lock_guard lock(m_mutex);
                for (auto it = m_recentBodies.rbegin(); it != m_recentBodies.rend(); ++it) {
                    if (it->first == source) {
                        return it->second;
                    }
                }
            }
            auto body = io::loadBody(source, m_projectFile.parent_path(), m_projectFile);
            ++m_bodiesBuilt;
            // A mannequin depends on its source alone; a mesh file may change on disk.
            if (body.ok() && source.meshPath.empty()) {
                const std::lock_guard lock(m_mutex);
                rememberBody(source, body.value());
            }
            return body;
        });
    m_session->setPublishing(true);
    m_session->setInteractive(true); // the step `atelier-cli bench drape` measures
    m_worker = std::thread([this] { loop(); });
}

DrapeController::~DrapeController() {
    {
        const std::lock_guard lock(m_mutex);
        m_quit = true;
    }
    m_running.store(false);
    m_wake.notify_all();
    m_worker.join();
}

void DrapeController::post(std::function<void()> command) {
    {
        const std::lock_guard lock(m_mutex);
        m_commands.push_back(std::move(command));
    }
    m_wake.notify_all();
}

void DrapeController::offerBody(const patterns::BodySource& source, patterns::Body body) {
    const std::lock_guard lock(m_mutex);
    rememberBody(source, std::move(body));
}

void DrapeController::rememberBody(const patterns::BodySource& source, patterns::Body body) {
    std::erase_if(m_recentBodies, [&](const auto& recent) { return recent.first == source; });
    m_recentBodies.emplace_back(source, std::move(body));
    if (m_recentBodies.size() > RECENT_BODIES) {
        m_recentBodies.erase(m_recentBodies.begin());
    }
}

void DrapeController::open(const QString& path) {
    m_running.store(false);
    post([this, path] { openOnWorker(path); });
}

void DrapeController::setProject(patterns::Project project, const QString& path) {
    m_running.store(false);
    post([this, project = std::move(project), path]() mutable {
        m_projectFile = path.isEmpty() ? std::filesystem::path()
                                       : std::filesystem::absolute(path.toStdString());
        m_project = std::move(project);
        placeOnWorker(path);
    });
}

void DrapeController::setDocument(patterns::GarmentDocument document) {
    post([this, document = std::move(document)]() mutable { editOnWorker(std::move(document)); });
}

void DrapeController::setDrapeSettings(const patterns::DrapeSettings& settings) {
    post([this, settings] {
        const bool remesh = settings.particleDistance != m_project.drape.particleDistance;
        m_project.drape = settings;
        if (m_session->simulation() == nullptr) {
            m_session->setProject(m_project); // taken by the next prepare
            return;
        }
        if (auto set = m_session->setDrapeSettings(settings); !set.ok()) {
            const QString message = QString::fromStdString(set.error().toString());
            QMetaObject::invokeMethod(this, [this, message] { Q_EMIT failed(message); });
            return;
        }
        if (remesh) {
            m_running.store(false);
            m_stepped.store(false); // snapshots before the re-mesh are of the old mesh
            m_grab = 0;
        }
        for (const patterns::DrapeEvent& e : m_session->takeEvents()) {
            const QString message = QString::fromStdString(e.message);
            QMetaObject::invokeMethod(this, [this, message] { Q_EMIT event(message); });
        }
        publishScene();
        QMetaObject::invokeMethod(this, [this, remesh] { Q_EMIT rebuilt(!remesh); });
    });
}

void DrapeController::start() {
    post([this] {
        if (m_session->phase() != patterns::DrapePhase::Empty && !m_session->finished()) {
            m_running.store(true);
        }
    });
}

void DrapeController::pause() {
    m_running.store(false);
}

void DrapeController::reset() {
    m_running.store(false);
    post([this] {
        if (!m_project.garment.panels.empty()) {
            m_session->setProject(m_project);
            prepareOnWorker();
        }
    });
}

void DrapeController::grab(const sim::ClothPoint& point, const sim::Vec3& target) {
    post([this, point, target] {
        sim::Simulation* simulation = m_session->simulation();
        if (simulation == nullptr || m_session->phase() == patterns::DrapePhase::Failed) {
            return;
        }
        if (m_grab != 0) {
            simulation->release(m_grab);
        }
        m_grab = simulation->grab(point, target);
        if (m_grab != 0) {
            m_session->wake();
            m_running.store(true);
        }
    });
}

void DrapeController::moveGrab(const sim::Vec3& target) {
    post([this, target] {
        if (m_grab != 0 && m_session->simulation() != nullptr) {
            m_session->simulation()->moveGrab(m_grab, target);
        }
    });
}

void DrapeController::release() {
    post([this] {
        if (m_grab != 0 && m_session->simulation() != nullptr) {
            m_session->simulation()->release(m_grab);
            m_session->wake(); // let it settle from where it was left
        }
        m_grab = 0;
    });
}

void DrapeController::pin(int vertex) {
    post([this, vertex] {
        auto pinned = m_session->pinVertex(vertex);
        if (!pinned.ok()) {
            const QString message = QString::fromStdString(pinned.error().toString());
            QMetaObject::invokeMethod(this, [this, message] { Q_EMIT failed(message); });
            return;
        }
        const patterns::PinnedVertex& p = pinned.value();
        const auto panel = static_cast<std::size_t>(p.panel);
        patterns::doc::Pin pin;
        pin.point = p.pin.point;
        pin.position = p.pin.position;
        // The session's garment and the document list a panel's pins in the same order.
        m_project.garment.panels[panel].pins.push_back(p.pin);
        if (auto edit =
                patterns::addPin(m_project.document, m_project.document.panels[panel].id, pin);
            !edit.ok()) {
            // A vertex's own pattern point always lies on its panel: this does not happen.
            const QString message = QString::fromStdString(edit.error().toString());
            QMetaObject::invokeMethod(this, [this, message] { Q_EMIT failed(message); });
        } else {
            QMetaObject::invokeMethod(this,
                                      [this, e = std::move(edit.value())] { Q_EMIT pinEdited(e); });
        }
        publishPins();
    });
}

void DrapeController::unpin(int vertex) {
    post([this, vertex] {
        const sim::Simulation* before = m_session->simulation();
        auto unpinned = m_session->unpinVertex(vertex);
        if (m_session->simulation() != before) {
            m_grab = 0; // the drape was rebuilt without the pin: it holds no grab
        }
        if (!unpinned.ok()) {
            const QString message = QString::fromStdString(unpinned.error().toString());
            QMetaObject::invokeMethod(this, [this, message] { Q_EMIT failed(message); });
            return;
        }
        const patterns::PinnedVertex& p = unpinned.value();
        const auto panel = static_cast<std::size_t>(p.panel);
        auto& garmentPins = m_project.garment.panels[panel].pins;
        auto& docPanel = m_project.document.panels[panel];
        if (p.index < static_cast<int>(garmentPins.size()) &&
            p.index < static_cast<int>(docPanel.pins.size())) {
            garmentPins.erase(garmentPins.begin() + p.index);
            if (auto edit =
                    patterns::removePin(m_project.document, docPanel.id,
                                        docPanel.pins[static_cast<std::size_t>(p.index)].id);
                edit.ok()) {
                QMetaObject::invokeMethod(
                    this, [this, e = std::move(edit.value())] { Q_EMIT pinEdited(e); });
            }
        }
        publishPins();
        if (m_session->phase() != patterns::DrapePhase::Failed) {
            m_session->wake(); // the cloth it held may fall
            m_running.store(true);
        }
    });
}

std::vector<int> DrapeController::pinnedVertices(double time) const {
    const std::lock_guard lock(m_mutex);
    std::vector<int> out;
    for (const auto& [vertex, release] : m_pinned) {
        if (time < release) {
            out.push_back(vertex);
        }
    }
    return out;
}

patterns::GarmentDocument DrapeController::document() const {
    const std::lock_guard lock(m_mutex);
    return m_document;
}

void DrapeController::publishPins() {
    std::vector<std::pair<int, double>> pinned;
    for (const patterns::HeldPin& h : m_session->assembled().pins) {
        pinned.emplace_back(h.hold.vertex, h.hold.releaseTime);
    }
    {
        const std::lock_guard lock(m_mutex);
        m_pinned = std::move(pinned);
        m_document = m_project.document;
    }
    QMetaObject::invokeMethod(this, [this] { Q_EMIT pinsChanged(); });
}

bool DrapeController::snapshot(sim::Snapshot& out) {
    if (!m_stepped.load()) {
        return false;
    }
    return m_session->snapshots().read(out);
}

DrapeProgress DrapeController::progress() {
    DrapeProgress p;
    sim::Snapshot s;
    if (snapshot(s)) {
        p.time = s.time;
        p.steps = s.steps;
        p.wallTime = s.wallTime;
        p.kineticEnergy = s.kineticEnergy;
        p.contacts = s.contacts;
    }
    p.phase = static_cast<patterns::DrapePhase>(m_phase.load());
    p.running = m_running.load();
    return p;
}

QString DrapeController::path() const {
    const std::lock_guard lock(m_mutex);
    return m_path;
}

std::shared_ptr<const StaticScene> DrapeController::staticScene() const {
    const std::lock_guard lock(m_mutex);
    return m_static;
}

void DrapeController::openOnWorker(const QString& path) {
    const std::filesystem::path file = path.toStdString();
    auto project = io::loadProject(file);
    if (!project.ok()) {
        const QString message = QString::fromStdString(project.error().toString());
        QMetaObject::invokeMethod(this, [this, message] { Q_EMIT failed(message); });
        return;
    }
    m_projectFile = std::filesystem::absolute(file);
    m_project = std::move(project.value());
    placeOnWorker(path);
}

void DrapeController::placeOnWorker(const QString& path) {
    {
        const std::lock_guard lock(m_mutex);
        m_path = path;
    }
    m_session->setProject(m_project); // phase Empty, no simulation until prepared
    if (!m_project.garment.panels.empty()) {
        prepareOnWorker();
        return;
    }
    // Nothing to drape (a new project): no scene until a panel is drawn.
    m_stepped.store(false);
    m_grab = 0;
    m_phase.store(static_cast<int>(patterns::DrapePhase::Empty));
    {
        const std::lock_guard lock(m_mutex);
        m_static.reset();
        m_pinned.clear();
        m_document = m_project.document;
    }
    QMetaObject::invokeMethod(this, [this, path] { Q_EMIT opened(path); });
}

bool DrapeController::prepareSession() {
    m_stepped.store(false);
    m_grab = 0; // a new simulation holds no grab
    if (auto prepared = m_session->prepare(); !prepared.ok()) {
        m_phase.store(static_cast<int>(patterns::DrapePhase::Failed));
        const QString message = QString::fromStdString(prepared.error().toString());
        QMetaObject::invokeMethod(this, [this, message] { Q_EMIT failed(message); });
        return false;
    }
    // Placed: the window learns it, and the panels lifted apart, from the static scene with
    // opened() or rebuilt().
    m_session->takeEvents();
    return true;
}

void DrapeController::prepareOnWorker() {
    if (!prepareSession()) {
        return;
    }
    publishScene();
    QString path;
    {
        const std::lock_guard lock(m_mutex);
        path = m_path;
    }
    QMetaObject::invokeMethod(this, [this, path] { Q_EMIT opened(path); });
}

namespace {

bool sameRanges(const std::vector<patterns::SeamEdge>& a,
                const std::vector<patterns::SeamEdge>& b) {
    if (a.size() != b.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.size(); ++i) {
        if (a[i].panel != b[i].panel || a[i].segment != b[i].segment || a[i].t0 != b[i].t0 ||
            a[i].t1 != b[i].t1) {
            return false;
        }
    }
    return true;
}

/// The same seams, over the same panels' segments (the index-based form the session holds).
bool sameSeams(const patterns::Garment& a, const patterns::Garment& b) {
    if (a.seams.size() != b.seams.size()) {
        return false;
    }
    for (std::size_t s = 0; s < a.seams.size(); ++s) {
        if (a.seams[s].name != b.seams[s].name || !sameRanges(a.seams[s].a, b.seams[s].a) ||
            !sameRanges(a.seams[s].b, b.seams[s].b)) {
            return false;
        }
    }
    return true;
}

/// The exact text of one panel (dumpDocument over a document holding only it).
std::string dumpPanel(const patterns::doc::Panel& panel) {
    patterns::GarmentDocument one;
    one.panels.push_back(panel);
    return patterns::dumpDocument(one);
}

/// The fabrics' values as text (names and every number), to compare two lists.
std::string dumpMaterial(const patterns::GarmentMaterial& material) {
    patterns::GarmentDocument one;
    one.materials.push_back(material);
    return patterns::dumpDocument(one);
}

} // namespace

void DrapeController::editOnWorker(patterns::GarmentDocument document) {
    patterns::Garment next = patterns::toGarment(document);
    const patterns::Garment& now = m_project.garment;
    std::vector<std::size_t> changed;
    bool incremental = m_session->simulation() != nullptr &&
                       m_session->phase() != patterns::DrapePhase::Failed &&
                       next.panels.size() == now.panels.size() &&
                       document.panels.size() == m_project.document.panels.size() &&
                       sameSeams(next, now) && next.materials.size() >= now.materials.size();
    std::vector<std::size_t> placed; // panels whose placement alone changed
    for (std::size_t p = 0; incremental && p < document.panels.size(); ++p) {
        const patterns::doc::Panel& before = m_project.document.panels[p];
        const patterns::doc::Panel& after = document.panels[p];
        if (before.id != after.id || before.name != after.name) {
            incremental = false;
        } else if (dumpPanel(before) != dumpPanel(after)) {
            patterns::doc::Panel moved = before;
            moved.placement = after.placement;
            (dumpPanel(moved) == dumpPanel(after) ? placed : changed).push_back(p);
        }
    }
    // Fabrics: the same names in the same order, new ones after them; those whose values
    // changed are set, new ones added.
    std::vector<std::size_t> refabric;
    for (std::size_t m = 0; incremental && m < now.materials.size(); ++m) {
        if (next.materials[m].name != now.materials[m].name) {
            incremental = false;
        } else if (dumpMaterial(next.materials[m]) != dumpMaterial(now.materials[m])) {
            refabric.push_back(m);
        }
    }
    const sim::Simulation* simulation = m_session->simulation();
    for (std::size_t k = 0; incremental && k < refabric.size(); ++k) {
        const patterns::GarmentMaterial& m = next.materials[refabric[k]];
        incremental = m_session->setMaterial(m.name, m.material).ok();
    }
    for (std::size_t m = now.materials.size(); incremental && m < next.materials.size(); ++m) {
        incremental = m_session->addMaterial(next.materials[m]).ok();
    }
    for (std::size_t k = 0; incremental && k < changed.size(); ++k) {
        incremental = m_session->setPanel(changed[k], next.panels[changed[k]]).ok();
    }
    for (std::size_t k = 0; incremental && k < placed.size(); ++k) {
        incremental = m_session->placePanel(placed[k], next.panels[placed[k]].placement).ok();
    }
    m_project.document = std::move(document);
    m_project.garment = std::move(next);
    if (!incremental) {
        // Placed again: every panel on its slot, the drape from the start.
        const QString path = this->path();
        m_running.store(false);
        if (m_project.garment.panels.empty()) {
            placeOnWorker(path);
            return;
        }
        m_session->setProject(m_project);
        if (!prepareSession()) {
            return;
        }
    } else if (m_session->simulation() != simulation) {
        m_stepped.store(false); // snapshots before the rebuild are of the garment as it was
        m_grab = 0;             // a rebuilt simulation holds no grab
    }
    for (const patterns::DrapeEvent& e : m_session->takeEvents()) {
        const QString message = QString::fromStdString(e.message);
        QMetaObject::invokeMethod(this, [this, message] { Q_EMIT event(message); });
    }
    publishScene();
    QMetaObject::invokeMethod(this, [this, incremental] { Q_EMIT rebuilt(incremental); });
}

void DrapeController::publishScene() {
    auto scene = std::make_shared<StaticScene>();
    const patterns::GarmentMesh& mesh = m_session->mesh();
    const patterns::AssembledGarment& assembled = m_session->assembled();
    const patterns::Garment& garment = m_session->project().garment;
    scene->garmentTriangles.resize(mesh.triangleCount, 3);
    scene->patternUvs.resize(assembled.panelOffsets.back(), 2);
    int t = 0;
    for (std::size_t p = 0; p < mesh.panels.size(); ++p) {
        const patterns::PanelMesh& pm = mesh.panels[p];
        const int offset = assembled.panelOffsets[p];
        const int count = static_cast<int>(pm.triangles.rows());
        scene->garmentTriangles.middleRows(t, count) = pm.triangles.array() + offset;
        scene->patternUvs.middleRows(offset, pm.pattern.rows()) = pm.pattern;
        scene->panelTriangles.emplace_back(t, count);
        scene->panelNames.push_back(garment.panels[p].name);
        t += count;
    }
    scene->startPositions = m_session->positions();
    scene->bodyPositions = m_session->body().vertices;
    scene->bodyTriangles = m_session->body().triangles;
    scene->garment = garment;
    scene->bodySlots = m_session->body().slots;
    scene->seamLines = seamLines(mesh, assembled.panelOffsets, scene->garmentTriangles);
    scene->placementLifts = m_session->placementLifts();
    scene->placedCrossings = m_session->placedCrossings();
    m_phase.store(static_cast<int>(m_session->phase()));
    publishPins();
    const std::lock_guard lock(m_mutex);
    m_static = std::move(scene);
}

void DrapeController::loop() {
    for (;;) {
        std::function<void()> command;
        {
            std::unique_lock lock(m_mutex);
            m_wake.wait(lock, [this] { return m_quit || !m_commands.empty() || m_running.load(); });
            if (m_quit) {
                return;
            }
            if (!m_commands.empty()) {
                command = std::move(m_commands.front());
                m_commands.pop_front();
            }
        }
        if (command) {
            command();
            continue; // commands first, then steps
        }
        if (!m_running.load()) {
            continue;
        }
        const patterns::DrapeStatus status = m_session->step();
        m_stepped.store(true);
        m_phase.store(static_cast<int>(m_session->phase()));
        for (const patterns::DrapeEvent& e : m_session->takeEvents()) {
            const QString message = QString::fromStdString(e.message);
            QMetaObject::invokeMethod(this, [this, message] { Q_EMIT event(message); });
        }
        if (m_session->finished() || status == patterns::DrapeStatus::Failed) {
            m_running.store(false);
            const patterns::DrapeFigures f = m_session->figures();
            QString how =
                f.rested ? QStringLiteral("at rest at t = %1 s").arg(f.time, 0, 'f', 2)
                : status == patterns::DrapeStatus::Failed
                    ? QStringLiteral("failed: %1").arg(QString::fromStdString(f.error))
                    : QStringLiteral("stopped at the time limit, t = %1 s").arg(f.time, 0, 'f', 2);
            if (status != patterns::DrapeStatus::Failed) {
                // Whether the garment fits, and what does not (patterns/fit.h).
                const patterns::FitVerdict fit = m_session->fit().verdict;
                how += QStringLiteral(": %1").arg(
                    QString::fromStdString(std::string(patterns::fitName(fit.fit))));
                if (!fit.message.empty()) {
                    how += QStringLiteral(" (%1)").arg(QString::fromStdString(fit.message));
                }
            }
            QMetaObject::invokeMethod(this, [this, how] { Q_EMIT finished(how); });
        }
    }
}

} // namespace atelier::ui
