#include "io/dxf_aama.h"

#include "io/atomic_file.h"
#include "io/dxf_reader.h"
#include "io/materials.h"

#include "patterns/curve.h"
#include "patterns/curve_fit.h"
#include "patterns/mesh.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <utility>

namespace atelier::io {

namespace {

using patterns::Loop;
using patterns::Segment;
using patterns::SegmentKind;
using patterns::Vec2;

/// A notch or turn point this close to the cut line is on it [m].
constexpr double ON_LINE = 0.001;
/// Two digitised points closer than this are one [m].
constexpr double SAME_POINT = 1e-7;
/// Most points of one piece's cut line, and of its internal lines and cut-outs together (the
/// inside tests compare every pair), and most notches of a piece.
constexpr std::size_t MAX_CUT_POINTS = 20'000;
constexpr std::size_t MAX_INNER_POINTS = 20'000;
constexpr std::size_t MAX_NOTCHES = 2'000;
/// Without turn points, a cut-line vertex where the direction turns by more than this is a
/// corner [rad] (30°).
constexpr double CORNER_TURN = 0.5235987755982988;

struct ParseError {
    int line;
    std::string message;
};

// ---- Geometry ----

double signedArea(const std::vector<Vec2>& p) {
    double a = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        a += sim::cross2d(p[i], p[(i + 1) % p.size()]);
    }
    return 0.5 * a;
}

/// A piece's digitised polyline in metres, repeated points removed, closed or open.
struct Chain {
    std::vector<Vec2> points;
    std::vector<double> bulges;
    bool closed = false;
};

Chain chainOf(const DxfShape& s, double scale) {
    Chain c;
    c.closed = s.closed;
    for (std::size_t i = 0; i < s.points.size(); ++i) {
        const Vec2 p = s.points[i] * scale;
        if (!c.points.empty() && (p - c.points.back()).norm() < SAME_POINT) {
            continue;
        }
        c.points.push_back(p);
        c.bulges.push_back(s.bulges[i]);
    }
    if (c.points.size() > 2 && (c.points.front() - c.points.back()).norm() < SAME_POINT) {
        c.points.pop_back();
        c.bulges.pop_back();
        c.closed = true;
    }
    return c;
}

double chainLength(const Chain& c) {
    double length = 0;
    const std::size_t spans = c.closed ? c.points.size() : c.points.size() - 1;
    for (std::size_t i = 0; i < spans; ++i) {
        Segment s;
        s.start = c.points[i];
        s.end = c.points[(i + 1) % c.points.size()];
        s.kind = c.bulges[i] != 0 ? SegmentKind::Arc : SegmentKind::Line;
        s.bulge = c.bulges[i];
        length += patterns::arcLength(s);
    }
    return length;
}

/// The cut line as an outline: corners at turn points (or, without any, where the line turns
/// by more than 30°), arcs where the file has bulges, fitted curves between.
Loop outlineOf(const Chain& cut, const std::vector<Vec2>& turnPoints, double tol, int& corners,
               double& error) {
    const std::size_t n = cut.points.size();
    std::vector<char> corner(n, 0);
    if (!turnPoints.empty()) {
        for (const Vec2& tp : turnPoints) {
            std::size_t best = 0;
            double bd = std::numeric_limits<double>::infinity();
            for (std::size_t i = 0; i < n; ++i) {
                const double d = (cut.points[i] - tp).norm();
                if (d < bd) {
                    bd = d;
                    best = i;
                }
            }
            if (bd <= ON_LINE) {
                corner[best] = 1;
            }
        }
    } else {
        for (std::size_t i = 0; i < n; ++i) {
            const Vec2 in = cut.points[i] - cut.points[(i + n - 1) % n];
            const Vec2 out = cut.points[(i + 1) % n] - cut.points[i];
            const double turn = std::atan2(std::abs(sim::cross2d(in, out)), in.dot(out));
            if (turn > CORNER_TURN) {
                corner[i] = 1;
            }
        }
    }
    // Spans with a bulge are arcs; their ends are breaks of the fitted runs (not corners).
    std::vector<char> brk(corner);
    for (std::size_t i = 0; i < n; ++i) {
        if (cut.bulges[i] != 0) {
            brk[i] = 1;
            brk[(i + 1) % n] = 1;
        }
    }
    corners = static_cast<int>(std::count(corner.begin(), corner.end(), 1));
    // Start the loop at a break (or anywhere on a smooth closed line: then two runs).
    std::size_t start = 0;
    while (start < n && !brk[start]) {
        ++start;
    }
    if (start == n) {
        start = 0;
        brk[0] = 1;
        brk[n / 2] = 1;
    }
    std::vector<Vec2> p;
    std::vector<double> bulge;
    std::vector<char> isBreak;
    for (std::size_t k = 0; k <= n; ++k) {
        const std::size_t i = (start + k) % n;
        p.push_back(cut.points[i]);
        bulge.push_back(cut.bulges[i]);
        isBreak.push_back(brk[i]);
    }
    Loop loop;
    std::size_t runStart = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (bulge[i] != 0) {
            Segment s;
            s.kind = SegmentKind::Arc;
            s.start = p[i];
            s.end = p[i + 1];
            s.bulge = std::clamp(bulge[i], -1e3, 1e3);
            loop.push_back(s);
            runStart = i + 1;
            continue;
        }
        if (isBreak[i + 1] || i + 1 == n) {
            patterns::fitPolyline(p, runStart, i + 1, tol, loop, error);
            runStart = i + 1;
        }
    }
    return loop;
}

