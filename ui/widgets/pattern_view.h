#pragma once
/// The 2D view: the garment document's panels as the designer drew them (outlines, holes,
/// internal lines) and its seams, one colour per panel as in the 3D view and one per seam.
/// Zoom with the wheel, pan by dragging the background (Select) or with the middle button
/// (every tool). Tools (toolActions()):
/// - Select (A): a click selects a panel (Ctrl+click adds or removes one) and shows its outline
///   and hole points, and the Bézier handles of its curved edges (an arc's: one on its middle,
///   whose drag sets its bulge). Drag a point or a handle to move it (lengths shown; Shift
///   snaps to a 5 mm grid, Ctrl+Shift to 1 mm; points snap to other points within a few
///   pixels); click an edge to select it (V makes it a curve or straight again); double-click
///   an edge to add a point; Delete deletes the selected point, or the selected seam (click a
///   sewn edge). Drag a panel's body to move it and its round handle to rotate it (Shift: 15°
///   steps): its place on the pattern sheet (the document's, one undoable edit), not its outline.
/// - Rectangle (S): drag out a rectangle, a new panel.
/// - Polygon (H): click corners; click the first one, double-click or press Enter to close,
///   Backspace drops the last, Esc cancels.
/// - Seam (N): click an outline edge, Shift+click to extend the range to another edge (Ctrl:
///   from or to the clicked point), then the same on the second side; R reverses the second
///   side, Enter sews, Esc cancels. Presses on the cloth in the 3D view pick too (pickSeamAt).
/// - Curve (P): a free-form panel, pen-style: click for a corner, press and drag for a smooth
///   point (the drag pulls its Bézier handles); close as a polygon.
/// - Internal line (L): click points inside a panel; double-click or Enter ends the line.
/// - Notch (K): click an outline edge.
/// - Dart (D): press on an outline edge and drag into the panel to the dart's tip (its width
///   is a quarter of its depth; shown while dragging).
/// In Select, the selected panel shows its grain line with a handle at its tip: drag it to
/// turn the grain (Shift: 15° steps). Clicking a notch or an internal line selects it; Delete
/// removes it, or the dart whose leg is the selected edge.
/// The view edits nothing itself: it asks, by signal or through the editor the window gives it
/// (setEditor), and draws the document the window hands back.

#include "patterns/document.h"
#include "patterns/document_edit.h"
#include "patterns/garment.h"

#include "sim/core/result.h"

#include <QGraphicsView>
#include <QTransform>

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

class QAction;
class QActionGroup;
class QGraphicsPathItem;
class QGraphicsSimpleTextItem;

namespace atelier::ui {

class PatternView : public QGraphicsView {
    Q_OBJECT
  public:
    enum class Tool { Select, Rectangle, Polygon, Seam, Curve, InternalLine, Notch, Dart };
    Q_ENUM(Tool)
    /// Makes one edit of the document (as MainWindow::edit takes it).
    using EditMaker = std::function<Result<patterns::Edit>(patterns::GarmentDocument&)>;
    /// Applies an edit through the window's undo stack; false when it was refused.
    using Editor = std::function<bool(const EditMaker&)>;

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
    /// Where the tools send their edits (drawn panels, curves, seams). Without one they do
    /// nothing.
    void setEditor(Editor editor) { m_editor = std::move(editor); }

    // ---- Tools ----

    Tool tool() const { return m_tool; }
    /// Changes the tool, dropping a drawing or seam pick under way.
    void setTool(Tool tool);
    /// Select, Rectangle, Polygon and Seam: checkable, exclusive, with their shortcuts.
    QList<QAction*> toolActions() const;
    /// Curve edge (V), Reverse seam (R), Sew (Enter in the Seam tool), for a menu.
    QList<QAction*> editActions() const;
    /// The text shown beside the mouse while drawing or dragging (empty otherwise): lengths,
    /// sizes, positions [mm].
    QString feedback() const;

    // ---- Selection ----

