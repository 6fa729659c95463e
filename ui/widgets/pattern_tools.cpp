#include "ui/widgets/pattern_tools.h"

#include "patterns/curve.h"

#include <algorithm>
#include <cmath>

namespace atelier::ui {

namespace {

/// Clearance of the first pair of drawn panels and the step between pairs (as the DXF
/// importer's pieces) [m].
constexpr double FIRST_CLEARANCE = 0.03;
constexpr double CLEARANCE_STEP = 0.05;

} // namespace

patterns::Panel drawnPanel(const patterns::GarmentDocument& document,
                           const std::vector<patterns::Vec2>& corners) {
    patterns::Panel panel;
    for (int k = 1;; ++k) {
        const std::string name = "panel " + std::to_string(k);
        if (document.panelNamed(name) == nullptr) {
            panel.name = name;
            break;
        }
    }
    std::vector<patterns::Vec2> points = corners;
    double twiceArea = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const patterns::Vec2& p = points[i];
        const patterns::Vec2& q = points[(i + 1) % points.size()];
        twiceArea += p.x() * q.y() - q.x() * p.y();
    }
    if (twiceArea < 0) {
        std::reverse(points.begin(), points.end());
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
        patterns::Segment s;
        s.start = points[i];
        s.end = points[(i + 1) % points.size()];
        panel.outline.push_back(s);
    }
    if (!document.materials.empty()) {
        panel.material = document.materials.front().name;
    }
    const std::size_t n = document.panels.size();
    const bool front = n % 2 == 0;
    panel.placement.slot = front ? "torso_front" : "torso_back";
    panel.side = front ? patterns::PanelSide::Front : patterns::PanelSide::Back;
    panel.placement.clearance = FIRST_CLEARANCE + CLEARANCE_STEP * static_cast<double>(n / 2);
    return panel;
}

patterns::Panel drawnCurvePanel(const patterns::GarmentDocument& document,
                                std::vector<PenPoint> points) {
    double twiceArea = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        const patterns::Vec2& p = points[i].at;
        const patterns::Vec2& q = points[(i + 1) % points.size()].at;
        twiceArea += p.x() * q.y() - q.x() * p.y();
    }
    if (twiceArea < 0) {
        std::reverse(points.begin(), points.end());
        for (PenPoint& p : points) {
            if (p.handle) {
                p.handle = 2 * p.at - *p.handle; // the incoming handle is outgoing now
            }
        }
    }
    std::vector<patterns::Vec2> corners;
    for (const PenPoint& p : points) {
        corners.push_back(p.at);
    }
    patterns::Panel panel = drawnPanel(document, corners); // counter-clockwise already: kept
    for (std::size_t i = 0; i < points.size() && i < panel.outline.size(); ++i) {
        const PenPoint& a = points[i];
        const PenPoint& b = points[(i + 1) % points.size()];
        if (!a.handle && !b.handle) {
            continue;
        }
        patterns::Segment& s = panel.outline[i];
        s.kind = patterns::SegmentKind::Cubic;
        s.control1 = a.handle ? *a.handle : a.at;
        s.control2 = b.handle ? patterns::Vec2(2 * b.at - *b.handle) : b.at;
    }
    return panel;
}

std::vector<patterns::doc::SeamRange>
outlineRanges(const patterns::doc::Panel& panel, OutlinePlace from, OutlinePlace to, bool forward) {
    std::vector<patterns::doc::SeamRange> out;
    const int n = static_cast<int>(panel.outline.edges.size());
    if (n == 0 || from.edge < 0 || from.edge >= n || to.edge < 0 || to.edge >= n) {
        return out;
    }
    const auto add = [&](int edge, double t0, double t1) {
        if (t0 != t1) {
            out.push_back({panel.id, panel.outline.edges[static_cast<std::size_t>(edge)].id,
                           std::clamp(t0, 0.0, 1.0), std::clamp(t1, 0.0, 1.0)});
        }
    };
    if (from.edge == to.edge && (forward ? from.t < to.t : from.t > to.t)) {
        add(from.edge, from.t, to.t);
        return out;
    }
    const int step = forward ? 1 : n - 1;
    const double first = forward ? 1.0 : 0.0; // where the first edge is left
    const double last = 1.0 - first;          // where the last edge is entered
    add(from.edge, from.t, first);
    for (int k = (from.edge + step) % n; k != to.edge; k = (k + step) % n) {
        add(k, last, first);
    }
    add(to.edge, last, to.t);
    return out;
}

std::vector<patterns::doc::SeamRange> reversedRanges(std::vector<patterns::doc::SeamRange> ranges) {
    std::reverse(ranges.begin(), ranges.end());
    for (patterns::doc::SeamRange& r : ranges) {
        std::swap(r.t0, r.t1);
    }
    return ranges;
}

double rangesLength(const patterns::GarmentDocument& document,
                    const std::vector<patterns::doc::SeamRange>& ranges) {
    double length = 0;
    for (const patterns::doc::SeamRange& r : ranges) {
        const patterns::doc::Panel* panel = document.panel(r.panel);
        const int e = panel == nullptr ? -1 : patterns::outlineEdgeIndex(*panel, r.edge);
        if (e >= 0) {
            length += patterns::arcLength(
                patterns::contourSegment(panel->outline, static_cast<std::size_t>(e)), r.t0, r.t1);
        }
    }
    return length;
}

std::pair<double, double> seamLengths(const patterns::GarmentDocument& document,
                                      const patterns::doc::Seam& seam) {
    return {rangesLength(document, seam.a), rangesLength(document, seam.b)};
}

std::string newSeamName(const patterns::GarmentDocument& document) {
    for (int k = 1;; ++k) {
        const std::string name = "seam " + std::to_string(k);
        if (std::none_of(document.seams.begin(), document.seams.end(),
                         [&](const patterns::doc::Seam& s) { return s.name == name; })) {
            return name;
        }
    }
}

double bulgeThrough(const patterns::Vec2& start, const patterns::Vec2& end,
                    const patterns::Vec2& through) {
    const patterns::Vec2 chord = end - start;
    const double c = chord.norm();
    if (!(c > 0)) {
        return 0;
    }
    const patterns::Vec2 left(-chord.y() / c, chord.x() / c);
    const double h = (through - 0.5 * (start + end)).dot(left);
    return std::clamp(-2 * h / c, -MAX_HANDLE_BULGE, MAX_HANDLE_BULGE);
}

} // namespace atelier::ui