/// Straight spans of an open or closed polyline as segments (internal lines, holes).
Loop spansOf(const Chain& c) {
    Loop out;
    const std::size_t spans = c.closed ? c.points.size() : c.points.size() - 1;
    for (std::size_t i = 0; i < spans; ++i) {
        Segment s;
        s.start = c.points[i];
        s.end = c.points[(i + 1) % c.points.size()];
        if (c.bulges[i] != 0) {
            s.kind = SegmentKind::Arc;
            s.bulge = std::clamp(c.bulges[i], -1e3, 1e3);
        }
        out.push_back(s);
    }
    return out;
}

std::string lower(std::string_view s) {
    std::string out(s);
    std::transform(out.begin(), out.end(), out.begin(),
                   [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
    return out;
}

/// `Key: value` lines of system text, keys lower case.
std::map<std::string, std::string> systemText(const std::vector<std::string>& texts) {
    std::map<std::string, std::string> out;
    for (const std::string& text : texts) {
        std::size_t from = 0;
        while (from <= text.size()) {
            const std::size_t nl = std::min(text.find('\n', from), text.size());
            const std::string_view line = std::string_view(text).substr(from, nl - from);
            const std::size_t colon = line.find(':');
            if (colon != std::string_view::npos) {
                const std::string key = lower(dxfTrimmed(line.substr(0, colon)));
                const std::string value(dxfTrimmed(line.substr(colon + 1)));
                if (!key.empty() && !out.contains(key)) {
                    out[key] = value;
                }
            }
            from = nl + 1;
        }
    }
    return out;
}

struct Units {
    double scale = 0.001;
    std::string name;
};

Units unitsOf(const DxfDrawing& raw, const DxfImportOptions& options,
              std::vector<std::string>& warnings) {
    static const std::map<std::string, double, std::less<>> named = {
        {"mm", 0.001}, {"cm", 0.01}, {"m", 1.0}, {"in", 0.0254}};
    if (options.units != "auto") {
        const auto it = named.find(options.units);
        if (it == named.end()) {
            throw ParseError{0, "unknown units " + dxfShown(options.units) +
                                    " (mm, cm, m, in or auto)"};
        }
        return {it->second, options.units + " (as asked)"};
    }
    const auto style = systemText(raw.styleTexts);
    if (const auto u = style.find("units"); u != style.end()) {
        const std::string v = lower(u->second);
        if (v.find("metric") != std::string::npos) {
            return {0.001, "mm (Units: METRIC)"};
        }
        if (v.find("english") != std::string::npos) {
            return {0.0254, "in (Units: ENGLISH)"};
        }
        warnings.push_back("style text Units: " + dxfShown(u->second) +
                           " is neither METRIC nor ENGLISH");
    }
    switch (raw.insUnits) {
    case 1:
        return {0.0254, "in ($INSUNITS 1)"};
    case 4:
        return {0.001, "mm ($INSUNITS 4)"};
    case 5:
        return {0.01, "cm ($INSUNITS 5)"};
    case 6:
        return {1.0, "m ($INSUNITS 6)"};
    default:
        break;
    }
    warnings.push_back("the file does not state its units (no Units: style text, no $INSUNITS): "
                       "read as millimetres; --units overrides");
    return {0.001, "mm (assumed)"};
}

/// What entities on an AAMA layer that is not imported are, and why it does not matter.
std::pair<std::string, std::string> layerWord(int layer) {
    switch (layer) {
    case 5:
        return {"grade reference lines (layer 5)", "one size is imported"};
    case 6:
        return {"mirror lines (layer 6)", "the piece is imported as drawn, not unfolded"};
    case 9:
        return {"stripe reference lines (layer 9)", ""};
    case 10:
        return {"plaid reference lines (layer 10)", ""};
    case 13:
        return {"drill holes (layer 13)", ""};
    case 14:
        return {"sew lines (layer 14)", "seams follow the cut line"};
    case 15:
        return {"annotation entities (layer 15)", ""};
    default:
        return {"entities on layer " + std::to_string(layer), ""};
    }
}

bool isNotchLayer(int layer) {
    return layer == 4 || (layer >= 80 && layer <= 83);
}

struct PieceResult {
    patterns::Panel panel;
    DxfPiece info;
};

/// Builds one piece from a block, step by step; warnings name the piece.
class AamaPieceBuilder {
  public:
    AamaPieceBuilder(const DxfBlock& block, double scale, std::vector<std::string>& warnings)
        : m_block(block), m_scale(scale), m_warnings(warnings) {}

    std::optional<PieceResult> build(const DxfImportOptions& options, const Limits& limits) {
        readText();
        checkReach(limits);
        if (!findCutLine() || !prepareCutLine()) {
            return std::nullopt;
        }
        std::vector<Vec2> turnPoints;
        std::vector<Vec2> notchPoints;
        readMarks(turnPoints, notchPoints);
        PieceResult& r = m_result;
        r.panel.outline =
            outlineOf(m_cut, turnPoints, options.fitTolerance, r.info.corners, r.info.fitError);
        if (!turnPoints.empty() && r.info.corners < static_cast<int>(turnPoints.size())) {
            warn(std::to_string(static_cast<int>(turnPoints.size()) - r.info.corners) +
                 " turn points (layer 2) are not on the cut line");
        }
        placeNotches(notchPoints);
        r.info.segments = static_cast<int>(r.panel.outline.size());
        r.info.outlineLength = 0;
        for (const Segment& s : r.panel.outline) {
            r.info.outlineLength += patterns::arcLength(s);
        }
        r.info.notches = static_cast<int>(r.panel.notches.size());
        r.info.internalLines = static_cast<int>(r.panel.internalLines.size());
        r.info.holes = static_cast<int>(r.panel.holes.size());
        if (r.info.quantity > 1) {
            warn("Quantity " + std::to_string(r.info.quantity) +
                 "; imported once (mirror or duplicate it in the window)");
        }
        return std::move(m_result);
    }

  private:
    void warn(const std::string& what) { m_warnings.push_back(m_who + ": " + what); }

    /// `Piece Name:` and `Quantity:` of the piece system text.
    void readText() {
        const auto text = systemText(m_block.texts);
        DxfPiece& info = m_result.info;
        info.block = m_block.name;
        info.line = m_block.line;
        if (const auto it = text.find("piece name"); it != text.end() && !it->second.empty()) {
            info.name = it->second.substr(0, 100);
        } else {
            info.name = m_block.name.empty() ? "piece" : m_block.name;
        }
        m_who = "piece " + dxfShown(info.name);
        if (const auto it = text.find("quantity"); it != text.end()) {
            const std::string& q = it->second;
            int v = 0;
            const auto [end, ec] = std::from_chars(q.data(), q.data() + q.size(), v);
            if (ec == std::errc() && v > 0 && v < 1000) {
                info.quantity = v;
            }
        }
    }

    /// Every point within the scene-coordinate limit, once in metres; the inside tests bounded.
    void checkReach(const Limits& limits) const {
        std::size_t innerPoints = 0;
        for (const DxfShape& s : m_block.shapes) {
            for (const Vec2& p : s.points) {
                if (std::abs(p.x() * m_scale) > limits.maxSceneCoordinate ||
                    std::abs(p.y() * m_scale) > limits.maxSceneCoordinate) {
                    throw ParseError{s.line, m_who + ": a point " +
                                                 std::to_string(p.norm() * m_scale) +
                                                 " m from the origin, beyond the limit "
                                                 "scene-coordinate-m (" +
                                                 std::to_string(limits.maxSceneCoordinate) + " m)"};
                }
            }
            if (s.layer == 8 || s.layer == 11) {
                innerPoints += s.points.size();
            }
        }
        if (innerPoints > MAX_INNER_POINTS) {
            throw ParseError{m_block.line, m_who + ": internal lines and cut-outs of " +
                                               std::to_string(innerPoints) + " points, more than " +
                                               std::to_string(MAX_INNER_POINTS)};
        }
    }

    /// The cut line: the longest closed (or nearly closed) polyline on layer 1.
    bool findCutLine() {
        double cutLength = 0;
        int cutLines = 0;
        for (const DxfShape& s : m_block.shapes) {
            if (s.layer != 1 || s.isPoint || s.points.size() < 3) {
                continue;
            }
            ++cutLines;
            const Chain c = chainOf(s, m_scale);
            if (c.points.size() < 3) {
                continue;
            }
            const double gap = (c.points.front() - c.points.back()).norm();
            const double length = chainLength(c);
            if ((c.closed || gap <= 0.005) && length > cutLength) {
                cutLength = length;
                m_cutShape = &s;
            }
        }
        if (m_cutShape == nullptr) {
            m_warnings.push_back("block " + dxfShown(m_block.name) + " (line " +
                                 std::to_string(m_block.line) +
                                 "): no closed cut line (layer 1); not a pattern piece, skipped");
            return false;
        }
        if (cutLines > 1) {
            warn(std::to_string(cutLines) +
                 " polylines on layer 1; the longest closed one is the cut line");
        }
        return true;
    }

    /// The cut line closed, counter-clockwise (as panels are) and centred on its box (the
    /// placement offset is the panel's origin on its slot).
    bool prepareCutLine() {
        m_cut = chainOf(*m_cutShape, m_scale);
        if (m_cut.points.size() > MAX_CUT_POINTS) {
            throw ParseError{m_cutShape->line,
                             m_who + ": a cut line of " + std::to_string(m_cut.points.size()) +
                                 " points, more than " + std::to_string(MAX_CUT_POINTS)};
        }
        if (!m_cut.closed) {
            warn("the cut line is open (its ends " +
                 std::to_string((m_cut.points.front() - m_cut.points.back()).norm() * 1000) +
                 " mm apart); closed with a straight edge");
            m_cut.closed = true;
        }
        const double area = signedArea(m_cut.points);
        if (std::abs(area) < 1e-8) {
            warn("the cut line encloses no area; skipped");
            return false;
        }
        if (area < 0) {
            std::reverse(m_cut.points.begin(), m_cut.points.end());
            std::vector<double> b(m_cut.bulges.size());
            for (std::size_t i = 0; i < b.size(); ++i) {
                // Span i of the reversed chain is span n-2-i of the original, run backwards.
                b[i] = -m_cut.bulges[(2 * b.size() - 2 - i) % b.size()];
            }
            m_cut.bulges = b;
        }
        Eigen::AlignedBox2d box;
        for (const Vec2& p : m_cut.points) {
            box.extend(p);
        }
        m_centre = box.center();
        for (Vec2& p : m_cut.points) {
            p -= m_centre;
        }
        m_result.info.cutPoints = static_cast<int>(m_cut.points.size());
        m_result.info.cutLength = chainLength(m_cut);
        return true;
    }

    /// A shape's chain in the piece's frame (metres, centred).
    Chain local(const DxfShape& s) const {
        Chain c = chainOf(s, m_scale);
        for (Vec2& p : c.points) {
            p -= m_centre;
        }
        return c;
    }

    bool insideCut(const Chain& c) const {
        return std::all_of(c.points.begin(), c.points.end(),
                           [&](const Vec2& p) { return patterns::insidePolygon(m_cut.points, p); });
    }

    /// Turn points, notches, the grain line, internal lines and cut-outs; other layers counted.
    void readMarks(std::vector<Vec2>& turnPoints, std::vector<Vec2>& notchPoints) {
        patterns::Panel& panel = m_result.panel;
        std::map<int, int> ignored;
        int grainLines = 0;
        for (const DxfShape& s : m_block.shapes) {
            if (&s == m_cutShape || s.layer == 1 || s.layer == 3) {
                continue; // the cut line and its curve points, the piece text's layer
            }
            if (s.layer == 2) {
                if (s.isPoint) {
                    turnPoints.push_back(s.points[0] * m_scale - m_centre);
                }
            } else if (isNotchLayer(s.layer)) {
                // The notch is at its end on the cut line (a LINE or a POINT).
                notchPoints.push_back(s.points.front() * m_scale - m_centre);
                if (s.points.size() > 1) {
                    notchPoints.push_back(s.points.back() * m_scale - m_centre);
                }
                if (notchPoints.size() > 2 * MAX_NOTCHES) {
                    throw ParseError{s.line, m_who + ": more than " + std::to_string(MAX_NOTCHES) +
                                                 " notches"};
                }
            } else if (s.layer == 7 && s.points.size() >= 2) {
                const Vec2 d = s.points.back() - s.points.front();
                if (d.norm() > 0 && grainLines++ == 0) {
                    panel.grainAngle = std::atan2(d.y(), d.x());
                    m_result.info.grainLine = true;
                }
            } else if (s.layer == 8 && !s.isPoint && s.points.size() >= 2) {
                Chain line = local(s);
                if (line.points.size() < 2) {
                    continue;
                }
                if (!insideCut(line)) {
                    warn("an internal line (layer 8, line " + std::to_string(s.line) +
                         ") leaves the cut line; not imported");
                    continue;
                }
                line.closed = false; // a closed mark becomes an open chain from its start
                panel.internalLines.push_back(patterns::InternalLine{spansOf(line), 0.0});
            } else if (s.layer == 11 && !s.isPoint && s.points.size() >= 3) {
                Chain hole = local(s);
                if (hole.points.size() < 3 || !insideCut(hole) ||
                    std::abs(signedArea(hole.points)) < 1e-8) {
                    warn("an internal cut-out (layer 11, line " + std::to_string(s.line) +
                         ") is not a closed loop inside the cut line; not imported");
                    continue;
                }
                hole.closed = true;
                panel.holes.push_back(spansOf(hole));
            } else {
                ++ignored[s.layer];
            }
        }
        if (grainLines > 1) {
            warn(std::to_string(grainLines) +
                 " grain lines (layer 7); the first gives the warp direction");
        }
        for (const auto& [layer, count] : ignored) {
            const auto [what, why] = layerWord(layer);
            warn(std::to_string(count) + " " + what + " not imported" +
                 (why.empty() ? "" : ": " + why));
        }
        if (!m_result.info.grainLine) {
            warn("no grain line (layer 7); the warp runs along +y");
        }
    }

    /// Of each notch's points, those on the outline; one notch per place (a LINE notch gives
    /// two candidate points, the one inside the piece dropped).
    void placeNotches(const std::vector<Vec2>& notchPoints) {
        patterns::Panel& panel = m_result.panel;
        for (const Vec2& q : notchPoints) {
            const patterns::NearestPoint n = patterns::nearestPoint(panel.outline, q);
            if (n.distance <= ON_LINE + m_result.info.fitError) {
                panel.notches.push_back(patterns::Notch{n.segment, std::clamp(n.t, 0.0, 1.0)});
            }
        }
        auto& notches = panel.notches;
        std::sort(notches.begin(), notches.end(), [](const auto& a, const auto& b) {
            return a.segment != b.segment ? a.segment < b.segment : a.t < b.t;
        });
        notches.erase(std::unique(notches.begin(), notches.end(),
                                  [](const auto& a, const auto& b) {
                                      return a.segment == b.segment && std::abs(a.t - b.t) < 1e-6;
                                  }),
                      notches.end());
    }

    const DxfBlock& m_block;
    double m_scale;
    std::vector<std::string>& m_warnings;
    std::string m_who;
    const DxfShape* m_cutShape = nullptr;
    Chain m_cut;
    Vec2 m_centre = Vec2::Zero();
    PieceResult m_result;
};

} // namespace

Result<DxfImport> parseDxfAama(std::string_view text, const std::string& file,
                               const DxfImportOptions& options, const Limits& limits) {
    try {
        auto drawing = readDxfDrawing(text, file);
        if (!drawing.ok()) {
            return drawing.error();
        }
        const DxfDrawing& raw = drawing.value();
        DxfImport out;
        const Units units = unitsOf(raw, options, out.warnings);
        out.units = units.name;
        if (!raw.otherLayers.empty()) {
            std::string names;
            for (const std::string& n : raw.otherLayers) {
                names += (names.empty() ? "" : ", ") + dxfShown(n);
            }
            out.warnings.push_back("entities on layers that are not AAMA layer numbers ignored: " +
                                   names);
        }
        if (!(options.fitTolerance > 0 && options.fitTolerance < 0.01)) {
            throw ParseError{0, "the fit tolerance must be above 0 and below 10 mm"};
        }
        const auto presets = builtinMaterialPresets();
        const auto preset = presets.find(options.fabric);
        if (preset == presets.end()) {
            throw ParseError{0, "unknown fabric preset " + dxfShown(options.fabric)};
        }
        patterns::Garment garment;
        garment.name = std::filesystem::path(file).stem().string();
        if (garment.name.empty()) {
            garment.name = "pattern";
        }
        garment.materials.push_back(patterns::GarmentMaterial{"fabric", preset->second});
        std::set<std::string> names;
        for (const DxfBlock& block : raw.blocks) {
            std::optional<PieceResult> piece =
                AamaPieceBuilder(block, units.scale, out.warnings).build(options, limits);
            if (!piece) {
                continue;
            }
            // Panel names are unique: a second "FRONT" becomes "FRONT 2".
            std::string name = piece->info.name;
            for (int k = 2; names.contains(name); ++k) {
                name = piece->info.name + " " + std::to_string(k);
            }
            names.insert(name);
            piece->info.name = name;
            piece->panel.name = name;
            piece->panel.material = "fabric";
            // No placement in the file: torso front and back in turn, to be arranged; pieces
            // on the same slot stand 5 cm further out each, so that none starts inside another.
            const bool front = garment.panels.size() % 2 == 0;
            piece->panel.placement.slot = front ? "torso_front" : "torso_back";
            piece->panel.side = front ? patterns::PanelSide::Front : patterns::PanelSide::Back;
            piece->panel.placement.clearance =
                0.03 + 0.05 * static_cast<double>(garment.panels.size() / 2);
            garment.panels.push_back(std::move(piece->panel));
            out.pieces.push_back(std::move(piece->info));
        }
        if (garment.panels.empty()) {
            throw ParseError{0, "no pattern piece: no block has a closed cut line on layer 1 "
                                "(is this a DXF-AAMA / ASTM D6673 file?)"};
        }
        if (const std::vector<patterns::GarmentIssue> issues = patterns::validateGarment(garment);
            !issues.empty()) {
            throw ParseError{0, "the imported pattern is not valid: " + issues.front().where +
                                    ": " + issues.front().message};
        }
        out.project.name = garment.name;
        out.project.garment = garment;
        out.project.document = patterns::fromGarment(garment);
        out.project.document.name = garment.name;
        // The samples' drape settings (assets/garments/*.atelier).
        out.project.drape.dt = 0.01;
        out.project.drape.sewingTime = 1.0;
        out.project.drape.seamWeldDistance = 0.0015;
        out.project.drape.timeLimit = 4;
        return out;
    } catch (const ParseError& e) {
        return Error{file, e.line > 0 ? "line " + std::to_string(e.line) : "", e.message};
    }
}

Result<DxfImport> importDxfAama(const std::filesystem::path& path, const DxfImportOptions& options,
                                const Limits& limits) {
    auto text = readFile(path, limits.maxMeshBytes);
    if (!text.ok()) {
        return text.error();
    }
    return parseDxfAama(text.value(), path.string(), options, limits);
}

} // namespace atelier::io
