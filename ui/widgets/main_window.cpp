#include "ui/widgets/main_window.h"

#include "ui/widgets/body_dock.h"
#include "ui/widgets/pattern_view.h"
#include "ui/widgets/viewport.h"

#include "io/atomic_file.h"
#include "io/body_file.h"
#include "io/dxf_aama.h"
#include "io/garmentcode.h"
#include "io/materials.h"
#include "io/mesh_import.h"
#include "io/obj.h"
#include "io/project_file.h"

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QCryptographicHash>
#include <QDateTime>
#include <QDir>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFileDialog>
#include <QFileInfo>
#include <QKeySequence>
#include <QMenuBar>
#include <QMimeData>
#include <QSaveFile>
#include <QSettings>
#include <QShowEvent>
#include <QSplitter>
#include <QStandardPaths>
#include <QStatusBar>
#include <QToolBar>
#include <QUndoCommand>

#include <algorithm>
#include <cerrno>
#include <set>

#ifdef Q_OS_UNIX
#include <sys/types.h>

#include <csignal>
#endif

namespace atelier::ui {

namespace {

/// The numbers of the windows open in this process (UI thread only), and the last one given.
std::set<int>& liveWindows() {
    static std::set<int> windows;
    return windows;
}
int& lastWindowNumber() {
    static int last = 0;
    return last;
}

constexpr int MAX_RECENT = 8;
constexpr int DEFAULT_AUTOSAVE_SECONDS = 60;

bool isBodyMesh(const QString& path) {
    const std::string suffix = "." + QFileInfo(path).suffix().toLower().toStdString();
    const std::vector<std::string>& kinds = io::bodyMeshExtensions();
    return std::find(kinds.begin(), kinds.end(), suffix) != kinds.end();
}

/// The kinds of file the window opens (by suffix): projects, GarmentCode specifications,
/// DXF-AAMA patterns, body meshes.
bool openable(const QString& path) {
    const QString suffix = QFileInfo(path).suffix().toLower();
    return suffix == "atelier" || suffix == "json" || suffix == "dxf" || isBodyMesh(path);
}

/// QUndoCommand::id() of edits that merge with the one below of the same merge key.
constexpr int MERGEABLE_EDIT = 1;
/// QUndoCommand::id() of Body dock changes that merge with the one below of the same field.
constexpr int MERGEABLE_BODY = 2;

/// A project without panels, with one fabric ("fabric", the cotton preset, as a DXF import's)
/// for the panels drawn in it, sewn over 1 s as the samples and the importers' projects are: a
/// tube of two rectangles drawn in the window, sewn over the default 0.3 s, ended at the time
/// limit stretched to 3.6 times its area (docs/benchmarks.md, "A skirt drawn in the window").
patterns::Project untitledProject() {
    patterns::Project project;
    project.name = "untitled";
    project.drape.sewingTime = 1.0;
    const io::MaterialPresets& presets = io::builtinMaterialPresets();
    if (const auto cotton = presets.find("cotton"); cotton != presets.end()) {
        project.document.materials.push_back(patterns::GarmentMaterial{"fabric", cotton->second});
        patterns::syncGarment(project);
    }
    return project;
}

} // namespace

/// One edit on the undo stack: redo and undo put the window's document in the edit's after-
/// and before-state and hand it to the drape.
class EditCommand : public QUndoCommand {
  public:
    /// `applied`: the document (and the drape) already hold the edit (a pin made in the 3D
    /// view); the first redo then does nothing.
    EditCommand(MainWindow* window, patterns::Edit edit, bool applied, QString mergeKey = {})
        : QUndoCommand(QString::fromStdString(edit.description)), m_window(window),
          m_edit(std::move(edit)), m_skipRedo(applied), m_mergeKey(std::move(mergeKey)) {}

    /// Edits with a merge key (a dock's field) merge with the one below of the same key.
    int id() const override { return m_mergeKey.isEmpty() ? -1 : MERGEABLE_EDIT; }
    /// The consecutive changes of one field of one panel are one entry: this edit's before,
    /// the newer one's after. Only edits of that one panel and nothing else merge.
    bool mergeWith(const QUndoCommand* other) override {
        const auto* newer = dynamic_cast<const EditCommand*>(other);
        const auto single = [](const patterns::Edit& e) {
            return e.panels.size() == 1 && e.seams.empty() && !e.materialsBefore &&
                   e.panels.front().before && e.panels.front().after;
        };
        if (newer == nullptr || newer->m_mergeKey != m_mergeKey || !single(m_edit) ||
            !single(newer->m_edit) ||
            newer->m_edit.panels.front().before->id != m_edit.panels.front().after->id) {
            return false;
        }
        m_edit.panels.front().after = newer->m_edit.panels.front().after;
        m_edit.panels.front().afterIndex = newer->m_edit.panels.front().afterIndex;
        m_edit.nextIdAfter = newer->m_edit.nextIdAfter;
        m_edit.description = newer->m_edit.description;
        setText(newer->text());
        return true;
    }

