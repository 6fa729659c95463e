#include "io/pattern_svg.h"

#include "io/atomic_file.h"
#include "io/xml_text.h"

#include "patterns/curve.h"
#include "patterns/seam_allowance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <optional>

namespace atelier::io {

namespace {

using patterns::Loop;
using patterns::Panel;
using patterns::Segment;
using patterns::SegmentKind;
using patterns::Vec2;

constexpr double MM_PER_M = 1000.0;

/// Pattern plane [m] → the panel's drawing [mm]: y down the sheet, x mirrored for a Back panel
/// (cut from the fabric turned over).
struct PanelFrame {
    double sx = 1;
    Vec2 map(const Vec2& p) const { return MM_PER_M * Vec2(sx * p.x(), -p.y()); }
    /// A sweep counter-clockwise in the pattern is one in SVG's positive-angle direction (from
    /// +x toward +y, clockwise on paper) when the map keeps orientation.
    bool sweepFlag(double sweep) const { return sweep * -sx > 0; }
};

/// One command of an SVG path in drawing coordinates [mm].
struct Cmd {
    char op = 'M';           ///< M, L, Q, C, A or Z
    std::array<Vec2, 3> p{}; ///< M, L, A: p[0]; Q: control p[0], end p[1]; C: p[0], p[1], end p[2]
    double radius = 0;       ///< A [mm]
    bool sweep = false;      ///< A: SVG sweep-flag
};

struct Path {
    std::string cls;
    std::string style;
    std::vector<Cmd> cmds = {};
};

struct Text {
    std::string cls;
    std::string style;
    Vec2 at = Vec2::Zero(); ///< centre of the block [mm]
    double size = 5;        ///< font size [mm]
    std::vector<std::string> lines;
};

/// A panel's (or the calibration square's) drawing before it is placed on the sheet.
struct Drawing {
    std::string id;
    std::string title;
    std::vector<Path> paths;
    std::vector<Text> texts;
    std::vector<Vec2> extent; ///< points of curves that their commands' points do not bound
    Vec2 min = Vec2::Zero(), max = Vec2::Zero();
};

const char* const CUT_STYLE = R"(fill="none" stroke="#000000" stroke-width="0.3")";
const char* const SEWING_STYLE =
    R"(fill="none" stroke="#000000" stroke-width="0.2" stroke-dasharray="3 2")";
const char* const INTERNAL_STYLE = R"(fill="none" stroke="#1f4e9c" stroke-width="0.2")";
const char* const FOLD_STYLE =
    R"(fill="none" stroke="#1f4e9c" stroke-width="0.2" stroke-dasharray="6 1.5 1 1.5")";
const char* const DART_STYLE =
    R"(fill="none" stroke="#1f4e9c" stroke-width="0.2" stroke-dasharray="1 1")";
const char* const NOTCH_STYLE = R"(fill="none" stroke="#000000" stroke-width="0.3")";
const char* const GRAIN_STYLE = R"(fill="none" stroke="#000000" stroke-width="0.25")";
const char* const SEAM_STYLE = R"(fill="none" stroke="#c0392b" stroke-width="0.3")";
const char* const SEAM_TEXT_STYLE = R"(fill="#c0392b")";
const char* const LABEL_STYLE = R"(fill="#000000")";

/// Text width estimate for layout: 0.6 em a character (sans-serif digits and lower case are
/// narrower), bytes counted, so multi-byte characters count more than they take.
double textWidth(const std::string& line, double size) {
    return 0.6 * size * static_cast<double>(line.size());
}

void addSegment(Path& path, const Segment& s, const PanelFrame& frame, std::vector<Vec2>& extent) {
    Cmd cmd;
    switch (s.kind) {
    case SegmentKind::Line:
        break;
    case SegmentKind::Quadratic:
        cmd.op = 'Q';
        cmd.p = {frame.map(s.control1), frame.map(s.end), Vec2::Zero()};
        path.cmds.push_back(cmd);
        return;
    case SegmentKind::Cubic:
        cmd.op = 'C';
        cmd.p = {frame.map(s.control1), frame.map(s.control2), frame.map(s.end)};
        path.cmds.push_back(cmd);
        return;
    case SegmentKind::Arc: {
        Vec2 centre;
        double radius = 0, start = 0, sweep = 0;
        if (!patterns::arcGeometry(s, centre, radius, start, sweep)) {
            break; // a straight "arc": drawn as the line it is
        }
        // SVG needs the large-arc flag for a sweep over 180°; two halves never need it.
        const int pieces = std::abs(sweep) > std::numbers::pi ? 2 : 1;
        for (int k = 1; k <= pieces; ++k) {
            cmd.op = 'A';
            cmd.p[0] = frame.map(patterns::pointAt(s, static_cast<double>(k) / pieces));
            cmd.radius = MM_PER_M * radius;
            cmd.sweep = frame.sweepFlag(sweep);
            path.cmds.push_back(cmd);
        }
        for (int k = 1; k < 16; ++k) {
            extent.push_back(frame.map(patterns::pointAt(s, k / 16.0)));
        }
        return;
    }
    }
    cmd.op = 'L';
    cmd.p[0] = frame.map(s.end);
    path.cmds.push_back(cmd);
}

/// A chain of segments as a subpath: moves to the first start; closes when `close`.
void addChain(Path& path, const std::vector<Segment>& chain, const PanelFrame& frame,
              std::vector<Vec2>& extent, bool close) {
    if (chain.empty()) {
        return;
    }
    Cmd move;
    move.p[0] = frame.map(chain.front().start);
    path.cmds.push_back(move);
    for (const Segment& s : chain) {
        addSegment(path, s, frame, extent);
    }
    if (close) {
        path.cmds.push_back(Cmd{'Z'});
    }
}

void addPolyline(Path& path, const std::vector<Vec2>& points, const PanelFrame& frame, bool close) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        Cmd cmd{i == 0 ? 'M' : 'L'};
        cmd.p[0] = frame.map(points[i]);
        path.cmds.push_back(cmd);
    }
    if (close && !points.empty()) {
        path.cmds.push_back(Cmd{'Z'});
    }
}

