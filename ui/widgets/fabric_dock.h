#pragma once
/// The Fabric dock: one of the document's fabrics, its preset and values (areal density,
/// stretch along weft and warp, shear, bending) with the figures that follow from them beside
/// it. Choosing a preset or changing a value is a request the window turns into one undoable
/// edit (setMaterial); every panel cut from that fabric takes it as the drape goes on. The
/// drape coefficient beside them is the Cusick test's (patterns/cusick.h) at 20 mm, run on a
/// thread of its own when asked (Measure drape), a few seconds of a core.

#include "patterns/cusick.h"
#include "patterns/document.h"

#include <QDockWidget>
#include <QStringList>

#include <atomic>
#include <map>
#include <string>
#include <thread>

class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;

namespace atelier::ui {

/// Standard gravity [m/s²], as the engine's.
constexpr double GRAVITY = 9.81;

/// Bending length of a fabric strip, the cantilever test's figure (Peirce):
/// $c = \left(\frac{B}{\rho g}\right)^{1/3}$ for flexural rigidity per unit width B [N·m] and
/// areal density ρ [kg/m²] [m]; 0 when either is not positive.
double bendingLength(double bending, double density);

class FabricDock : public QDockWidget {
    Q_OBJECT
  public:
    explicit FabricDock(QWidget* parent = nullptr);
    ~FabricDock() override;
    FabricDock(const FabricDock&) = delete;
    FabricDock& operator=(const FabricDock&) = delete;

    /// The document to show (after every change of it).
    void setDocument(const patterns::GarmentDocument& document);
    /// The presets the preset chooser offers (io::builtinMaterialPresets).
    void setPresets(std::map<std::string, sim::Material> presets);
    /// The fabric shown, or empty.
    QString fabric() const { return m_fabric; }
    /// The figures shown beside the values (tests read them).
    QString figuresText() const;
    /// The Cusick test behind the drape coefficient shown: the fabric is set per test.
    static patterns::CusickOptions drapeTest();

    QComboBox* fabricChooser() const { return m_chooser; }
    QComboBox* presetChooser() const { return m_preset; }
    QDoubleSpinBox* densityField() const { return m_density; }
    QDoubleSpinBox* bendingField() const { return m_bending; }
    QPushButton* measureDrapeButton() const { return m_measure; }

  public Q_SLOTS:
    /// Shows the document's fabric `name` (the selected panel's, or one chosen here).
    void showFabric(const QString& name);

  Q_SIGNALS:
    /// New values for the fabric `material.name`.
    void materialRequested(const patterns::GarmentMaterial& material);
    /// The drape coefficient shown was computed (for the values now shown).
    void drapeCoefficientShown();

  private:
    void refresh();
    /// Starts the Cusick test of the values shown (stopping one under way).
    void startDrapeTest();
    /// Stops a test under way and waits for its thread.
    void stopDrapeTest();
    void emitValues();
    const patterns::GarmentMaterial* shown() const;

    patterns::GarmentDocument m_document;
    std::map<std::string, sim::Material> m_presets;
    QString m_fabric;
    QComboBox* m_chooser;
    QComboBox* m_preset;
    QDoubleSpinBox* m_density;
    QDoubleSpinBox* m_weft;
    QDoubleSpinBox* m_warp;
    QDoubleSpinBox* m_shear;
    QDoubleSpinBox* m_bending;
    QLabel* m_figures;
    QString m_drapeText; ///< the drape coefficient's line, for the values in m_drapeFor
    sim::Material m_drapeFor;
    bool m_drapeKnown = false;
    QPushButton* m_measure;
    bool m_drapeRunning = false;
    std::thread m_drapeThread;
    std::atomic<bool> m_drapeCancel{false};
    unsigned m_drapeGeneration = 0; ///< of the test last started (UI thread only)
};

} // namespace atelier::ui