    void redo() override {
        if (m_skipRedo) {
            m_skipRedo = false;
            return;
        }
        patterns::redo(m_window->m_project.document, m_edit);
        m_window->documentChanged();
    }
    void undo() override {
        patterns::undo(m_window->m_project.document, m_edit);
        m_window->documentChanged();
    }

  private:
    MainWindow* m_window;
    patterns::Edit m_edit;
    bool m_skipRedo;
    QString m_mergeKey;
};

MainWindow::MainWindow(QString samplesDir, QWidget* parent)
    : QMainWindow(parent), m_drape(new DrapeController(this)), m_pattern(new PatternView),
      m_viewport(new Viewport(m_drape)), m_samplesDir(std::move(samplesDir)) {
    m_splitter = new QSplitter;
    m_splitter->addWidget(m_pattern);
    m_splitter->addWidget(m_viewport);
    m_splitter->setSizes({480, 800});
    setCentralWidget(m_splitter);
    setAcceptDrops(true);
    m_prompts = Prompts{
        [this](const QString& name) {
            return QMessageBox::question(
                this, tr("Atelier"), tr("Save the changes to %1?").arg(name),
                QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
        },
        [this](const QString& recovery, const QString& project) {
            return QMessageBox::question(
                       this, tr("Atelier"),
                       tr("Atelier did not close cleanly. Restore the unsaved changes to %1 "
                          "(autosaved %2)?")
                           .arg(project.isEmpty() ? tr("an untitled project") : project,
                                QFileInfo(recovery).lastModified().toString()),
                       QMessageBox::Yes | QMessageBox::No, QMessageBox::Yes) == QMessageBox::Yes;
        },
        [this] {
            return QFileDialog::getSaveFileName(this, tr("Save the project"), lastDirectory(),
                                                tr("Atelier projects (*.atelier)"));
        },
        [this](const QString& message) { QMessageBox::warning(this, tr("Atelier"), message); }};
    m_recoveryDir =
        QStandardPaths::writableLocation(QStandardPaths::AppLocalDataLocation) + "/recovery";
    m_windowNumber = ++lastWindowNumber();
    liveWindows().insert(m_windowNumber);
    m_project = untitledProject();
    buildMenus();
    buildDocks();
    buildPatternTools();
    // The untitled project's fabric is the one panels drawn before any file is opened take.
    m_pattern->setDocument(m_project.document);
    docksFollowDocument(true);
    updateTitle();
    connect(&m_undo, &QUndoStack::cleanChanged, this, [this] { updateTitle(); });
    connect(&m_autosave, &QTimer::timeout, this, [this] { autosave(); });
    setAutosaveSeconds(QSettings().value("autosave/seconds", DEFAULT_AUTOSAVE_SECONDS).toInt());

    for (QLabel* label : {&m_phase, &m_time, &m_speed, &m_energy, &m_contacts, &m_fps}) {
        label->setMinimumWidth(90);
        statusBar()->addPermanentWidget(label);
    }
    connect(&m_statusTimer, &QTimer::timeout, this, &MainWindow::updateStatus);
    m_statusTimer.start(250);
    updateStatus();

    connect(m_drape, &DrapeController::opened, this, [this](const QString& /*path*/) {
        m_viewport->sceneChanged();
        if (const auto scene = m_drape->staticScene()) {
            showPlaced(*scene, false);
        }
        m_lastSteps = 0;
        m_lastWall = 0;
        Q_EMIT projectReady();
    });
    connect(m_drape, &DrapeController::rebuilt, this, [this](bool continued) {
        m_viewport->sceneChanged(true);
        if (const auto scene = m_drape->staticScene(); scene && !continued) {
            showPlaced(*scene, true);
        }
        Q_EMIT documentApplied();
    });
    connect(m_drape, &DrapeController::pinEdited, this, [this](const patterns::Edit& e) {
        // The drape and its copy of the document hold the pin already; the window's document
        // takes the same edit, and the stack can undo it.
        patterns::redo(m_project.document, e);
        patterns::syncGarment(m_project);
        m_undo.push(new EditCommand(this, e, true));
    });
    connect(m_pattern, &PatternView::pointMoveRequested, this,
            [this](quint32 panel, quint32 point, double x, double y) {
                edit([&](patterns::GarmentDocument& d) {
                    return patterns::movePoint(d, patterns::PanelId{panel},
                                               patterns::PointId{point}, patterns::Vec2(x, y));
                });
            });
    connect(
        m_pattern, &PatternView::pointDeleteRequested, this, [this](quint32 panel, quint32 point) {
            edit([&](patterns::GarmentDocument& d) {
                return patterns::deletePoint(d, patterns::PanelId{panel}, patterns::PointId{point});
            });
        });
    connect(m_pattern, &PatternView::pointAddRequested, this,
            [this](quint32 panel, quint32 edge, double t, double x, double y) {
                edit([&](patterns::GarmentDocument& d) {
                    return patterns::addPoint(d, patterns::PanelId{panel}, patterns::EdgeId{edge},
                                              t, patterns::Vec2(x, y));
                });
            });
    connect(m_drape, &DrapeController::failed, this, [this](const QString& message) {
        statusBar()->showMessage(message);
        if (isVisible()) {
            showError(message);
        }
    });
    connect(m_drape, &DrapeController::event, this,
            [this](const QString& message) { statusBar()->showMessage(message, 4000); });
    connect(m_drape, &DrapeController::finished, this,
            [this](const QString& how) { statusBar()->showMessage(tr("Drape %1").arg(how)); });
    connect(m_pattern, &PatternView::panelSelected, this, [this](const QString& name) {
        if (!name.isEmpty()) {
            statusBar()->showMessage(tr("Panel %1").arg(name), 3000);
        }
    });
    resize(1280, 760);
    const QSettings settings;
    restoreGeometry(settings.value("window/geometry").toByteArray());
    // The docks' and toolbars' state is restored in the first showEvent.
    m_splitter->restoreState(settings.value("window/splitter").toByteArray());
}

MainWindow::~MainWindow() {
    liveWindows().erase(m_windowNumber);
}

void MainWindow::setPrompts(Prompts prompts) {
    if (prompts.saveChanges) {
        m_prompts.saveChanges = std::move(prompts.saveChanges);
    }
    if (prompts.restore) {
        m_prompts.restore = std::move(prompts.restore);
    }
    if (prompts.saveFileName) {
        m_prompts.saveFileName = std::move(prompts.saveFileName);
    }
    if (prompts.error) {
        m_prompts.error = std::move(prompts.error);
    }
}

void MainWindow::buildMenus() {
    QMenu* file = menuBar()->addMenu(tr("&File"));
    QAction* newAction = file->addAction(tr("&New"), this, [this] { newProject(); });
    newAction->setShortcut(QKeySequence::New);
    QAction* open = file->addAction(tr("&Open…"), this, [this] {
        const QString path = QFileDialog::getOpenFileName(
            this, tr("Open a garment project"), lastDirectory(),
            tr("Atelier projects (*.atelier);;GarmentCode specifications (*.json);;"
               "DXF-AAMA patterns (*.dxf)"));
        if (!path.isEmpty()) {
            QSettings().setValue("files/lastDirectory", QFileInfo(path).absolutePath());
            openFile(path);
        }
    });
    open->setShortcut(QKeySequence::Open);
    m_recent = file->addMenu(tr("Open &recent"));
    connect(m_recent, &QMenu::aboutToShow, this, &MainWindow::fillRecentMenu);
    if (!m_samplesDir.isEmpty()) {
        QMenu* samples = file->addMenu(tr("&Samples"));
        for (const QString& name : QDir(m_samplesDir).entryList({"*.atelier"}, QDir::Files)) {
            samples->addAction(QFileInfo(name).baseName(), this,
                               [this, name] { openProject(QDir(m_samplesDir).filePath(name)); });
        }
    }
    QAction* saveAction = file->addAction(tr("&Save"), this, [this] { save(); });
    saveAction->setShortcut(QKeySequence::Save);
    QAction* saveAsAction = file->addAction(tr("Save &as…"), this, [this] {
        const QString path = m_prompts.saveFileName();
        if (!path.isEmpty()) {
            saveAs(path);
        }
    });
    saveAsAction->setShortcut(QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_S));
    file->addSeparator();
    file->addAction(tr("&Export draped mesh…"), this, &MainWindow::exportMesh);
    file->addAction(tr("Save &picture…"), this, &MainWindow::savePicture);
    addFileActions(file);
    file->addSeparator();
    QAction* quit = file->addAction(tr("&Quit"), this, &QWidget::close);
    quit->setShortcut(QKeySequence::Quit);

    QMenu* editMenu = menuBar()->addMenu(tr("&Edit"));
    QAction* undo = m_undo.createUndoAction(this, tr("&Undo"));
    undo->setShortcut(QKeySequence::Undo);
    QAction* redo = m_undo.createRedoAction(this, tr("&Redo"));
    redo->setShortcuts(
        {QKeySequence(Qt::CTRL | Qt::SHIFT | Qt::Key_Z), QKeySequence(Qt::CTRL | Qt::Key_Y)});
    editMenu->addAction(undo);
    editMenu->addAction(redo);
    editMenu->addSeparator();
    editMenu->addAction(tr("&Mirror panel"), this, [this] { mirrorSelectedPanel(); });
    QAction* duplicate =
        editMenu->addAction(tr("&Duplicate panel"), this, [this] { duplicateSelectedPanel(); });
    duplicate->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_D));

    QMenu* sim = menuBar()->addMenu(tr("&Simulation"));
    m_run = sim->addAction(tr("&Drape / pause"), this, &MainWindow::toggleRun);
    m_run->setShortcut(Qt::Key_Space);
    QAction* reset = sim->addAction(tr("&Reset"), this, [this] { m_drape->reset(); });
    reset->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_R));
    m_reset = reset;

    QMenu* view = menuBar()->addMenu(tr("&View"));
    m_viewMenu = view;
    int key = Qt::Key_1;
    for (const render::View v : render::ALL_VIEWS) {
        QAction* a = view->addAction(QString::fromUtf8(render::viewName(v).data()), this,
                                     [this, v] { m_viewport->setView(v); });
        a->setShortcut(QKeySequence(key++));
    }

    QToolBar* tools = addToolBar(tr("Main"));
    tools->setObjectName("main-toolbar");
    tools->addAction(open);
    tools->addAction(m_run);
    tools->addAction(reset);
}

