#include "ui/widgets/pattern_view.h"

#include "ui/render/scene.h"
#include "ui/widgets/pattern_tools.h"
#include "ui/widgets/pattern_view_detail.h"

#include "patterns/curve.h"

#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QGraphicsEllipseItem>
#include <QGraphicsPathItem>
#include <QGraphicsSimpleTextItem>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QScrollBar>
#include <QWheelEvent>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace atelier::ui {

using namespace detail;

namespace {

QPainterPath loopPath(const patterns::Loop& loop) {
    QPainterPath path;
    const std::vector<patterns::Vec2> points = sampleLoop(loop);
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (i == 0) {
            path.moveTo(local(points[i]));
        } else {
            path.lineTo(local(points[i]));
        }
    }
    path.closeSubpath();
    return path;
}

/// The panel's outline and holes in the scene, through its layout.
QPainterPath panelPath(const patterns::doc::Panel& panel, const QTransform& layout) {
    QPainterPath path = loopPath(contourLoop(panel.outline));
    for (const patterns::doc::Hole& hole : panel.holes) {
        path.addPath(loopPath(contourLoop(hole.contour)));
    }
    path.setFillRule(Qt::OddEvenFill);
    return layout.map(path);
}

/// The horizontal extent of a panel's outline [pattern mm].
std::pair<double, double> extentMm(const patterns::doc::Panel& panel) {
    double minX = INFINITY;
    double maxX = -INFINITY;
    for (const patterns::Vec2& v : sampleLoop(contourLoop(panel.outline))) {
        minX = std::min(minX, v.x() * MM);
        maxX = std::max(maxX, v.x() * MM);
    }
    return {minX, maxX};
}

/// A panel laid `dx` mm right of the scene's origin: pattern mm (y up) to scene (y down).
QTransform shiftedLayout(double dx, double dy = 0) {
    return {1, 0, 0, -1, dx, dy};
}

/// The layout of a panel placed on the sheet (metres, y up, counter-clockwise) as the scene's
/// transform (millimetres, y down): the panel's y flipped, turned, then moved.
QTransform sheetLayout(const patterns::doc::SheetPlace& place) {
    return QTransform(1, 0, 0, -1, 0, 0) *
           QTransform().rotate(-place.angle * 180 / std::numbers::pi) *
           QTransform::fromTranslate(place.at.x() * MM, -place.at.y() * MM);
}

/// The sheet place of a layout made of a flip, turns and moves (sheetLayout's inverse).
patterns::doc::SheetPlace sheetPlace(const QTransform& layout) {
    return {patterns::Vec2(layout.dx() / MM, -layout.dy() / MM),
            std::atan2(-layout.m12(), layout.m11())};
}

} // namespace

std::vector<patterns::Vec2> sampleLoop(const patterns::Loop& loop) {
    std::vector<patterns::Vec2> out;
    for (const patterns::Segment& s : loop) {
        const int n = s.kind == patterns::SegmentKind::Line ? 1 : 24;
        for (int i = 0; i < n; ++i) {
            out.push_back(patterns::pointAt(s, double(i) / n));
        }
    }
    return out;
}

patterns::Loop contourLoop(const patterns::doc::Contour& contour) {
    patterns::Loop loop;
    for (std::size_t i = 0; i < contour.edges.size(); ++i) {
        loop.push_back(patterns::contourSegment(contour, i));
    }
    return loop;
}

PatternView::PatternView(QWidget* parent) : QGraphicsView(parent) {
    setScene(&m_scene);
    m_scene.setSceneRect(-SCENE_HALF_MM, -SCENE_HALF_MM, 2 * SCENE_HALF_MM, 2 * SCENE_HALF_MM);
    setRenderHint(QPainter::Antialiasing);
    setDragMode(QGraphicsView::ScrollHandDrag);
    setTransformationAnchor(QGraphicsView::AnchorUnderMouse);
    setBackgroundBrush(QColor(250, 250, 247));
    setMinimumSize(240, 240);
    setFocusPolicy(Qt::StrongFocus);
    connect(&m_scene, &QGraphicsScene::selectionChanged, this, [this] {
        if (m_redrawing) {
            return;
        }
        // The panels selected, in the order they were: those still selected, then the new
        // ones (Ctrl+click adds one); the last one added is the selected panel, whose points
        // and handles are shown and which the docks show.
        std::vector<patterns::PanelId> now;
        for (const QGraphicsItem* item : m_scene.selectedItems()) {
            now.push_back(patterns::PanelId{item->data(DATA_PANEL).value<quint32>()});
        }
        const auto in = [](const std::vector<patterns::PanelId>& list, patterns::PanelId id) {
            return std::find(list.begin(), list.end(), id) != list.end();
        };
        std::vector<patterns::PanelId> ordered;
        for (const patterns::PanelId id : m_selectedPanels) {
            if (in(now, id)) {
                ordered.push_back(id);
            }
        }
        patterns::PanelId id = in(ordered, m_selectedPanel) ? m_selectedPanel
                               : ordered.empty()            ? patterns::PanelId{}
                                                            : ordered.back();
        for (const patterns::PanelId added : now) {
            if (!in(ordered, added)) {
                ordered.push_back(added);
                id = added;
            }
        }
        m_selectedPanels = std::move(ordered);
        if (id != m_selectedPanel) {
            m_selectedPanel = id;
            m_selectedPoint = {};
            m_selectedEdge = {};
            m_selectedNotch = {};
            m_selectedLine = {};
            drawHandles();
        }
        const patterns::doc::Panel* shown = panel(m_selectedPanel);
        Q_EMIT panelSelected(shown != nullptr ? QString::fromStdString(shown->name) : QString());
        if (m_selectedPanels.size() > 1) {
            Q_EMIT message(tr("%1 panels selected: click a body slot in the 3D view to place "
                              "them side by side")
                               .arg(m_selectedPanels.size()));
        }
    });

    m_toolGroup = new QActionGroup(this);
    const auto addTool = [this](Tool tool, const QString& text, Qt::Key key, const QString& tip) {
        auto* action = new QAction(text, this);
        action->setCheckable(true);
        action->setShortcut(QKeySequence(key));
        action->setToolTip(tr("%1 (%2): %3")
                               .arg(text.split('&').join(QString()))
                               .arg(QKeySequence(key).toString(QKeySequence::NativeText), tip));
        action->setStatusTip(tip);
        m_toolGroup->addAction(action);
        connect(action, &QAction::triggered, this, [this, tool] { setTool(tool); });
        m_toolActions[tool] = action;
        addAction(action);
    };
    addTool(Tool::Select, tr("&Select"), Qt::Key_A,
            tr("select, move points and handles, move and rotate panels"));
    addTool(Tool::Rectangle, tr("&Rectangle"), Qt::Key_S, tr("drag out a rectangular panel"));
    addTool(Tool::Polygon, tr("&Polygon"), Qt::Key_H,
            tr("click corners; click the first, double-click or Enter to close; Esc cancels"));
    addTool(Tool::Seam, tr("S&eam"), Qt::Key_N,
            tr("click an edge (Shift+click extends, Ctrl from the point), then the other side; "
               "R reverses it, Enter sews"));
    addTool(Tool::Curve, tr("&Curve"), Qt::Key_P,
            tr("click for corners, press and drag for smooth points; close on the first point, "
               "double-click or Enter"));
    addTool(Tool::InternalLine, tr("&Internal line"), Qt::Key_L,
            tr("click points inside a panel; double-click or Enter ends the line"));
    addTool(Tool::Notch, tr("&Notch"), Qt::Key_K, tr("click an outline edge to put a notch"));
    addTool(Tool::Dart, tr("&Dart"), Qt::Key_D,
            tr("press on an outline edge and drag into the panel to the dart's tip"));
    m_toolActions[Tool::Select]->setChecked(true);

    auto* curve = new QAction(tr("&Curve or straighten edge"), this);
    curve->setShortcut(QKeySequence(Qt::Key_V));
    curve->setStatusTip(tr("the selected edge becomes a Bézier curve, or straight again"));
    connect(curve, &QAction::triggered, this, [this] { toggleCurve(); });
    auto* reverse = new QAction(tr("Re&verse seam"), this);
    reverse->setShortcut(QKeySequence(Qt::Key_R));
    reverse->setStatusTip(tr("the second side of the seam runs the other way"));
    connect(reverse, &QAction::triggered, this, [this] { reverseSeam(); });
    auto* sewAction = new QAction(tr("Se&w"), this);
    sewAction->setStatusTip(tr("sew the two sides picked with the seam tool (Enter)"));
    connect(sewAction, &QAction::triggered, this, [this] { sew(); });
    m_editActions = {curve, reverse, sewAction};
    for (QAction* a : m_editActions) {
        addAction(a);
    }
}

