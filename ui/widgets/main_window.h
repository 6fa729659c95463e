#pragma once
/// The application window: the pattern (2D) and the drape (3D) side by side, menus and a
/// toolbar for files, edits, the simulation and the views, and a status bar with the drape's
/// live figures. The window owns the project being edited (its document, file and modified
/// state) and an undo stack: every edit is a patterns::Edit on the stack, and each change of
/// the document goes to DrapeController, whose worker thread re-meshes what changed and
/// continues the drape; nothing here waits for it.

#include "ui/widgets/drape_controller.h"

#include "patterns/document_edit.h"
#include "patterns/project.h"

#include <QLabel>
#include <QMainWindow>
#include <QMessageBox>
#include <QTimer>
#include <QUndoStack>

#include <functional>
#include <vector>

class QAction;
class QMenu;
class QSplitter;

namespace atelier::ui {

class BodyDock;
class BodyPreview;
class FabricDock;
class PanelDock;
class PatternView;
class SeamDock;
class SimulationDock;
class Viewport;

/// The questions the window asks the user. Each defaults to a modal dialog; tests replace them
/// so that nothing blocks.
struct Prompts {
    /// The project `name` has unsaved changes: Save, Discard or Cancel.
    std::function<QMessageBox::StandardButton(const QString& name)> saveChanges;
    /// A recovery file newer than its project (`project`, empty for an unsaved one) was found:
    /// true restores it.
    std::function<bool(const QString& recovery, const QString& project)> restore;
    /// Where to save a project that has no file yet (empty: cancelled).
    std::function<QString()> saveFileName;
    /// Shows an error message.
    std::function<void(const QString& message)> error;
};

class MainWindow : public QMainWindow {
    Q_OBJECT
  public:
    /// `samplesDir`: where the sample garments are (the File > Samples menu), or empty.
    explicit MainWindow(QString samplesDir, QWidget* parent = nullptr);
    ~MainWindow() override;

    /// Replaces the dialogs the window would show (tests); unset members keep theirs.
    void setPrompts(Prompts prompts);

    // ---- Files ----

    /// Reads the project at `path` and drapes it. A file that cannot be read is an error
    /// message naming it (and the JSON path) and the window keeps what it had. Asks to save
    /// unsaved changes first. False when nothing was opened.
    bool openProject(const QString& path);
    /// Opens a dropped or imported file by its kind: a project, a GarmentCode specification
    /// (.json) imported onto the default body, or a body mesh (setBodyMesh).
    bool openFile(const QString& path);
    /// Drapes the project on the body mesh at `path` (any format io::importBody reads; the
    /// project keeps its absolute path) instead of its body: an undoable change, the garment
    /// placed again. A mesh that cannot be read or is no body is an error message.
    bool setBodyMesh(const QString& path);
    /// A project without panels on the default body (asks to save unsaved changes first).
    bool newProject();
    /// Saves to the project's file (or asks where, as Save As). False when not saved.
    bool save();
    /// Saves to `path` (atomically), which becomes the project's file.
    bool saveAs(const QString& path);
    const patterns::Project& project() const { return m_project; }
    /// The project's file, or empty.
    QString projectPath() const { return m_path; }
    bool isModified() const;
    /// The recently opened or saved projects, newest first (at most 8; QSettings).
    QStringList recentFiles() const;
    /// Opens a recent file; one that no longer exists is removed from the list, with a message.
    bool openRecent(const QString& path);

    // ---- Autosave and recovery ----

    /// Where recovery files go (default: the application's local data folder, "recovery").
    void setRecoveryDirectory(const QString& dir);
    QString recoveryDirectory() const { return m_recoveryDir; }
    /// Autosave period [s] while modified (default 60, QSettings "autosave/seconds").
    void setAutosaveSeconds(int seconds);
    /// The recovery file of the project being edited by this window: HASH-PID-N.atelier, HASH
    /// its project file's path's, PID the process's and N the window's number in it.
    QString recoveryFile() const;
    /// Writes the recovery file now if the project is modified (the autosave timer calls it).
    bool autosave();
    /// Looks for a recovery file newer than its project and, if the user agrees, opens it
    /// (modified, with the project's file as its file). Stale recovery files are removed.
    bool offerRecovery();

    // ---- Edits ----

    /// Applies an edit of the document (`make` edits it and returns the Edit) through the
    /// undo stack. An edit refused is an error message; false then. Consecutive edits with the
    /// same non-empty `mergeKey` (a dock field's, naming the panel) of one panel are one undo
    /// entry (QUndoCommand::mergeWith).
    bool edit(const std::function<Result<patterns::Edit>(patterns::GarmentDocument&)>& make,
              const QString& mergeKey = {});
    bool mirrorSelectedPanel();
    bool duplicateSelectedPanel();
    QUndoStack& undoStack() { return m_undo; }

    DrapeController& drape() { return *m_drape; }
    Viewport& viewport() { return *m_viewport; }
    PatternView& patternView() { return *m_pattern; }

    // ---- Docks, arrangement and file additions ----