bool MainWindow::openProject(const QString& path) {
    if (!maybeSave()) {
        return false;
    }
    auto project = io::loadProject(path.toStdString());
    if (!project.ok()) {
        showError(tr("Could not open %1:\n%2")
                      .arg(path, QString::fromStdString(project.error().toString())));
        return false;
    }
    adopt(std::move(project.value()), path, false);
    addRecent(path);
    return true;
}

bool MainWindow::openFile(const QString& path) {
    if (isBodyMesh(path)) {
        return setBodyMesh(path);
    }
    const QString suffix = QFileInfo(path).suffix().toLower();
    if (suffix != "json" && suffix != "dxf") {
        return openProject(path);
    }
    if (!maybeSave()) {
        return false;
    }
    if (suffix == "dxf") { // its pieces, unsewn, laid on the torso slots
        return adoptImport(path, io::importDxfAama(path.toStdString()));
    }
    // A GarmentCode specification, placed on the default mannequin's slots.
    const patterns::BodySource body;
    auto mannequin = io::loadBody(body, {}, {});
    if (!mannequin.ok()) {
        showError(QString::fromStdString(mannequin.error().toString()));
        return false;
    }
    return adoptImport(path, io::importGarmentCode(path.toStdString(), mannequin.value()));
}

template <class Imported>
bool MainWindow::adoptImport(const QString& path, Result<Imported> imported) {
    if (!imported.ok()) {
        showError(tr("Could not import %1:\n%2")
                      .arg(path, QString::fromStdString(imported.error().toString())));
        return false;
    }
    adopt(std::move(imported.value().project), QString(), true);
    const std::size_t warnings = imported.value().warnings.size();
    statusBar()->showMessage(
        warnings == 0 ? tr("Imported %1").arg(path)
                      : tr("Imported %1 with %2 warning(s): %3")
                            .arg(path)
                            .arg(warnings)
                            .arg(QString::fromStdString(imported.value().warnings.front())),
        8000);
    return true;
}

