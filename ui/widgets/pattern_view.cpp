#include "ui/widgets/pattern_view.h"

#include "ui/render/scene.h"

#include "patterns/curve.h"

#include <QGraphicsEllipseItem>
#include <QGraphicsPathItem>
#include <QGraphicsSimpleTextItem>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QWheelEvent>

#include <cmath>

namespace atelier::ui {

namespace {

constexpr double MM = 1000.0; // the scene is in millimetres, y down
constexpr double GAP_MM = 60.0;
constexpr double HANDLE_PX = 9.0;    // handle diameter on screen
constexpr double PICK_EDGE_PX = 8.0; // a double-click this close to an edge adds a point
constexpr int DATA_NAME = 0;
constexpr int DATA_PANEL = 1;
constexpr int DATA_POINT = 2;

QColor qColour(const render::Colour& c) {
    return QColor::fromRgbF(c.r, c.g, c.b, c.a);
}

QPainterPath loopPath(const patterns::Loop& loop, double dx) {
    QPainterPath path;
    const std::vector<patterns::Vec2> points = sampleLoop(loop);
    for (std::size_t i = 0; i < points.size(); ++i) {
        const QPointF p(points[i].x() * MM + dx, -points[i].y() * MM);
        if (i == 0) {
            path.moveTo(p);
        } else {
            path.lineTo(p);
        }
    }
    path.closeSubpath();
    return path;
}

QPainterPath panelPath(const patterns::doc::Panel& panel, double dx) {
    QPainterPath path = loopPath(contourLoop(panel.outline), dx);
    for (const patterns::doc::Hole& hole : panel.holes) {
        path.addPath(loopPath(contourLoop(hole.contour), dx));
    }
    path.setFillRule(Qt::OddEvenFill);
    return path;
}

/// The horizontal extent of a panel's outline [mm].
std::pair<double, double> extentMm(const patterns::doc::Panel& panel) {
    double minX = INFINITY;
    double maxX = -INFINITY;
    for (const patterns::Vec2& v : sampleLoop(contourLoop(panel.outline))) {
        minX = std::min(minX, v.x() * MM);
        maxX = std::max(maxX, v.x() * MM);
    }
    return {minX, maxX};
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
        const QList<QGraphicsItem*> selected = m_scene.selectedItems();
        const patterns::PanelId id{
            selected.isEmpty() ? 0U : selected.front()->data(DATA_PANEL).value<quint32>()};
        if (id != m_selectedPanel) {
            m_selectedPanel = id;
            m_selectedPoint = {};
            drawHandles();
        }
        Q_EMIT panelSelected(selected.isEmpty() ? QString()
                                                : selected.front()->data(DATA_NAME).toString());
    });
}

PatternView::~PatternView() {
    m_redrawing = true; // the scene's items go with it: nothing to redraw
    m_handles.clear();
}

const patterns::doc::Panel* PatternView::panel(patterns::PanelId id) const {
    return m_document.panel(id);
}

double PatternView::offset(patterns::PanelId id) const {
    const auto it = m_offsets.find(id.value);
    return it == m_offsets.end() ? 0.0 : it->second;
}

patterns::Vec2 PatternView::toPattern(patterns::PanelId id, const QPointF& scene) const {
    return {(scene.x() - offset(id)) / MM, -scene.y() / MM};
}

QPointF PatternView::toScene(patterns::PanelId id, const patterns::Vec2& at) const {
    return {at.x() * MM + offset(id), -at.y() * MM};
}

QPoint PatternView::viewPoint(patterns::PanelId panel, const patterns::Vec2& at) const {
    return mapFromScene(toScene(panel, at));
}

void PatternView::setDocument(const patterns::GarmentDocument& document, bool keepLayout) {
    m_document = document;
    m_drag.reset();
    if (!keepLayout) {
        m_offsets.clear();
        m_selectedPanel = {};
        m_selectedPoint = {};
    }
    // Panels already laid out keep their shift; new ones go right of the rightmost.
    double x = 0;
    for (const patterns::doc::Panel& p : m_document.panels) {
        if (const auto it = m_offsets.find(p.id.value); it != m_offsets.end()) {
            const double maxX = extentMm(p).second;
            if (std::isfinite(maxX)) {
                x = std::max(x, maxX + it->second + GAP_MM);
            }
        }
    }
    for (const patterns::doc::Panel& p : m_document.panels) {
        if (m_offsets.count(p.id.value) == 0) {
            const auto [minX, maxX] = extentMm(p);
            if (!std::isfinite(minX)) {
                continue;
            }
            m_offsets[p.id.value] = x - minX;
            x += maxX - minX + GAP_MM;
        }
    }
    if (m_selectedPanel && panel(m_selectedPanel) == nullptr) {
        m_selectedPanel = {};
    }
    if (m_selectedPoint) {
        int index = 0;
        patterns::doc::Panel* selected = m_document.panel(m_selectedPanel);
        if (selected == nullptr ||
            patterns::contourOfPoint(*selected, m_selectedPoint, index) == nullptr) {
            m_selectedPoint = {};
        }
    }
    redraw();
    if (!keepLayout) {
        m_scene.setSceneRect(
            m_scene.itemsBoundingRect().adjusted(-GAP_MM, -GAP_MM, GAP_MM, GAP_MM));
        fitInView(m_scene.sceneRect(), Qt::KeepAspectRatio);
    } else {
        m_scene.setSceneRect(m_scene.sceneRect().united(
            m_scene.itemsBoundingRect().adjusted(-GAP_MM, -GAP_MM, GAP_MM, GAP_MM)));
    }
}