PatternView::~PatternView() {
    m_redrawing = true; // the scene's items go with it: nothing to redraw
    m_handles.clear();
    m_overlay.clear();
}

QList<QAction*> PatternView::toolActions() const {
    return {m_toolActions.at(Tool::Select),  m_toolActions.at(Tool::Rectangle),
            m_toolActions.at(Tool::Polygon), m_toolActions.at(Tool::Curve),
            m_toolActions.at(Tool::Seam),    m_toolActions.at(Tool::InternalLine),
            m_toolActions.at(Tool::Notch),   m_toolActions.at(Tool::Dart)};
}

QList<QAction*> PatternView::editActions() const {
    return m_editActions;
}

void PatternView::setTool(Tool tool) {
    cancelTool();
    m_tool = tool;
    m_toolActions.at(tool)->setChecked(true);
    setDragMode(tool == Tool::Select ? QGraphicsView::ScrollHandDrag : QGraphicsView::NoDrag);
    if (tool == Tool::Select) {
        viewport()->unsetCursor();
    } else {
        viewport()->setCursor(Qt::CrossCursor);
    }
    Q_EMIT message(m_toolActions.at(tool)->statusTip());
    Q_EMIT toolChanged(tool);
}

void PatternView::cancelTool() {
    m_drawing.reset();
    m_pen.reset();
    m_line.reset();
    m_dart.reset();
    m_grainDrag.reset();
    m_sides[0].reset();
    m_sides[1].reset();
    m_seamRanges[0].clear();
    m_seamRanges[1].clear();
    m_secondReversed = false;
    m_layoutDrag.reset();
    m_handleDrag.reset();
    clearOverlay();
}

const patterns::doc::Panel* PatternView::panel(patterns::PanelId id) const {
    return m_document.panel(id);
}

QTransform PatternView::layout(patterns::PanelId id) const {
    const auto it = m_layouts.find(id.value);
    return it == m_layouts.end() ? shiftedLayout(0) : it->second;
}

patterns::Vec2 PatternView::toPattern(patterns::PanelId id, const QPointF& scene) const {
    const QPointF p = layout(id).inverted().map(scene);
    return {p.x() / MM, p.y() / MM};
}

QPointF PatternView::toScene(patterns::PanelId id, const patterns::Vec2& at) const {
    return layout(id).map(local(at));
}

QPointF PatternView::scenePoint(patterns::PanelId panel, const patterns::Vec2& at) const {
    return toScene(panel, at);
}

QPoint PatternView::viewPoint(patterns::PanelId panel, const patterns::Vec2& at) const {
    return mapFromScene(toScene(panel, at));
}

double PatternView::sceneUnitsPerPixel() const {
    return 1.0 / std::max(1e-9, transform().m11());
}

void PatternView::setDocument(const patterns::GarmentDocument& document, bool keepLayout) {
    m_document = document;
    m_drag.reset();
    m_handleDrag.reset();
    m_layoutDrag.reset();
    if (!keepLayout) {
        m_layouts.clear();
        m_freeLayouts.clear();
        m_selectedPanel = {};
        m_selectedPanels.clear();
        m_selectedPoint = {};
        m_selectedEdge = {};
        m_selectedSeam = {};
        cancelTool();
    }
    // A panel placed on the sheet lies where the document says; one that is not lies where the
    // view first laid it out (as before its first move, after that move is undone).
    for (const patterns::doc::Panel& p : m_document.panels) {
        if (p.sheet) {
            m_layouts[p.id.value] = sheetLayout(*p.sheet);
        } else if (const auto it = m_freeLayouts.find(p.id.value); it != m_freeLayouts.end()) {
            m_layouts[p.id.value] = it->second;
        }
    }
    // Panels already laid out keep their place; new ones go right of the rightmost (or where
    // they were drawn).
    double x = 0;
    for (const patterns::doc::Panel& p : m_document.panels) {
        if (const auto it = m_layouts.find(p.id.value); it != m_layouts.end()) {
            const QRectF box = panelPath(p, it->second).boundingRect();
            if (!p.outline.points.empty()) {
                x = std::max(x, box.right() + GAP_MM);
            }
        }
    }
    for (const patterns::doc::Panel& p : m_document.panels) {
        if (m_layouts.count(p.id.value) != 0) {
            continue;
        }
        if (m_pendingLayout && m_pendingLayout->first == p.name) {
            m_layouts[p.id.value] = m_pendingLayout->second;
            m_freeLayouts[p.id.value] = m_pendingLayout->second;
            m_pendingLayout.reset();
            continue;
        }
        const auto [minX, maxX] = extentMm(p);
        if (!std::isfinite(minX)) {
            continue;
        }
        m_layouts[p.id.value] = shiftedLayout(x - minX);
        m_freeLayouts[p.id.value] = m_layouts[p.id.value];
        x += maxX - minX + GAP_MM;
    }
    std::erase_if(m_selectedPanels, [this](patterns::PanelId id) { return panel(id) == nullptr; });
    if (m_selectedPanel && panel(m_selectedPanel) == nullptr) {
        m_selectedPanel = m_selectedPanels.empty() ? patterns::PanelId{} : m_selectedPanels.back();
    }
    patterns::doc::Panel* selected = m_document.panel(m_selectedPanel);
    int index = 0;
    if (m_selectedPoint &&
        (selected == nullptr ||
         patterns::contourOfPoint(*selected, m_selectedPoint, index) == nullptr)) {
        m_selectedPoint = {};
    }
    if (m_selectedEdge && (selected == nullptr ||
                           patterns::contourOfEdge(*selected, m_selectedEdge, index) == nullptr)) {
        m_selectedEdge = {};
    }
    if (selected == nullptr ||
        std::none_of(selected->notches.begin(), selected->notches.end(),
                     [&](const patterns::doc::Notch& n) { return n.id == m_selectedNotch; })) {
        m_selectedNotch = {};
    }
    if (selected == nullptr ||
        std::none_of(
            selected->internalLines.begin(), selected->internalLines.end(),
            [&](const patterns::doc::InternalLine& l) { return l.id == m_selectedLine; })) {
        m_selectedLine = {};
    }
    if (m_selectedSeam && m_document.seam(m_selectedSeam) == nullptr) {
        m_selectedSeam = {};
    }
    for (auto& side : m_sides) {
        const patterns::doc::Panel* p = side ? panel(side->panel) : nullptr;
        const auto n = p == nullptr ? 0 : static_cast<int>(p->outline.edges.size());
        if (side && (side->fromEdge >= n || side->toEdge >= n)) {
            side.reset();
        }
    }
    if (!m_sides[0]) {
        m_sides[1].reset();
    }
    redraw();
    if (!keepLayout) {
        const QRectF items = m_scene.itemsBoundingRect();
        fitInView(items.isEmpty() ? QRectF(-600, -400, 1200, 800)
                                  : items.adjusted(-GAP_MM, -GAP_MM, GAP_MM, GAP_MM),
                  Qt::KeepAspectRatio);
    }
}