bool MainWindow::newProject() {
    if (!maybeSave()) {
        return false;
    }
    adopt(untitledProject(), QString(), false);
    return true;
}

void MainWindow::adopt(patterns::Project project, const QString& path, bool modified) {
    removeRecoveryFile(); // the project left behind was saved or its changes discarded
    m_project = std::move(project);
    patterns::syncGarment(m_project);
    m_path = path;
    m_undo.clear();
    m_modifiedOutsideStack = modified;
    m_pattern->setDocument(m_project.document);
    docksFollowDocument(true);
    statusBar()->showMessage(tr("Opening %1…").arg(path.isEmpty() ? tr("untitled") : path));
    m_drape->setProject(m_project, path);
    updateTitle();
}

bool MainWindow::save() {
    QString path = m_path;
    if (path.isEmpty()) {
        path = m_prompts.saveFileName();
        if (path.isEmpty()) {
            return false;
        }
    }
    return saveAs(path);
}

bool MainWindow::saveAs(const QString& path) {
    if (auto saved = io::saveProject(path.toStdString(), m_project); !saved.ok()) {
        showError(tr("Could not save %1:\n%2")
                      .arg(path, QString::fromStdString(saved.error().toString())));
        return false;
    }
    removeRecoveryFile();
    m_path = path;
    m_modifiedOutsideStack = false;
    m_undo.setClean();
    QSettings().setValue("files/lastDirectory", QFileInfo(path).absolutePath());
    addRecent(path);
    updateTitle();
    statusBar()->showMessage(tr("Saved %1").arg(path), 4000);
    return true;
}