void PatternView::selectPanel(patterns::PanelId id) {
    if (const auto it = m_items.find(id.value); it != m_items.end()) {
        m_scene.clearSelection();
        it->second->setSelected(true);
    }
}

void PatternView::redraw() {
    m_redrawing = true;
    m_scene.clear();
    m_items.clear();
    m_handles.clear();
    m_lengths = nullptr;
    m_panels = 0;
    for (std::size_t p = 0; p < m_document.panels.size(); ++p) {
        const patterns::doc::Panel& panel = m_document.panels[p];
        if (m_offsets.count(panel.id.value) == 0) {
            continue; // an outline without points
        }
        const double dx = offset(panel.id);
        const QPainterPath path = panelPath(panel, dx);
        auto* item = m_scene.addPath(path, QPen(QColor(60, 60, 70), 0),
                                     QBrush(qColour(render::panelColour(static_cast<int>(p)))));
        item->setFlag(QGraphicsItem::ItemIsSelectable);
        item->setData(DATA_NAME, QString::fromStdString(panel.name));
        item->setData(DATA_PANEL, quint32(panel.id.value));
        item->setToolTip(QString::fromStdString(panel.name));
        m_items[panel.id.value] = item;
        for (const patterns::doc::InternalLine& line : panel.internalLines) {
            QPainterPath l;
            bool first = true;
            for (std::size_t e = 0; e < line.edges.size(); ++e) {
                const patterns::Segment s = patterns::segmentOf(
                    line.edges[e].curve, line.points[e].position, line.points[e + 1].position);
                for (int i = 0; i <= 16; ++i) {
                    const patterns::Vec2 v = patterns::pointAt(s, i / 16.0);
                    const QPointF q(v.x() * MM + dx, -v.y() * MM);
                    first ? l.moveTo(q) : l.lineTo(q);
                    first = false;
                }
            }
            m_scene.addPath(l, QPen(QColor(60, 60, 70), 0, Qt::DashLine));
        }
        auto* label = m_scene.addSimpleText(QString::fromStdString(panel.name));
        label->setBrush(QColor(40, 40, 50));
        const QRectF box = path.boundingRect();
        label->setScale(std::max(1.0, box.width() / 200.0));
        label->setPos(box.center() - QPointF(label->boundingRect().width() * label->scale() / 2,
                                             label->boundingRect().height() * label->scale() / 2));
        ++m_panels;
    }
    if (const auto it = m_items.find(m_selectedPanel.value); it != m_items.end()) {
        it->second->setSelected(true);
    }
    m_redrawing = false;
    drawHandles();
}

void PatternView::drawHandles() {
    for (QGraphicsItem* h : m_handles) {
        m_scene.removeItem(h);
        delete h;
    }
    m_handles.clear();
    const patterns::doc::Panel* selected = panel(m_selectedPanel);
    if (selected == nullptr) {
        return;
    }
    const auto addHandles = [&](const patterns::doc::Contour& contour) {
        for (const patterns::doc::Point& point : contour.points) {
            const bool current = point.id == m_selectedPoint;
            auto* h = m_scene.addEllipse(-HANDLE_PX / 2, -HANDLE_PX / 2, HANDLE_PX, HANDLE_PX,
                                         QPen(QColor(30, 30, 40), 1),
                                         current ? QBrush(QColor(220, 40, 40)) : QBrush(Qt::white));
            h->setFlag(QGraphicsItem::ItemIgnoresTransformations);
            h->setPos(toScene(selected->id, point.position));
            h->setZValue(10);
            h->setData(DATA_PANEL, quint32(selected->id.value));
            h->setData(DATA_POINT, quint32(point.id.value));
            m_handles.push_back(h);
        }
    };
    addHandles(selected->outline);
    for (const patterns::doc::Hole& hole : selected->holes) {
        addHandles(hole.contour);
    }
}