/// A straight line in drawing coordinates as a subpath.
void addLine(Path& path, const Vec2& a, const Vec2& b) {
    Cmd move{'M'}, line{'L'};
    move.p[0] = a;
    line.p[0] = b;
    path.cmds.push_back(move);
    path.cmds.push_back(line);
}

/// A panel's fabric: the outline's polyline, then its holes' [m].
using Fabric = std::vector<std::vector<Vec2>>;

/// Whether `p` lies in the fabric (inside the outline, outside every hole).
bool inFabric(const Fabric& fabric, const Vec2& p) {
    bool inside = false;
    for (const std::vector<Vec2>& loop : fabric) {
        inside ^= patterns::insidePolyline(loop, p);
    }
    return inside;
}

/// Where the line `origin + s·dir` crosses the fabric's edges, sorted by s: between the
/// first and second, third and fourth... it runs in the fabric.
std::vector<double> crossings(const Fabric& fabric, const Vec2& origin, const Vec2& dir) {
    std::vector<double> out;
    for (const std::vector<Vec2>& poly : fabric) {
        for (std::size_t i = 0; i < poly.size(); ++i) {
            const Vec2& a = poly[i];
            const Vec2 e = poly[(i + 1) % poly.size()] - a;
            const double denom = dir.x() * e.y() - dir.y() * e.x();
            if (denom == 0) {
                continue;
            }
            const Vec2 w = a - origin;
            const double u = (dir.y() * w.x() - dir.x() * w.y()) / denom; // along the edge
            if (u >= 0 && u < 1) {
                out.push_back((w.x() * e.y() - w.y() * e.x()) / denom);
            }
        }
    }
    std::sort(out.begin(), out.end());
    return out;
}

