#include "patterns/mesh.h"

#include "patterns/curve.h"
#include "patterns/seam_check.h"
#include "patterns/triangulate.h"
#include "patterns/triangulation_cache.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace atelier::patterns {

namespace {

constexpr double T_EPS = 1e-9; ///< parameters closer than this are the same point [-]

std::string pointer(int panel, const std::string& rest) {
    return "/panels/" + std::to_string(panel) + rest;
}

bool finite(const Vec2& v) {
    return std::isfinite(v.x()) && std::isfinite(v.y());
}

bool segmentFinite(const Segment& s) {
    return finite(s.start) && finite(s.end) && finite(s.control1) && finite(s.control2) &&
           std::isfinite(s.bulge);
}

/// A loop flattened to a polygon, `pieces` per curved segment, with the segment of each edge.
struct Flat {
    std::vector<Vec2> points;
    std::vector<int> segmentOf;
};

Flat flatten(const Loop& loop, int pieces) {
    Flat f;
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const int n = loop[i].kind == SegmentKind::Line ? 1 : pieces;
        for (int k = 0; k < n; ++k) {
            f.points.push_back(pointAt(loop[i], static_cast<double>(k) / n));
            f.segmentOf.push_back(static_cast<int>(i));
        }
    }
    return f;
}

/// Proper or touching intersection of segments pq and rs (not counting shared endpoints).
bool segmentsCross(const Vec2& p, const Vec2& q, const Vec2& r, const Vec2& s) {
    const double d1 = sim::cross2d(q - p, r - p), d2 = sim::cross2d(q - p, s - p);
    const double d3 = sim::cross2d(s - r, p - r), d4 = sim::cross2d(s - r, q - r);
    return ((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0));
}

/// First pair of crossing edges of a flattened loop, as segment indices, or {-1, -1}.
std::pair<int, int> selfCrossing(const Flat& f) {
    const std::size_t n = f.points.size();
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) {
                continue; // adjacent through the loop's closure
            }
            if (segmentsCross(f.points[i], f.points[(i + 1) % n], f.points[j],
                              f.points[(j + 1) % n])) {
                return {f.segmentOf[i], f.segmentOf[j]};
            }
        }
    }
    return {-1, -1};
}

void checkLoop(const Loop& loop, const std::string& where, std::vector<GarmentIssue>& issues) {
    if (loop.size() < 2) {
        issues.push_back({where, "a closed outline needs at least two segments"});
        return;
    }
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const Segment& s = loop[i];
        const std::string w = where + "/" + std::to_string(i);
        if (!segmentFinite(s)) {
            issues.push_back({w, "coordinates must be finite"});
            return;
        }
        if (arcLength(s) < 1e-6) {
            issues.push_back({w, "segment has zero length"});
            return;
        }
        const Segment& next = loop[(i + 1) % loop.size()];
        if ((s.end - next.start).norm() > 1e-9) {
            issues.push_back({w, "segment does not end where the next one starts"});
            return;
        }
    }
    const auto [a, b] = selfCrossing(flatten(loop, 32));
    if (a >= 0) {
        std::ostringstream m;
        m << "outline intersects itself (segments " << a << " and " << b << ")";
        issues.push_back({where, m.str()});
    }
}

/// A panel wider or taller than MAX_PANEL_EXTENT, measured on its flattened outline (so that
/// an arc's bulge counts). Non-finite coordinates are left to checkLoop.
void checkExtent(const Panel& panel, const std::string& where, std::vector<GarmentIssue>& issues) {
    if (!std::all_of(panel.outline.begin(), panel.outline.end(), segmentFinite)) {
        return;
    }
    const Flat f = flatten(panel.outline, 32);
    if (f.points.empty()) {
        return;
    }
    Vec2 lo = f.points.front();
    Vec2 hi = lo;
    for (const Vec2& q : f.points) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
    }
    const double extent = (hi - lo).maxCoeff();
    if (!(extent <= MAX_PANEL_EXTENT)) {
        std::ostringstream m;
        m.precision(4);
        m << "panel \"" << panel.name << "\" is " << extent << " m across, more than the "
          << MAX_PANEL_EXTENT << " m a panel may span (outline points are millimetres)";
        issues.push_back({where, m.str()});
    }
}

/// A point on a panel's boundary: loop, segment, parameter (t in [0, 1)).
struct BoundaryKey {
    int loop = 0;
    int segment = 0;
    double t = 0;
};

struct SeamSidePoint {
    int panel;
    BoundaryKey key;
};

/// A seam side as ranges of segments (darts and seams alike).
struct SideRange {
    int panel;
    int segment;
    double t0, t1;
};

double rangeLength(const Garment& g, const SideRange& r) {
    return arcLength(
        g.panels[static_cast<std::size_t>(r.panel)].outline[static_cast<std::size_t>(r.segment)],
        r.t0, r.t1);
}