bool MainWindow::isModified() const {
    return m_modifiedOutsideStack || !m_undo.isClean();
}

bool MainWindow::maybeSave() {
    if (!isModified()) {
        return true;
    }
    const QString name = m_path.isEmpty() ? tr("the untitled project") : m_path;
    switch (m_prompts.saveChanges(name)) {
    case QMessageBox::Save:
        return save();
    case QMessageBox::Discard:
        return true;
    default:
        return false;
    }
}

void MainWindow::updateTitle() {
    const QString name =
        m_path.isEmpty() ? QString::fromStdString(m_project.name) : QFileInfo(m_path).fileName();
    setWindowTitle(tr("%1[*] — Atelier").arg(name));
    setWindowModified(isModified());
}

QString MainWindow::lastDirectory() const {
    const QString last = QSettings().value("files/lastDirectory").toString();
    return !last.isEmpty() && QFileInfo(last).isDir() ? last : m_samplesDir;
}

QStringList MainWindow::recentFiles() const {
    return QSettings().value("files/recent").toStringList();
}

void MainWindow::addRecent(const QString& path) {
    const QString absolute = QFileInfo(path).absoluteFilePath();
    QStringList recent = recentFiles();
    recent.removeAll(absolute);
    recent.prepend(absolute);
    while (recent.size() > MAX_RECENT) {
        recent.removeLast();
    }
    QSettings().setValue("files/recent", recent);
}

void MainWindow::fillRecentMenu() {
    m_recent->clear();
    for (const QString& path : recentFiles()) {
        m_recent->addAction(QFileInfo(path).fileName(), this, [this, path] { openRecent(path); })
            ->setToolTip(path);
    }
    m_recent->setEnabled(!m_recent->isEmpty());
}

bool MainWindow::openRecent(const QString& path) {
    if (!QFileInfo(path).isFile()) {
        QStringList recent = recentFiles();
        recent.removeAll(path);
        QSettings().setValue("files/recent", recent);
        showError(tr("%1 no longer exists; it is removed from the recent files.").arg(path));
        return false;
    }
    return openProject(path);
}

void MainWindow::showError(const QString& message) {
    statusBar()->showMessage(message, 10000);
    m_prompts.error(message);
}

/// A new body for the project (not a document edit): redo and undo swap the body source and
/// place the garment again on it.
class BodyCommand : public QUndoCommand {
  public:
    /// `mergeKey` (a Body dock field's): consecutive changes of one field are one entry.
    BodyCommand(MainWindow* window, patterns::BodySource before, patterns::BodySource after,
                const QString& text, QString mergeKey = {})
        : QUndoCommand(text), m_window(window), m_before(std::move(before)),
          m_after(std::move(after)), m_mergeKey(std::move(mergeKey)) {}
    void redo() override { m_window->setBody(m_after); }
    void undo() override { m_window->setBody(m_before); }
    int id() const override { return m_mergeKey.isEmpty() ? -1 : MERGEABLE_BODY; }
    bool mergeWith(const QUndoCommand* other) override {
        const auto* newer = dynamic_cast<const BodyCommand*>(other);
        if (newer == nullptr || newer->m_mergeKey != m_mergeKey) {
            return false;
        }
        m_after = newer->m_after;
        return true;
    }

  private:
    MainWindow* m_window;
    patterns::BodySource m_before;
    patterns::BodySource m_after;
    QString m_mergeKey;
};

bool MainWindow::setBodyMesh(const QString& path) {
    // Read it here so that a mesh that is no body is an error at once, naming the file.
    if (auto body = io::importBody(path.toStdString()); !body.ok()) {
        showError(tr("Could not use %1 as the body:\n%2")
                      .arg(path, QString::fromStdString(body.error().toString())));
        return false;
    }
    patterns::BodySource source;
    source.meshPath = QFileInfo(path).absoluteFilePath().toStdString(); // kept absolute
    pushBody(source, tr("body %1").arg(QFileInfo(path).fileName()));
    return true;
}