/// The stretch [s0, s1] of the line `origin + s·dir` in the fabric that holds s = 0, if any.
std::optional<std::pair<double, double>> insideStretch(const Fabric& fabric, const Vec2& origin,
                                                       const Vec2& dir) {
    const std::vector<double> s = crossings(fabric, origin, dir);
    for (std::size_t i = 0; i + 1 < s.size(); i += 2) {
        if (s[i] <= 0 && s[i + 1] >= 0) {
            return std::make_pair(s[i], s[i + 1]);
        }
    }
    return std::nullopt;
}

/// A point well in the fabric: the middle of the widest stretch in it of the horizontal through
/// the outline's area centroid (which can lie outside a concave outline, or in a hole) [m].
Vec2 labelPoint(const Fabric& fabric) {
    const std::vector<Vec2>& poly = fabric.front();
    Vec2 centroid = Vec2::Zero();
    double area = 0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        const Vec2 &a = poly[i], &b = poly[(i + 1) % poly.size()];
        const double c = a.x() * b.y() - b.x() * a.y();
        area += c;
        centroid += c * (a + b);
    }
    centroid = area != 0 ? Vec2(centroid / (3 * area)) : poly.front();
    const std::vector<double> s = crossings(fabric, centroid, Vec2(1, 0));
    double best = -1, at = 0;
    for (std::size_t i = 0; i + 1 < s.size(); i += 2) {
        if (s[i + 1] - s[i] > best) {
            best = s[i + 1] - s[i];
            at = 0.5 * (s[i] + s[i + 1]);
        }
    }
    return best > 0 ? Vec2(centroid + Vec2(at, 0)) : centroid;
}

/// Unit normal pointing out of the fabric at parameter t of an outline segment.
Vec2 outwardNormal(const Segment& s, double t, bool counterClockwise) {
    Vec2 tangent = patterns::tangentAt(s, t);
    if (tangent.norm() == 0) {
        tangent = s.end - s.start;
    }
    const Vec2 right =
        tangent.norm() > 0 ? Vec2(Vec2(tangent.y(), -tangent.x()).normalized()) : Vec2(0, 0);
    return counterClockwise ? right : Vec2(-right);
}

/// A seam edge's range on one panel, with the seam's name.
struct SeamMark {
    std::string seam;
    int segment = 0;
    double t0 = 0, t1 = 1;
};

std::string fabricText(const patterns::Garment& garment, const Panel& panel) {
    for (const patterns::GarmentMaterial& m : garment.materials) {
        if (m.name == panel.material) {
            const std::string& preset = m.material.name;
            return preset.empty() || preset == m.name || preset == "custom"
                       ? "fabric: " + m.name
                       : "fabric: " + m.name + " (" + preset + ")";
        }
    }
    return "fabric: " + panel.material;
}