void PatternView::selectPanel(patterns::PanelId id) {
    if (const auto it = m_items.find(id.value); it != m_items.end()) {
        m_scene.clearSelection();
        it->second->setSelected(true);
    }
}

void PatternView::selectSeam(patterns::SeamId seam) {
    m_selectedSeam = m_document.seam(seam) != nullptr ? seam : patterns::SeamId{};
    redraw();
}

void PatternView::selectSeamAndSay(patterns::SeamId seam) {
    selectSeam(seam);
    const patterns::doc::Seam* s = m_document.seam(m_selectedSeam);
    if (s == nullptr) {
        return;
    }
    Q_EMIT seamSelected(m_selectedSeam.value);
    const auto [a, b] = seamLengths(m_document, *s);
    Q_EMIT message(tr("Seam %1: %2 mm and %3 mm, mismatch %4 mm")
                       .arg(QString::fromStdString(s->name))
                       .arg(a * MM, 0, 'f', 1)
                       .arg(b * MM, 0, 'f', 1)
                       .arg(std::abs(a - b) * MM, 0, 'f', 1));
}

namespace {

/// An arrowhead `px` pixels long at `tip` pointing along `direction` [scene].
QGraphicsPathItem* addArrow(QGraphicsScene& scene, const QPointF& tip, const QPointF& direction,
                            const QColor& colour, double px) {
    QPainterPath head;
    head.moveTo(0, 0);
    head.lineTo(-px, -px * 0.45);
    head.lineTo(-px, px * 0.45);
    head.closeSubpath();
    auto* item = scene.addPath(head, QPen(Qt::NoPen), QBrush(colour));
    item->setFlag(QGraphicsItem::ItemIgnoresTransformations);
    item->setPos(tip);
    item->setRotation(std::atan2(direction.y(), direction.x()) * 180 / std::numbers::pi);
    item->setZValue(8);
    return item;
}

} // namespace

void PatternView::redraw() {
    m_redrawing = true;
    m_scene.clear();
    m_items.clear();
    m_handles.clear();
    m_overlay.clear();
    m_lengths = nullptr;
    m_panels = 0;
    for (std::size_t p = 0; p < m_document.panels.size(); ++p) {
        const patterns::doc::Panel& panel = m_document.panels[p];
        if (m_layouts.count(panel.id.value) == 0) {
            continue; // an outline without points
        }
        const QTransform t = layout(panel.id);
        const QPainterPath path = panelPath(panel, t);
        auto* item = m_scene.addPath(path, QPen(QColor(60, 60, 70), 0),
                                     QBrush(qColour(render::panelColour(static_cast<int>(p)))));
        item->setFlag(QGraphicsItem::ItemIsSelectable);
        item->setData(DATA_NAME, QString::fromStdString(panel.name));
        item->setData(DATA_PANEL, quint32(panel.id.value));
        item->setToolTip(QString::fromStdString(panel.name));
        m_items[panel.id.value] = item;
        drawMarks(panel, t);
        auto* label = m_scene.addSimpleText(QString::fromStdString(panel.name));
        label->setBrush(QColor(40, 40, 50));
        const QRectF box = path.boundingRect();
        label->setScale(std::max(1.0, box.width() / 200.0));
        label->setPos(box.center() - QPointF(label->boundingRect().width() * label->scale() / 2,
                                             label->boundingRect().height() * label->scale() / 2));
        ++m_panels;
    }
    // Seams: both sides in the seam's colour, an arrow at each side's end.
    for (std::size_t k = 0; k < m_document.seams.size(); ++k) {
        const patterns::doc::Seam& seam = m_document.seams[k];
        const QColor colour = qColour(render::seamColour(static_cast<int>(k)));
        const bool selected = seam.id == m_selectedSeam;
        for (const auto* side : {&seam.a, &seam.b}) {
            QPointF tip;
            QPointF direction;
            for (const patterns::doc::SeamRange& r : *side) {
                const patterns::doc::Panel* p = panel(r.panel);
                const int e = p == nullptr ? -1 : patterns::outlineEdgeIndex(*p, r.edge);
                if (e < 0 || m_layouts.count(p->id.value) == 0) {
                    continue;
                }
                const patterns::Segment s =
                    patterns::contourSegment(p->outline, static_cast<std::size_t>(e));
                auto* item = m_scene.addPath(layout(p->id).map(segmentPath(s, r.t0, r.t1)),
                                             screenPen(colour, selected ? 6 : 3));
                item->setZValue(5);
                tip = toScene(p->id, patterns::pointAt(s, r.t1));
                direction = tip - toScene(p->id, patterns::pointAt(s, r.t1 - 0.02 * (r.t1 - r.t0)));
            }
            if (!direction.isNull()) {
                addArrow(m_scene, tip, direction, colour, selected ? 16 : 12);
            }
        }
    }
    for (const patterns::PanelId id : m_selectedPanels) {
        if (const auto it = m_items.find(id.value); it != m_items.end()) {
            it->second->setSelected(true);
        }
    }
    m_redrawing = false;
    drawHandles();
    drawOverlay();
}