QString PatternView::dragLengths() const {
    return m_lengths != nullptr && m_drag ? m_lengths->text() : QString();
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
        it->second->setPath(panelPath(moved, offset(m_drag->panel)));
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
    if (m_lengths == nullptr) {
        m_lengths = m_scene.addSimpleText(QString());
        m_lengths->setFlag(QGraphicsItem::ItemIgnoresTransformations);
        m_lengths->setZValue(11);
        m_lengths->setBrush(QColor(20, 20, 120));
    }
    m_lengths->setText(tr("%1 mm ← · → %2 mm  (%3, %4)")
                           .arg(before * MM, 0, 'f', 1)
                           .arg(after * MM, 0, 'f', 1)
                           .arg(m_drag->position.x() * MM, 0, 'f', 1)
                           .arg(m_drag->position.y() * MM, 0, 'f', 1));
    m_lengths->setPos(toScene(m_drag->panel, m_drag->position) + QPointF(6, 6) / transform().m11());
}

void PatternView::mousePressEvent(QMouseEvent* event) {
    if (event->button() == Qt::LeftButton) {
        for (QGraphicsItem* item : items(event->position().toPoint())) {
            if (!item->data(DATA_POINT).isValid()) {
                continue;
            }
            const patterns::PanelId id{item->data(DATA_PANEL).value<quint32>()};
            const patterns::PointId point{item->data(DATA_POINT).value<quint32>()};
            m_selectedPoint = point;
            m_drag = Drag{id, point, toPattern(id, item->pos()), false};
            drawHandles();
            event->accept();
            return;
        }
        if (m_selectedPoint) {
            m_selectedPoint = {};
            drawHandles();
        }
        if (pickEdge(event->position().toPoint())) {
            event->accept(); // on the selected panel's edge: it stays selected (double-click)
            return;
        }
    }
    QGraphicsView::mousePressEvent(event);
}

void PatternView::mouseMoveEvent(QMouseEvent* event) {
    if (!m_drag) {
        QGraphicsView::mouseMoveEvent(event);
        return;
    }
    patterns::Vec2 at = toPattern(m_drag->panel, mapToScene(event->position().toPoint()));
    if (event->modifiers() & Qt::ShiftModifier) {
        // Snap to the grid in pattern coordinates: 5 mm, or 1 mm with Ctrl too.
        const double grid = (event->modifiers() & Qt::ControlModifier ? 1.0 : 5.0) / MM;
        at = (at / grid).array().round().matrix() * grid;
    }
    m_drag->position = at;
    m_drag->moved = true;
    showDrag();
    event->accept();
}

void PatternView::mouseReleaseEvent(QMouseEvent* event) {
    if (!m_drag || event->button() != Qt::LeftButton) {
        QGraphicsView::mouseReleaseEvent(event);
        return;
    }
    const Drag drag = *m_drag;
    m_drag.reset();
    if (m_lengths != nullptr) {
        m_scene.removeItem(m_lengths);
        delete m_lengths;
        m_lengths = nullptr;
    }
    event->accept();
    if (drag.moved) {
        // The window makes the edit and draws the document again; until then, as it was.
        redraw();
        Q_EMIT pointMoveRequested(drag.panel.value, drag.point.value, drag.position.x(),
                                  drag.position.y());
    }
}

std::optional<PatternView::EdgePick> PatternView::pickEdge(const QPoint& at) const {
    const patterns::doc::Panel* selected = panel(m_selectedPanel);
    if (selected == nullptr) {
        return std::nullopt;
    }
    const patterns::Vec2 p = toPattern(selected->id, mapToScene(at));
    double best = PICK_EDGE_PX / std::max(1e-9, transform().m11()) / MM; // [m]
    std::optional<EdgePick> pick;
    const auto search = [&](const patterns::doc::Contour& contour) {
        for (std::size_t e = 0; e < contour.edges.size(); ++e) {
            const patterns::Segment s = patterns::contourSegment(contour, e);
            constexpr int SAMPLES = 200;
            for (int k = 1; k < SAMPLES; ++k) {
                const double t = double(k) / SAMPLES;
                const patterns::Vec2 q = patterns::pointAt(s, t);
                if (const double d = (q - p).norm(); d < best) {
                    best = d;
                    pick = EdgePick{contour.edges[e].id, t, q};
                }
            }
        }
    };
    search(selected->outline);
    for (const patterns::doc::Hole& hole : selected->holes) {
        search(hole.contour);
    }
    return pick;
}

void PatternView::mouseDoubleClickEvent(QMouseEvent* event) {
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
    if ((event->key() == Qt::Key_Delete || event->key() == Qt::Key_Backspace) && m_selectedPanel &&
        m_selectedPoint) {
        event->accept();
        Q_EMIT pointDeleteRequested(m_selectedPanel.value, m_selectedPoint.value);
        return;
    }
    QGraphicsView::keyPressEvent(event);
}

void PatternView::wheelEvent(QWheelEvent* event) {
    const double factor = std::pow(1.15, event->angleDelta().y() / 120.0);
    scale(factor, factor);
}

} // namespace atelier::ui