Result<Drawing> drawPanel(const patterns::Garment& garment, std::size_t index,
                          const std::vector<SeamMark>& marks, const PatternSvgOptions& options) {
    const Panel& panel = garment.panels[index];
    const std::string where = "panel \"" + panel.name + "\"";
    const double tolerance = options.curveToleranceMm / MM_PER_M;
    const double allowance = options.seamAllowanceMm / MM_PER_M;
    const double mm = 1.0 / MM_PER_M;
    const std::vector<Vec2> poly = patterns::loopPolyline(panel.outline, tolerance);
    if (poly.size() < 3) {
        return Error{"", where, "the outline encloses nothing"};
    }
    std::size_t points = poly.size();
    for (const Loop& hole : panel.holes) {
        points += patterns::loopPolyline(hole, tolerance).size();
    }
    if (points > MAX_PANEL_POINTS) {
        return Error{"", where,
                     "its outline and holes need " + std::to_string(points) +
                         " points to draw within the curve tolerance, more than " +
                         std::to_string(MAX_PANEL_POINTS)};
    }
    const bool ccw = patterns::polylineArea(poly) > 0;
    const PanelFrame frame{panel.side == patterns::PanelSide::Back ? -1.0 : 1.0};

    Drawing d;
    d.id = "panel-" + std::to_string(index);
    d.title = panel.name;

    Path cut{"cut-line", CUT_STYLE};
    if (allowance > 0) {
        for (const auto& loop :
             patterns::offsetPolyline(poly, allowance, patterns::OffsetSide::Outside, tolerance)) {
            addPolyline(cut, loop, frame, true);
        }
        for (const Loop& hole : panel.holes) {
            const auto holePoly = patterns::loopPolyline(hole, tolerance);
            for (const auto& loop : patterns::offsetPolyline(
                     holePoly, allowance, patterns::OffsetSide::Inside, tolerance)) {
                addPolyline(cut, loop, frame, true);
            }
        }
    } else {
        addChain(cut, panel.outline, frame, d.extent, true);
        for (const Loop& hole : panel.holes) {
            addChain(cut, hole, frame, d.extent, true);
        }
    }
    d.paths.push_back(std::move(cut));

    Path sewing{"sewing-line", SEWING_STYLE};
    addChain(sewing, panel.outline, frame, d.extent, true);
    d.paths.push_back(std::move(sewing));
    for (const Loop& hole : panel.holes) {
        Path path{"sewing-line hole", SEWING_STYLE};
        addChain(path, hole, frame, d.extent, true);
        d.paths.push_back(std::move(path));
    }

    for (const patterns::InternalLine& line : panel.internalLines) {
        const bool fold = line.foldAngle != 0;
        Path path{fold ? "internal-line fold" : "internal-line",
                  fold ? FOLD_STYLE : INTERNAL_STYLE};
        addChain(path, line.path, frame, d.extent, false);
        d.paths.push_back(std::move(path));
    }

    const int segments = static_cast<int>(panel.outline.size());
    if (!panel.darts.empty()) {
        Path path{"dart", DART_STYLE};
        for (const patterns::Dart& dart : panel.darts) {
            if (dart.leg < 0 || dart.leg >= segments) {
                return Error{"", where,
                             "a dart's leg " + std::to_string(dart.leg) +
                                 " is not an outline segment"};
            }
            const Segment& leg1 = panel.outline[static_cast<std::size_t>(dart.leg)];
            const Segment& leg2 =
                panel.outline[static_cast<std::size_t>((dart.leg + 1) % segments)];
            addLine(path, frame.map(0.5 * (leg1.start + leg2.end)), frame.map(leg1.end));
        }
        d.paths.push_back(std::move(path));
    }

    if (!panel.notches.empty()) {
        // Across the cut line: from 6 mm inside it (not inside the sewing line by more than
        // 3 mm) to 2 mm outside it.
        Path path{"notch", NOTCH_STYLE};
        for (const patterns::Notch& notch : panel.notches) {
            if (notch.segment < 0 || notch.segment >= segments || !(notch.t >= 0 && notch.t <= 1)) {
                return Error{"", where, "a notch is not on the outline"};
            }
            const Segment& s = panel.outline[static_cast<std::size_t>(notch.segment)];
            const Vec2 p = patterns::pointAt(s, notch.t);
            const Vec2 n = outwardNormal(s, notch.t, ccw);
            addLine(path, frame.map(p + std::max(allowance - 6 * mm, -3 * mm) * n),
                    frame.map(p + (allowance + 2 * mm) * n));
        }
        d.paths.push_back(std::move(path));
    }

    if (!marks.empty()) {
        // A 5 mm tick into the fabric across the sewing line at each end of each seam edge,
        // and the seam's name 9 mm inside the middle of the edge.
        Path path{"seam-mark", SEAM_STYLE};
        for (const SeamMark& mark : marks) {
            const Segment& s = panel.outline[static_cast<std::size_t>(mark.segment)];
            for (double t : {mark.t0, mark.t1}) {
                const Vec2 p = patterns::pointAt(s, t);
                addLine(path, frame.map(p), frame.map(p - 5 * mm * outwardNormal(s, t, ccw)));
            }
            const double tm = 0.5 * (mark.t0 + mark.t1);
            const Vec2 at = patterns::pointAt(s, tm) - 9 * mm * outwardNormal(s, tm, ccw);
            d.texts.push_back(Text{"seam-label", SEAM_TEXT_STYLE, frame.map(at), 4.0, {mark.seam}});
        }
        d.paths.push_back(std::move(path));
    }

    // The label at a point well inside; the grain line beside it, along the warp.
    Text label{
        "label",
        LABEL_STYLE,
        Vec2::Zero(),
        6.0,
        {panel.name, fabricText(garment, panel),
         panel.side == patterns::PanelSide::Back ? "cut 1 mirrored (fabric face down)" : "cut 1"}};
    Fabric fabric = {poly};
    for (const Loop& hole : panel.holes) {
        fabric.push_back(patterns::loopPolyline(hole, tolerance));
    }
    const Vec2 centre = labelPoint(fabric);
    double labelWidth = 0;
    for (const std::string& line : label.lines) {
        labelWidth = std::max(labelWidth, textWidth(line, label.size));
    }
    const Vec2 grain(std::cos(panel.grainAngle), std::sin(panel.grainAngle));
    const Vec2 across(-grain.y(), grain.x());
    Vec2 grainAt = centre;
    for (double side : {1.0, -1.0}) {
        const Vec2 candidate = centre + side * (0.5 * labelWidth + 6.0) * mm * across;
        if (inFabric(fabric, candidate)) {
            grainAt = candidate;
            break;
        }
    }
    label.at = frame.map(centre);
    d.texts.push_back(label);
    if (const auto stretch = insideStretch(fabric, grainAt, grain)) {
        const double mid = 0.5 * (stretch->first + stretch->second);
        const double half = 0.35 * (stretch->second - stretch->first);
        const Vec2 a = frame.map(grainAt + (mid - half) * grain);
        const Vec2 b = frame.map(grainAt + (mid + half) * grain);
        Path path{"grain-line", GRAIN_STYLE};
        addLine(path, a, b);
        // 5 mm heads at 25° at both ends.
        const Vec2 u = (b - a).normalized();
        const double c = std::cos(25.0 * std::numbers::pi / 180),
                     s = std::sin(25.0 * std::numbers::pi / 180);
        const Vec2 back1(c * u.x() - s * u.y(), s * u.x() + c * u.y());
        const Vec2 back2(c * u.x() + s * u.y(), -s * u.x() + c * u.y());
        addLine(path, b, b - 5.0 * back1);
        addLine(path, b, b - 5.0 * back2);
        addLine(path, a, a + 5.0 * back1);
        addLine(path, a, a + 5.0 * back2);
        d.paths.push_back(std::move(path));
    }
    return d;
}

