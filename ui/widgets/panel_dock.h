#pragma once
/// The Panel dock: the selected panel's name, its placement on the body (slot, offset around
/// and along the slot, rotation, clearance), its fabric, its particle distance and the fold
/// angle of the internal line and the width and depth of the dart selected in the pattern. Each
/// change is a request the window turns into one undoable document edit (renamePanel, placePanel,
/// setPanelMaterial, setPanelParticleDistance, setFoldAngle, setDartSize); the dock shows the
/// document as it is after it.

#include "patterns/document.h"

#include <QDockWidget>
#include <QStringList>

class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QLineEdit;

namespace atelier::ui {

class PanelDock : public QDockWidget {
    Q_OBJECT
  public:
    explicit PanelDock(QWidget* parent = nullptr);

    /// The document to show (after every change of it).
    void setDocument(const patterns::GarmentDocument& document);
    /// The body's slot names (the slot chooser's entries).
    void setSlotNames(const QStringList& names);
    /// Fabric presets offered beside the document's fabrics (picking one adds it).
    void setPresetNames(const QStringList& names);
    /// The panel shown, or none.
    patterns::PanelId panel() const { return m_panel; }

    // The fields, for tests and keyboard users' focus chains.
    QLineEdit* nameField() const { return m_name; }
    QComboBox* slotChooser() const { return m_slot; }
    QDoubleSpinBox* aroundField() const { return m_around; }
    QDoubleSpinBox* alongField() const { return m_along; }
    QDoubleSpinBox* rotationField() const { return m_rotation; }
    QDoubleSpinBox* clearanceField() const { return m_clearance; }
    QComboBox* fabricChooser() const { return m_fabric; }
    /// The panel's own particle distance [mm]; 0 (shown as "drape's") for the drape's.
    QDoubleSpinBox* particleDistanceField() const { return m_particleDistance; }
    /// The fold angle of the internal line selected in the pattern [°]; disabled when none.
    QDoubleSpinBox* foldAngleField() const { return m_foldAngle; }
    /// The width and depth of the dart selected in the pattern [mm]; disabled when none.
    QDoubleSpinBox* dartWidthField() const { return m_dartWidth; }
    QDoubleSpinBox* dartDepthField() const { return m_dartDepth; }

  public Q_SLOTS:
    /// Shows panel `panel` (0: none; the fields are disabled).
    void showPanel(quint32 panel);
    /// Shows internal line `line` of panel `panel` (the one selected in the pattern; 0: none)
    /// in the fold angle field.
    void showLine(quint32 panel, quint32 line);
    /// Shows dart `dart` of panel `panel` (the one selected in the pattern; 0: none) in the
    /// dart fields.
    void showDart(quint32 panel, quint32 dart);

  Q_SIGNALS:
    void renameRequested(quint32 panel, const QString& name);
    /// The placement the fields show now (slot, offset, rotation, clearance) [m, rad]; `field`
    /// names the spin box that changed ("around", "along", "rotation", "clearance"), empty for
    /// the slot: consecutive changes of one field are one undo entry.
    void placeRequested(quint32 panel, const patterns::Placement& placement, const QString& field);
    /// A fabric of the document, or a preset's name (`preset` true) to add and give the panel.
    void fabricRequested(quint32 panel, const QString& fabric, bool preset);
    /// The panel's own particle distance [m] (0: the drape's).
    void particleDistanceRequested(quint32 panel, double distance);
    /// The rest angle of the hinges along internal line `line` [rad].
    void foldAngleRequested(quint32 panel, quint32 line, double angle);
    /// A new size for dart `dart` [m] (patterns::setDartSize); `field` ("width", "depth") names
    /// the field changed: consecutive changes of one field are one undo entry.
    void dartSizeRequested(quint32 panel, quint32 dart, double width, double depth,
                           const QString& field);

  private:
    void refresh();
    void emitPlacement(const QString& field);
    const patterns::doc::Panel* shown() const;
    /// The internal line shown in the fold angle field, or null.
    const patterns::doc::InternalLine* shownLine() const;

    patterns::GarmentDocument m_document;
    patterns::PanelId m_panel;
    QStringList m_slotNames;
    QStringList m_presetNames;
    QLabel* m_title;
    QLineEdit* m_name;
    QComboBox* m_slot;
    QDoubleSpinBox* m_around;
    QDoubleSpinBox* m_along;
    QDoubleSpinBox* m_rotation;
    QDoubleSpinBox* m_clearance;
    QComboBox* m_fabric;
    QDoubleSpinBox* m_particleDistance;
    QDoubleSpinBox* m_foldAngle;
    patterns::LineId m_line; ///< the internal line shown (of m_panel), or none
    QDoubleSpinBox* m_dartWidth;
    QDoubleSpinBox* m_dartDepth;
    patterns::DartId m_dart; ///< the dart shown (of m_panel), or none
};

} // namespace atelier::ui