    /// The selected panel, or none: the last one selected.
    patterns::PanelId selectedPanel() const { return m_selectedPanel; }
    /// Every selected panel (Ctrl+click adds or removes one), in the order they were selected;
    /// the last is selectedPanel().
    const std::vector<patterns::PanelId>& selectedPanels() const { return m_selectedPanels; }
    /// Selects `panel` alone.
    void selectPanel(patterns::PanelId panel);
    /// The selected outline or hole point of the selected panel, or none.
    patterns::PointId selectedPoint() const { return m_selectedPoint; }
    /// The selected outline or hole edge of the selected panel, or none.
    patterns::EdgeId selectedEdge() const { return m_selectedEdge; }
    /// The selected seam, or none.
    patterns::SeamId selectedSeam() const { return m_selectedSeam; }
    /// The selected notch / internal line of the selected panel, or none.
    patterns::NotchId selectedNotch() const { return m_selectedNotch; }
    patterns::LineId selectedLine() const { return m_selectedLine; }
    /// Where the selected panel's grain handle is drawn (viewport coordinates); (-1, -1) when
    /// no panel is selected.
    QPoint grainHandle() const;
    void selectSeam(patterns::SeamId seam);
    /// Where pattern point `at` [m] of `panel` is drawn, in the view's viewport coordinates.
    QPoint viewPoint(patterns::PanelId panel, const patterns::Vec2& at) const;
    /// The same in scene coordinates [mm, y down], exactly.
    QPointF scenePoint(patterns::PanelId panel, const patterns::Vec2& at) const;
    /// The edge lengths shown while a point is dragged (empty otherwise).
    QString dragLengths() const;

    // ---- Edits the tools make ----

    /// Makes the selected edge a cubic curve (handles on its chord, a third from each end), or
    /// straight again when it is curved (setCurve). False when no edge is selected or refused.
    bool toggleCurve();
    /// In the Seam tool with a second side picked: that side runs the other way. Otherwise the
    /// selected seam is sewn the other way round (reverseSeam). False when neither.
    bool reverseSeam();
    /// Sews the two sides picked with the Seam tool (addSeam). False when a side is missing or
    /// the edit is refused.
    bool sew();
    /// Removes the selected notch or internal line, or the dart whose leg is the selected
    /// edge. False when none is selected or the edit is refused.
    bool deleteSelectedMark();
    /// With the Seam tool, picks the outline edge of `panel` nearest its pattern point `at` [m]
    /// (a press on the cloth in the 3D view), within 40 mm, as a click on that edge here with
    /// `modifiers` picks it (the same sides, Shift and Ctrl). False, and a message, when none
    /// is that near; false when another tool is active or there is no such panel.
    bool pickSeamAt(patterns::PanelId panel, const patterns::Vec2& at,
                    Qt::KeyboardModifiers modifiers);
    /// The ranges picked with the Seam tool: side 0 (a) or 1 (b).
    const std::vector<patterns::doc::SeamRange>& seamPick(int side) const;