/// Bounding box of everything drawn, text boxes by estimate [mm].
void measure(Drawing& d) {
    Vec2 lo(INFINITY, INFINITY), hi(-INFINITY, -INFINITY);
    auto add = [&](const Vec2& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    };
    for (const Path& path : d.paths) {
        for (const Cmd& cmd : path.cmds) {
            const int used = cmd.op == 'Q' ? 2 : cmd.op == 'C' ? 3 : cmd.op == 'Z' ? 0 : 1;
            for (int k = 0; k < used; ++k) {
                add(cmd.p[static_cast<std::size_t>(k)]);
            }
        }
    }
    for (const Vec2& p : d.extent) {
        add(p);
    }
    for (const Text& t : d.texts) {
        double w = 0;
        for (const std::string& line : t.lines) {
            w = std::max(w, textWidth(line, t.size));
        }
        const double h = 1.2 * t.size * static_cast<double>(t.lines.size());
        add(t.at - 0.5 * Vec2(w, h));
        add(t.at + 0.5 * Vec2(w, h));
    }
    d.min = lo;
    d.max = hi;
}

/// Writes numbers with three decimals at most (micrometres), never "-0".
class SvgOut {
  public:
    void num(double v) {
        if (!std::isfinite(v)) {
            m_finite = false;
            v = 0;
        }
        char buf[48];
        std::snprintf(buf, sizeof buf, "%.3f", v);
        std::string s = buf;
        while (!s.empty() && s.back() == '0') {
            s.pop_back();
        }
        if (!s.empty() && s.back() == '.') {
            s.pop_back();
        }
        m_text += s == "-0" ? "0" : s;
    }
    void point(const Vec2& p, const Vec2& offset) {
        num(p.x() + offset.x());
        m_text += ' ';
        num(p.y() + offset.y());
    }
    SvgOut& operator<<(const std::string& s) {
        m_text += s;
        return *this;
    }
    SvgOut& operator<<(const char* s) {
        m_text += s;
        return *this;
    }
    SvgOut& operator<<(double v) {
        num(v);
        return *this;
    }