void PatternView::drawHandles() {
    if (m_selectedLine.value != m_announcedLine.value) {
        m_announcedLine = m_selectedLine;
        Q_EMIT lineSelected(m_selectedPanel.value, m_selectedLine.value);
    }
    patterns::DartId dart; // the dart whose leg is the selected edge
    if (const patterns::doc::Panel* p = panel(m_selectedPanel); p != nullptr && m_selectedEdge) {
        for (const patterns::doc::Dart& d : p->darts) {
            if (d.leg1 == m_selectedEdge || d.leg2 == m_selectedEdge) {
                dart = d.id;
            }
        }
    }
    if (dart.value != m_announcedDart.value) {
        m_announcedDart = dart;
        Q_EMIT dartSelected(m_selectedPanel.value, dart.value);
    }
    for (QGraphicsItem* h : m_handles) {
        m_scene.removeItem(h);
        delete h;
    }
    m_handles.clear();
    const patterns::doc::Panel* selected = panel(m_selectedPanel);
    if (selected == nullptr) {
        return;
    }
    const QTransform t = layout(selected->id);
    // A curve's square handle at `at` [m]: control 1 or 2 of a Bézier edge, or an arc's bulge.
    const auto addControl = [&](const patterns::Vec2& at, patterns::EdgeId edge, int control) {
        auto* h = m_scene.addRect(-HANDLE_PX / 2, -HANDLE_PX / 2, HANDLE_PX, HANDLE_PX,
                                  QPen(QColor(30, 30, 40), 1), QBrush(QColor(80, 160, 230)));
        h->setFlag(QGraphicsItem::ItemIgnoresTransformations);
        h->setPos(toScene(selected->id, at));
        h->setZValue(10);
        h->setData(DATA_ROLE, ROLE_CONTROL);
        h->setData(DATA_PANEL, quint32(selected->id.value));
        h->setData(DATA_EDGE, quint32(edge.value));
        h->setData(DATA_CONTROL, control);
        m_handles.push_back(h);
        return h;
    };
    const auto addHandles = [&](const patterns::doc::Contour& contour) {
        for (std::size_t e = 0; e < contour.edges.size(); ++e) {
            const patterns::doc::Edge& edge = contour.edges[e];
            const patterns::Segment s = patterns::contourSegment(contour, e);
            if (edge.id == m_selectedEdge) {
                auto* line =
                    m_scene.addPath(t.map(segmentPath(s, 0, 1)), screenPen(QColor(20, 20, 30), 4));
                line->setZValue(6);
                m_handles.push_back(line);
            }
            if (s.kind == patterns::SegmentKind::Arc) {
                // The bulge handle: a square on the arc's middle, on a line from the chord's.
                const patterns::Vec2 middle = patterns::pointAt(s, 0.5);
                auto* arm = m_scene.addLine(QLineF(toScene(selected->id, 0.5 * (s.start + s.end)),
                                                   toScene(selected->id, middle)),
                                            screenPen(QColor(90, 90, 110), 1));
                arm->setZValue(9);
                m_handles.push_back(arm);
                addControl(middle, edge.id, CONTROL_BULGE)->setToolTip(tr("drag to bend the arc"));
                continue;
            }
            if (s.kind != patterns::SegmentKind::Quadratic &&
                s.kind != patterns::SegmentKind::Cubic) {
                continue;
            }
            // Bézier handles as in vector editors: a line from each end to its control point
            // and a small square there.
            const bool cubic = s.kind == patterns::SegmentKind::Cubic;
            QPainterPath arms;
            arms.moveTo(toScene(selected->id, s.start));
            arms.lineTo(toScene(selected->id, s.control1));
            arms.moveTo(toScene(selected->id, s.end));
            arms.lineTo(toScene(selected->id, cubic ? s.control2 : s.control1));
            auto* armItem = m_scene.addPath(arms, screenPen(QColor(90, 90, 110), 1));
            armItem->setZValue(9);
            m_handles.push_back(armItem);
            for (int c = 1; c <= (cubic ? 2 : 1); ++c) {
                addControl(c == 1 ? s.control1 : s.control2, edge.id, c);
            }
        }
        for (const patterns::doc::Point& point : contour.points) {
            const bool current = point.id == m_selectedPoint;
            auto* h = m_scene.addEllipse(-HANDLE_PX / 2, -HANDLE_PX / 2, HANDLE_PX, HANDLE_PX,
                                         QPen(QColor(30, 30, 40), 1),
                                         current ? QBrush(QColor(220, 40, 40)) : QBrush(Qt::white));
            h->setFlag(QGraphicsItem::ItemIgnoresTransformations);
            h->setPos(toScene(selected->id, point.position));
            h->setZValue(10);
            h->setData(DATA_ROLE, ROLE_POINT);
            h->setData(DATA_PANEL, quint32(selected->id.value));
            h->setData(DATA_POINT, quint32(point.id.value));
            m_handles.push_back(h);
        }
    };
    addHandles(selected->outline);
    for (const patterns::doc::Hole& hole : selected->holes) {
        addHandles(hole.contour);
    }
    // The rotate handle: above the middle of the panel, joined to it by a thin line.
    if (const auto it = m_items.find(selected->id.value); it != m_items.end()) {
        const QRectF box = it->second->path().boundingRect();
        const QPointF top(box.center().x(), box.top());
        const QPointF knob = top - QPointF(0, ROTATE_HANDLE_PX * sceneUnitsPerPixel());
        auto* stem = m_scene.addLine(QLineF(top, knob), screenPen(QColor(90, 90, 110), 1));
        stem->setZValue(9);
        m_handles.push_back(stem);
        auto* h = m_scene.addEllipse(-HANDLE_PX / 2, -HANDLE_PX / 2, HANDLE_PX, HANDLE_PX,
                                     QPen(QColor(30, 30, 40), 1), QBrush(QColor(120, 200, 120)));
        h->setFlag(QGraphicsItem::ItemIgnoresTransformations);
        h->setPos(knob);
        h->setZValue(10);
        h->setData(DATA_ROLE, ROLE_ROTATE);
        h->setData(DATA_PANEL, quint32(selected->id.value));
        h->setToolTip(tr("drag to rotate the panel in the 2D layout (Shift: 15° steps)"));
        m_handles.push_back(h);
    }
    drawGrainHandle(*selected);
}

void PatternView::clearOverlay() {
    for (QGraphicsItem* item : m_overlay) {
        m_scene.removeItem(item);
        delete item;
    }
    m_overlay.clear();
    if (m_lengths != nullptr) {
        m_scene.removeItem(m_lengths);
        delete m_lengths;
        m_lengths = nullptr;
    }
    m_feedback.clear();
}

void PatternView::setFeedback(const QString& text, const QPointF& scene) {
    m_feedback = text;
    if (m_lengths == nullptr) {
        m_lengths = m_scene.addSimpleText(QString());
        m_lengths->setFlag(QGraphicsItem::ItemIgnoresTransformations);
        m_lengths->setZValue(11);
        m_lengths->setBrush(QColor(20, 20, 120));
    }
    m_lengths->setText(text);
    m_lengths->setPos(scene + QPointF(8, 8) * sceneUnitsPerPixel());
}

QString PatternView::feedback() const {
    return m_feedback;
}

QString PatternView::dragLengths() const {
    return m_drag ? m_feedback : QString();
}

void PatternView::drawOverlay() {
    clearOverlay();
    if (m_drawing && !m_drawing->points.empty()) {
        const QPen pen = screenPen(QColor(20, 20, 120), 1.5, Qt::DashLine);
        const std::vector<QPointF>& points = m_drawing->points;
        const QPointF cursor = m_drawing->cursor;
        if (m_tool == Tool::Rectangle) {
            const QRectF box = QRectF(points.front(), cursor).normalized();
            m_overlay.push_back(m_scene.addRect(box, pen));
            setFeedback(tr("%1 × %2 mm").arg(box.width(), 0, 'f', 1).arg(box.height(), 0, 'f', 1),
                        cursor);
        } else {
            QPainterPath path(points.front());
            double perimeter = 0;
            for (std::size_t i = 1; i < points.size(); ++i) {
                path.lineTo(points[i]);
                perimeter += distance(points[i - 1], points[i]);
            }
            path.lineTo(cursor);
            const double segment = distance(points.back(), cursor);
            m_overlay.push_back(m_scene.addPath(path, pen));
            // The first corner: clicking it closes the outline.
            auto* first = m_scene.addEllipse(-HANDLE_PX / 2, -HANDLE_PX / 2, HANDLE_PX, HANDLE_PX,
                                             QPen(QColor(20, 20, 120), 1), QBrush(Qt::white));
            first->setFlag(QGraphicsItem::ItemIgnoresTransformations);
            first->setPos(points.front());
            m_overlay.push_back(first);
            setFeedback(tr("%1 mm, outline %2 mm, %3 corners")
                            .arg(segment, 0, 'f', 1)
                            .arg(perimeter + segment, 0, 'f', 1)
                            .arg(points.size()),
                        cursor);
        }
        for (QGraphicsItem* item : m_overlay) {
            item->setZValue(std::max(item->zValue(), 7.0));
        }
    }
    if (!m_seamRanges[0].empty()) {
        const QColor colour =
            qColour(render::seamColour(static_cast<int>(m_document.seams.size())));
        QPointF last;
        for (int side = 0; side < 2; ++side) {
            QPointF tip;
            QPointF direction;
            for (const patterns::doc::SeamRange& r : m_seamRanges[side]) {
                const patterns::doc::Panel* p = panel(r.panel);
                const int e = p == nullptr ? -1 : patterns::outlineEdgeIndex(*p, r.edge);
                if (e < 0) {
                    continue;
                }
                const patterns::Segment s =
                    patterns::contourSegment(p->outline, static_cast<std::size_t>(e));
                auto* item =
                    m_scene.addPath(layout(p->id).map(segmentPath(s, r.t0, r.t1)),
                                    screenPen(colour, 7, side == 0 ? Qt::SolidLine : Qt::DashLine));
                item->setOpacity(0.8);
                item->setZValue(7);
                m_overlay.push_back(item);
                tip = toScene(p->id, patterns::pointAt(s, r.t1));
                direction = tip - toScene(p->id, patterns::pointAt(s, r.t1 - 0.02 * (r.t1 - r.t0)));
            }
            if (!direction.isNull()) {
                m_overlay.push_back(addArrow(m_scene, tip, direction, colour, 18));
                last = tip;
            }
        }
        const double a = rangesLength(m_document, m_seamRanges[0]);
        const double b = rangesLength(m_document, m_seamRanges[1]);
        setFeedback(m_seamRanges[1].empty()
                        ? tr("first side %1 mm").arg(a * MM, 0, 'f', 1)
                        : tr("%1 mm and %2 mm, mismatch %3 mm (R reverses, Enter sews)")
                              .arg(a * MM, 0, 'f', 1)
                              .arg(b * MM, 0, 'f', 1)
                              .arg(std::abs(a - b) * MM, 0, 'f', 1),
                    last);
    }
    drawMarkOverlay();
}

