#include "ui/widgets/pattern_view.h"

#include "ui/render/scene.h"

#include "patterns/curve.h"

#include <QGraphicsPathItem>
#include <QGraphicsSimpleTextItem>
#include <QWheelEvent>

#include <cmath>

namespace atelier::ui {

namespace {

constexpr double MM = 1000.0; // the scene is in millimetres, y down
constexpr double GAP_MM = 60.0;

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

PatternView::PatternView(QWidget* parent) : QGraphicsView(parent) {
    setScene(&m_scene);
    setRenderHint(QPainter::Antialiasing);
    setDragMode(QGraphicsView::ScrollHandDrag);
    setTransformationAnchor(QGraphicsView::AnchorUnderMouse);
    setBackgroundBrush(QColor(250, 250, 247));
    setMinimumSize(240, 240);
    connect(&m_scene, &QGraphicsScene::selectionChanged, this, [this] {
        const QList<QGraphicsItem*> selected = m_scene.selectedItems();
        emit panelSelected(selected.isEmpty() ? QString() : selected.front()->data(0).toString());
    });
}

void PatternView::setGarment(const patterns::Garment& garment) {
    m_scene.clear();
    m_panels = 0;
    double x = 0;
    for (std::size_t p = 0; p < garment.panels.size(); ++p) {
        const patterns::Panel& panel = garment.panels[p];
        // Lay the panels side by side: shift each so its left edge is right of the last.
        double minX = INFINITY;
        double maxX = -INFINITY;
        for (const patterns::Vec2& v : sampleLoop(panel.outline)) {
            minX = std::min(minX, v.x() * MM);
            maxX = std::max(maxX, v.x() * MM);
        }
        if (!std::isfinite(minX)) {
            continue;
        }
        const double dx = x - minX;
        x += maxX - minX + GAP_MM;
        QPainterPath path = loopPath(panel.outline, dx);
        for (const patterns::Loop& hole : panel.holes) {
            path.addPath(loopPath(hole, dx));
        }
        path.setFillRule(Qt::OddEvenFill);
        auto* item = m_scene.addPath(path, QPen(QColor(60, 60, 70), 0),
                                     QBrush(qColour(render::panelColour(static_cast<int>(p)))));
        item->setFlag(QGraphicsItem::ItemIsSelectable);
        item->setData(0, QString::fromStdString(panel.name));
        item->setToolTip(QString::fromStdString(panel.name));
        for (const patterns::InternalLine& line : panel.internalLines) {
            QPainterPath l;
            bool first = true;
            for (const patterns::Segment& s : line.path) {
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
    m_scene.setSceneRect(m_scene.itemsBoundingRect().adjusted(-GAP_MM, -GAP_MM, GAP_MM, GAP_MM));
    fitInView(m_scene.sceneRect(), Qt::KeepAspectRatio);
}

void PatternView::wheelEvent(QWheelEvent* event) {
    const double factor = std::pow(1.15, event->angleDelta().y() / 120.0);
    scale(factor, factor);
}

} // namespace atelier::ui
