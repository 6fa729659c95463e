#include "ui/widgets/simulation_dock.h"

#include "ui/widgets/drape_plot.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QToolButton>

#include <cmath>

namespace atelier::ui {

namespace {

constexpr double MM_PER_M = 1000.0;
constexpr double MS = 1000.0;

} // namespace

SimulationDock::SimulationDock(QAction* run, QAction* reset, QWidget* parent)
    : QDockWidget(tr("Simulation"), parent) {
    setObjectName("simulation-dock");
    auto* body = new QWidget;
    auto* form = new QFormLayout(body);
    auto* buttons = new QHBoxLayout;
    for (QAction* action : {run, reset}) {
        auto* button = new QToolButton;
        button->setDefaultAction(action);
        button->setToolButtonStyle(Qt::ToolButtonTextOnly);
        buttons->addWidget(button);
    }
    buttons->addStretch();
    form->addRow(buttons);
    m_distance = new QDoubleSpinBox;
    m_distance->setRange(2, 100);
    m_distance->setDecimals(1);
    m_distance->setSuffix(tr(" mm"));
    m_distance->setKeyboardTracking(false);
    m_distance->setToolTip(tr("Target edge length of the cloth mesh: a new value re-meshes and "
                              "places the garment again"));
    m_dt = new QDoubleSpinBox;
    m_dt->setRange(0.05, 50);
    m_dt->setDecimals(3);
    m_dt->setSuffix(tr(" ms"));
    m_dt->setKeyboardTracking(false);
    m_phase = new QLabel;
    form->addRow(tr("Particle distance"), m_distance);
    form->addRow(tr("Time step"), m_dt);
    form->addRow(tr("Phase"), m_phase);
    m_plot = new DrapePlot;
    form->addRow(m_plot);
    setWidget(body);
    for (QDoubleSpinBox* box : {m_distance, m_dt}) {
        connect(box, &QDoubleSpinBox::valueChanged, this, [this] { emitSettings(); });
    }
    setSettings(m_settings);
}

void SimulationDock::setSettings(const patterns::DrapeSettings& settings) {
    m_settings = settings;
    const QSignalBlocker a(m_distance);
    const QSignalBlocker b(m_dt);
    m_distance->setValue(settings.particleDistance * MM_PER_M);
    m_dt->setValue(settings.dt * MS);
}

void SimulationDock::setPhase(const QString& phase) {
    m_phase->setText(phase);
}

void SimulationDock::emitSettings() {
    // A field left alone keeps its exact value (1/300 s shows as 3.333 ms).
    const auto pick = [](const QDoubleSpinBox* field, double value, double scale) {
        const double step = std::pow(10.0, -field->decimals());
        return std::abs(field->value() - value * scale) < 0.5 * step ? value
                                                                     : field->value() / scale;
    };
    patterns::DrapeSettings changed = m_settings;
    changed.particleDistance = pick(m_distance, m_settings.particleDistance, MM_PER_M);
    changed.dt = pick(m_dt, m_settings.dt, MS);
    if (changed.particleDistance != m_settings.particleDistance || changed.dt != m_settings.dt) {
        Q_EMIT settingsRequested(changed);
    }
}

} // namespace atelier::ui