/// Per panel, per loop, per segment: fixed parameters and the parameter ranges seams cover.
struct PanelPoints {
    std::vector<std::vector<std::set<double>>> fixed;                         // [loop][segment]
    std::vector<std::vector<std::vector<std::pair<double, double>>>> covered; // [loop][segment]
};

BoundaryKey normalise(const Loop& loop, int loopIndex, int segment, double t) {
    if (t >= 1 - T_EPS) {
        return {loopIndex, (segment + 1) % static_cast<int>(loop.size()), 0.0};
    }
    return {loopIndex, segment, std::max(0.0, t)};
}

/// Inserts t unless a parameter within T_EPS is there already (one point, one vertex).
void insertSnapped(std::set<double>& ts, double t) {
    auto it = ts.lower_bound(t - T_EPS);
    if (it == ts.end() || std::abs(*it - t) > T_EPS) {
        ts.insert(t);
    }
}

double snap(const std::set<double>& ts, double t) {
    auto it = ts.lower_bound(t - T_EPS);
    if (it != ts.end() && std::abs(*it - t) <= T_EPS) {
        return *it;
    }
    return t;
}

} // namespace

bool insidePanel(const Panel& panel, const Vec2& point) {
    // A point on a contour counts as inside: pins go on corners and edges as often as not.
    const auto nearContour = [&](const std::vector<Vec2>& poly) {
        for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
            const Vec2 d = poly[i] - poly[j];
            const double t =
                std::clamp((point - poly[j]).dot(d) / std::max(d.squaredNorm(), 1e-30), 0.0, 1.0);
            if ((poly[j] + t * d - point).norm() <= PIN_CONTOUR_TOLERANCE) {
                return true;
            }
        }
        return false;
    };
    if (!point.allFinite() || panel.outline.empty()) {
        return false;
    }
    const std::vector<Vec2> outline = flatten(panel.outline, 32).points;
    if (!insidePolygon(outline, point) && !nearContour(outline)) {
        return false;
    }
    return std::none_of(panel.holes.begin(), panel.holes.end(), [&](const Loop& hole) {
        if (hole.empty()) {
            return false;
        }
        const std::vector<Vec2> poly = flatten(hole, 32).points;
        return insidePolygon(poly, point) && !nearContour(poly);
    });
}

