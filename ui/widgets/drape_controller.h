#pragma once
/// The drape behind the window: a DrapeSession owned by a worker thread, which prepares and
/// steps it; the window sends it commands (open, start, pause, reset) and reads what it
/// publishes (snapshots, figures) without ever waiting for a step.

#include "patterns/document_edit.h"
#include "patterns/drape_session.h"

#include "sim/simulation.h"

#include <QObject>
#include <QString>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

namespace atelier::ui {

/// One document seam's sewn edges in the cloth: both sides, as cloth edges between consecutive
/// sewn vertices of a side.
struct SeamLine {
    int seam = 0;              ///< the seam's index in the document (render::seamColour's)
    std::vector<int> vertices; ///< global garment vertices on the seam's two sides
    sim::MatX2i segments;      ///< (|S|×2) indices into `vertices`; each a cloth mesh edge
};

/// What does not change while a drape runs: the triangles, the panels' ranges and colours'
/// order, the body, the start positions. Made once per prepare, shared read-only.
struct StaticScene {
    sim::MatX3i garmentTriangles;                    ///< (|F|×3) over all panels
    std::vector<std::pair<int, int>> panelTriangles; ///< per panel: first triangle, count
    std::vector<std::string> panelNames;
    sim::MatX2 patternUvs;     ///< (|V|×2) pattern coordinates [m]
    sim::MatX3 startPositions; ///< (|V|×3) the garment as placed [m]
    sim::MatX3 bodyPositions;  ///< (|B|×3) [m]
    sim::MatX3i bodyTriangles; ///< (|T|×3)
    patterns::Garment garment; ///< the garment as meshed (the pattern view draws it)
    /// The body's arrangement slots (the 3D view marks them; panels are placed on them).
    std::vector<patterns::ArrangementSlot> bodySlots;
    /// Each seam's lines (the 3D view draws them in the seam's colour, following the cloth).
    std::vector<SeamLine> seamLines;
    /// Panels moved apart on their slots because they were placed through others
    /// (patterns::DrapeSession::placementLifts), and the triangle pairs that crossed before.
    std::vector<patterns::PlacementLift> placementLifts;
    long placedCrossings = 0;
};

/// The figures the status bar shows, from the latest snapshot and the session's phase.
struct DrapeProgress {
    double time = 0; ///< simulated [s]
    long steps = 0;
    double wallTime = 0;      ///< wall time in steps [s]
    double kineticEnergy = 0; ///< [J]
    long contacts = 0;
    patterns::DrapePhase phase = patterns::DrapePhase::Empty;
    bool running = false;
};

class DrapeController : public QObject {
    Q_OBJECT
  public:
    explicit DrapeController(QObject* parent = nullptr);
    ~DrapeController() override;
    DrapeController(const DrapeController&) = delete;
    DrapeController& operator=(const DrapeController&) = delete;

    /// A body already built for `source` (the Body dock's preview): a prepare whose project
    /// has that body source takes it instead of building it again (as it does the last few
    /// mannequins it built itself).
    void offerBody(const patterns::BodySource& source, patterns::Body body);
    /// Bodies the drape has built or loaded itself (not taken from the recent ones).
    int bodiesBuilt() const { return m_bodiesBuilt.load(); }

    /// Loads a project file and prepares its drape on the worker (opened() or failed() follow).
    void open(const QString& path);
    /// Drapes `project` (read by the window; `path` is its file, empty when it has none, and
    /// body meshes resolve against it): placed anew, opened() or failed() follow. A project
    /// without panels is opened with nothing to drape.
    void setProject(patterns::Project project, const QString& path);
    /// The window's edited document. When the same panels and seams remain, the panels whose
    /// drawing or pins changed are re-meshed and the drape continues from where it is
    /// (DrapeSession::setPanel: unchanged panels stay where they are), a panel whose placement
    /// alone changed is placed again on its slot (DrapeSession::placePanel), and fabrics whose
    /// values changed take them and new fabrics are added as the drape goes on; when panels
    /// were added, removed, reordered or renamed, seams changed or fabrics were removed or
    /// reordered, the garment is placed again. rebuilt()
    /// or failed() follow.
    void setDocument(patterns::GarmentDocument document);
    /// New drape settings for the project: a new particle distance re-meshes and places the
    /// garment again, anything else continues the drape (DrapeSession::setDrapeSettings).
    /// rebuilt() or failed() follow.
    void setDrapeSettings(const patterns::DrapeSettings& settings);
    void start();
    void pause();
    /// The garment back where it was placed, nothing stepped.
    void reset();
    bool running() const { return m_running.load(); }