void MainWindow::pushBody(const patterns::BodySource& body, const QString& text,
                          const QString& mergeKey) {
    m_undo.push(new BodyCommand(this, m_project.body, body, text, mergeKey));
}

void MainWindow::setBody(const patterns::BodySource& body) {
    m_project.body = body;
    m_bodyDock->setBody(body);
    statusBar()->showMessage(tr("Placing the garment on the new body…"));
    m_drape->setProject(m_project, m_path);
    updateTitle();
}

// ---- Edits ----

bool MainWindow::edit(const std::function<Result<patterns::Edit>(patterns::GarmentDocument&)>& make,
                      const QString& mergeKey) {
    auto made = make(m_project.document);
    if (!made.ok()) {
        showError(QString::fromStdString(made.error().toString()));
        return false;
    }
    // Back to the state before, so that the stack's first redo applies it like any other.
    patterns::undo(m_project.document, made.value());
    m_undo.push(new EditCommand(this, std::move(made.value()), false, mergeKey));
    return true;
}

void MainWindow::documentChanged() {
    patterns::syncGarment(m_project);
    m_pattern->setDocument(m_project.document, true);
    docksFollowDocument();
    m_drape->setDocument(m_project.document);
    updateTitle();
}

bool MainWindow::mirrorSelectedPanel() {
    const patterns::PanelId panel = m_pattern->selectedPanel();
    if (!panel) {
        statusBar()->showMessage(tr("Select a panel to mirror"), 4000);
        return false;
    }
    return edit([panel](patterns::GarmentDocument& d) { return patterns::mirrorPanel(d, panel); });
}

bool MainWindow::duplicateSelectedPanel() {
    const patterns::doc::Panel* panel = m_project.document.panel(m_pattern->selectedPanel());
    if (panel == nullptr) {
        statusBar()->showMessage(tr("Select a panel to duplicate"), 4000);
        return false;
    }
    std::string name = panel->name + " copy";
    for (int k = 2; m_project.document.panelNamed(name) != nullptr; ++k) {
        name = panel->name + " copy " + std::to_string(k);
    }
    const patterns::PanelId id = panel->id;
    return edit(
        [id, name](patterns::GarmentDocument& d) { return patterns::duplicatePanel(d, id, name); });
}

// ---- Pattern tools ----

void MainWindow::buildPatternTools() {
    // The pattern view's tools make their edits through the undo stack.
    m_pattern->setEditor([this](const PatternView::EditMaker& make) { return edit(make); });
    connect(m_pattern, &PatternView::message, this,
            [this](const QString& text) { statusBar()->showMessage(text, 8000); });
    QMenu* menu = menuBar()->addMenu(tr("&Tools"));
    QToolBar* bar = addToolBar(tr("Pattern tools"));
    bar->setObjectName("pattern-toolbar");
    for (QAction* a : m_pattern->toolActions()) {
        menu->addAction(a);
        bar->addAction(a);
    }
    menu->addSeparator();
    for (QAction* a : m_pattern->editActions()) {
        menu->addAction(a);
    }
}

// ---- Autosave and recovery ----

void MainWindow::setRecoveryDirectory(const QString& dir) {
    m_recoveryDir = dir;
}

void MainWindow::setAutosaveSeconds(int seconds) {
    m_autosave.stop();
    if (seconds > 0) {
        m_autosave.start(seconds * 1000);
    }
}

QString MainWindow::recoveryFile() const {
    // One file per project file and window, named by its path's hash (unsaved projects: the
    // hash of "untitled"), the process id and the window's number in the process: two windows
    // editing one project at once, in one program or two, write two files.
    const QString key =
        m_path.isEmpty() ? QStringLiteral("untitled") : QFileInfo(m_path).absoluteFilePath();
    const QString hash = QString::fromLatin1(
        QCryptographicHash::hash(key.toUtf8(), QCryptographicHash::Sha1).toHex().left(16));
    return QDir(m_recoveryDir)
        .filePath(QStringLiteral("%1-%2-%3.atelier")
                      .arg(hash)
                      .arg(QCoreApplication::applicationPid())
                      .arg(m_windowNumber));
}