std::vector<GarmentIssue> validateGarment(const Garment& garment) {
    std::vector<GarmentIssue> issues;
    for (std::size_t p = 0; p < garment.panels.size(); ++p) {
        const Panel& panel = garment.panels[p];
        const int pi = static_cast<int>(p);
        if (garment.panelIndex(panel.name) != pi) {
            issues.push_back({pointer(pi, "/name"), "duplicate panel name \"" + panel.name + "\""});
        }
        const std::size_t before = issues.size();
        checkExtent(panel, pointer(pi, "/outline"), issues);
        if (issues.size() != before) {
            continue;
        }
        checkLoop(panel.outline, pointer(pi, "/outline"), issues);
        if (issues.size() != before) {
            continue;
        }
        if (loopArea(panel.outline) <= 0) {
            issues.push_back({pointer(pi, "/outline"),
                              "outline must run counter-clockwise (its area is negative)"});
            continue;
        }
        const Flat outline = flatten(panel.outline, 32);
        for (std::size_t h = 0; h < panel.holes.size(); ++h) {
            const std::string w = pointer(pi, "/holes/" + std::to_string(h));
            const std::size_t b = issues.size();
            checkLoop(panel.holes[h], w, issues);
            if (issues.size() != b) {
                continue;
            }
            for (const Vec2& q : flatten(panel.holes[h], 8).points) {
                if (!insidePolygon(outline.points, q)) {
                    issues.push_back({w, "hole is not inside the outline"});
                    break;
                }
            }
        }
        for (std::size_t l = 0; l < panel.internalLines.size(); ++l) {
            const InternalLine& line = panel.internalLines[l];
            const std::string w = pointer(pi, "/internal_lines/" + std::to_string(l));
            if (line.path.empty()) {
                issues.push_back({w, "internal line has no segments"});
                continue;
            }
            if (!std::isfinite(line.foldAngle)) {
                issues.push_back({w + "/fold_deg", "must be finite"});
            }
            for (std::size_t k = 0; k < line.path.size(); ++k) {
                const Segment& s = line.path[k];
                const std::string ws = w + "/segments/" + std::to_string(k);
                if (!segmentFinite(s)) {
                    issues.push_back({ws, "coordinates must be finite"});
                    break;
                }
                if (arcLength(s) < 1e-6) {
                    issues.push_back({ws, "segment has zero length"});
                    break;
                }
                bool outside = false;
                for (int i = 0; i <= 8 && !outside; ++i) {
                    const Vec2 q = pointAt(s, i / 8.0);
                    outside = !insidePolygon(outline.points, q);
                    for (const Loop& hole : panel.holes) {
                        outside = outside || insidePolygon(flatten(hole, 8).points, q);
                    }
                }
                if (outside) {
                    issues.push_back({ws, "internal line leaves the panel (it must lie inside)"});
                    break;
                }
            }
        }
        for (std::size_t d = 0; d < panel.darts.size(); ++d) {
            const int leg = panel.darts[d].leg;
            if (leg < 0 || leg + 1 >= static_cast<int>(panel.outline.size())) {
                issues.push_back({pointer(pi, "/darts/" + std::to_string(d) + "/leg"),
                                  "dart legs " + std::to_string(leg) + " and " +
                                      std::to_string(leg + 1) + " are not in the outline"});
            }
        }
        for (std::size_t n = 0; n < panel.notches.size(); ++n) {
            const Notch& notch = panel.notches[n];
            const std::string w = pointer(pi, "/notches/" + std::to_string(n));
            if (notch.segment < 0 || notch.segment >= static_cast<int>(panel.outline.size())) {
                issues.push_back({w + "/segment", "no such outline segment"});
            } else if (!(notch.t >= 0 && notch.t <= 1)) {
                issues.push_back({w + "/t", "must be within [0, 1]"});
            }
        }
        for (std::size_t k = 0; k < panel.pins.size(); ++k) {
            const Pin& pin = panel.pins[k];
            const std::string w = pointer(pi, "/pins/" + std::to_string(k));
            if (pin.notch >= static_cast<int>(panel.notches.size())) {
                issues.push_back({w + "/notch", "no such notch on panel \"" + panel.name + "\""});
            } else if (pin.notch < 0 && !insidePanel(panel, pin.point)) {
                char at[96];
                std::snprintf(at, sizeof at, "(%.6g, %.6g) mm", pin.point.x() * 1e3,
                              pin.point.y() * 1e3);
                issues.push_back({w + "/at", std::string("pin point ") + at +
                                                 " is not inside panel \"" + panel.name + "\""});
            }
            if (pin.position && !(pin.position->cwiseAbs().maxCoeff() <= MAX_PIN_POSITION)) {
                issues.push_back({w + "/position_mm",
                                  "must be finite and within 10 m of the body's origin "
                                  "(positions are millimetres)"});
            }
            if (!(pin.releaseTime >= 0)) {
                issues.push_back({w + "/release_s", "must be a time of at least 0"});
            }
        }
        if (!std::isfinite(panel.grainAngle)) {
            issues.push_back({pointer(pi, "/grain_deg"), "must be finite"});
        }
        if (!(panel.particleDistance == 0 ||
              (panel.particleDistance >= MIN_PANEL_PARTICLE_DISTANCE &&
               panel.particleDistance <= MAX_PANEL_PARTICLE_DISTANCE))) {
            issues.push_back({pointer(pi, "/particle_distance_mm"),
                              "must be 0 (the drape's) or between 1 and 1000 mm"});
        }
    }
    for (std::size_t s = 0; s < garment.seams.size(); ++s) {
        const Seam& seam = garment.seams[s];
        for (int side = 0; side < 2; ++side) {
            const auto& edges = side == 0 ? seam.a : seam.b;
            const std::string ws = "/seams/" + std::to_string(s) + (side == 0 ? "/a" : "/b");
            if (edges.empty()) {
                issues.push_back({ws, "seam side has no edges"});
            }
            for (std::size_t e = 0; e < edges.size(); ++e) {
                const SeamEdge& edge = edges[e];
                const std::string w = ws + "/" + std::to_string(e);
                const int pi = garment.panelIndex(edge.panel);
                if (pi < 0) {
                    issues.push_back(
                        {w + "/panel", "seam names missing panel \"" + edge.panel + "\""});
                    continue;
                }
                const Panel& panel = garment.panels[static_cast<std::size_t>(pi)];
                if (edge.segment < 0 || edge.segment >= static_cast<int>(panel.outline.size())) {
                    issues.push_back({w + "/segment", "panel \"" + edge.panel +
                                                          "\" has no segment " +
                                                          std::to_string(edge.segment)});
                    continue;
                }
                if (!(edge.t0 >= 0 && edge.t0 <= 1)) {
                    issues.push_back({w + "/t0", "must be within [0, 1]"});
                } else if (!(edge.t1 >= 0 && edge.t1 <= 1)) {
                    issues.push_back({w + "/t1", "must be within [0, 1]"});
                } else if (std::abs(edge.t1 - edge.t0) < 1e-6) {
                    issues.push_back({w, "seam range is empty (t0 = t1)"});
                }
            }
        }
    }
    if (!(garment.easeTolerance >= 0)) {
        issues.push_back({"/ease_tolerance_mm", "must be zero or positive"});
    }
    if (issues.empty()) {
        checkSewnRanges(garment, issues);
    }
    return issues;
}