void PatternView::showDrag() {
    const patterns::doc::Panel* original = panel(m_drag->panel);
    if (original == nullptr) {
        return;
    }
    patterns::doc::Panel moved = *original;
    int index = 0;
    patterns::doc::Contour* contour = patterns::contourOfPoint(moved, m_drag->point, index);
    if (contour == nullptr) {
        return;
    }
    contour->points[static_cast<std::size_t>(index)].position = m_drag->position;
    if (const auto it = m_items.find(m_drag->panel.value); it != m_items.end()) {
        it->second->setPath(panelPath(moved, layout(m_drag->panel)));
    }
    for (QGraphicsItem* h : m_handles) {
        if (h->data(DATA_POINT).value<quint32>() == m_drag->point.value) {
            h->setPos(toScene(m_drag->panel, m_drag->position));
        }
    }
    const std::size_t n = contour->edges.size();
    const auto i = static_cast<std::size_t>(index);
    const double before = patterns::arcLength(patterns::contourSegment(*contour, (i + n - 1) % n));
    const double after = patterns::arcLength(patterns::contourSegment(*contour, i));
    setFeedback(tr("%1 mm ← · → %2 mm  (%3, %4)")
                    .arg(before * MM, 0, 'f', 1)
                    .arg(after * MM, 0, 'f', 1)
                    .arg(m_drag->position.x() * MM, 0, 'f', 1)
                    .arg(m_drag->position.y() * MM, 0, 'f', 1),
                toScene(m_drag->panel, m_drag->position));
}

void PatternView::showHandleDrag() {
    const patterns::doc::Panel* original = panel(m_handleDrag->panel);
    if (original == nullptr) {
        return;
    }
    patterns::doc::Panel curved = *original;
    int index = 0;
    patterns::doc::Contour* contour = patterns::contourOfEdge(curved, m_handleDrag->edge, index);
    if (contour == nullptr) {
        return;
    }
    contour->edges[static_cast<std::size_t>(index)].curve = m_handleDrag->curve;
    if (const auto it = m_items.find(m_handleDrag->panel.value); it != m_items.end()) {
        it->second->setPath(panelPath(curved, layout(m_handleDrag->panel)));
    }
    const patterns::Segment segment =
        patterns::contourSegment(*contour, static_cast<std::size_t>(index));
    const bool arc = m_handleDrag->control == CONTROL_BULGE;
    const patterns::Vec2 at = arc                          ? patterns::pointAt(segment, 0.5)
                              : m_handleDrag->control == 1 ? m_handleDrag->curve.control1
                                                           : m_handleDrag->curve.control2;
    for (QGraphicsItem* h : m_handles) {
        if (h->data(DATA_EDGE).value<quint32>() == m_handleDrag->edge.value &&
            h->data(DATA_CONTROL).toInt() == m_handleDrag->control) {
            h->setPos(toScene(m_handleDrag->panel, at));
        }
    }
    const double length = patterns::arcLength(segment);
    if (arc) {
        const double sagitta = (at - 0.5 * (segment.start + segment.end)).norm();
        setFeedback(
            tr("edge %1 mm  height %2 mm").arg(length * MM, 0, 'f', 1).arg(sagitta * MM, 0, 'f', 1),
            toScene(m_handleDrag->panel, at));
        return;
    }
    setFeedback(tr("edge %1 mm  (%2, %3)")
                    .arg(length * MM, 0, 'f', 1)
                    .arg(at.x() * MM, 0, 'f', 1)
                    .arg(at.y() * MM, 0, 'f', 1),
                toScene(m_handleDrag->panel, at));
}

QPointF PatternView::snap(const QPointF& scene, Qt::KeyboardModifiers modifiers,
                          patterns::PointId exclude, patterns::PanelId gridPanel) const {
    const QTransform view = viewportTransform();
    const QPointF at = view.map(scene);
    double best = SNAP_PX;
    std::optional<QPointF> onto;
    for (const patterns::doc::Panel& p : m_document.panels) {
        if (m_layouts.count(p.id.value) == 0) {
            continue;
        }
        const auto search = [&](const patterns::doc::Contour& contour) {
            for (const patterns::doc::Point& point : contour.points) {
                if (point.id == exclude) {
                    continue;
                }
                const QPointF q = toScene(p.id, point.position);
                if (const double d = distance(view.map(q), at); d < best) {
                    best = d;
                    onto = q;
                }
            }
        };
        search(p.outline);
        for (const patterns::doc::Hole& hole : p.holes) {
            search(hole.contour);
        }
    }
    if (onto) {
        return *onto;
    }
    if (!(modifiers & Qt::ShiftModifier)) {
        return scene;
    }
    // The grid of the panel's pattern coordinates (or of the scene): 5 mm, or 1 mm with Ctrl.
    const double grid = modifiers & Qt::ControlModifier ? 1.0 : 5.0;
    const QTransform toGrid = gridPanel ? layout(gridPanel).inverted() : QTransform();
    const QPointF g = toGrid.map(scene);
    const QPointF snapped(std::round(g.x() / grid) * grid, std::round(g.y() / grid) * grid);
    return toGrid.inverted().map(snapped);
}

std::optional<PatternView::EdgePick> PatternView::pickEdge(const QPoint& at,
                                                           patterns::PanelId only) const {
    const QTransform view = viewportTransform();
    double best = PICK_EDGE_PX;
    std::optional<EdgePick> pick;
    const auto search = [&](const patterns::doc::Panel& p, const patterns::doc::Contour& contour,
                            bool outline) {
        for (std::size_t e = 0; e < contour.edges.size(); ++e) {
            const patterns::Segment s = patterns::contourSegment(contour, e);
            constexpr int SAMPLES = 200;
            for (int k = 1; k < SAMPLES; ++k) {
                const double t = double(k) / SAMPLES;
                const patterns::Vec2 q = patterns::pointAt(s, t);
                if (const double d = distance(view.map(toScene(p.id, q)), QPointF(at)); d < best) {
                    best = d;
                    pick = EdgePick{p.id, contour.edges[e].id, static_cast<int>(e), outline, t, q};
                }
            }
        }
    };
    for (const patterns::doc::Panel& p : m_document.panels) {
        if ((only && p.id != only) || m_layouts.count(p.id.value) == 0) {
            continue;
        }
        search(p, p.outline, true);
        if (only) {
            for (const patterns::doc::Hole& hole : p.holes) {
                search(p, hole.contour, false);
            }
        }
    }
    return pick;
}

patterns::SeamId PatternView::seamAt(const EdgePick& pick) const {
    for (const patterns::doc::Seam& seam : m_document.seams) {
        for (const auto* side : {&seam.a, &seam.b}) {
            for (const patterns::doc::SeamRange& r : *side) {
                if (r.panel == pick.panel && r.edge == pick.edge &&
                    pick.t >= std::min(r.t0, r.t1) && pick.t <= std::max(r.t0, r.t1)) {
                    return seam.id;
                }
            }
        }
    }
    return {};
}

bool PatternView::applyEdit(const EditMaker& make) {
    if (!m_editor) {
        return false;
    }
    return m_editor(make);
}