    /// Grabs the cloth at `point` (a garment triangle, in StaticScene::garmentTriangles' order,
    /// and barycentric coordinates) and pulls it towards `target` [m]; the drape runs (a drape
    /// at rest wakes). The seed paper's interactive manipulation: the engine's grab drive.
    void grab(const sim::ClothPoint& point, const sim::Vec3& target);
    /// Moves the grab's target [m].
    void moveGrab(const sim::Vec3& target);
    /// Lets go of the cloth.
    void release();

    /// Pins garment vertex `vertex` (global, as StaticScene's arrays) where it is now: the
    /// engine holds it from the next step and the project's document gains the pin (its
    /// pattern point, held at its present position), so saving or resetting keeps it.
    void pin(int vertex);
    /// Removes the pin holding `vertex` from the drape and the document; the drape runs so the
    /// cloth can move again.
    void unpin(int vertex);
    /// Global vertices held by the garment's pins at simulated time `time` [s] (a snapshot's:
    /// a pin whose release time has passed is left out), as of the last pin command or prepare
    /// (any thread). All of them by default.
    std::vector<int> pinnedVertices(double time = -1) const;
    /// The project's garment document as the window has edited it (any thread).
    patterns::GarmentDocument document() const;

    /// Copies the latest published snapshot (any thread); false when none since the prepare.
    bool snapshot(sim::Snapshot& out);
    /// The drape's figures now (any thread).
    DrapeProgress progress();
    /// The project's file, or empty.
    QString path() const;
    /// The garment as it is now (positions) with its static scene; empty when nothing is open.
    std::shared_ptr<const StaticScene> staticScene() const;

  Q_SIGNALS:
    /// A project was opened and prepared: its static scene is ready.
    void opened(const QString& path);
    /// Opening or a step failed: the message says what (file, JSON path, cause).
    void failed(const QString& message);
    /// The drape stopped by itself: at rest, at the time limit, or failed.
    void finished(const QString& how);
    /// A sewing event (seams sewn, gravity on, at rest, ...), for the status bar.
    void event(const QString& message);
    /// A pin was added or removed (pinnedVertices() and document() have changed).
    void pinsChanged();
    /// A pin command changed the document by `edit` (addPin or removePin), so that the window
    /// can apply it to its own document and put it on its undo stack.
    void pinEdited(const patterns::Edit& edit);
    /// setDocument() was applied: the static scene is the edited garment's; `continued` says
    /// whether the drape went on from where it was (else it was placed again).
    void rebuilt(bool continued);

  private:
    void post(std::function<void()> command);
    void loop();
    void openOnWorker(const QString& path);
    /// Gives the session m_project and prepares it (or, without panels, clears the scene).
    void placeOnWorker(const QString& path);
    /// Prepares the session's project; publishes its scene and emits opened() (or failed()).
    void prepareOnWorker();
    /// Prepares the session (worker thread): false, with failed() emitted, when it cannot.
    bool prepareSession();
    void editOnWorker(patterns::GarmentDocument document);
    /// Copies the session's meshes, body and positions into a new static scene.
    void publishScene();
    /// Copies the pinned vertices and the document for other threads (worker thread).
    void publishPins();

    /// One session for the window's life (its snapshot buffer is read from the UI thread);
    /// opening a project gives it the new project. Stepped on the worker thread only.
    std::unique_ptr<patterns::DrapeSession> m_session;
    patterns::Project m_project;         ///< worker thread only
    std::filesystem::path m_projectFile; ///< worker thread only (the body provider reads it)
    /// A step has been published since the last prepare (snapshots before it are of the
    /// garment as it was).
    std::atomic<bool> m_stepped{false};
    QString m_path;                              ///< guarded by m_mutex
    std::shared_ptr<const StaticScene> m_static; ///< guarded by m_mutex
    /// Pinned vertices and their release times [s] (simulated); guarded by m_mutex.
    std::vector<std::pair<int, double>> m_pinned;
    patterns::GarmentDocument m_document; ///< guarded by m_mutex
    /// Bodies built lately and their sources, the latest last: offered ones (offerBody) and
    /// mannequins the drape built, so that undoing a body change does not build the earlier
    /// one again (1–4 s); at most RECENT_BODIES; guarded by m_mutex.
    std::vector<std::pair<patterns::BodySource, patterns::Body>> m_recentBodies;
    static constexpr std::size_t RECENT_BODIES = 4;
    std::atomic<int> m_bodiesBuilt{0};
    /// Keeps `body` as the latest of m_recentBodies (m_mutex held).
    void rememberBody(const patterns::BodySource& source, patterns::Body body);

    mutable std::mutex m_mutex;
    std::condition_variable m_wake;
    std::deque<std::function<void()>> m_commands; ///< guarded by m_mutex
    bool m_quit = false;                          ///< guarded by m_mutex
    std::atomic<bool> m_running{false};
    int m_grab = 0; ///< the engine's grab handle, 0 = none (worker thread only)
    std::atomic<int> m_phase{0};
    std::thread m_worker;
};

} // namespace atelier::ui