namespace {

/// Whether recovery file `path` (HASH-PID-WINDOW.atelier) is being written by a window still
/// open: one of this process's, or any of another running process (its id names a process).
/// A file of a process that crashed, or of the older name without ids, is not.
bool recoveryFileInUse(const QString& path) {
    const QStringList parts = QFileInfo(path).completeBaseName().split('-');
    bool pidOk = false, windowOk = false;
    const qint64 pid = parts.size() == 3 ? parts[1].toLongLong(&pidOk) : 0;
    const int window = parts.size() == 3 ? parts[2].toInt(&windowOk) : 0;
    if (!pidOk || !windowOk || pid <= 0) {
        return false;
    }
    if (pid == QCoreApplication::applicationPid()) {
        return liveWindows().count(window) != 0;
    }
#ifdef Q_OS_UNIX
    // Signal 0 checks that the process exists (EPERM: it does, another user's).
    return ::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM;
#else
    return false;
#endif
}

/// The file beside a recovery file that names its project's file (empty: unsaved).
QString originOf(const QString& recovery) {
    return recovery.left(recovery.size() - int(QStringLiteral(".atelier").size())) + ".origin";
}

} // namespace

bool MainWindow::autosave() {
    if (!isModified()) {
        removeRecoveryFile(); // undone back to the file: nothing to recover
        return false;
    }
    if (!QDir().mkpath(m_recoveryDir)) {
        statusBar()->showMessage(tr("Autosave: cannot create %1").arg(m_recoveryDir), 8000);
        return false;
    }
    const QString recovery = recoveryFile();
    const QString origin = m_path.isEmpty() ? QString() : QFileInfo(m_path).absoluteFilePath();
    auto written = io::writeFileAtomically(originOf(recovery).toStdString(), origin.toStdString());
    if (written.ok()) {
        written = io::writeFileAtomically(recovery.toStdString(), io::formatProject(m_project));
    }
    if (!written.ok()) {
        statusBar()->showMessage(
            tr("Autosave failed: %1").arg(QString::fromStdString(written.error().toString())),
            8000);
        return false;
    }
    return true;
}

void MainWindow::removeRecoveryFile() {
    const QString recovery = recoveryFile();
    QFile::remove(recovery);
    QFile::remove(originOf(recovery));
}

bool MainWindow::offerRecovery() {
    const QDir dir(m_recoveryDir);
    for (const QFileInfo& recovery :
         dir.entryInfoList({"*.atelier"}, QDir::Files, QDir::Time)) { // newest first
        const QString path = recovery.absoluteFilePath();
        if (recoveryFileInUse(path)) {
            continue; // another window's, open now: neither offered nor removed
        }
        auto origin = io::readFile(originOf(path).toStdString(), 64 * 1024);
        const QString project = origin.ok() ? QString::fromStdString(origin.value()) : QString();
        const QFileInfo projectInfo(project);
        if (!origin.ok() || (!project.isEmpty() && projectInfo.exists() &&
                             projectInfo.lastModified() >= recovery.lastModified())) {
            // Stale (its project was saved after it) or without its origin: not offered.
            QFile::remove(path);
            QFile::remove(originOf(path));
            continue;
        }
        if (!m_prompts.restore(path, project)) {
            QFile::remove(path);
            QFile::remove(originOf(path));
            continue;
        }
        auto text = io::readFile(path.toStdString());
        auto restored = text.ok() ? io::parseProject(text.value(), path.toStdString())
                                  : Result<patterns::Project>(text.error());
        if (!restored.ok()) {
            showError(tr("Could not restore %1:\n%2")
                          .arg(path, QString::fromStdString(restored.error().toString())));
            continue;
        }
        adopt(std::move(restored.value()), project, true);
        // The restored file gives way to this window's own.
        QFile::remove(path);
        QFile::remove(originOf(path));
        autosave();
        statusBar()->showMessage(tr("Restored the unsaved changes to %1")
                                     .arg(project.isEmpty() ? tr("an untitled project") : project),
                                 8000);
        return true;
    }
    return false;
}

// ---- Window events ----

void MainWindow::showEvent(QShowEvent* event) {
    QMainWindow::showEvent(event);
    if (!m_stateRestored) {
        // Once the window has its restored size: before it, the docks' widths are scaled to
        // the default size (298 px saved came back as 237 in a 1100 px window).
        m_stateRestored = true;
        restoreState(QSettings().value("window/state").toByteArray());
    }
}

void MainWindow::closeEvent(QCloseEvent* event) {
    if (!maybeSave()) {
        event->ignore();
        return;
    }
    QSettings settings;
    settings.setValue("window/geometry", saveGeometry());
    if (m_stateRestored) { // else the saved state was never applied: keep it
        settings.setValue("window/state", saveState());
    }
    settings.setValue("window/splitter", m_splitter->saveState());
    removeRecoveryFile();
    m_autosave.stop();
    m_drape->pause();
    event->accept();
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
    for (const QUrl& url : event->mimeData()->urls()) {
        if (url.isLocalFile() && openable(url.toLocalFile())) {
            event->acceptProposedAction();
            return;
        }
    }
    event->ignore();
}