bool PatternView::addDrawnPanel(const std::vector<QPointF>& corners,
                                const std::vector<std::optional<QPointF>>& handles) {
    double left = INFINITY;
    double right = -INFINITY;
    double top = INFINITY;
    double bottom = -INFINITY;
    for (const QPointF& c : corners) {
        left = std::min(left, c.x());
        right = std::max(right, c.x());
        top = std::min(top, c.y());
        bottom = std::max(bottom, c.y());
    }
    const QRectF box(QPointF(left, top), QPointF(right, bottom));
    const QPointF centre = box.center();
    const auto pattern = [&](const QPointF& c) {
        return patterns::Vec2((c.x() - centre.x()) / MM, -(c.y() - centre.y()) / MM);
    };
    std::vector<PenPoint> points;
    for (std::size_t i = 0; i < corners.size(); ++i) {
        PenPoint p{pattern(corners[i]), std::nullopt};
        if (i < handles.size() && handles[i]) {
            p.handle = pattern(*handles[i]);
        }
        points.push_back(p);
    }
    const patterns::Panel drawn = drawnCurvePanel(m_document, points);
    m_pendingLayout = std::make_pair(drawn.name, shiftedLayout(centre.x(), centre.y()));
    std::uint32_t created = 0;
    const bool ok = applyEdit([&](patterns::GarmentDocument& d) {
        auto made = patterns::addPanel(d, drawn);
        if (made.ok()) {
            created = made.value().created;
        }
        return made;
    });
    m_pendingLayout.reset();
    if (ok) {
        selectPanel(patterns::PanelId{created});
        Q_EMIT message(tr("Added %1 (%2 × %3 mm)")
                           .arg(QString::fromStdString(drawn.name))
                           .arg(box.width(), 0, 'f', 1)
                           .arg(box.height(), 0, 'f', 1));
    }
    return ok;
}

bool PatternView::finishPolygon() {
    if (!m_drawing || m_drawing->points.size() < 3) {
        Q_EMIT message(tr("A polygon needs at least 3 corners"));
        return false;
    }
    const std::vector<QPointF> corners = m_drawing->points;
    m_drawing.reset();
    clearOverlay();
    return addDrawnPanel(corners);
}

bool PatternView::toggleCurve() {
    const patterns::doc::Panel* selected = panel(m_selectedPanel);
    if (selected == nullptr || !m_selectedEdge) {
        Q_EMIT message(tr("Select an edge of a panel to curve or straighten it"));
        return false;
    }
    patterns::doc::Panel copy = *selected;
    int index = 0;
    const patterns::doc::Contour* contour = patterns::contourOfEdge(copy, m_selectedEdge, index);
    if (contour == nullptr) {
        return false;
    }
    const patterns::Segment s = patterns::contourSegment(*contour, static_cast<std::size_t>(index));
    patterns::doc::Curve curve; // straight again
    if (s.kind == patterns::SegmentKind::Line) {
        // Handles on the chord: the same line, ready to be bent.
        curve.kind = patterns::SegmentKind::Cubic;
        curve.control1 = s.start + (s.end - s.start) / 3;
        curve.control2 = s.start + (s.end - s.start) * 2 / 3;
    }
    const patterns::PanelId id = selected->id;
    const patterns::EdgeId edge = m_selectedEdge;
    return applyEdit(
        [&](patterns::GarmentDocument& d) { return patterns::setCurve(d, id, edge, curve); });
}

std::vector<patterns::doc::SeamRange> PatternView::rangesOf(const SidePick& side) const {
    const patterns::doc::Panel* p = panel(side.panel);
    if (p == nullptr) {
        return {};
    }
    return outlineRanges(*p, {side.fromEdge, side.fromT}, {side.toEdge, side.toT}, side.forward);
}

void PatternView::pickSeamEdge(const EdgePick& pick, Qt::KeyboardModifiers modifiers) {
    const bool extend = (modifiers & Qt::ShiftModifier) != 0;
    const bool partial = (modifiers & Qt::ControlModifier) != 0;
    const int side = !m_sides[0] ? 0 : (m_sides[1] ? 1 : (extend ? 0 : 1));
    std::optional<SidePick>& s = m_sides[side];
    const patterns::doc::Panel* p = panel(pick.panel);
    if (p == nullptr) {
        return;
    }
    if (extend && s && s->panel == pick.panel) {
        // From where the side starts to the clicked edge, the shorter way round.
        const int n = static_cast<int>(p->outline.edges.size());
        const int ahead = (pick.index - s->fromEdge + n) % n;
        const int behind = (s->fromEdge - pick.index + n) % n;
        bool forward = ahead <= behind;
        if (pick.index == s->fromEdge) {
            forward = partial ? pick.t > s->fromT : s->forward;
        }
        if (!s->partialStart) {
            s->fromT = forward ? 0 : 1;
        }
        s->toEdge = pick.index;
        s->toT = partial ? pick.t : (forward ? 1 : 0);
        s->forward = forward;
    } else {
        s = SidePick{pick.panel, pick.index, partial ? pick.t : 0.0, pick.index, 1.0,
                     true,       partial};
        if (side == 1) {
            m_secondReversed = false;
        }
    }
    updateSeamPick();
}

bool PatternView::pickSeamAt(patterns::PanelId id, const patterns::Vec2& at,
                             Qt::KeyboardModifiers modifiers) {
    const patterns::doc::Panel* p = panel(id);
    if (m_tool != Tool::Seam || p == nullptr) {
        return false;
    }
    // The outline point nearest `at`, sampled as pickEdge samples (in pattern metres here).
    double best = SEAM_PICK_3D_MM / MM;
    std::optional<EdgePick> pick;
    for (std::size_t e = 0; e < p->outline.edges.size(); ++e) {
        const patterns::Segment s = patterns::contourSegment(p->outline, e);
        constexpr int SAMPLES = 200;
        for (int k = 1; k < SAMPLES; ++k) {
            const double t = double(k) / SAMPLES;
            const patterns::Vec2 q = patterns::pointAt(s, t);
            if (const double d = (q - at).norm(); d < best) {
                best = d;
                pick = EdgePick{id, p->outline.edges[e].id, static_cast<int>(e), true, t, q};
            }
        }
    }
    if (!pick) {
        Q_EMIT message(tr("Click the cloth within %1 mm of an edge of the panel to pick it")
                           .arg(SEAM_PICK_3D_MM));
        return false;
    }
    pickSeamEdge(*pick, modifiers);
    return true;
}

void PatternView::updateSeamPick() {
    m_seamRanges[0] = m_sides[0] ? rangesOf(*m_sides[0]) : std::vector<patterns::doc::SeamRange>{};
    m_seamRanges[1].clear();
    if (m_sides[1] && !m_seamRanges[0].empty()) {
        std::vector<patterns::doc::SeamRange> b = rangesOf(*m_sides[1]);
        const auto end = [&](const std::vector<patterns::doc::SeamRange>& ranges, bool last) {
            const patterns::doc::SeamRange& r = last ? ranges.back() : ranges.front();
            const patterns::doc::Panel* p = panel(r.panel);
            const auto e = static_cast<std::size_t>(patterns::outlineEdgeIndex(*p, r.edge));
            return toScene(p->id, patterns::pointAt(patterns::contourSegment(p->outline, e),
                                                    last ? r.t1 : r.t0));
        };
        if (!b.empty()) {
            // Start to start as the panels lie: the way whose ends are nearer each other.
            const QPointF a0 = end(m_seamRanges[0], false);
            const QPointF a1 = end(m_seamRanges[0], true);
            const QPointF b0 = end(b, false);
            const QPointF b1 = end(b, true);
            const bool crossed =
                distance(a0, b1) + distance(a1, b0) < distance(a0, b0) + distance(a1, b1);
            if (crossed != m_secondReversed) {
                b = reversedRanges(std::move(b));
            }
        }
        m_seamRanges[1] = std::move(b);
    }
    drawOverlay();
}

const std::vector<patterns::doc::SeamRange>& PatternView::seamPick(int side) const {
    return m_seamRanges[side == 0 ? 0 : 1];
}