double minTriangleAngleDeg(const sim::MatX2& points, const sim::MatX3i& triangles) {
    double worst = 180;
    for (int t = 0; t < triangles.rows(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const Vec2 a = points.row(triangles(t, k)).transpose();
            const Vec2 b = points.row(triangles(t, (k + 1) % 3)).transpose();
            const Vec2 c = points.row(triangles(t, (k + 2) % 3)).transpose();
            const Vec2 u = b - a, v = c - a;
            const double angle = std::atan2(std::abs(sim::cross2d(u, v)), u.dot(v));
            worst = std::min(worst, angle * 180.0 / M_PI);
        }
    }
    return worst;
}

namespace {

/// Seams and darts as pairs of side ranges, matched by arc-length fraction.
struct SeamSides {
    int seam; // index, or −1 − panel for a dart
    std::string name;
    std::vector<SideRange> a, b;
};

/// Two boundary points to be sewn, resolved to vertices once the panels are meshed.
struct PendingPair {
    SeamSidePoint a, b;
    int seam;
};

/// Per panel: the vertex at each (loop, segment, parameter) of its boundary.
using BoundaryVertices = std::map<std::tuple<int, int, double>, int>;

/// Loop `loop` of panel p: 0 the outline, 1 + i hole i.
const Loop& loopOf(const Garment& garment, std::size_t p, int loop) {
    const Panel& panel = garment.panels[p];
    return loop == 0 ? panel.outline : panel.holes[static_cast<std::size_t>(loop - 1)];
}

/// Per panel: every segment of every loop starts at a fixed point (t = 0); notches are fixed
/// points too.
std::vector<PanelPoints> initialPoints(const Garment& garment) {
    const std::size_t panelCount = garment.panels.size();
    std::vector<PanelPoints> points(panelCount);
    for (std::size_t p = 0; p < panelCount; ++p) {
        const Panel& panel = garment.panels[p];
        const std::size_t loops = 1 + panel.holes.size();
        points[p].fixed.resize(loops);
        points[p].covered.resize(loops);
        for (std::size_t l = 0; l < loops; ++l) {
            const Loop& loop = loopOf(garment, p, static_cast<int>(l));
            points[p].fixed[l].resize(loop.size());
            points[p].covered[l].resize(loop.size());
            for (auto& ts : points[p].fixed[l]) {
                ts.insert(0.0);
            }
        }
        for (const Notch& n : panel.notches) {
            const BoundaryKey k = normalise(panel.outline, 0, n.segment, n.t);
            insertSnapped(points[p].fixed[0][static_cast<std::size_t>(k.segment)], k.t);
        }
    }
    return points;
}

/// The garment's seams, then every panel's darts (each dart's two legs), as pairs of sides.
std::vector<SeamSides> sewingSides(const Garment& garment) {
    std::vector<SeamSides> sewing;
    for (std::size_t s = 0; s < garment.seams.size(); ++s) {
        SeamSides ss{static_cast<int>(s), garment.seams[s].name, {}, {}};
        for (const SeamEdge& e : garment.seams[s].a) {
            ss.a.push_back({garment.panelIndex(e.panel), e.segment, e.t0, e.t1});
        }
        for (const SeamEdge& e : garment.seams[s].b) {
            ss.b.push_back({garment.panelIndex(e.panel), e.segment, e.t0, e.t1});
        }
        sewing.push_back(std::move(ss));
    }
    for (std::size_t p = 0; p < garment.panels.size(); ++p) {
        for (const Dart& d : garment.panels[p].darts) {
            const int pi = static_cast<int>(p);
            sewing.push_back(
                {-1 - pi,
                 "dart " + std::to_string(d.leg) + " of \"" + garment.panels[p].name + "\"",
                 {{pi, d.leg, 1.0, 0.0}},
                 {{pi, d.leg + 1, 0.0, 1.0}}});
        }
    }
    return sewing;
}

/// One side of a seam with the length of each of its ranges and their total [m].
struct MeasuredSide {
    const std::vector<SideRange>& ranges;
    std::vector<double> lengths;
    double total = 0;
};

MeasuredSide measure(const Garment& garment, const std::vector<SideRange>& ranges) {
    MeasuredSide side{ranges, {}, 0};
    for (const SideRange& r : ranges) {
        side.lengths.push_back(rangeLength(garment, r));
        side.total += side.lengths.back();
    }
    return side;
}

/// Maps a fraction of a side to its boundary points (two at a junction of edges).
std::vector<SeamSidePoint> locate(const Garment& garment, const MeasuredSide& measured, double f) {
    const std::vector<SideRange>& side = measured.ranges;
    const std::vector<double>& lens = measured.lengths;
    const double total = measured.total;
    std::vector<SeamSidePoint> pts;
    const double s = f * total;
    double cum = 0;
    for (std::size_t i = 0; i < side.size(); ++i) {
        const SideRange& r = side[i];
        const Loop& loop = garment.panels[static_cast<std::size_t>(r.panel)].outline;
        const double lo = cum, hi = cum + lens[i];
        const bool first = i == 0, last = i + 1 == side.size();
        if (s >= lo - 1e-12 * total - (first ? 1e-9 : 0) &&
            s <= hi + 1e-12 * total + (last ? 1e-9 : 0)) {
            double t;
            if (std::abs(s - lo) <= 1e-12 * std::max(1.0, total)) {
                t = r.t0;
            } else if (std::abs(s - hi) <= 1e-12 * std::max(1.0, total)) {
                t = r.t1;
            } else {
                t = parameterAtLength(loop[static_cast<std::size_t>(r.segment)], r.t0, r.t1,
                                      s - lo);
            }
            pts.push_back({r.panel, normalise(loop, 0, r.segment, t)});
        }
        cum = hi;
    }
    return pts;
}

/// The fractions where both sides break into edges: 0, 1 and every junction of ranges on
/// either side.
std::vector<double> breakFractions(const MeasuredSide& a, const MeasuredSide& b) {
    std::vector<double> breaks = {0.0, 1.0};
    double acc = 0;
    for (std::size_t i = 0; i + 1 < a.lengths.size(); ++i) {
        acc += a.lengths[i];
        breaks.push_back(acc / a.total);
    }
    acc = 0;
    for (std::size_t i = 0; i + 1 < b.lengths.size(); ++i) {
        acc += b.lengths[i];
        breaks.push_back(acc / b.total);
    }
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end(),
                             [](double x, double y) { return std::abs(x - y) < 1e-9; }),
                 breaks.end());
    return breaks;
}

