#pragma once
/// The 2D view: the garment document's panels as the designer drew them (outlines, holes,
/// internal lines), laid side by side in pattern space, one colour per panel as in the 3D view.
/// Zoom with the wheel, pan by dragging the background; a click selects a panel and shows its
/// outline and hole points as handles. Dragging a handle moves the point (the lengths of its
/// two edges shown; Shift snaps to a 5 mm grid, Ctrl+Shift to 1 mm), Delete deletes the
/// selected point, a double-click on an edge of the selected panel adds a point there. The view
/// edits nothing itself: it asks, by signal, and the window makes the edit.

#include "patterns/document.h"
#include "patterns/garment.h"

#include <QGraphicsView>

#include <map>
#include <optional>

class QGraphicsPathItem;
class QGraphicsSimpleTextItem;

namespace atelier::ui {

class PatternView : public QGraphicsView {
    Q_OBJECT
  public:
    explicit PatternView(QWidget* parent = nullptr);
    ~PatternView() override;
    PatternView(const PatternView&) = delete;
    PatternView& operator=(const PatternView&) = delete;

    /// Draws `document` (replacing what was shown). `keepLayout`: an edit of what is shown,
    /// so panels already drawn keep their place, the zoom and the selection stay; otherwise
    /// the panels are laid out anew and fitted in the view.
    void setDocument(const patterns::GarmentDocument& document, bool keepLayout = false);
    /// The panels drawn (one item each), for tests.
    int panelCount() const { return m_panels; }

    /// The selected panel, or none.
    patterns::PanelId selectedPanel() const { return m_selectedPanel; }
    void selectPanel(patterns::PanelId panel);
    /// The selected outline or hole point of the selected panel, or none.
    patterns::PointId selectedPoint() const { return m_selectedPoint; }
    /// Where pattern point `at` [m] of `panel` is drawn, in the view's viewport coordinates.
    QPoint viewPoint(patterns::PanelId panel, const patterns::Vec2& at) const;
    /// The edge lengths shown while a point is dragged (empty otherwise).
    QString dragLengths() const;

  Q_SIGNALS:
    /// The selected panel's name (empty when none).
    void panelSelected(const QString& name);
    /// A point was dragged to (x, y) [m] and let go.
    void pointMoveRequested(quint32 panel, quint32 point, double x, double y);
    /// Delete was pressed with a point selected.
    void pointDeleteRequested(quint32 panel, quint32 point);
    /// An edge was double-clicked at curve parameter t, at (x, y) on it [m].
    void pointAddRequested(quint32 panel, quint32 edge, double t, double x, double y);

  protected:
    void wheelEvent(QWheelEvent* event) override;
    void mousePressEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void mouseDoubleClickEvent(QMouseEvent* event) override;
    void keyPressEvent(QKeyEvent* event) override;

  private:
    struct Drag {
        patterns::PanelId panel;
        patterns::PointId point;
        patterns::Vec2 position = patterns::Vec2::Zero(); ///< where it is now [m]
        bool moved = false;
    };
    /// An outline or hole edge of the selected panel within a few pixels of `at` (viewport).
    struct EdgePick {
        patterns::EdgeId edge;
        double t = 0;                               ///< curve parameter of the nearest point
        patterns::Vec2 at = patterns::Vec2::Zero(); ///< that point [m]
    };
    std::optional<EdgePick> pickEdge(const QPoint& at) const;
    const patterns::doc::Panel* panel(patterns::PanelId id) const;
    double offset(patterns::PanelId id) const;
    /// Pattern coordinates [m] of a scene point over panel `id`.
    patterns::Vec2 toPattern(patterns::PanelId id, const QPointF& scene) const;
    QPointF toScene(patterns::PanelId id, const patterns::Vec2& at) const;
    void redraw();
    void drawHandles();
    /// Redraws the dragged panel's outline with the point at the drag's position and the
    /// lengths of its two edges beside it.
    void showDrag();

    QGraphicsScene m_scene;
    patterns::GarmentDocument m_document;
    /// Horizontal shift of each panel in the scene [mm], by panel id.
    std::map<std::uint32_t, double> m_offsets;
    std::map<std::uint32_t, QGraphicsPathItem*> m_items;
    std::vector<QGraphicsItem*> m_handles;
    QGraphicsSimpleTextItem* m_lengths = nullptr;
    int m_panels = 0;
    patterns::PanelId m_selectedPanel;
    patterns::PointId m_selectedPoint;
    std::optional<Drag> m_drag;
    /// Items are being removed (a redraw, the destructor): selection changes are not acted on.
    bool m_redrawing = false;
};

/// The points of a loop's segments, sampled finely enough to draw (lines: their ends; curves:
/// 24 points each) [m].
std::vector<patterns::Vec2> sampleLoop(const patterns::Loop& loop);

/// A contour's segments, in order [m].
patterns::Loop contourLoop(const patterns::doc::Contour& contour);

} // namespace atelier::ui