bool PatternView::reverseSeam() {
    if (m_tool == Tool::Seam && m_sides[1]) {
        m_secondReversed = !m_secondReversed;
        updateSeamPick();
        return true;
    }
    if (!m_selectedSeam) {
        Q_EMIT message(tr("Pick a second side with the seam tool, or select a seam, to reverse"));
        return false;
    }
    const patterns::SeamId seam = m_selectedSeam;
    const bool ok =
        applyEdit([seam](patterns::GarmentDocument& d) { return patterns::reverseSeam(d, seam); });
    if (ok) {
        selectSeamAndSay(seam);
    }
    return ok;
}

bool PatternView::sew() {
    if (m_seamRanges[0].empty() || m_seamRanges[1].empty()) {
        Q_EMIT message(tr("Pick both sides of the seam first"));
        return false;
    }
    const std::string name = newSeamName(m_document);
    const std::vector<patterns::doc::SeamRange> a = m_seamRanges[0];
    const std::vector<patterns::doc::SeamRange> b = m_seamRanges[1];
    std::uint32_t created = 0;
    const bool ok = applyEdit([&](patterns::GarmentDocument& d) {
        auto made = patterns::addSeam(d, name, a, b);
        if (made.ok()) {
            created = made.value().created;
        }
        return made;
    });
    if (ok) {
        cancelTool();
        selectSeamAndSay(patterns::SeamId{created});
    }
    return ok;
}

void PatternView::mousePressEvent(QMouseEvent* event) {
    const QPoint at = event->position().toPoint();
    const QPointF scene = mapToScene(at);
    m_pressPassedOn = event->button() != Qt::LeftButton;
    if (event->button() == Qt::MiddleButton) {
        m_pan = at; // pans in every tool
        event->accept();
        return;
    }
    if (event->button() != Qt::LeftButton) {
        QGraphicsView::mousePressEvent(event);
        return;
    }
    if (pressMarkTool(event)) {
        return;
    }
    switch (m_tool) {
    case Tool::Rectangle: {
        const QPointF p = snap(scene, event->modifiers(), {}, {});
        m_drawing = Drawing{{p}, p, true};
        drawOverlay();
        event->accept();
        return;
    }
    case Tool::Polygon: {
        const QPointF p = snap(scene, event->modifiers(), {}, {});
        if (!m_drawing) {
            m_drawing = Drawing{{p}, p, false};
        } else if (m_drawing->points.size() >= 3 &&
                   distance(mapFromScene(m_drawing->points.front()), at) <= SNAP_PX) {
            finishPolygon();
            event->accept();
            return;
        } else if (distance(mapFromScene(m_drawing->points.back()), at) > 2) {
            m_drawing->points.push_back(p);
        }
        m_drawing->cursor = p;
        drawOverlay();
        event->accept();
        return;
    }
    case Tool::Seam:
        if (const auto pick = pickEdge(at, {})) {
            pickSeamEdge(*pick, event->modifiers());
        }
        event->accept();
        return;
    default: // Select; the mark and curve tools took their presses
        break;
    }
    for (QGraphicsItem* item : items(at)) {
        const int role = item->data(DATA_ROLE).toInt();
        const patterns::PanelId id{item->data(DATA_PANEL).value<quint32>()};
        if (role == ROLE_ROTATE) {
            const QRectF box = m_items.count(id.value) != 0
                                   ? m_items.at(id.value)->path().boundingRect()
                                   : QRectF();
            m_layoutDrag = LayoutDrag{id, layout(id), scene, box.center(), true, false, at};
            event->accept();
            return;
        }
        if (role == ROLE_CONTROL) {
            const patterns::EdgeId edge{item->data(DATA_EDGE).value<quint32>()};
            patterns::doc::Panel copy = *panel(id);
            int index = 0;
            if (const patterns::doc::Contour* c = patterns::contourOfEdge(copy, edge, index)) {
                const patterns::Segment s =
                    patterns::contourSegment(*c, static_cast<std::size_t>(index));
                m_handleDrag = HandleDrag{id,
                                          edge,
                                          item->data(DATA_CONTROL).toInt(),
                                          c->edges[static_cast<std::size_t>(index)].curve,
                                          false,
                                          s.start,
                                          s.end};
                m_selectedEdge = edge;
                event->accept();
                return;
            }
        }
        if (role == ROLE_POINT) {
            const patterns::PointId point{item->data(DATA_POINT).value<quint32>()};
            m_selectedPoint = point;
            m_drag = Drag{id, point, toPattern(id, item->pos()), false};
            drawHandles();
            event->accept();
            return;
        }
    }
    if (m_selectedPoint) {
        m_selectedPoint = {};
        drawHandles();
    }
    if (const auto pick = pickEdge(at)) {
        // An edge of the selected panel: it is selected (V curves it; a double-click adds a
        // point), and so is a seam along it.
        m_selectedEdge = pick->edge;
        const patterns::SeamId seam = seamAt(*pick);
        if (seam != m_selectedSeam) {
            selectSeamAndSay(seam);
        } else {
            drawHandles();
        }
        event->accept();
        return;
    }
    if (const auto pick = pickEdge(at, {})) {
        if (const patterns::SeamId seam = seamAt(*pick)) {
            selectSeamAndSay(seam);
            event->accept();
            return;
        }
    }
    if (m_selectedSeam) {
        selectSeam({});
    }
    m_pressPassedOn = true;
    QGraphicsView::mousePressEvent(event); // selects the panel under the mouse, or pans
    for (QGraphicsItem* item : items(at)) {
        const patterns::PanelId id{item->data(DATA_PANEL).value<quint32>()};
        if (id && id == m_selectedPanel && item->data(DATA_ROLE).toInt() == 0) {
            m_layoutDrag = LayoutDrag{id, layout(id), scene, QPointF(), false, false, at};
            break;
        }
    }
}

void PatternView::mouseMoveEvent(QMouseEvent* event) {
    const QPoint at = event->position().toPoint();
    const QPointF scene = mapToScene(at);
    if (m_pan) {
        const QPoint delta = at - *m_pan;
        m_pan = at;
        horizontalScrollBar()->setValue(horizontalScrollBar()->value() - delta.x());
        verticalScrollBar()->setValue(verticalScrollBar()->value() - delta.y());
        event->accept();
        return;
    }
    if (m_drawing) {
        m_drawing->cursor = snap(scene, event->modifiers(), {}, {});
        drawOverlay();
        event->accept();
        return;
    }
    if (moveMarkTool(event)) {
        return;
    }
    if (m_layoutDrag) {
        LayoutDrag& d = *m_layoutDrag;
        if (!d.moved && (at - d.pressView).manhattanLength() < QApplication::startDragDistance()) {
            event->accept();
            return;
        }
        d.moved = true;
        QTransform next;
        QString text;
        if (d.rotate) {
            const QPointF from = d.pressScene - d.pivot;
            const QPointF to = scene - d.pivot;
            double degrees = (std::atan2(to.y(), to.x()) - std::atan2(from.y(), from.x())) * 180 /
                             std::numbers::pi;
            degrees = std::remainder(degrees, 360.0);
            if (event->modifiers() & Qt::ShiftModifier) {
                degrees = std::round(degrees / ROTATE_STEP_DEG) * ROTATE_STEP_DEG;
            }
            next = d.start * QTransform::fromTranslate(-d.pivot.x(), -d.pivot.y()) *
                   QTransform().rotate(degrees) *
                   QTransform::fromTranslate(d.pivot.x(), d.pivot.y());
            text = tr("%1°").arg(-degrees, 0, 'f', 1); // counter-clockwise positive, as angles
        } else {
            const QPointF delta = scene - d.pressScene;
            next = d.start * QTransform::fromTranslate(delta.x(), delta.y());
            text = tr("%1, %2 mm").arg(delta.x(), 0, 'f', 1).arg(-delta.y(), 0, 'f', 1);
        }
        m_layouts[d.panel.value] = next;
        redraw();
        setFeedback(text, scene);
        event->accept();
        return;
    }
    if (m_handleDrag) {
        const patterns::Vec2 p = toPattern(
            m_handleDrag->panel, snap(scene, event->modifiers(), {}, m_handleDrag->panel));
        if (m_handleDrag->control == CONTROL_BULGE) {
            m_handleDrag->curve.bulge = bulgeThrough(m_handleDrag->start, m_handleDrag->end, p);
        } else {
            (m_handleDrag->control == 1 ? m_handleDrag->curve.control1
                                        : m_handleDrag->curve.control2) = p;
        }
        m_handleDrag->moved = true;
        showHandleDrag();
        event->accept();
        return;
    }
    if (!m_drag) {
        QGraphicsView::mouseMoveEvent(event);
        return;
    }
    m_drag->position =
        toPattern(m_drag->panel, snap(scene, event->modifiers(), m_drag->point, m_drag->panel));
    m_drag->moved = true;
    showDrag();
    event->accept();
}