/// Whether n equal pieces of [f0, f1] keep every piece's chord within the sagitta on both sides.
bool chordsFine(const Garment& garment, const MeasuredSide& a, const MeasuredSide& b, double f0,
                double f1, int n, double sagitta) {
    bool fine = true;
    for (int i = 0; i < n && fine; ++i) {
        const double fa = f0 + (f1 - f0) * i / n, fb = f0 + (f1 - f0) * (i + 1) / n;
        for (int side = 0; side < 2 && fine; ++side) {
            const MeasuredSide& rs = side == 0 ? a : b;
            const auto pa = locate(garment, rs, 0.5 * (fa + fb));
            const auto p0 = locate(garment, rs, fa);
            const auto p1 = locate(garment, rs, fb);
            if (pa.empty() || p0.empty() || p1.empty()) {
                continue;
            }
            auto pos = [&](const SeamSidePoint& q) {
                const Panel& panel = garment.panels[static_cast<std::size_t>(q.panel)];
                return pointAt(panel.outline[static_cast<std::size_t>(q.key.segment)], q.key.t);
            };
            const Vec2 pA = pos(p0.back()), pB = pos(p1.front()), m = pos(pa.front());
            const Vec2 ab = pB - pA;
            const double len = ab.norm();
            if (len > 0 && std::abs(sim::cross2d(ab, m - pA)) / len > sagitta) {
                fine = false;
            }
        }
    }
    return fine;
}

/// The fractions of a seam where both sides get a point: between consecutive breaks, pieces of
/// about h, finer where either side bends (every piece's chord within the sagitta), and 1.
std::vector<double> seamFractions(const Garment& garment, const MeasuredSide& a,
                                  const MeasuredSide& b, double h, double sagitta) {
    const std::vector<double> breaks = breakFractions(a, b);
    std::vector<double> fractions;
    for (std::size_t j = 0; j + 1 < breaks.size(); ++j) {
        const double f0 = breaks[j], f1 = breaks[j + 1];
        int n =
            std::max(1, static_cast<int>(std::lround(std::max(a.total, b.total) * (f1 - f0) / h)));
        // Finer where either side bends: every piece's chord within the sagitta.
        for (int attempt = 0; attempt < 6; ++attempt) {
            if (chordsFine(garment, a, b, f0, f1, n, sagitta)) {
                break;
            }
            n *= 2;
        }
        for (int i = 0; i < n; ++i) {
            fractions.push_back(f0 + (f1 - f0) * i / n);
        }
    }
    fractions.push_back(1.0);
    return fractions;
}