  Q_SIGNALS:
    /// The selected panel's name (empty when none).
    void panelSelected(const QString& name);
    /// The selected internal line changed: its panel and id (line 0: none selected).
    void lineSelected(quint32 panel, quint32 line);
    /// The selected dart changed (the dart whose leg is the selected edge): its panel and id
    /// (dart 0: none selected).
    void dartSelected(quint32 panel, quint32 dart);
    /// A seam was picked with the mouse (its id's value).
    void seamSelected(quint32 seam);
    /// A point was dragged to (x, y) [m] and let go.
    void pointMoveRequested(quint32 panel, quint32 point, double x, double y);
    /// Delete was pressed with a point selected.
    void pointDeleteRequested(quint32 panel, quint32 point);
    /// An edge was double-clicked at curve parameter t, at (x, y) on it [m].
    void pointAddRequested(quint32 panel, quint32 edge, double t, double x, double y);
    /// A line for the status bar: the selected seam's lengths and mismatch, what a tool does.
    void message(const QString& text);
    void toolChanged(atelier::ui::PatternView::Tool tool);

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
    /// A Bézier handle, or an arc's bulge handle, being dragged.
    struct HandleDrag {
        patterns::PanelId panel;
        patterns::EdgeId edge;
        int control = 1;            ///< 1 or 2, or CONTROL_BULGE (an arc's middle)
        patterns::doc::Curve curve; ///< with the handle where it is now
        bool moved = false;
        patterns::Vec2 start = patterns::Vec2::Zero(); ///< the edge's ends [m]
        patterns::Vec2 end = patterns::Vec2::Zero();
    };
    /// A panel being moved or rotated in the layout.
    struct LayoutDrag {
        patterns::PanelId panel;
        QTransform start;   ///< its layout when pressed
        QPointF pressScene; ///< where it was pressed [scene]
        QPointF pivot;      ///< rotation centre [scene]
        bool rotate = false;
        bool moved = false;
        QPoint pressView; ///< where it was pressed [viewport]
    };
    /// A rectangle or polygon being drawn [scene].
    struct Drawing {
        std::vector<QPointF> points;
        QPointF cursor;
        bool dragging = false; ///< the rectangle's button is down
    };
    /// One side of a seam being picked: a run along one panel's outline.
    struct SidePick {
        patterns::PanelId panel;
        int fromEdge = 0;
        double fromT = 0;
        int toEdge = 0;
        double toT = 1;
        bool forward = true;
        bool partialStart = false; ///< from the clicked point (Ctrl), not the edge's end
    };
    /// An outline (or hole) edge within a few pixels of a viewport point.
    struct EdgePick {
        patterns::PanelId panel;
        patterns::EdgeId edge;
        int index = 0;                              ///< of the edge in its contour
        bool outline = true;                        ///< on the outline (not a hole)
        double t = 0;                               ///< curve parameter of the nearest point
        patterns::Vec2 at = patterns::Vec2::Zero(); ///< that point [m]
    };
    /// The edge nearest `at` within a few pixels: of panel `only` (outline and holes), or of
    /// every panel's outline when `only` is none.
    std::optional<EdgePick> pickEdge(const QPoint& at, patterns::PanelId only) const;
    std::optional<EdgePick> pickEdge(const QPoint& at) const {
        return pickEdge(at, m_selectedPanel);
    }
    /// The seam with a range through `pick`, or none.
    patterns::SeamId seamAt(const EdgePick& pick) const;
    const patterns::doc::Panel* panel(patterns::PanelId id) const;
    /// The panel's layout: pattern millimetres (y up) to scene (y down).
    QTransform layout(patterns::PanelId id) const;
    /// Pattern coordinates [m] of a scene point over panel `id`.
    patterns::Vec2 toPattern(patterns::PanelId id, const QPointF& scene) const;
    QPointF toScene(patterns::PanelId id, const patterns::Vec2& at) const;
    /// Scene units (mm) per viewport pixel.
    double sceneUnitsPerPixel() const;
    /// A scene point snapped: onto an outline or hole point within a few pixels (not
    /// `exclude`), else with Shift onto the grid of panel `gridPanel`'s pattern coordinates
    /// (the scene's millimetres when none): 5 mm, 1 mm with Ctrl.
    QPointF snap(const QPointF& scene, Qt::KeyboardModifiers modifiers, patterns::PointId exclude,
                 patterns::PanelId gridPanel) const;
    void redraw();
    void drawHandles();
    /// The drawing, the seam pick and the feedback text, drawn again.
    void drawOverlay();
    void clearOverlay();
    /// Redraws the dragged panel's outline with the point at the drag's position and the
    /// lengths of its two edges beside it.
    void showDrag();
    void showHandleDrag();
    void setFeedback(const QString& text, const QPointF& scene);
    void selectSeamAndSay(patterns::SeamId seam);
    /// Closes the polygon being drawn (≥ 3 corners) into a new panel.
    bool finishPolygon();
    /// Adds the panel of `corners` [scene], placed in the view where they were drawn.
    /// `handles`: a smooth point's outgoing handle [scene] by corner (empty: all corners).
    bool addDrawnPanel(const std::vector<QPointF>& corners,
                       const std::vector<std::optional<QPointF>>& handles = {});
    bool applyEdit(const EditMaker& make);
    std::vector<patterns::doc::SeamRange> rangesOf(const SidePick& side) const;
    // ---- The mark and curve tools (pattern_marks.cpp) ----
    /// A free curve being drawn with the pen [scene]; `out` is a smooth point's handle.
    struct PenDrawing {
        std::vector<QPointF> points;
        std::vector<std::optional<QPointF>> handles;
        QPointF cursor;
        bool dragging = false; ///< the button is down on the last point
    };
    /// An internal line being drawn on one panel [m].
    struct LineDrawing {
        patterns::PanelId panel;
        std::vector<patterns::Vec2> points;
        patterns::Vec2 cursor = patterns::Vec2::Zero();
    };
    /// A dart being dragged out of an outline edge.
    struct DartDrag {
        EdgePick base;
        patterns::Vec2 tip = patterns::Vec2::Zero(); ///< [m]
    };
    /// The grain handle being dragged.
    struct GrainDrag {
        patterns::PanelId panel;
        double angle = 0; ///< [rad]
        bool moved = false;
    };
    /// The notch or internal line within a few pixels of `at` (viewport): its panel, whether it
    /// is a notch, and its id's value.
    std::optional<std::tuple<patterns::PanelId, bool, std::uint32_t>>
    pickMark(const QPoint& at) const;
    /// The tools' press, move and release; true when the event was theirs.
    bool pressMarkTool(QMouseEvent* event);
    bool moveMarkTool(QMouseEvent* event);
    bool releaseMarkTool(QMouseEvent* event);
    /// Enter, Backspace and double-click for the pen and the internal line.
    bool finishMarkDrawing();
    bool dropLastMarkPoint();
    /// Notches, internal lines and the grain line of a panel, drawn through `layout`.
    void drawMarks(const patterns::doc::Panel& panel, const QTransform& layout);
    /// The selected panel's grain handle (part of the handles).
    void drawGrainHandle(const patterns::doc::Panel& panel);
    /// The pen drawing, the line drawing or the dart being dragged.
    void drawMarkOverlay();
    /// The grain line's ends [scene]: through the middle of the panel's outline, along `angle`.
    std::pair<QPointF, QPointF> grainLine(const patterns::doc::Panel& panel, double angle) const;
    bool finishPen();
    bool finishLine();
    void pickSeamEdge(const EdgePick& pick, Qt::KeyboardModifiers modifiers);
    /// The picked sides' ranges again; the second one runs so that the seam sews start to
    /// start as the panels lie in the view, unless the user reversed it.
    void updateSeamPick();
    void cancelTool();

