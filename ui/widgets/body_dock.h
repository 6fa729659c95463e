#pragma once
/// The Body dock: the project's body. For the parametric mannequin, its base and measurements
/// (patterns::BodyMeasurements, in cm) as spin boxes: a change is announced once the fields
/// have been left alone for a moment (PREVIEW_DELAY_MS), and the window builds that body off
/// the UI thread, shows it and makes it the project's body as one undoable change. For an
/// imported body mesh, its file, unit and up axis. The Import body… button is the File menu's
/// action.

#include "patterns/project.h"

#include <QDockWidget>
#include <QTimer>

#include <vector>

class QAction;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QToolButton;

namespace atelier::ui {

class BodyDock : public QDockWidget {
    Q_OBJECT
  public:
    /// `importBody`: the window's File > Import body… action, shown as a button.
    explicit BodyDock(QAction* importBody, QWidget* parent = nullptr);

    /// The project's body to show (after every change of it); the same body again keeps the
    /// changes not yet announced.
    void setBody(const patterns::BodySource& body);
    /// The body the fields show now (the project's, with the changes not yet announced).
    const patterns::BodySource& body() const { return m_shown; }
    /// The spin box of measurement `name` (a patterns::measurementFields() name: "waist",
    /// "under_bust", ...) [cm], or null.
    QDoubleSpinBox* field(const QString& name) const;
    QComboBox* baseChooser() const { return m_base; }
    /// The imported mesh's file, unit and up axis (empty for the mannequin).
    QString meshText() const;
    QToolButton* importButton() const { return m_import; }
    /// Shows what is wrong with the measurements (empty: nothing).
    void setProblem(const QString& problem);
    QString problem() const;

    /// How long the fields must be left alone before a change is announced [ms].
    static constexpr int PREVIEW_DELAY_MS = 300;

  Q_SIGNALS:
    /// The body the fields show, PREVIEW_DELAY_MS after the last change; `field` names the
    /// field changed last (a measurement's name, or "base"): consecutive changes of one field
    /// are one undo entry.
    void bodyEdited(const patterns::BodySource& body, const QString& field);

  private:
    void refresh();
    void fieldChanged(const QString& name, double valueCm);

    patterns::BodySource m_body;  ///< the project's
    patterns::BodySource m_shown; ///< the fields'
    QString m_lastField;
    QTimer m_delay;
    QComboBox* m_base;
    std::vector<std::pair<QString, QDoubleSpinBox*>> m_fields;
    QLabel* m_mesh;
    QLabel* m_problem;
    QToolButton* m_import;
};

} // namespace atelier::ui
