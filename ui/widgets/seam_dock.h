#pragma once
/// The Seam dock: one seam's two sides (each range's panel, edge and curve parameters), their
/// lengths along the curves and the mismatch between them, flagged beyond the document's ease
/// tolerance; how it bends once sewn (its rest fold angle and its rigidity as a multiple of the
/// cloth's); Reverse (sews side b the other way round) and Delete. Each change is a request the
/// window turns into an undoable edit (setSeamBending, reverseSeam, removeSeam). The seam shown
/// comes from showSeam(): the chooser in the dock, or a seam picked in a view.

#include "patterns/document.h"

#include <QDockWidget>

class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;

namespace atelier::ui {

/// Length of one side of a seam: the sum of its ranges' arc lengths [m]. Ranges on a missing
/// panel or edge count 0.
double seamSideLength(const patterns::GarmentDocument& document,
                      const std::vector<patterns::doc::SeamRange>& side);

class SeamDock : public QDockWidget {
    Q_OBJECT
  public:
    explicit SeamDock(QWidget* parent = nullptr);

    /// The document to show (after every change of it); a seam that is gone is no longer shown.
    void setDocument(const patterns::GarmentDocument& document);
    /// The seam shown, or none.
    patterns::SeamId seam() const { return m_seam; }
    /// What the dock shows of side a / b and the mismatch (tests read them).
    QString sideText(int side) const;
    QString mismatchText() const;
    QComboBox* seamChooser() const { return m_chooser; }
    QPushButton* reverseButton() const { return m_reverse; }
    QPushButton* deleteButton() const { return m_delete; }
    /// Fold angle once sewn [deg] and bending scale [-]; a value entered (editingFinished)
    /// requests the edit.
    QDoubleSpinBox* foldBox() const { return m_fold; }
    QDoubleSpinBox* bendingScaleBox() const { return m_bendingScale; }

  public Q_SLOTS:
    /// Shows seam `seam` (none or unknown: nothing shown, the buttons disabled).
    void showSeam(patterns::SeamId seam);

  Q_SIGNALS:
    void reverseRequested(quint32 seam);
    void removeRequested(quint32 seam);
    /// The seam's fold angle [rad] and bending scale [-] as entered.
    void bendingRequested(quint32 seam, double foldAngle, double bendingScale);

  private:
    void refresh();

    patterns::GarmentDocument m_document;
    patterns::SeamId m_seam;
    QComboBox* m_chooser;
    QLabel* m_sides[2];
    QLabel* m_mismatch;
    QDoubleSpinBox* m_fold;
    QDoubleSpinBox* m_bendingScale;
    QPushButton* m_reverse;
    QPushButton* m_delete;
};

} // namespace atelier::ui
