#include "ui/widgets/main_window.h"

#include "ui/widgets/pattern_view.h"
#include "ui/widgets/viewport.h"

#include "io/obj.h"

#include <QAction>
#include <QApplication>
#include <QDir>
#include <QFileDialog>
#include <QFileInfo>
#include <QKeySequence>
#include <QMenuBar>
#include <QMessageBox>
#include <QSaveFile>
#include <QSplitter>
#include <QStatusBar>
#include <QToolBar>

namespace atelier::ui {

MainWindow::MainWindow(QString samplesDir, QWidget* parent)
    : QMainWindow(parent), m_drape(new DrapeController(this)), m_pattern(new PatternView),
      m_viewport(new Viewport(m_drape)), m_samplesDir(std::move(samplesDir)) {
    setWindowTitle(tr("Atelier"));
    auto* splitter = new QSplitter;
    splitter->addWidget(m_pattern);
    splitter->addWidget(m_viewport);
    splitter->setSizes({480, 800});
    setCentralWidget(splitter);
    buildMenus();

    for (QLabel* label : {&m_phase, &m_time, &m_speed, &m_energy, &m_contacts, &m_fps}) {
        label->setMinimumWidth(90);
        statusBar()->addPermanentWidget(label);
    }
    connect(&m_statusTimer, &QTimer::timeout, this, &MainWindow::updateStatus);
    m_statusTimer.start(250);
    updateStatus();

    connect(m_drape, &DrapeController::opened, this, [this](const QString& path) {
        if (auto scene = m_drape->staticScene()) {
            m_pattern->setGarment(scene->garment);
        }
        m_viewport->sceneChanged();
        setWindowTitle(tr("%1 — Atelier").arg(QFileInfo(path).fileName()));
        statusBar()->showMessage(tr("Placed: press Space to drape"), 5000);
        m_lastSteps = 0;
        m_lastWall = 0;
        emit projectReady();
    });
    connect(m_drape, &DrapeController::failed, this, [this](const QString& message) {
        statusBar()->showMessage(message);
        if (isVisible()) {
            QMessageBox::warning(this, tr("Atelier"), message);
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
}

MainWindow::~MainWindow() = default;

void MainWindow::buildMenus() {
    QMenu* file = menuBar()->addMenu(tr("&File"));
    QAction* open = file->addAction(tr("&Open…"), this, [this] {
        const QString path = QFileDialog::getOpenFileName(
            this, tr("Open a garment project"), m_samplesDir, tr("Atelier projects (*.atelier)"));
        if (!path.isEmpty()) {
            openProject(path);
        }
    });
    open->setShortcut(QKeySequence::Open);
    if (!m_samplesDir.isEmpty()) {
        QMenu* samples = file->addMenu(tr("&Samples"));
        for (const QString& name : QDir(m_samplesDir).entryList({"*.atelier"}, QDir::Files)) {
            samples->addAction(QFileInfo(name).baseName(), this,
                               [this, name] { openProject(QDir(m_samplesDir).filePath(name)); });
        }
    }
    file->addSeparator();
    file->addAction(tr("&Export draped mesh…"), this, &MainWindow::exportMesh);
    file->addAction(tr("Save &picture…"), this, &MainWindow::savePicture);
    file->addSeparator();
    QAction* quit = file->addAction(tr("&Quit"), qApp, &QApplication::quit);
    quit->setShortcut(QKeySequence::Quit);

    QMenu* sim = menuBar()->addMenu(tr("&Simulation"));
    m_run = sim->addAction(tr("&Drape / pause"), this, &MainWindow::toggleRun);
    m_run->setShortcut(Qt::Key_Space);
    QAction* reset = sim->addAction(tr("&Reset"), this, [this] { m_drape->reset(); });
    reset->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_R));

    QMenu* view = menuBar()->addMenu(tr("&View"));
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

void MainWindow::openProject(const QString& path) {
    statusBar()->showMessage(tr("Opening %1…").arg(path));
    m_drape->open(path);
}

void MainWindow::toggleRun() {
    if (m_drape->running()) {
        m_drape->pause();
    } else {
        m_drape->start();
    }
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
}

void MainWindow::exportMesh() {
    const auto scene = m_drape->staticScene();
    if (!scene) {
        return;
    }
    const QString path = QFileDialog::getSaveFileName(this, tr("Export the draped garment"),
                                                      QString(), tr("OBJ meshes (*.obj)"));
    if (path.isEmpty()) {
        return;
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
        QMessageBox::warning(this, tr("Atelier"),
                             QString::fromStdString(written.error().toString()));
    } else {
        statusBar()->showMessage(tr("Wrote %1").arg(path), 4000);
    }
}

void MainWindow::savePicture() {
    const QString path = QFileDialog::getSaveFileName(this, tr("Save a picture of the 3D view"),
                                                      QString(), tr("PNG pictures (*.png)"));
    if (path.isEmpty()) {
        return;
    }
    QSaveFile out(path); // written whole or not at all
    if (!out.open(QIODevice::WriteOnly) || !m_viewport->picture().save(&out, "PNG") ||
        !out.commit()) {
        QMessageBox::warning(this, tr("Atelier"),
                             tr("Could not write %1: %2").arg(path, out.errorString()));
    }
}

} // namespace atelier::ui
