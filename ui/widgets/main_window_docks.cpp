// The window's docks (panel, seam, fabric, simulation with its live plot), the arrangement on
// the body's slots, and the File menu's pattern export, picture render and body import: the
// MainWindow members declared under "Docks, arrangement and file additions".
#include "ui/widgets/body_dock.h"
#include "ui/widgets/body_preview.h"
#include "ui/widgets/drape_plot.h"
#include "ui/widgets/fabric_dock.h"
#include "ui/widgets/main_window.h"
#include "ui/widgets/panel_dock.h"
#include "ui/widgets/pattern_view.h"
#include "ui/widgets/seam_dock.h"
#include "ui/widgets/simulation_dock.h"
#include "ui/widgets/viewport.h"

#include "io/materials.h"
#include "io/mesh_import.h"
#include "io/pattern_svg.h"

#include <QAction>
#include <QDateTime>
#include <QDir>
#include <QDockWidget>
#include <QFileDialog>
#include <QFileInfo>
#include <QMenu>
#include <QSaveFile>
#include <QSettings>
#include <QStatusBar>
#include <QUndoCommand>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <map>
#include <numbers>

namespace atelier::ui {

namespace {

/// Picture size of File > Render image [px].
constexpr int RENDER_WIDTH = 1920;
constexpr int RENDER_HEIGHT = 1080;

} // namespace

/// New drape settings for the project (not a document edit): redo and undo swap them.
class DrapeSettingsCommand : public QUndoCommand {
  public:
    DrapeSettingsCommand(MainWindow* window, patterns::DrapeSettings before,
                         patterns::DrapeSettings after)
        : QUndoCommand(MainWindow::tr("drape settings")), m_window(window), m_before(before),
          m_after(after) {}
    void redo() override { m_window->applyDrapeSettings(m_after); }
    void undo() override { m_window->applyDrapeSettings(m_before); }

