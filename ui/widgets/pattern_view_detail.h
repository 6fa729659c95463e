#pragma once
/// What the pattern view's source files share (pattern_view.cpp, pattern_marks.cpp): the
/// scene's units, item roles and drawing helpers. Not for use outside ui/widgets/.

#include "ui/render/scene.h"
#include "ui/widgets/pattern_view.h"

#include "patterns/curve.h"

#include <QColor>
#include <QPainterPath>
#include <QPen>
#include <QPointF>

#include <cmath>

namespace atelier::ui::detail {

constexpr double MM = 1000.0; // the scene is in millimetres, y down
constexpr double GAP_MM = 60.0;
constexpr double HANDLE_PX = 9.0;         // handle diameter on screen
constexpr double PICK_EDGE_PX = 8.0;      // a click this close to an edge picks it
constexpr double SEAM_PICK_3D_MM = 40.0;  // a seam pick on the cloth this close to an edge
constexpr double SNAP_PX = 8.0;           // a point this close to another snaps onto it
constexpr double ROTATE_HANDLE_PX = 24.0; // the rotate handle's distance above the panel
constexpr double ROTATE_STEP_DEG = 15.0;  // Shift while rotating
constexpr double SCENE_HALF_MM = 50000.0; // the scene spans ±50 m: room to draw and pan
constexpr int DATA_NAME = 0;
constexpr int DATA_PANEL = 1;
constexpr int DATA_POINT = 2;
constexpr int DATA_ROLE = 3;
constexpr int DATA_EDGE = 4;
constexpr int DATA_CONTROL = 5;
constexpr int CONTROL_BULGE = 3; // DATA_CONTROL of an arc's bulge handle (Béziers': 1, 2)
constexpr int ROLE_POINT = 1;
constexpr int ROLE_CONTROL = 2;
constexpr int ROLE_ROTATE = 3;
constexpr int ROLE_GRAIN = 4; // the grain line's handle
constexpr int ROLE_NOTCH = 5;
constexpr int ROLE_LINE = 6;              // an internal line
constexpr int DATA_MARK = 6;              // the id of a notch or internal line
constexpr double PICK_MARK_PX = 5.0;      // a click this close to a notch or internal line picks it
constexpr double NOTCH_MM = 6.0;          // a notch's tick into the panel
constexpr double DART_WIDTH_SHARE = 0.25; // a dart drawn with the mouse: width / depth

inline QColor qColour(const render::Colour& c) {
    return QColor::fromRgbF(c.r, c.g, c.b, c.a);
}

/// A pen `px` pixels wide whatever the zoom.
inline QPen screenPen(const QColor& colour, double px, Qt::PenStyle style = Qt::SolidLine) {
    QPen pen(colour, px, style, Qt::RoundCap, Qt::RoundJoin);
    pen.setCosmetic(true);
    return pen;
}

/// Pattern millimetres (y up) of a point [m].
inline QPointF local(const patterns::Vec2& v) {
    return {v.x() * MM, v.y() * MM};
}

/// A segment from t0 to t1 in pattern millimetres (y up).
inline QPainterPath segmentPath(const patterns::Segment& s, double t0, double t1) {
    QPainterPath path;
    const int n = s.kind == patterns::SegmentKind::Line ? 1 : 24;
    for (int i = 0; i <= n; ++i) {
        const QPointF q = local(patterns::pointAt(s, t0 + (t1 - t0) * i / n));
        if (i == 0) {
            path.moveTo(q);
        } else {
            path.lineTo(q);
        }
    }
    return path;
}

inline double distance(const QPointF& a, const QPointF& b) {
    return std::hypot(a.x() - b.x(), a.y() - b.y());
}

} // namespace atelier::ui::detail