    void path(const Path& path, const Vec2& offset) {
        m_text += "<path class=\"" + path.cls + "\" d=\"";
        for (std::size_t i = 0; i < path.cmds.size(); ++i) {
            const Cmd& cmd = path.cmds[i];
            if (i > 0) {
                m_text += ' ';
            }
            m_text += cmd.op;
            switch (cmd.op) {
            case 'M':
            case 'L':
                m_text += ' ';
                point(cmd.p[0], offset);
                break;
            case 'Q':
                for (int k = 0; k < 2; ++k) {
                    m_text += ' ';
                    point(cmd.p[static_cast<std::size_t>(k)], offset);
                }
                break;
            case 'C':
                for (int k = 0; k < 3; ++k) {
                    m_text += ' ';
                    point(cmd.p[static_cast<std::size_t>(k)], offset);
                }
                break;
            case 'A':
                m_text += ' ';
                num(cmd.radius);
                m_text += ' ';
                num(cmd.radius);
                m_text += cmd.sweep ? " 0 0 1 " : " 0 0 0 ";
                point(cmd.p[0], offset);
                break;
            default:
                break;
            }
        }
        m_text += "\" " + path.style + "/>\n";
    }

    void text(const Text& t, const Vec2& offset) {
        const double lineHeight = 1.2 * t.size;
        const double top =
            t.at.y() + offset.y() - 0.5 * lineHeight * static_cast<double>(t.lines.size());
        *this << "<text class=\"" << t.cls << "\" " << t.style
              << " font-family=\"sans-serif\" font-size=\"" << t.size
              << "\" text-anchor=\"middle\">";
        for (std::size_t i = 0; i < t.lines.size(); ++i) {
            *this << "<tspan x=\"" << t.at.x() + offset.x() << "\" y=\""
                  << top + (static_cast<double>(i) + 0.8) * lineHeight << "\">"
                  << xmlEscape(t.lines[i]) << "</tspan>";
        }
        *this << "</text>\n";
    }

    bool finite() const { return m_finite; }
    std::string& str() { return m_text; }

  private:
    std::string m_text;
    bool m_finite = true;
};

Drawing calibrationSquare() {
    Drawing d;
    d.id = "calibration";
    d.title = "calibration square, 100 mm";
    Path square{"calibration", R"(fill="none" stroke="#000000" stroke-width="0.3")"};
    const std::array<Vec2, 4> corners = {Vec2(0, 0), Vec2(100, 0), Vec2(100, 100), Vec2(0, 100)};
    for (std::size_t i = 0; i < corners.size(); ++i) {
        Cmd cmd{i == 0 ? 'M' : 'L'};
        cmd.p[0] = corners[i];
        square.cmds.push_back(cmd);
    }
    square.cmds.push_back(Cmd{'Z'});
    d.paths.push_back(square);
    d.texts.push_back(Text{"calibration-label",
                           LABEL_STYLE,
                           Vec2(50, 50),
                           5.0,
                           {"100 mm x 100 mm", "print at 100 %"}});
    measure(d);
    return d;
}

/// Items placed left to right in shelves no wider than `inner`, tallest first (`order`).
struct Packing {
    std::vector<Vec2> corners; ///< each item's top-left corner, from the first shelf's [mm]
    double width = 0, height = 0;
};

Packing packShelves(const std::vector<Vec2>& sizes, const std::vector<std::size_t>& order,
                    double inner, double gap) {
    Packing p;
    p.corners.resize(sizes.size(), Vec2::Zero());
    double x = 0, y = 0, shelf = 0;
    for (std::size_t i : order) {
        if (x > 0 && x + sizes[i].x() > inner) {
            y += shelf + gap;
            x = 0;
            shelf = 0;
        }
        p.corners[i] = Vec2(x, y);
        x += sizes[i].x() + gap;
        p.width = std::max(p.width, x - gap);
        shelf = std::max(shelf, sizes[i].y());
    }
    p.height = y + shelf;
    return p;
}

} // namespace