  private:
    MainWindow* m_window;
    patterns::DrapeSettings m_before;
    patterns::DrapeSettings m_after;
};

void MainWindow::buildDocks() {
    m_panelDock = new PanelDock(this);
    m_seamDock = new SeamDock(this);
    m_fabricDock = new FabricDock(this);
    m_simulationDock = new SimulationDock(m_run, m_reset, this);
    m_bodyDock = new BodyDock(m_importBody, this);
    m_bodyPreview = new BodyPreview(this);
    addDockWidget(Qt::RightDockWidgetArea, m_panelDock);
    addDockWidget(Qt::RightDockWidgetArea, m_fabricDock);
    addDockWidget(Qt::RightDockWidgetArea, m_seamDock);
    addDockWidget(Qt::RightDockWidgetArea, m_bodyDock);
    addDockWidget(Qt::RightDockWidgetArea, m_simulationDock);
    tabifyDockWidget(m_panelDock, m_fabricDock);
    tabifyDockWidget(m_fabricDock, m_seamDock);
    tabifyDockWidget(m_seamDock, m_bodyDock);
    m_panelDock->raise();

    QStringList presetNames;
    std::map<std::string, sim::Material> presets;
    for (const auto& [name, material] : io::builtinMaterialPresets()) {
        presetNames << QString::fromStdString(name);
        presets.emplace(name, material);
    }
    m_panelDock->setPresetNames(presetNames);
    m_fabricDock->setPresets(std::move(presets));

    m_viewMenu->addSeparator();
    m_showSlots = m_viewMenu->addAction(tr("Body &slots"));
    m_showSlots->setCheckable(true);
    m_showSlots->setShortcut(QKeySequence(Qt::CTRL | Qt::Key_L));
    m_showSlots->setChecked(QSettings().value("view/slots", false).toBool());
    m_viewport->setSlotsShown(m_showSlots->isChecked());
    connect(m_showSlots, &QAction::toggled, this, [this](bool on) {
        m_viewport->setSlotsShown(on);
        QSettings().setValue("view/slots", on);
    });
    m_strainMap = m_viewMenu->addAction(tr("S&train map"));
    m_strainMap->setCheckable(true);
    m_strainMap->setStatusTip(tr("Colour the cloth by its strain against the pattern (±%1%)")
                                  .arg(Viewport::STRAIN_RANGE * 100));
    connect(m_strainMap, &QAction::toggled, m_viewport, &Viewport::setStrainShown);
    m_seamLines = m_viewMenu->addAction(tr("Seam &lines"));
    m_seamLines->setCheckable(true);
    m_seamLines->setChecked(m_viewport->seamLinesShown());
    m_seamLines->setStatusTip(tr("Draw the seams on the cloth in their pattern colours"));
    connect(m_seamLines, &QAction::toggled, m_viewport, &Viewport::setSeamLinesShown);
    QMenu* docks = m_viewMenu->addMenu(tr("&Docks"));
    for (QDockWidget* dock : std::initializer_list<QDockWidget*>{
             m_panelDock, m_fabricDock, m_seamDock, m_bodyDock, m_simulationDock}) {
        docks->addAction(dock->toggleViewAction());
    }

    // Selection: the dock shows the panel picked in the pattern and its fabric.
    connect(m_pattern, &PatternView::panelSelected, this, [this](const QString& /*name*/) {
        const patterns::PanelId panel = m_pattern->selectedPanel();
        const patterns::doc::Panel* selected = m_project.document.panel(panel);
        m_viewport->setSelectedPanel(selected != nullptr ? QString::fromStdString(selected->name)
                                                         : QString());
        if (!panel) {
            return; // the docks keep the last panel, as the 3D view's slot clicks need one
        }
        m_panelDock->showPanel(panel.value);
        if (const patterns::doc::Panel* p = m_project.document.panel(panel)) {
            m_fabricDock->showFabric(QString::fromStdString(p->material));
            m_viewport->setHighlightedSlot(QString::fromStdString(p->placement.slot));
        }
    });
    // An internal line selected in the pattern: its fold angle in the Panel dock.
    connect(m_pattern, &PatternView::lineSelected, m_panelDock, &PanelDock::showLine);
    // A dart's leg selected in the pattern: its width and depth in the Panel dock.
    connect(m_pattern, &PatternView::dartSelected, m_panelDock, &PanelDock::showDart);
    // The placement handle dragged in 3D: the panel moves on its slot, one undoable step.
    connect(m_viewport, &Viewport::placementMoveRequested, this,
            [this](const QString& name, double around, double along) {
                for (const patterns::doc::Panel& p : m_project.document.panels) {
                    if (QString::fromStdString(p.name) != name) {
                        continue;
                    }
                    patterns::Placement placement = p.placement;
                    placement.offset += patterns::Vec2(around, along);
                    const patterns::PanelId id = p.id;
                    edit([&](patterns::GarmentDocument& d) {
                        return patterns::placePanel(d, id, placement);
                    });
                    return;
                }
            });
    connect(m_viewport, &Viewport::placementTurnRequested, this,
            [this](const QString& name, double angle) {
                for (const patterns::doc::Panel& p : m_project.document.panels) {
                    if (QString::fromStdString(p.name) == name) {
                        patterns::Placement placement = p.placement;
                        placement.rotation =
                            std::remainder(placement.rotation + angle, 2 * std::numbers::pi);
                        const patterns::PanelId id = p.id;
                        edit([&](patterns::GarmentDocument& d) {
                            return patterns::placePanel(d, id, placement);
                        });
                        return;
                    }
                }
            });
    // With the Seam tool, a press on the cloth in 3D picks the edge nearest it, as a click on
    // the pattern does (the pattern view's picks: one seam tool, two views).
    connect(m_pattern, &PatternView::toolChanged, this, [this](PatternView::Tool tool) {
        m_viewport->setSeamPicking(tool == PatternView::Tool::Seam);
    });
    connect(m_viewport, &Viewport::seamPointPicked, this,
            [this](const QString& name, double x, double y, Qt::KeyboardModifiers modifiers) {
                if (const patterns::doc::Panel* p =
                        m_project.document.panelNamed(name.toStdString())) {
                    m_pattern->pickSeamAt(p->id, patterns::Vec2(x, y), modifiers);
                }
            });
    // A press on the cloth in 3D selects its panel in the pattern (and so in the docks).
    connect(m_viewport, &Viewport::panelPicked, this, [this](const QString& name) {
        for (const patterns::doc::Panel& p : m_project.document.panels) {
            if (QString::fromStdString(p.name) == name) {
                m_pattern->selectPanel(p.id);
                return;
            }
        }
    });
    // The body's slots, once a scene is there.
    const auto slotNames = [this] {
        QStringList names;
        if (const auto scene = m_drape->staticScene()) {
            for (const patterns::ArrangementSlot& slot : scene->bodySlots) {
                names << QString::fromStdString(slot.name);
            }
        }
        m_panelDock->setSlotNames(names);
    };
    connect(m_drape, &DrapeController::opened, this, slotNames);
    connect(m_drape, &DrapeController::rebuilt, this, slotNames);
    connect(m_viewport, &Viewport::slotClicked, this, [this](const QString& slot) {
        if (const std::vector<patterns::PanelId> selected = m_pattern->selectedPanels();
            selected.size() > 1) {
            placePanelsOnSlot(selected, slot); // a copy: the edit redraws the selection
            return;
        }
        if (!m_panelDock->panel()) {
            statusBar()->showMessage(tr("Select a panel, then click a slot to place it"), 4000);
            return;
        }
        placePanelOnSlot(m_panelDock->panel(), slot);
    });

    // The Body dock: the edited body is built off the UI thread and shown at once; built, it
    // becomes the project's body (one undo entry per field edited in a row) and the drape
    // takes the body built instead of building it again.
    connect(m_bodyDock, &BodyDock::bodyEdited, this,
            [this](const patterns::BodySource& body, const QString& field) {
                m_bodyField = field;
                statusBar()->showMessage(tr("Building the body…"));
                m_bodyPreview->request(body);
            });
    connect(m_bodyPreview, &BodyPreview::built, this,
            [this](const patterns::BodySource& source, const patterns::Body& body) {
                m_bodyDock->setProblem({});
                m_viewport->setPreviewBody(body.vertices, body.triangles);
                if (source == m_project.body) {
                    return;
                }
                m_drape->offerBody(source, body);
                pushBody(source, tr("body: %1").arg(m_bodyField),
                         QStringLiteral("body ") + m_bodyField);
            });
    connect(m_bodyPreview, &BodyPreview::failed, this,
            [this](const patterns::BodySource& /*source*/, const QString& message) {
                m_bodyDock->setProblem(message);
                statusBar()->showMessage(tr("The body cannot be built: %1").arg(message), 8000);
            });

    // Each dock's request is one undoable edit.
    connect(
        m_panelDock, &PanelDock::renameRequested, this, [this](quint32 panel, const QString& name) {
            if (!edit([&](patterns::GarmentDocument& d) {
                    return patterns::renamePanel(d, patterns::PanelId{panel}, name.toStdString());
                })) {
                docksFollowDocument(); // the refused name goes back to the panel's
            }
        });
    connect(m_panelDock, &PanelDock::placeRequested, this,
            [this](quint32 panel, const patterns::Placement& placement, const QString& field) {
                // A slot chosen for one of several panels selected: all go there.
                const std::vector<patterns::PanelId> selected = m_pattern->selectedPanels();
                if (field.isEmpty() && selected.size() > 1 &&
                    std::find(selected.begin(), selected.end(), patterns::PanelId{panel}) !=
                        selected.end()) {
                    if (!placePanelsOnSlot(selected, QString::fromStdString(placement.slot))) {
                        docksFollowDocument();
                    }
                    return;
                }
                const QString merge = field.isEmpty()
                                          ? QString()
                                          : QStringLiteral("place %1 %2").arg(panel).arg(field);
                if (!edit(
                        [&](patterns::GarmentDocument& d) {
                            return patterns::placePanel(d, patterns::PanelId{panel}, placement);
                        },
                        merge)) {
                    docksFollowDocument();
                }
            });
    connect(m_panelDock, &PanelDock::dartSizeRequested, this,
            [this](quint32 panel, quint32 dart, double width, double depth, const QString& field) {
                if (!edit(
                        [&](patterns::GarmentDocument& d) {
                            return patterns::setDartSize(d, patterns::PanelId{panel},
                                                         patterns::DartId{dart}, width, depth);
                        },
                        QStringLiteral("dart %1 %2 %3").arg(panel).arg(dart).arg(field))) {
                    docksFollowDocument(); // the fields show the dart as it is
                }
            });
    connect(m_panelDock, &PanelDock::particleDistanceRequested, this,
            [this](quint32 panel, double distance) {
                if (!edit(
                        [&](patterns::GarmentDocument& d) {
                            return patterns::setPanelParticleDistance(d, patterns::PanelId{panel},
                                                                      distance);
                        },
                        QStringLiteral("particle distance %1").arg(panel))) {
                    docksFollowDocument();
                }
            });
    connect(m_panelDock, &PanelDock::foldAngleRequested, this,
            [this](quint32 panel, quint32 line, double angle) {
                if (!edit(
                        [&](patterns::GarmentDocument& d) {
                            return patterns::setFoldAngle(d, patterns::PanelId{panel},
                                                          patterns::LineId{line}, angle);
                        },
                        QStringLiteral("fold %1 %2").arg(panel).arg(line))) {
                    docksFollowDocument();
                }
            });
    connect(m_panelDock, &PanelDock::fabricRequested, this,
            [this](quint32 panel, const QString& fabric, bool preset) {
                const patterns::PanelId id{panel};
                const std::string name = fabric.toStdString();
                if (!preset) {
                    edit([&](patterns::GarmentDocument& d) {
                        return patterns::setPanelMaterial(d, id, name);
                    });
                } else if (const auto found = io::builtinMaterialPresets().find(name);
                           found != io::builtinMaterialPresets().end()) {
                    // The preset becomes a fabric of the document and the panel's: one step.
                    m_undo.beginMacro(tr("fabric %1").arg(fabric));
                    patterns::GarmentMaterial material{name, found->second};
                    material.material.name = name;
                    if (edit([&](patterns::GarmentDocument& d) {
                            return patterns::setMaterial(d, material);
                        })) {
                        edit([&](patterns::GarmentDocument& d) {
                            return patterns::setPanelMaterial(d, id, name);
                        });
                    }
                    m_undo.endMacro();
                }
                m_fabricDock->showFabric(fabric);
            });
    // A seam picked in the pattern shows in the Seam dock.
    connect(m_pattern, &PatternView::seamSelected, this, [this](quint32 seam) {
        m_seamDock->showSeam(patterns::SeamId{seam});
        m_seamDock->raise();
    });
    connect(m_seamDock, &SeamDock::reverseRequested, this, [this](quint32 seam) {
        edit([&](patterns::GarmentDocument& d) {
            return patterns::reverseSeam(d, patterns::SeamId{seam});
        });
    });
    connect(m_seamDock, &SeamDock::bendingRequested, this,
            [this](quint32 seam, double foldAngle, double bendingScale) {
                edit([&](patterns::GarmentDocument& d) {
                    return patterns::setSeamBending(d, patterns::SeamId{seam}, foldAngle,
                                                    bendingScale);
                });
            });
    connect(m_seamDock, &SeamDock::removeRequested, this, [this](quint32 seam) {
        edit([&](patterns::GarmentDocument& d) {
            return patterns::removeSeam(d, patterns::SeamId{seam});
        });
    });
    connect(m_fabricDock, &FabricDock::materialRequested, this,
            [this](const patterns::GarmentMaterial& material) {
                if (!edit([&](patterns::GarmentDocument& d) {
                        return patterns::setMaterial(d, material);
                    })) {
                    docksFollowDocument();
                }
            });
    connect(m_simulationDock, &SimulationDock::settingsRequested, this,
            [this](const patterns::DrapeSettings& settings) { setDrapeSettings(settings); });
    docksFollowDocument();
}

void MainWindow::docksFollowDocument(bool newProject) {
    if (newProject) { // ids of the project left behind may name other objects in this one
        m_panelDock->showPanel(0);
        m_seamDock->showSeam({});
        m_bodyPreview->cancel(); // a body edited in the project left behind is not this one's
    }
    m_panelDock->setDocument(m_project.document);
    m_seamDock->setDocument(m_project.document);
    m_fabricDock->setDocument(m_project.document);
    m_simulationDock->setSettings(m_project.drape);
    m_bodyDock->setBody(m_project.body);
    const patterns::doc::Panel* selected = m_project.document.panel(m_pattern->selectedPanel());
    m_viewport->setSelectedPanel(selected != nullptr ? QString::fromStdString(selected->name)
                                                     : QString()); // a rename follows
    const patterns::doc::Panel* shown = m_project.document.panel(m_panelDock->panel());
    m_viewport->setHighlightedSlot(
        shown == nullptr ? QString() : QString::fromStdString(shown->placement.slot));
}

void MainWindow::docksFollowDrape(const DrapeProgress& progress) {
    m_simulationDock->setPhase(m_phase.text());
    if (progress.phase == patterns::DrapePhase::Empty) {
        m_simulationDock->plot().clear();
    } else if (progress.steps > 0) {
        m_simulationDock->plot().addSample(
            {progress.time, progress.kineticEnergy, progress.contacts, progress.phase});
    }
}

bool MainWindow::placePanelOnSlot(patterns::PanelId panel, const QString& slot) {
    const patterns::doc::Panel* p = m_project.document.panel(panel);
    if (p == nullptr) {
        showError(tr("No panel #%1 to place").arg(panel.value));
        return false;
    }
    patterns::Placement placement = p->placement;
    placement.slot = slot.toStdString();
    return edit(
        [&](patterns::GarmentDocument& d) { return patterns::placePanel(d, panel, placement); });
}

bool MainWindow::placePanelsOnSlot(const std::vector<patterns::PanelId>& panels,
                                   const QString& slot) {
    const std::string name = slot.toStdString();
    return edit([&](patterns::GarmentDocument& d) {
        return patterns::placePanels(d, patterns::sideBySide(d, panels, name));
    });
}

bool MainWindow::setDrapeSettings(const patterns::DrapeSettings& settings) {
    if (!(settings.particleDistance > 0) || !(settings.dt > 0) ||
        !std::isfinite(settings.particleDistance) || !std::isfinite(settings.dt)) {
        showError(tr("The particle distance and the time step must be positive"));
        m_simulationDock->setSettings(m_project.drape);
        return false;
    }
    m_undo.push(new DrapeSettingsCommand(this, m_project.drape, settings));
    return true;
}

void MainWindow::applyDrapeSettings(const patterns::DrapeSettings& settings) {
    m_project.drape = settings;
    m_simulationDock->setSettings(settings);
    m_drape->setDrapeSettings(settings);
    updateTitle();
}

// ---- Files ----

void MainWindow::addFileActions(QMenu* file) {
    file->addAction(tr("Export pattern as S&VG…"), this, [this] {
        const QString path = QFileDialog::getSaveFileName(
            this, tr("Export the pattern"), lastDirectory(), tr("SVG drawings (*.svg)"));
        if (!path.isEmpty()) {
            exportPatternSvg(path);
        }
    });
    file->addAction(tr("&Render image…"), this, [this] {
        const QString path = QFileDialog::getSaveFileName(
            this, tr("Render the 3D view (%1×%2)").arg(RENDER_WIDTH).arg(RENDER_HEIGHT),
            lastDirectory(), tr("PNG pictures (*.png)"));
        if (!path.isEmpty()) {
            renderImage(path, RENDER_WIDTH, RENDER_HEIGHT);
        }
    });
    m_importBody = file->addAction(tr("Import &body…"), this, [this] {
        QStringList patterns;
        for (const std::string& suffix : io::bodyMeshExtensions()) {
            patterns << QString::fromStdString("*" + suffix);
        }
        const QString path =
            QFileDialog::getOpenFileName(this, tr("Drape on a body mesh"), lastDirectory(),
                                         tr("Body meshes (%1)").arg(patterns.join(' ')));
        if (!path.isEmpty()) {
            QSettings().setValue("files/lastDirectory", QFileInfo(path).absolutePath());
            setBodyMesh(path);
        }
    });
}

bool MainWindow::exportPatternSvg(const QString& path) {
    if (m_project.document.panels.empty()) {
        showError(tr("The project has no panels to export"));
        return false;
    }
    patterns::syncGarment(m_project);
    auto written = io::writePatternSvg(path.toStdString(), m_project.garment, {});
    if (!written.ok()) {
        showError(tr("Could not export the pattern to %1:\n%2")
                      .arg(path, QString::fromStdString(written.error().toString())));
        return false;
    }
    statusBar()->showMessage(tr("Wrote %1: %2 panels on a %3 × %4 mm sheet")
                                 .arg(path)
                                 .arg(written.value().panels.size())
                                 .arg(written.value().widthMm, 0, 'f', 0)
                                 .arg(written.value().heightMm, 0, 'f', 0),
                             6000);
    return true;
}

bool MainWindow::renderImage(const QString& path, int width, int height) {
    QString why;
    const QImage image = m_viewport->renderImage(width, height, &why);
    if (image.isNull()) {
        showError(tr("Could not render %1: %2").arg(path, why));
        return false;
    }
    QSaveFile out(path); // written whole or not at all
    if (!out.open(QIODevice::WriteOnly) || !image.save(&out, "PNG") || !out.commit()) {
        showError(tr("Could not write %1: %2").arg(path, out.errorString()));
        return false;
    }
    statusBar()->showMessage(tr("Wrote %1 (%2×%3)").arg(path).arg(width).arg(height), 4000);
    return true;
}

bool MainWindow::openFirstRunSample() {
    QSettings settings;
    if (!settings.allKeys().isEmpty()) {
        return false; // not the first start
    }
    settings.setValue("app/firstRun", QDateTime::currentDateTimeUtc().toString(Qt::ISODate));
    const QString tshirt = QDir(m_samplesDir).filePath("tshirt.atelier");
    if (m_samplesDir.isEmpty() || !QFileInfo(tshirt).isFile() || !openProject(tshirt)) {
        return false;
    }
    statusBar()->showMessage(tr("Welcome: this is the tshirt sample. Space drapes it; File > "
                                "Samples has the others, File > New starts from nothing."),
                             15000);
    return true;
}

} // namespace atelier::ui