/// Places one seam's (or dart's) points on both sides at the same fractions, fixing them on the
/// panels' boundaries and pairing them; the ranges it covers get no other points. Warns when
/// the sides' lengths differ by more than the ease tolerance.
void placeSeam(const Garment& garment, const SeamSides& ss, double h, double sagitta,
               std::vector<PanelPoints>& points, std::vector<PendingPair>& pending,
               std::vector<std::string>& warnings) {
    const MeasuredSide a = measure(garment, ss.a);
    const MeasuredSide b = measure(garment, ss.b);
    if (std::abs(a.total - b.total) > garment.easeTolerance) {
        std::ostringstream w;
        w.precision(4);
        w << "seam \"" << ss.name << "\": lengths " << a.total << " m and " << b.total
          << " m differ by more than " << garment.easeTolerance << " m";
        warnings.push_back(w.str());
    }
    for (double f : seamFractions(garment, a, b, h, sagitta)) {
        const auto pa = locate(garment, a, f);
        const auto pb = locate(garment, b, f);
        for (const auto& q : pa) {
            insertSnapped(points[static_cast<std::size_t>(q.panel)]
                              .fixed[0][static_cast<std::size_t>(q.key.segment)],
                          q.key.t);
        }
        for (const auto& q : pb) {
            insertSnapped(points[static_cast<std::size_t>(q.panel)]
                              .fixed[0][static_cast<std::size_t>(q.key.segment)],
                          q.key.t);
        }
        for (const auto& qa : pa) {
            for (const auto& qb : pb) {
                pending.push_back({qa, qb, ss.seam});
            }
        }
    }
    for (int side = 0; side < 2; ++side) {
        for (const SideRange& r : side == 0 ? ss.a : ss.b) {
            points[static_cast<std::size_t>(r.panel)]
                .covered[0][static_cast<std::size_t>(r.segment)]
                .emplace_back(std::min(r.t0, r.t1), std::max(r.t0, r.t1));
        }
    }
}

/// Appends to `in` the points of segment s of loop l between its fixed parameters ta < tb:
/// pieces of about h, finer where the curve bends (each chord within the sagitta); none inside
/// a range a seam covers (the seam placed those).
void subdivideSegment(const Segment& seg, const PanelPoints& points, std::size_t l, std::size_t s,
                      double ta, double tb, double h, double sagitta, TriangulationInput& in) {
    bool covered = false;
    for (const auto& [c0, c1] : points.covered[l][s]) {
        covered = covered || (ta >= c0 - T_EPS && tb <= c1 + T_EPS);
    }
    if (covered || tb - ta < T_EPS) {
        return;
    }
    int n = std::max(1, static_cast<int>(std::lround(arcLength(seg, ta, tb) / h)));
    std::vector<double> sub = equalLengthParameters(seg, ta, tb, n);
    for (int attempt = 0; attempt < 6; ++attempt) {
        bool fine = true;
        for (std::size_t i = 0; i + 1 < sub.size() && fine; ++i) {
            fine = chordDeviation(seg, sub[i], sub[i + 1]) <= sagitta;
        }
        if (fine) {
            break;
        }
        n *= 2;
        sub = equalLengthParameters(seg, ta, tb, n);
    }
    for (std::size_t i = 1; i + 1 < sub.size(); ++i) {
        in.points.push_back(pointAt(seg, sub[i]));
    }
}

/// A point just inside the hole whose boundary polygon is `poly`, beside one of its edges.
void addHoleSeed(const std::vector<Vec2>& poly, TriangulationInput& in) {
    for (std::size_t e = 0; e < poly.size(); ++e) {
        const Vec2& a = poly[e];
        const Vec2& b = poly[(e + 1) % poly.size()];
        const Vec2 normal = Vec2(-(b - a).y(), (b - a).x()) * 0.05;
        const Vec2 m = 0.5 * (a + b);
        if (insidePolygon(poly, m + normal)) {
            in.holeSeeds.push_back(m + normal);
            break;
        }
        if (insidePolygon(poly, m - normal)) {
            in.holeSeeds.push_back(m - normal);
            break;
        }
    }
}

/// Appends panel p's boundary to `in`: each loop's fixed points (recorded in vertexOf) and the
/// points between them, as a closed chain of constraints; a seed inside each hole.
void addBoundary(const Garment& garment, std::size_t p, const PanelPoints& points, double h,
                 double sagitta, TriangulationInput& in, BoundaryVertices& vertexOf) {
    const auto& fixed = points.fixed;
    for (std::size_t l = 0; l < fixed.size(); ++l) {
        const Loop& loop = loopOf(garment, p, static_cast<int>(l));
        const int first = static_cast<int>(in.points.size());
        for (std::size_t s = 0; s < loop.size(); ++s) {
            const Segment& seg = loop[s];
            std::vector<double> ts(fixed[l][s].begin(), fixed[l][s].end());
            ts.push_back(1.0);
            for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
                const double ta = ts[k], tb = ts[k + 1];
                vertexOf[{static_cast<int>(l), static_cast<int>(s), ta}] =
                    static_cast<int>(in.points.size());
                in.points.push_back(pointAt(seg, ta));
                subdivideSegment(seg, points, l, s, ta, tb, h, sagitta, in);
            }
        }
        const int last = static_cast<int>(in.points.size());
        for (int i = first; i < last; ++i) {
            in.constraints.push_back({i, i + 1 < last ? i + 1 : first});
        }
        if (l > 0) {
            const std::vector<Vec2> poly(in.points.begin() + first, in.points.begin() + last);
            addHoleSeed(poly, in);
        }
    }
}

