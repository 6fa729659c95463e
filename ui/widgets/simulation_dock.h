#pragma once
/// The Simulation dock: the drape settings a designer changes (particle distance, time step),
/// the window's Drape/pause and Reset actions as buttons (the same actions as Space and Ctrl+R),
/// the phase, and the live plot of kinetic energy and contacts. A changed setting is a request
/// the window makes an undoable change of the project.

#include "patterns/project.h"

#include <QDockWidget>

class QAction;
class QDoubleSpinBox;
class QLabel;

namespace atelier::ui {

class DrapePlot;

class SimulationDock : public QDockWidget {
    Q_OBJECT
  public:
    /// `run` and `reset`: the window's actions, shown as buttons.
    SimulationDock(QAction* run, QAction* reset, QWidget* parent = nullptr);

    /// The project's settings to show.
    void setSettings(const patterns::DrapeSettings& settings);
    /// The phase to show ("sewing (running)").
    void setPhase(const QString& phase);
    DrapePlot& plot() { return *m_plot; }
    QDoubleSpinBox* particleDistanceField() const { return m_distance; }
    QDoubleSpinBox* timeStepField() const { return m_dt; }

  Q_SIGNALS:
    /// The settings shown with the field the user changed.
    void settingsRequested(const patterns::DrapeSettings& settings);

  private:
    void emitSettings();

    patterns::DrapeSettings m_settings;
    QDoubleSpinBox* m_distance;
    QDoubleSpinBox* m_dt;
    QLabel* m_phase;
    DrapePlot* m_plot;
};

} // namespace atelier::ui