Result<PatternSvg> patternSvg(const patterns::Garment& garment, const PatternSvgOptions& options) {
    if (!(options.seamAllowanceMm >= 0 && options.seamAllowanceMm <= MAX_SEAM_ALLOWANCE_MM)) {
        char text[96];
        std::snprintf(text, sizeof text, "seam allowance %g mm: must be from 0 to %g mm",
                      options.seamAllowanceMm, MAX_SEAM_ALLOWANCE_MM);
        return Error{"", "", text};
    }
    if (!(options.sheetWidthMm >= 0 && std::isfinite(options.sheetWidthMm))) {
        return Error{"", "", "the sheet width must be 0 (chosen) or more"};
    }
    if (!(options.gapMm >= 0) || !(options.curveToleranceMm > 0)) {
        return Error{"", "", "the gap must be 0 or more and the curve tolerance above 0"};
    }
    if (garment.panels.empty()) {
        return Error{"", "", "the garment has no panels"};
    }

    std::vector<std::vector<SeamMark>> marks(garment.panels.size());
    for (const patterns::Seam& seam : garment.seams) {
        for (const auto* side : {&seam.a, &seam.b}) {
            for (const patterns::SeamEdge& e : *side) {
                const int p = garment.panelIndex(e.panel);
                if (p < 0 || e.segment < 0 ||
                    e.segment >= static_cast<int>(
                                     garment.panels[static_cast<std::size_t>(p)].outline.size()) ||
                    !(e.t0 >= 0 && e.t0 <= 1 && e.t1 >= 0 && e.t1 <= 1)) {
                    return Error{"", "seam \"" + seam.name + "\"",
                                 "panel \"" + e.panel + "\" has no outline segment " +
                                     std::to_string(e.segment) + " to sew"};
                }
                marks[static_cast<std::size_t>(p)].push_back({seam.name, e.segment, e.t0, e.t1});
            }
        }
    }

    std::vector<Drawing> items;
    for (std::size_t i = 0; i < garment.panels.size(); ++i) {
        auto drawing = drawPanel(garment, i, marks[i], options);
        if (!drawing.ok()) {
            return drawing.error();
        }
        items.push_back(std::move(drawing).value());
        measure(items.back());
    }
    items.push_back(calibrationSquare());

    // Shelves, tallest first: on the sheet width asked for, or on the width (from the widest
    // item to all in one row) that gives the smallest sheet.
    const double gap = options.gapMm;
    char header[256];
    std::snprintf(header, sizeof header,
                  "seam allowance %g mm: cut on the solid line, sew on the dashed line",
                  options.seamAllowanceMm);
    const std::string headerLine = garment.name.empty() ? header : garment.name + ": " + header;
    const double headerSize = 5.0;
    const double top = gap + 1.2 * headerSize + gap;
    std::vector<Vec2> sizes;
    std::size_t widestItem = 0;
    for (const Drawing& d : items) {
        sizes.emplace_back(d.max - d.min);
        if (sizes.back().x() > sizes[widestItem].x()) {
            widestItem = sizes.size() - 1;
        }
    }
    std::vector<std::size_t> order(items.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return sizes[a].y() > sizes[b].y(); });
    Packing packing;
    if (options.sheetWidthMm > 0) {
        const double inner = options.sheetWidthMm - 2 * gap;
        if (sizes[widestItem].x() > inner) {
            char text[256];
            std::snprintf(text, sizeof text,
                          "is %.0f mm wide with its seam allowance and marks, more than the "
                          "%g mm sheet less its %g mm margins",
                          sizes[widestItem].x(), options.sheetWidthMm, gap);
            return Error{"",
                         items[widestItem].id == "calibration"
                             ? std::string("the calibration square")
                             : "panel \"" + items[widestItem].title + "\"",
                         text};
        }
        packing = packShelves(sizes, order, inner, gap);
        packing.width = inner;
    } else {
        std::vector<double> widths = {sizes[widestItem].x()};
        double row = -gap;
        for (std::size_t i : order) {
            row += sizes[i].x() + gap;
            if (row > widths.front()) {
                widths.push_back(row);
            }
        }
        for (double inner : widths) {
            Packing candidate = packShelves(sizes, order, inner, gap);
            candidate.width = std::max(candidate.width, textWidth(headerLine, headerSize));
            const auto area = [&](const Packing& p) {
                return (p.width + 2 * gap) * (p.height + top + gap);
            };
            if (packing.corners.empty() || area(candidate) < area(packing)) {
                packing = std::move(candidate);
            }
        }
    }
    std::vector<Vec2> offsets(items.size());
    for (std::size_t i = 0; i < items.size(); ++i) {
        offsets[i] = Vec2(gap, top) + packing.corners[i] - items[i].min;
    }

    PatternSvg out;
    out.widthMm =
        options.sheetWidthMm > 0 ? options.sheetWidthMm : std::ceil(gap + packing.width + gap);
    out.heightMm = std::ceil(top + packing.height + gap);
    SvgOut svg;
    svg << "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << out.widthMm
        << "mm\" height=\"" << out.heightMm << "mm\" viewBox=\"0 0 " << out.widthMm << " "
        << out.heightMm << "\">\n"
        << "<title>" << xmlEscape(garment.name.empty() ? "pattern" : garment.name + " pattern")
        << "</title>\n"
        << "<desc>Real size: 1 unit = 1 mm; print at 100 % and check the 100 mm square. Cut "
           "lines solid, sewing lines dashed, seam marks red.</desc>\n";
    svg.text(Text{"header",
                  LABEL_STYLE,
                  Vec2(gap + 0.5 * textWidth(headerLine, headerSize), gap + 0.6 * headerSize),
                  headerSize,
                  {headerLine}},
             Vec2::Zero());
    for (std::size_t i = 0; i < items.size(); ++i) {
        const Drawing& d = items[i];
        svg << "<g id=\"" << d.id << "\"" << (d.id == "calibration" ? "" : " class=\"panel\"")
            << ">\n<title>" << xmlEscape(d.title) << "</title>\n";
        for (const Path& path : d.paths) {
            svg.path(path, offsets[i]);
        }
        for (const Text& text : d.texts) {
            svg.text(text, offsets[i]);
        }
        svg << "</g>\n";
        if (i < garment.panels.size()) {
            const Vec2 lo = d.min + offsets[i], hi = d.max + offsets[i];
            out.panels.push_back({garment.panels[i].name, lo.x(), lo.y(), hi.x(), hi.y()});
        }
    }
    svg << "</svg>\n";
    if (!svg.finite()) {
        return Error{"", "", "the pattern's geometry is not finite"};
    }
    out.text = std::move(svg.str());
    return out;
}

Result<PatternSvg> writePatternSvg(const std::filesystem::path& path,
                                   const patterns::Garment& garment,
                                   const PatternSvgOptions& options) {
    auto svg = patternSvg(garment, options);
    if (!svg.ok()) {
        return svg.error();
    }
    auto written = writeFileAtomically(path, svg.value().text);
    if (!written.ok()) {
        return written.error();
    }
    return svg;
}

} // namespace atelier::io
