#pragma once
/// The application window: the pattern (2D) and the drape (3D) side by side, menus and a
/// toolbar for files, the simulation and the views, and a status bar with the drape's live
/// figures. The drape runs on DrapeController's worker thread; nothing here waits for it.

#include "ui/widgets/drape_controller.h"

#include <QLabel>
#include <QMainWindow>
#include <QTimer>

class QAction;

namespace atelier::ui {

class PatternView;
class Viewport;

class MainWindow : public QMainWindow {
    Q_OBJECT
  public:
    /// `samplesDir`: where the sample garments are (the File > Samples menu), or empty.
    explicit MainWindow(QString samplesDir, QWidget* parent = nullptr);
    ~MainWindow() override;

    void openProject(const QString& path);
    DrapeController& drape() { return *m_drape; }
    Viewport& viewport() { return *m_viewport; }
    PatternView& patternView() { return *m_pattern; }

  signals:
    /// The project is open and placed (the views show it).
    void projectReady();

  private:
    void buildMenus();
    void updateStatus();
    void exportMesh();
    void savePicture();
    void toggleRun();

    DrapeController* m_drape;
    PatternView* m_pattern;
    Viewport* m_viewport;
    QString m_samplesDir;
    QAction* m_run = nullptr;
    QLabel m_phase;
    QLabel m_time;
    QLabel m_speed;
    QLabel m_energy;
    QLabel m_contacts;
    QLabel m_fps;
    QTimer m_statusTimer;
    long m_lastSteps = 0;
    double m_lastWall = 0;
};

} // namespace atelier::ui