    PanelDock& panelDock() { return *m_panelDock; }
    SeamDock& seamDock() { return *m_seamDock; }
    FabricDock& fabricDock() { return *m_fabricDock; }
    SimulationDock& simulationDock() { return *m_simulationDock; }
    BodyDock& bodyDock() { return *m_bodyDock; }
    /// Builds the bodies the Body dock edits, off the UI thread.
    BodyPreview& bodyPreview() { return *m_bodyPreview; }
    /// View > Strain map and View > Seam lines (checkable).
    QAction* strainMapAction() { return m_strainMap; }
    QAction* seamLinesAction() { return m_seamLines; }
    /// Places `panel` on the body's slot `slot` (placePanel, its offset, rotation and clearance
    /// kept): one undoable edit; the panel is placed again there.
    bool placePanelOnSlot(patterns::PanelId panel, const QString& slot);
    /// Places `panels` side by side on slot `slot`, in that order (patterns::sideBySide, each
    /// keeping its rotation, clearance and offset along the slot): one undoable edit.
    bool placePanelsOnSlot(const std::vector<patterns::PanelId>& panels, const QString& slot);
    /// New drape settings for the project: an undoable change (a new particle distance
    /// re-meshes and places the garment again; other values continue the drape).
    bool setDrapeSettings(const patterns::DrapeSettings& settings);
    /// Writes the pattern as SVG (io::writePatternSvg, as `atelier-cli export-pattern`), with a
    /// 10 mm seam allowance, atomically. An error is a message; false then.
    bool exportPatternSvg(const QString& path);
    /// Writes the garment as draped now (the latest snapshot) to an OBJ file, one group per
    /// panel, pattern UVs (File > Export draped mesh), atomically. An error is a message; false
    /// then.
    bool exportDrapedMesh(const QString& path);
    /// Renders the 3D view as it is (camera, drape) at `width`×`height` pixels to a PNG,
    /// atomically. An error is a message; false then.
    bool renderImage(const QString& path, int width, int height);
    /// On the very first start (no settings at all) opens the tshirt sample and says where the
    /// others are; false (nothing done) otherwise or without the sample.
    bool openFirstRunSample();

  Q_SIGNALS:
    /// The project is open and placed (the views show it).
    void projectReady();
    /// An edit (or its undo) reached the drape: the views show the edited garment.
    void documentApplied();

  protected:
    void closeEvent(QCloseEvent* event) override;
    void showEvent(QShowEvent* event) override;
    void dragEnterEvent(QDragEnterEvent* event) override;
    void dropEvent(QDropEvent* event) override;

  private:
    friend class EditCommand;
    friend class BodyCommand;
    friend class DrapeSettingsCommand;
    void setBody(const patterns::BodySource& body);
    /// Makes `body` the project's body through the undo stack (a BodyCommand named `text`,
    /// merging with the one below of the same non-empty `mergeKey`).
    void pushBody(const patterns::BodySource& body, const QString& text,
                  const QString& mergeKey = {});
    void buildMenus();
    /// The docks, their View menu entries and their connections (after buildMenus).
    void buildDocks();
    /// File menu entries: export pattern SVG, render image, import body.
    void addFileActions(QMenu* file);
    /// Shows the document (and drape settings) in the docks; `newProject`: nothing selected.
    void docksFollowDocument(bool newProject = false);
    /// Feeds the live plot and the Simulation dock's phase (the status timer).
    void docksFollowDrape(const DrapeProgress& progress);
    void applyDrapeSettings(const patterns::DrapeSettings& settings);
    /// The pattern view's tools in a Tools menu and a tool bar; its edits on the undo stack.
    void buildPatternTools();
    void updateStatus();
    /// "Placed: press Space to drape" (`again`: "Placed again"), naming the panels the drape
    /// moved apart on their slots because they were placed through others (shown longer then).
    void showPlaced(const StaticScene& scene, bool again);
    void exportMesh();
    void savePicture();
    void toggleRun();
    /// Asks to save unsaved changes: false when the user cancelled (or saving failed).
    bool maybeSave();
    /// Makes `project` (read from `path`) the one being edited and drapes it.
    void adopt(patterns::Project project, const QString& path, bool modified);
    /// An imported pattern (GarmentCode, DXF) adopted as a new, unsaved project; its warnings
    /// in the status bar; an import error in a dialog.
    template <class Imported> bool adoptImport(const QString& path, Result<Imported> imported);
    /// The document changed (an edit, undo or redo): the views and the drape follow.
    void documentChanged();
    void updateTitle();
    void addRecent(const QString& path);
    void fillRecentMenu();
    void removeRecoveryFile();
    void showError(const QString& message);
    QString lastDirectory() const;

    DrapeController* m_drape;
    PatternView* m_pattern;
    Viewport* m_viewport;
    QSplitter* m_splitter = nullptr;
    QString m_samplesDir;
    QAction* m_run = nullptr;
    QAction* m_reset = nullptr;
    QMenu* m_viewMenu = nullptr;
    PanelDock* m_panelDock = nullptr;
    SeamDock* m_seamDock = nullptr;
    FabricDock* m_fabricDock = nullptr;
    SimulationDock* m_simulationDock = nullptr;
    BodyDock* m_bodyDock = nullptr;
    BodyPreview* m_bodyPreview = nullptr;
    QString m_bodyField; ///< the Body dock's field edited last
    QAction* m_importBody = nullptr;
    QAction* m_showSlots = nullptr;
    QAction* m_strainMap = nullptr;
    QAction* m_seamLines = nullptr;
    bool m_stateRestored = false; ///< the docks' state, restored when first shown
    QMenu* m_recent = nullptr;
    QLabel m_phase;
    QLabel m_time;
    QLabel m_speed;
    QLabel m_energy;
    QLabel m_contacts;
    QLabel m_fps;
    QTimer m_statusTimer;
    long m_lastSteps = 0;
    double m_lastWall = 0;

    patterns::Project m_project; ///< the project being edited (its document is the truth)
    QString m_path;              ///< its file, or empty
    QUndoStack m_undo;
    /// Modified without an edit on the stack (a restored recovery file, an import).
    bool m_modifiedOutsideStack = false;
    Prompts m_prompts;
    QString m_recoveryDir;
    int m_windowNumber = 0; ///< this window's number in the process (its recovery file's name)
    QTimer m_autosave;
};

} // namespace atelier::ui