/// Appends the panel's internal lines to `in` as chains of constrained points about h apart;
/// returns, per line edge, its constraint and the line's fold angle.
std::vector<std::pair<int, double>> addInternalLines(const Panel& panel, double h,
                                                     TriangulationInput& in) {
    std::vector<std::pair<int, double>> lineEdges;
    for (const InternalLine& line : panel.internalLines) {
        int previous = -1;
        for (const Segment& seg : line.path) {
            const int n = std::max(1, static_cast<int>(std::lround(arcLength(seg) / h)));
            const std::vector<double> sub = equalLengthParameters(seg, 0.0, 1.0, n);
            for (std::size_t i = 0; i < sub.size(); ++i) {
                const Vec2 q = pointAt(seg, sub[i]);
                if (previous >= 0 &&
                    (in.points[static_cast<std::size_t>(previous)] - q).norm() < 1e-12) {
                    continue;
                }
                const int id = static_cast<int>(in.points.size());
                in.points.push_back(q);
                if (previous >= 0) {
                    in.constraints.push_back({previous, id});
                    lineEdges.emplace_back(static_cast<int>(in.constraints.size()) - 1,
                                           line.foldAngle);
                }
                previous = id;
            }
        }
    }
    return lineEdges;
}

/// Rest shape: the pattern mirrored for a Back panel, rotated so that the grain is +y.
void setRestShape(const Panel& panel, PanelMesh& pm) {
    const int nv = static_cast<int>(pm.pattern.rows());
    const bool mirror = panel.side == PanelSide::Back;
    const double grain = mirror ? M_PI - panel.grainAngle : panel.grainAngle;
    const double turn = M_PI / 2 - grain;
    const double c = std::cos(turn), s = std::sin(turn);
    pm.rest.resize(nv, 2);
    for (int i = 0; i < nv; ++i) {
        const double x = mirror ? -pm.pattern(i, 0) : pm.pattern(i, 0);
        const double y = pm.pattern(i, 1);
        pm.rest.row(i) << c * x - s * y, s * x + c * y;
    }
    if (mirror) {
        pm.triangles.col(1).swap(pm.triangles.col(2));
    }
}

/// Triangulates panel p with its boundary points and internal lines into `pm`; adds its
/// smallest angle and triangle count to `out`. Returns what went wrong, naming the panel.
std::optional<std::string> meshPanel(const Garment& garment, std::size_t p,
                                     const PanelPoints& points, const MeshOptions& options,
                                     double h, double sagitta, BoundaryVertices& vertexOf,
                                     GarmentMesh& out) {
    const Panel& panel = garment.panels[p];
    TriangulationInput in;
    in.maxEdge = 1.45 * h; // the size bound is on the longest edge: mean edges come out ≈ h
    in.minAngleDeg = options.minAngleDeg;
    addBoundary(garment, p, points, h, sagitta, in, vertexOf);
    PanelMesh& pm = out.panels[p];
    const std::vector<std::pair<int, double>> lineEdges = addInternalLines(panel, h, in);
    TriangulationOutput tri;
    const long computedBefore = options.cache ? options.cache->computed() : 0;
    auto err = options.cache ? options.cache->triangulate(in, tri) : triangulate(in, tri);
    out.panelsTriangulated +=
        options.cache ? static_cast<int>(options.cache->computed() - computedBefore) : 1;
    if (err) {
        return "panel \"" + panel.name + "\": " + *err;
    }
    const int nv = static_cast<int>(tri.points.size());
    pm.pattern.resize(nv, 2);
    for (int i = 0; i < nv; ++i) {
        pm.pattern.row(i) = tri.points[static_cast<std::size_t>(i)].transpose();
    }
    pm.triangles = tri.triangles;
    for (const auto& [constraint, fold] : lineEdges) {
        pm.lineEdges.push_back(in.constraints[static_cast<std::size_t>(constraint)]);
        pm.lineFoldAngles.push_back(fold);
    }
    for (const Notch& n : panel.notches) {
        const BoundaryKey k = normalise(panel.outline, 0, n.segment, n.t);
        const double t = snap(points.fixed[0][static_cast<std::size_t>(k.segment)], k.t);
        pm.notchVertices.push_back(vertexOf.at({0, k.segment, t}));
    }
    setRestShape(panel, pm);
    out.minAngleDeg = std::min(out.minAngleDeg, minTriangleAngleDeg(pm.pattern, tri.triangles));
    out.triangleCount += pm.triangles.rows();
    return std::nullopt;
}