void PatternView::mouseReleaseEvent(QMouseEvent* event) {
    if (event->button() == Qt::MiddleButton && m_pan) {
        m_pan.reset();
        event->accept();
        return;
    }
    if (event->button() != Qt::LeftButton) {
        QGraphicsView::mouseReleaseEvent(event);
        return;
    }
    if (releaseMarkTool(event)) {
        return;
    }
    if (m_tool == Tool::Rectangle && m_drawing) {
        m_drawing->cursor =
            snap(mapToScene(event->position().toPoint()), event->modifiers(), {}, {});
        const QRectF box = QRectF(m_drawing->points.front(), m_drawing->cursor).normalized();
        m_drawing.reset();
        clearOverlay();
        event->accept();
        const QRectF onScreen = mapFromScene(box).boundingRect();
        if (box.width() >= 1 && box.height() >= 1 && onScreen.width() >= 4 &&
            onScreen.height() >= 4) {
            // Counter-clockwise in pattern coordinates (y up): the scene's bottom-left first.
            addDrawnPanel({box.bottomLeft(), box.bottomRight(), box.topRight(), box.topLeft()});
        }
        return;
    }
    if (m_drawing) {
        event->accept();
        return;
    }
    if (m_layoutDrag) {
        const LayoutDrag d = *m_layoutDrag;
        m_layoutDrag.reset();
        clearOverlay();
        if (d.moved) {
            drawHandles();
            // Where it lies on the sheet is the document's (saved, undoable); its outline and
            // its drape are unchanged.
            const patterns::doc::SheetPlace place = sheetPlace(m_layouts[d.panel.value]);
            applyEdit([&](patterns::GarmentDocument& doc) {
                return patterns::setSheetPlace(doc, d.panel, place);
            });
            Q_EMIT message(d.rotate ? tr("Rotated on the pattern sheet (the pattern is unchanged)")
                                    : tr("Moved on the pattern sheet (the pattern is unchanged)"));
        }
        if (m_pressPassedOn) {
            QGraphicsView::mouseReleaseEvent(event); // pressed through it, on the panel
        } else {
            event->accept();
        }
        return;
    }
    if (m_handleDrag) {
        const HandleDrag drag = *m_handleDrag;
        m_handleDrag.reset();
        clearOverlay();
        event->accept();
        if (drag.moved) {
            redraw(); // as it was until the window hands back the edited document
            applyEdit([&](patterns::GarmentDocument& d) {
                return patterns::setCurve(d, drag.panel, drag.edge, drag.curve);
            });
        }
        return;
    }
    if (!m_drag) {
        // The view's own release only after its own press: after a press this view took (an
        // edge picked), it would take the click for one on the background and deselect.
        if (m_pressPassedOn) {
            QGraphicsView::mouseReleaseEvent(event);
        } else {
            event->accept();
        }
        return;
    }
    const Drag drag = *m_drag;
    m_drag.reset();
    clearOverlay();
    event->accept();
    if (drag.moved) {
        // The window makes the edit and draws the document again; until then, as it was.
        redraw();
        Q_EMIT pointMoveRequested(drag.panel.value, drag.point.value, drag.position.x(),
                                  drag.position.y());
    }
}

void PatternView::mouseDoubleClickEvent(QMouseEvent* event) {
    if (event->button() == Qt::LeftButton && m_tool == Tool::Polygon) {
        event->accept();
        // The double-click's own press put its corner down already, unless it came alone.
        const QPoint at = event->position().toPoint();
        if (m_drawing && distance(mapFromScene(m_drawing->points.back()), at) > 2) {
            m_drawing->points.push_back(snap(mapToScene(at), event->modifiers(), {}, {}));
        }
        finishPolygon();
        return;
    }
    if (event->button() == Qt::LeftButton &&
        (m_tool == Tool::Curve || m_tool == Tool::InternalLine)) {
        // As the polygon: the double-click's own press put its point down, unless it came
        // alone.
        event->accept();
        const QPoint at = event->position().toPoint();
        const bool alone =
            m_pen ? distance(mapFromScene(m_pen->points.back()), at) > 2
                  : m_line && distance(mapFromScene(toScene(m_line->panel, m_line->points.back())),
                                       at) > 2;
        if (alone) {
            pressMarkTool(event);
            releaseMarkTool(event);
        }
        finishMarkDrawing();
        return;
    }
    if (m_tool != Tool::Select) {
        mousePressEvent(event); // a quick second click: another corner, edge or rectangle
        return;
    }
    const auto pick =
        event->button() == Qt::LeftButton ? pickEdge(event->position().toPoint()) : std::nullopt;
    if (!pick) {
        QGraphicsView::mouseDoubleClickEvent(event);
        return;
    }
    event->accept();
    Q_EMIT pointAddRequested(m_selectedPanel.value, pick->edge.value, pick->t, pick->at.x(),
                             pick->at.y());
}

void PatternView::keyPressEvent(QKeyEvent* event) {
    const int key = event->key();
    if (key == Qt::Key_Escape && (m_drawing || m_sides[0] || m_pen || m_line || m_dart)) {
        event->accept();
        cancelTool();
        Q_EMIT message(tr("Cancelled"));
        return;
    }
    if (key == Qt::Key_Return || key == Qt::Key_Enter) {
        if (m_tool == Tool::Polygon && m_drawing) {
            event->accept();
            finishPolygon();
            return;
        }
        if (m_pen || m_line) {
            event->accept();
            finishMarkDrawing();
            return;
        }
        if (m_tool == Tool::Seam && m_sides[1]) {
            event->accept();
            sew();
            return;
        }
    }
    if (key == Qt::Key_Backspace && (m_pen || m_line)) {
        event->accept();
        dropLastMarkPoint();
        return;
    }
    if (key == Qt::Key_Backspace && m_tool == Tool::Polygon && m_drawing) {
        event->accept();
        m_drawing->points.pop_back();
        if (m_drawing->points.empty()) {
            m_drawing.reset();
        }
        drawOverlay();
        return;
    }
    if (key == Qt::Key_Delete || key == Qt::Key_Backspace) {
        if (m_selectedNotch || m_selectedLine) {
            event->accept();
            deleteSelectedMark();
            return;
        }
        if (m_selectedPanel && m_selectedPoint) {
            event->accept();
            Q_EMIT pointDeleteRequested(m_selectedPanel.value, m_selectedPoint.value);
            return;
        }
        if (m_selectedSeam) {
            event->accept();
            const patterns::SeamId seam = m_selectedSeam;
            applyEdit(
                [seam](patterns::GarmentDocument& d) { return patterns::removeSeam(d, seam); });
            return;
        }
        if (m_selectedEdge && deleteSelectedMark()) { // a dart's leg
            event->accept();
            return;
        }
    }
    QGraphicsView::keyPressEvent(event);
}

void PatternView::wheelEvent(QWheelEvent* event) {
    const double factor = std::pow(1.15, event->angleDelta().y() / 120.0);
    scale(factor, factor);
}

} // namespace atelier::ui
