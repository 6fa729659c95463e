// The pattern view's marks and free curves: the pen (Curve), Internal line, Notch and Dart
// tools, and the grain line's handle in Select (ui/widgets/pattern_view.h).

#include "ui/widgets/pattern_tools.h"
#include "ui/widgets/pattern_view.h"
#include "ui/widgets/pattern_view_detail.h"

#include "patterns/curve.h"

#include <QApplication>
#include <QGraphicsEllipseItem>
#include <QGraphicsPathItem>
#include <QMouseEvent>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <tuple>
#include <utility>

namespace atelier::ui {

using namespace detail;

namespace {

constexpr double GRAIN_STEP_DEG = 15.0;  // Shift while turning the grain
constexpr double MIN_DART_DEPTH = 0.005; // a shorter drag is a click, not a dart [m]

QPointF unit(const QPointF& v) {
    const double n = std::hypot(v.x(), v.y());
    return n > 0 ? v / n : QPointF(0, 0);
}

/// A notch's tick: from its point on the outline NOTCH_MM into the panel, square to the edge
/// [m]; nullopt when its edge is gone.
std::optional<std::pair<patterns::Vec2, patterns::Vec2>>
notchTick(const patterns::doc::Panel& panel, const patterns::doc::Notch& notch) {
    const int e = patterns::outlineEdgeIndex(panel, notch.edge);
    if (e < 0) {
        return std::nullopt;
    }
    const patterns::Segment s = patterns::contourSegment(panel.outline, std::size_t(e));
    const patterns::Vec2 at = patterns::pointAt(s, notch.t);
    const patterns::Vec2 along = patterns::tangentAt(s, notch.t).normalized();
    // The outline runs counter-clockwise: the inside is to the left.
    return std::make_pair(
        at, patterns::Vec2(at + NOTCH_MM / MM * patterns::Vec2(-along.y(), along.x())));
}

} // namespace

std::pair<QPointF, QPointF> PatternView::grainLine(const patterns::doc::Panel& panel,
                                                   double angle) const {
    patterns::Vec2 lo = patterns::Vec2::Constant(INFINITY);
    patterns::Vec2 hi = patterns::Vec2::Constant(-INFINITY);
    for (const patterns::Vec2& v : sampleLoop(contourLoop(panel.outline))) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
    const patterns::Vec2 centre = 0.5 * (lo + hi);
    const double half = 0.3 * (hi - lo).minCoeff();
    const patterns::Vec2 along(std::cos(angle), std::sin(angle));
    return {toScene(panel.id, centre - half * along), toScene(panel.id, centre + half * along)};
}

QPoint PatternView::grainHandle() const {
    const patterns::doc::Panel* p = panel(m_selectedPanel);
    if (p == nullptr) {
        return {-1, -1};
    }
    return mapFromScene(grainLine(*p, p->grainAngle).second);
}

void PatternView::drawMarks(const patterns::doc::Panel& panel, const QTransform& t) {
    const QColor ink(60, 60, 70);
    const bool current = panel.id == m_selectedPanel;
    for (const patterns::doc::InternalLine& line : panel.internalLines) {
        QPainterPath l;
        for (std::size_t e = 0; e < line.edges.size(); ++e) {
            const patterns::Segment s = patterns::segmentOf(
                line.edges[e].curve, line.points[e].position, line.points[e + 1].position);
            l.addPath(segmentPath(s, 0, 1));
        }
        const bool selected = current && line.id == m_selectedLine;
        auto* item =
            m_scene.addPath(t.map(l), selected ? screenPen(QColor(220, 40, 40), 3, Qt::DashLine)
                                               : screenPen(ink, 1.2, Qt::DashLine));
        item->setZValue(4);
        item->setData(DATA_ROLE, ROLE_LINE);
        item->setData(DATA_PANEL, quint32(panel.id.value));
        item->setData(DATA_MARK, quint32(line.id.value));
        item->setToolTip(
            tr("internal line, fold %1°").arg(line.foldAngle * 180 / std::numbers::pi, 0, 'f', 0));
    }
    // Notches: a short tick from the edge into the panel, square to it.
    for (const patterns::doc::Notch& notch : panel.notches) {
        const auto ends = notchTick(panel, notch);
        if (!ends) {
            continue;
        }
        QPainterPath tick;
        tick.moveTo(local(ends->first));
        tick.lineTo(local(ends->second));
        const bool selected = current && notch.id == m_selectedNotch;
        auto* item = m_scene.addPath(
            t.map(tick), screenPen(selected ? QColor(220, 40, 40) : ink, selected ? 4 : 2.5));
        item->setZValue(6);
        item->setData(DATA_ROLE, ROLE_NOTCH);
        item->setData(DATA_PANEL, quint32(panel.id.value));
        item->setData(DATA_MARK, quint32(notch.id.value));
        item->setToolTip(tr("notch"));
    }
    // The grain line: a thin double arrow through the middle of the panel.
    const auto [from, to] = grainLine(panel, panel.grainAngle);
    const QPointF d = unit(to - from) * 8 * sceneUnitsPerPixel();
    const QPointF n(-d.y(), d.x());
    QPainterPath grain;
    grain.moveTo(from);
    grain.lineTo(to);
    for (const auto& [tip, back] : {std::pair{to, -d}, std::pair{from, d}}) {
        grain.moveTo(tip + back + n * 0.5);
        grain.lineTo(tip);
        grain.lineTo(tip + back - n * 0.5);
    }
    auto* item = m_scene.addPath(grain, screenPen(QColor(90, 90, 110), 1));
    item->setZValue(3);
    item->setToolTip(tr("grain line (warp)"));
}

void PatternView::drawGrainHandle(const patterns::doc::Panel& panel) {
    const double angle = m_grainDrag ? m_grainDrag->angle : panel.grainAngle;
    auto* h = m_scene.addEllipse(-HANDLE_PX / 2, -HANDLE_PX / 2, HANDLE_PX, HANDLE_PX,
                                 QPen(QColor(30, 30, 40), 1), QBrush(QColor(230, 180, 60)));
    h->setFlag(QGraphicsItem::ItemIgnoresTransformations);
    h->setPos(grainLine(panel, angle).second);
    h->setZValue(10);
    h->setData(DATA_ROLE, ROLE_GRAIN);
    h->setData(DATA_PANEL, quint32(panel.id.value));
    h->setToolTip(tr("drag to turn the grain line (Shift: 15° steps)"));
    m_handles.push_back(h);
}

void PatternView::drawMarkOverlay() {
    const QPen pen = screenPen(QColor(20, 20, 120), 1.5, Qt::DashLine);
    const auto dot = [&](const QPointF& at) {
        auto* d = m_scene.addEllipse(-3, -3, 6, 6, QPen(QColor(20, 20, 120), 1),
                                     QBrush(QColor(20, 20, 120)));
        d->setFlag(QGraphicsItem::ItemIgnoresTransformations);
        d->setPos(at);
        d->setZValue(11);
        m_overlay.push_back(d);
    };
    if (m_pen && !m_pen->points.empty()) {
        // The curve as it will be: each segment a cubic from the handles, the last to the cursor.
        const auto& pts = m_pen->points;
        const auto& hs = m_pen->handles;
        QPainterPath path;
        path.moveTo(pts.front());
        const auto outOf = [&](std::size_t i) { return hs[i] ? *hs[i] : pts[i]; };
        const auto inOf = [&](std::size_t i) { return hs[i] ? 2 * pts[i] - *hs[i] : pts[i]; };
        for (std::size_t i = 1; i < pts.size(); ++i) {
            path.cubicTo(outOf(i - 1), inOf(i), pts[i]);
        }
        if (!m_pen->dragging) {
            path.cubicTo(outOf(pts.size() - 1), m_pen->cursor, m_pen->cursor);
        }
        auto* item = m_scene.addPath(path, pen);
        item->setZValue(11);
        m_overlay.push_back(item);
        for (std::size_t i = 0; i < pts.size(); ++i) {
            dot(pts[i]);
            if (hs[i]) {
                auto* arm =
                    m_scene.addLine(QLineF(inOf(i), outOf(i)), screenPen(QColor(90, 90, 110), 1));
                arm->setZValue(11);
                m_overlay.push_back(arm);
            }
        }
    }
    if (m_line && !m_line->points.empty()) {
        QPainterPath path;
        path.moveTo(toScene(m_line->panel, m_line->points.front()));
        for (std::size_t i = 1; i < m_line->points.size(); ++i) {
            path.lineTo(toScene(m_line->panel, m_line->points[i]));
        }
        path.lineTo(toScene(m_line->panel, m_line->cursor));
        auto* item = m_scene.addPath(path, pen);
        item->setZValue(11);
        m_overlay.push_back(item);
        for (const patterns::Vec2& p : m_line->points) {
            dot(toScene(m_line->panel, p));
        }
        const patterns::Vec2 last = m_line->points.back();
        setFeedback(tr("%1 mm").arg((m_line->cursor - last).norm() * MM, 0, 'f', 1),
                    toScene(m_line->panel, m_line->cursor));
    }
    if (m_dart) {
        const patterns::PanelId id = m_dart->base.panel;
        const patterns::Vec2 base = m_dart->base.at;
        const double depth = (m_dart->tip - base).norm();
        const patterns::Vec2 side =
            patterns::Vec2(m_dart->tip - base).normalized() * (DART_WIDTH_SHARE * depth / 2);
        const patterns::Vec2 across(side.y(), -side.x());
        QPainterPath path;
        path.moveTo(toScene(id, base + across));
        path.lineTo(toScene(id, m_dart->tip));
        path.lineTo(toScene(id, base - across));
        auto* item = m_scene.addPath(path, pen);
        item->setZValue(11);
        m_overlay.push_back(item);
        setFeedback(tr("dart %1 × %2 mm")
                        .arg(DART_WIDTH_SHARE * depth * MM, 0, 'f', 1)
                        .arg(depth * MM, 0, 'f', 1),
                    toScene(id, m_dart->tip));
    }
}

std::optional<std::tuple<patterns::PanelId, bool, std::uint32_t>>
PatternView::pickMark(const QPoint& at) const {
    const QPointF p(at);
    const auto segmentDistance = [&](const QPointF& a, const QPointF& b) {
        const QPointF ab = b - a;
        const double len2 = QPointF::dotProduct(ab, ab);
        const double t =
            len2 > 0 ? std::clamp(QPointF::dotProduct(p - a, ab) / len2, 0.0, 1.0) : 0.0;
        return distance(p, a + t * ab);
    };
    double best = PICK_MARK_PX;
    std::optional<std::tuple<patterns::PanelId, bool, std::uint32_t>> out;
    for (const patterns::doc::Panel& panel : m_document.panels) {
        if (m_layouts.count(panel.id.value) == 0) {
            continue;
        }
        const auto view = [&](const patterns::Vec2& v) {
            return QPointF(mapFromScene(toScene(panel.id, v)));
        };
        for (const patterns::doc::Notch& notch : panel.notches) {
            const auto ends = notchTick(panel, notch);
            if (!ends) {
                continue;
            }
            if (const double d = segmentDistance(view(ends->first), view(ends->second)); d < best) {
                best = d;
                out = std::make_tuple(panel.id, true, notch.id.value);
            }
        }
        for (const patterns::doc::InternalLine& line : panel.internalLines) {
            for (std::size_t e = 0; e < line.edges.size(); ++e) {
                const patterns::Segment s = patterns::segmentOf(
                    line.edges[e].curve, line.points[e].position, line.points[e + 1].position);
                constexpr int SAMPLES = 16;
                for (int k = 0; k < SAMPLES; ++k) {
                    const double d =
                        segmentDistance(view(patterns::pointAt(s, double(k) / SAMPLES)),
                                        view(patterns::pointAt(s, double(k + 1) / SAMPLES)));
                    if (d < best) {
                        best = d;
                        out = std::make_tuple(panel.id, false, line.id.value);
                    }
                }
            }
        }
    }
    return out;
}

bool PatternView::pressMarkTool(QMouseEvent* event) {
    const QPoint at = event->position().toPoint();
    const QPointF scene = mapToScene(at);
    switch (m_tool) {
    case Tool::Curve: {
        const QPointF p = snap(scene, event->modifiers(), {}, {});
        if (m_pen && m_pen->points.size() >= 3 &&
            distance(mapFromScene(m_pen->points.front()), at) <= SNAP_PX) {
            finishPen();
        } else {
            if (!m_pen) {
                m_pen = PenDrawing{};
            }
            m_pen->points.push_back(p);
            m_pen->handles.emplace_back();
            m_pen->cursor = p;
            m_pen->dragging = true;
            drawOverlay();
        }
        event->accept();
        return true;
    }
    case Tool::InternalLine: {
        const patterns::PanelId onto = m_line ? m_line->panel : [&] {
            for (QGraphicsItem* item : items(at)) {
                if (const patterns::PanelId id{item->data(DATA_PANEL).value<quint32>()};
                    id && item->data(DATA_ROLE).toInt() == 0) {
                    return id;
                }
            }
            return patterns::PanelId{};
        }();
        if (!onto) {
            Q_EMIT message(tr("An internal line starts inside a panel"));
        } else {
            const patterns::Vec2 p = toPattern(onto, snap(scene, event->modifiers(), {}, onto));
            if (!m_line) {
                m_line = LineDrawing{onto, {}, p};
            }
            if (m_line->points.empty() || (p - m_line->points.back()).norm() > 1e-4) {
                m_line->points.push_back(p);
            }
            m_line->cursor = p;
            drawOverlay();
        }
        event->accept();
        return true;
    }
    case Tool::Notch:
        if (const auto pick = pickEdge(at, {}); pick && pick->outline) {
            const auto made = applyEdit([&](patterns::GarmentDocument& d) {
                return patterns::addNotch(d, pick->panel, pick->edge, pick->t);
            });
            if (made) {
                Q_EMIT message(tr("Notch added"));
            }
        }
        event->accept();
        return true;
    case Tool::Dart:
        if (const auto pick = pickEdge(at, {}); pick && pick->outline) {
            m_dart = DartDrag{*pick, pick->at};
            drawOverlay();
        }
        event->accept();
        return true;
    case Tool::Select: {
        for (QGraphicsItem* item : items(at)) {
            const int role = item->data(DATA_ROLE).toInt();
            if (role == ROLE_GRAIN) {
                const patterns::PanelId id{item->data(DATA_PANEL).value<quint32>()};
                const patterns::doc::Panel* p = panel(id);
                m_grainDrag = GrainDrag{id, p != nullptr ? p->grainAngle : 0, false};
                event->accept();
                return true;
            }
            if (role == ROLE_POINT || role == ROLE_CONTROL || role == ROLE_ROTATE) {
                break; // a handle on top: Select's own
            }
        }
        if (const auto mark = pickMark(at)) {
            const auto [id, isNotch, value] = *mark;
            if (id != m_selectedPanel) {
                selectPanel(id); // clears the marks
            }
            m_selectedNotch = isNotch ? patterns::NotchId{value} : patterns::NotchId{};
            m_selectedLine = isNotch ? patterns::LineId{} : patterns::LineId{value};
            m_selectedPoint = {};
            redraw();
            Q_EMIT message(isNotch ? tr("Notch selected (Delete removes it)")
                                   : tr("Internal line selected (Delete removes it)"));
            event->accept();
            return true;
        }
        if (m_selectedNotch || m_selectedLine) {
            m_selectedNotch = {};
            m_selectedLine = {};
            redraw();
        }
        return false;
    }
    default:
        return false;
    }
}

bool PatternView::moveMarkTool(QMouseEvent* event) {
    const QPoint at = event->position().toPoint();
    const QPointF scene = mapToScene(at);
    if (m_pen) {
        if (m_pen->dragging) {
            const QPointF p = m_pen->points.back();
            if (distance(mapFromScene(p), at) >= QApplication::startDragDistance()) {
                m_pen->handles.back() = scene;
            }
        }
        m_pen->cursor = snap(scene, event->modifiers(), {}, {});
        drawOverlay();
        event->accept();
        return true;
    }
    if (m_line) {
        m_line->cursor =
            toPattern(m_line->panel, snap(scene, event->modifiers(), {}, m_line->panel));
        drawOverlay();
        event->accept();
        return true;
    }
    if (m_dart) {
        m_dart->tip =
            toPattern(m_dart->base.panel, snap(scene, event->modifiers(), {}, m_dart->base.panel));
        drawOverlay();
        event->accept();
        return true;
    }
    if (m_grainDrag) {
        const patterns::doc::Panel* p = panel(m_grainDrag->panel);
        if (p == nullptr) {
            m_grainDrag.reset();
            return false;
        }
        const auto [from, to] = grainLine(*p, p->grainAngle);
        const QPointF centre = (from + to) / 2;
        // Scene y runs down, pattern y up; the layout may turn the panel, so measure the angle
        // in pattern coordinates.
        const patterns::Vec2 c = toPattern(p->id, centre);
        const patterns::Vec2 q = toPattern(p->id, scene);
        double angle = std::atan2(q.y() - c.y(), q.x() - c.x());
        if (event->modifiers() & Qt::ShiftModifier) {
            const double step = GRAIN_STEP_DEG * std::numbers::pi / 180;
            angle = std::round(angle / step) * step;
        }
        m_grainDrag->angle = angle;
        m_grainDrag->moved = true;
        drawHandles();
        setFeedback(tr("grain %1°").arg(angle * 180 / std::numbers::pi, 0, 'f', 1), scene);
        event->accept();
        return true;
    }
    return false;
}

bool PatternView::releaseMarkTool(QMouseEvent* event) {
    if (m_pen && m_pen->dragging) {
        m_pen->dragging = false;
        drawOverlay();
        event->accept();
        return true;
    }
    if (m_dart) {
        const DartDrag dart = *m_dart;
        m_dart.reset();
        clearOverlay();
        const double depth = (dart.tip - dart.base.at).norm();
        if (depth >= MIN_DART_DEPTH) {
            const bool made = applyEdit([&](patterns::GarmentDocument& d) {
                return patterns::addDart(d, dart.base.panel, dart.base.edge, dart.base.t,
                                         DART_WIDTH_SHARE * depth, depth);
            });
            if (made) {
                Q_EMIT message(tr("Dart added (%1 × %2 mm)")
                                   .arg(DART_WIDTH_SHARE * depth * MM, 0, 'f', 1)
                                   .arg(depth * MM, 0, 'f', 1));
            }
        }
        event->accept();
        return true;
    }
    if (m_grainDrag) {
        const GrainDrag grain = *m_grainDrag;
        m_grainDrag.reset();
        clearOverlay();
        if (grain.moved) {
            applyEdit([&](patterns::GarmentDocument& d) {
                return patterns::setGrainAngle(d, grain.panel, grain.angle);
            });
        }
        drawHandles();
        event->accept();
        return true;
    }
    return false;
}

bool PatternView::finishMarkDrawing() {
    if (m_pen) {
        return finishPen();
    }
    if (m_line) {
        return finishLine();
    }
    return false;
}

bool PatternView::dropLastMarkPoint() {
    if (m_pen) {
        m_pen->points.pop_back();
        m_pen->handles.pop_back();
        if (m_pen->points.empty()) {
            m_pen.reset();
        }
    } else if (m_line) {
        m_line->points.pop_back();
        if (m_line->points.empty()) {
            m_line.reset();
        }
    } else {
        return false;
    }
    drawOverlay();
    return true;
}

bool PatternView::finishPen() {
    if (!m_pen || m_pen->points.size() < 3) {
        Q_EMIT message(tr("A free curve needs at least 3 points"));
        return false;
    }
    const PenDrawing pen = *m_pen;
    m_pen.reset();
    clearOverlay();
    return addDrawnPanel(pen.points, pen.handles);
}

bool PatternView::finishLine() {
    if (!m_line || m_line->points.size() < 2) {
        Q_EMIT message(tr("An internal line needs at least 2 points"));
        return false;
    }
    const LineDrawing line = *m_line;
    m_line.reset();
    clearOverlay();
    const bool made = applyEdit([&](patterns::GarmentDocument& d) {
        return patterns::addInternalLine(d, line.panel, line.points);
    });
    if (made) {
        Q_EMIT message(tr("Internal line added"));
    }
    return made;
}

bool PatternView::deleteSelectedMark() {
    const patterns::PanelId id = m_selectedPanel;
    const patterns::doc::Panel* p = panel(id);
    if (p == nullptr) {
        return false;
    }
    if (m_selectedNotch) {
        const patterns::NotchId notch = m_selectedNotch;
        m_selectedNotch = {};
        return applyEdit(
            [&](patterns::GarmentDocument& d) { return patterns::removeNotch(d, id, notch); });
    }
    if (m_selectedLine) {
        const patterns::LineId line = m_selectedLine;
        m_selectedLine = {};
        return applyEdit([&](patterns::GarmentDocument& d) {
            return patterns::removeInternalLine(d, id, line);
        });
    }
    for (const patterns::doc::Dart& dart : p->darts) {
        if (m_selectedEdge && (dart.leg1 == m_selectedEdge || dart.leg2 == m_selectedEdge)) {
            const patterns::DartId which = dart.id;
            m_selectedEdge = {};
            return applyEdit(
                [&](patterns::GarmentDocument& d) { return patterns::removeDart(d, id, which); });
        }
    }
    return false;
}

} // namespace atelier::ui