    QGraphicsScene m_scene;
    patterns::GarmentDocument m_document;
    Editor m_editor;
    /// Each panel's layout in the scene (pattern mm, y up → scene), by panel id.
    std::map<std::uint32_t, QTransform> m_layouts;
    /// The layouts the view gave panels that are not placed on the sheet (kept for an undo).
    std::map<std::uint32_t, QTransform> m_freeLayouts;
    /// The layout of the next panel added under this name (one just drawn).
    std::optional<std::pair<std::string, QTransform>> m_pendingLayout;
    std::map<std::uint32_t, QGraphicsPathItem*> m_items;
    std::vector<QGraphicsItem*> m_handles;
    std::vector<QGraphicsItem*> m_overlay;
    QGraphicsSimpleTextItem* m_lengths = nullptr;
    QString m_feedback;
    int m_panels = 0;
    patterns::PanelId m_selectedPanel;
    std::vector<patterns::PanelId> m_selectedPanels; ///< in selection order, m_selectedPanel last
    patterns::PointId m_selectedPoint;
    patterns::EdgeId m_selectedEdge;
    patterns::SeamId m_selectedSeam;
    std::optional<Drag> m_drag;
    std::optional<HandleDrag> m_handleDrag;
    std::optional<LayoutDrag> m_layoutDrag;
    std::optional<Drawing> m_drawing;
    std::optional<PenDrawing> m_pen;
    std::optional<LineDrawing> m_line;
    std::optional<DartDrag> m_dart;
    std::optional<GrainDrag> m_grainDrag;
    patterns::NotchId m_selectedNotch;
    patterns::LineId m_selectedLine;
    patterns::LineId m_announcedLine; ///< the last lineSelected() said
    patterns::DartId m_announcedDart; ///< the last dartSelected() said
    /// The middle button is down: the view pans with the mouse (from here, viewport).
    std::optional<QPoint> m_pan;
    std::optional<SidePick> m_sides[2];
    /// The second side was reversed by the user (R) against the direction chosen for it.
    bool m_secondReversed = false;
    std::vector<patterns::doc::SeamRange> m_seamRanges[2];
    Tool m_tool = Tool::Select;
    QActionGroup* m_toolGroup = nullptr;
    std::map<Tool, QAction*> m_toolActions;
    QList<QAction*> m_editActions;
    /// The last left press went on to QGraphicsView (selection, panning), so its release does.
    bool m_pressPassedOn = false;
    /// Items are being removed (a redraw, the destructor): selection changes are not acted on.
    bool m_redrawing = false;
};

/// The points of a loop's segments, sampled finely enough to draw (lines: their ends; curves:
/// 24 points each) [m].
std::vector<patterns::Vec2> sampleLoop(const patterns::Loop& loop);

/// A contour's segments, in order [m].
patterns::Loop contourLoop(const patterns::doc::Contour& contour);

} // namespace atelier::ui
