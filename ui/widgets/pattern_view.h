#pragma once
/// The 2D view: the garment's panels as the designer drew them (outlines, holes, internal
/// lines, seam ranges), laid side by side in pattern space, one colour per panel as in the 3D
/// view. Zoom with the wheel, pan by dragging; a click selects a panel.

#include "patterns/garment.h"

#include <QGraphicsView>

namespace atelier::ui {

class PatternView : public QGraphicsView {
    Q_OBJECT
  public:
    explicit PatternView(QWidget* parent = nullptr);

    /// Draws `garment` (replacing what was shown) and fits it in the view.
    void setGarment(const patterns::Garment& garment);
    /// The panels drawn (one item each), for tests.
    int panelCount() const { return m_panels; }

  signals:
    /// The selected panel's name (empty when none).
    void panelSelected(const QString& name);

  protected:
    void wheelEvent(QWheelEvent* event) override;

  private:
    QGraphicsScene m_scene;
    int m_panels = 0;
};

/// The points of a loop's segments, sampled finely enough to draw (lines: their ends; curves:
/// 24 points each) [m].
std::vector<patterns::Vec2> sampleLoop(const patterns::Loop& loop);

} // namespace atelier::ui