void MainWindow::dropEvent(QDropEvent* event) {
    for (const QUrl& url : event->mimeData()->urls()) {
        if (url.isLocalFile() && openable(url.toLocalFile())) {
            event->acceptProposedAction();
            openFile(url.toLocalFile());
            return;
        }
    }
    event->ignore();
}

void MainWindow::toggleRun() {
    if (m_drape->running()) {
        m_drape->pause();
    } else {
        m_drape->start();
    }
}

void MainWindow::showPlaced(const StaticScene& scene, bool again) {
    const QString placed = again ? tr("Placed again") : tr("Placed");
    if (scene.placementLifts.empty()) {
        statusBar()->showMessage(tr("%1: press Space to drape").arg(placed), 5000);
        return;
    }
    QStringList lifts;
    for (const patterns::PlacementLift& l : scene.placementLifts) {
        lifts << QString::fromStdString(patterns::liftText(l));
    }
    statusBar()->showMessage(tr("%1, panels placed through each other (%2 triangle pairs) moved "
                                "apart on their slots: %3; press Space to drape")
                                 .arg(placed)
                                 .arg(scene.placedCrossings)
                                 .arg(lifts.join(QStringLiteral("; "))),
                             20000);
}

void MainWindow::updateStatus() {
    const DrapeProgress p = m_drape->progress();
    m_phase.setText(tr("%1%2")
                        .arg(QString::fromUtf8(patterns::phaseName(p.phase).data()))
                        .arg(p.running ? tr(" (running)") : QString()));
    m_time.setText(tr("t = %1 s").arg(p.time, 0, 'f', 2));
    const long steps = p.steps - m_lastSteps;
    const double wall = p.wallTime - m_lastWall;
    if (p.running && steps > 0 && wall > 0) {
        m_speed.setText(
            tr("%1 steps/s").arg(steps / (m_statusTimer.interval() / 1000.0), 0, 'f', 0));
    } else if (!p.running) {
        m_speed.setText(tr("%1 steps").arg(p.steps));
    }
    m_lastSteps = p.steps;
    m_lastWall = p.wallTime;
    m_energy.setText(tr("KE %1 J").arg(p.kineticEnergy, 0, 'e', 1));
    m_contacts.setText(tr("%1 contacts").arg(p.contacts));
    m_fps.setText(tr("%1 fps, %2 ms")
                      .arg(m_viewport->framesPerSecond(), 0, 'f', 0)
                      .arg(m_viewport->drawMilliseconds(), 0, 'f', 0));
    docksFollowDrape(p);
}

void MainWindow::exportMesh() {
    if (!m_drape->staticScene()) {
        return;
    }
    const QString path = QFileDialog::getSaveFileName(this, tr("Export the draped garment"),
                                                      QString(), tr("OBJ meshes (*.obj)"));
    if (!path.isEmpty()) {
        exportDrapedMesh(path);
    }
}

bool MainWindow::exportDrapedMesh(const QString& path) {
    const auto scene = m_drape->staticScene();
    if (!scene) {
        showError(tr("Nothing to export: open a project"));
        return false;
    }
    sim::Snapshot s;
    const sim::MatX3& x =
        m_drape->snapshot(s) && s.clothPositions.rows() == scene->startPositions.rows()
            ? s.clothPositions
            : scene->startPositions;
    io::ObjWriteOptions options;
    options.uvs = scene->patternUvs;
    for (std::size_t p = 0; p < scene->panelTriangles.size(); ++p) {
        options.groups.push_back(io::ObjGroup{scene->panelNames[p], scene->panelTriangles[p].first,
                                              scene->panelTriangles[p].second});
    }
    if (auto written = io::writeObj(path.toStdString(), x, scene->garmentTriangles, options);
        !written.ok()) {
        showError(QString::fromStdString(written.error().toString()));
        return false;
    }
    statusBar()->showMessage(tr("Wrote %1").arg(path), 4000);
    return true;
}

void MainWindow::savePicture() {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save a picture of the 3D view"),
                                                      QString(), tr("PNG pictures (*.png)"));
    if (path.isEmpty()) {
        return;
    }
    m_viewport->drawNow(); // the scene as it is, not the last frame handed back
    QSaveFile out(path);   // written whole or not at all
    if (!out.open(QIODevice::WriteOnly) || !m_viewport->picture().save(&out, "PNG") ||
        !out.commit()) {
        QMessageBox::warning(this, tr("Atelier"),
                             tr("Could not write %1: %2").arg(path, out.errorString()));
    }
}

} // namespace atelier::ui