/// The seam pairs resolved to vertices, each pair once (a dart's tip, sewn to itself, is not a
/// pair).
void resolveSeamPairs(const std::vector<PendingPair>& pending,
                      const std::vector<PanelPoints>& points,
                      const std::vector<BoundaryVertices>& vertexOf, GarmentMesh& out) {
    std::set<std::tuple<int, int, int, int>> seen;
    for (const PendingPair& pp : pending) {
        auto vertex = [&](const SeamSidePoint& q) {
            const auto& ts = points[static_cast<std::size_t>(q.panel)]
                                 .fixed[0][static_cast<std::size_t>(q.key.segment)];
            return vertexOf[static_cast<std::size_t>(q.panel)].at(
                {0, q.key.segment, snap(ts, q.key.t)});
        };
        const VertexRef a{pp.a.panel, vertex(pp.a)};
        const VertexRef b{pp.b.panel, vertex(pp.b)};
        if (a == b) {
            continue; // a dart's tip
        }
        const auto key =
            std::make_tuple(std::min(a.panel, b.panel) == a.panel ? a.panel : b.panel,
                            std::min(a.panel, b.panel) == a.panel ? a.vertex : b.vertex,
                            std::min(a.panel, b.panel) == a.panel ? b.panel : a.panel,
                            std::min(a.panel, b.panel) == a.panel ? b.vertex : a.vertex);
        if (!seen.insert(key).second) {
            continue;
        }
        out.seamPairs.push_back({a, b});
        out.seamOfPair.push_back(pp.seam);
    }
}

} // namespace

std::optional<std::string> meshGarment(const Garment& garment, const MeshOptions& options,
                                       GarmentMesh& out) {
    const auto start = std::chrono::steady_clock::now();
    out = {};
    if (const auto issues = validateGarment(garment); !issues.empty()) {
        return issues.front().where + ": " + issues.front().message;
    }
    if (!(options.particleDistance > 0)) {
        return std::string("particle distance must be positive");
    }
    const std::size_t panelCount = garment.panels.size();
    std::vector<double> hOf(panelCount);
    for (std::size_t p = 0; p < panelCount; ++p) {
        hOf[p] = panelParticleDistance(garment.panels[p], options.particleDistance);
    }
    // Chord error allowed on curves (area within ~0.2%).
    const auto sagittaOf = [](double h) { return 0.05 * h; };

    // Seams and darts first: their points, matched by arc-length fraction, are fixed on both
    // sides before the panels are meshed, at the finest distance of the panels they join.
    std::vector<PanelPoints> points = initialPoints(garment);
    std::vector<PendingPair> pending;
    for (const SeamSides& ss : sewingSides(garment)) {
        double h = INFINITY;
        for (const auto* side : {&ss.a, &ss.b}) {
            for (const SideRange& r : *side) {
                h = std::min(h, hOf[static_cast<std::size_t>(r.panel)]);
            }
        }
        placeSeam(garment, ss, h, sagittaOf(h), points, pending, out.warnings);
    }

    // Boundary polygons, triangulation, panel meshes.
    std::vector<BoundaryVertices> vertexOf(panelCount);
    out.panels.resize(panelCount);
    out.minAngleDeg = 180;
    for (std::size_t p = 0; p < panelCount; ++p) {
        if (auto err = meshPanel(garment, p, points[p], options, hOf[p], sagittaOf(hOf[p]),
                                 vertexOf[p], out)) {
            return err;
        }
    }
    resolveSeamPairs(pending, points, vertexOf, out);
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return std::nullopt;
}

double panelParticleDistance(const Panel& panel, double particleDistance) {
    return panel.particleDistance > 0 ? panel.particleDistance : particleDistance;
}

MeshEstimate estimateGarmentMesh(const Garment& garment, double particleDistance) {
    const auto count = [](double n) {
        const double most = static_cast<double>(std::numeric_limits<long>::max() / 2);
        return std::isfinite(n) && n >= 0 && n < most ? static_cast<long>(std::llround(n))
                                                      : static_cast<long>(most);
    };
    double vertices = 0;
    double triangles = 0;
    for (const Panel& panel : garment.panels) {
        const double h = panelParticleDistance(panel, particleDistance);
        if (!(h > 0) || !std::isfinite(h)) {
            return {count(-1), count(-1)};
        }
        double area = std::abs(loopArea(panel.outline));
        for (const Loop& hole : panel.holes) {
            area -= std::abs(loopArea(hole));
        }
        double length = 0;
        for (const Segment& s : panel.outline) {
            length += arcLength(s);
        }
        const double perVertex = std::sqrt(3.0) / 2 * h * h; // area per interior vertex [m²]
        vertices += area / perVertex + length / h;
        triangles += 2 * area / perVertex;
    }
    if (!(particleDistance > 0) || !std::isfinite(particleDistance)) {
        return {count(-1), count(-1)};
    }
    return {count(vertices), count(triangles)};
}

} // namespace atelier::patterns
