// Version 2 of the `.atelier` project format: the garment document with its stable ids
// (patterns::GarmentDocument). Each corner of a contour is stored once, with the edge that
// leaves it; seams, darts and notches name panel and edge ids.
#include "io/project_json.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <regex>

namespace atelier::io::detail {

namespace {

using nlohmann::json;
using nlohmann::ordered_json;
using patterns::SegmentKind;
namespace doc = patterns::doc;

/// The largest id a file may hold, so that `next_id` (above every id) fits 32 bits.
constexpr long long MAX_ID = std::numeric_limits<std::uint32_t>::max() - 1LL;

/// Reads a document's panels and seams, checking ids and references as it goes: panels come
/// before seams, and a panel's outline before its darts and notches, so every reference is to
/// something already read.
class DocumentReader {
  public:
    explicit DocumentReader(patterns::GarmentDocument& document) : m_doc(document) {}

    void read(ObjectReader& root) {
        if (const auto next = root.optionalInteger("next_id")) {
            if (*next < 1 || *next > MAX_ID + 1) {
                root.fail("next_id", "must be an integer in [1, " + std::to_string(MAX_ID + 1) +
                                         "] (found " + std::to_string(*next) + ")");
            }
            m_nextId = static_cast<std::uint32_t>(*next);
        }
        forEachIn(root, "panels", [&](const json& v, const std::string& p) {
            m_doc.panels.push_back(readPanel(v, p));
        });
        forEachIn(root, "seams", [&](const json& v, const std::string& p) {
            m_doc.seams.push_back(readSeam(v, p));
        });
        m_doc.nextId =
            m_nextId ? *m_nextId : (m_claimed.empty() ? 1 : m_claimed.rbegin()->first + 1);
    }

  private:
    /// An integer that can be an id.
    static std::uint32_t idValue(ObjectReader& r, std::string_view key) {
        const long long v = r.integer(key);
        if (v < 1 || v > MAX_ID) {
            r.fail(key, "must be an id, an integer in [1, " + std::to_string(MAX_ID) + "] (found " +
                            std::to_string(v) + ")");
        }
        return static_cast<std::uint32_t>(v);
    }

    /// A new id, held by nothing read before and below `next_id`.
    template <class IdType> IdType claim(ObjectReader& r, std::string_view key) {
        const std::uint32_t v = idValue(r, key);
        if (m_nextId && v >= *m_nextId) {
            r.fail(key, "id " + std::to_string(v) + " is not below next_id (" +
                            std::to_string(*m_nextId) + ")");
        }
        const auto [it, inserted] = m_claimed.emplace(v, r.pointerOf(key));
        if (!inserted) {
            r.fail(key,
                   "duplicate id " + std::to_string(v) + " (already used at " + it->second + ")");
        }
        return IdType{v};
    }

    /// The id of an outline edge of `panel`.
    static patterns::EdgeId outlineEdge(ObjectReader& r, std::string_view key,
                                        const doc::Panel& panel) {
        const patterns::EdgeId edge{idValue(r, key)};
        if (patterns::outlineEdgeIndex(panel, edge) < 0) {
            r.fail(key, "panel " + inQuotes(panel.name) + " has no outline edge with id " +
                            std::to_string(edge.value));
        }
        return edge;
    }

    static doc::Curve readCurve(ObjectReader& r) {
        doc::Curve c;
        const std::string kindName = r.string("curve", "line");
        const auto kind = segmentKindFromName(kindName);
        if (!kind) {
            r.fail("curve", "unknown curve " + inQuotes(kindName) + " (expected one of " +
                                segmentKindList() + ")");
        }
        c.kind = *kind;
        if (c.kind == SegmentKind::Quadratic || c.kind == SegmentKind::Cubic) {
            c.control1 = point(r, "c1");
        }
        if (c.kind == SegmentKind::Cubic) {
            c.control2 = point(r, "c2");
        }
        if (c.kind == SegmentKind::Arc) {
            c.bulge = r.number("bulge");
        }
        return c;
    }

    /// A chain of `{"point", "at", "edge", "curve", ...}`: each point with the edge to the next
    /// one; in a `closed` contour the last edge returns to the first point, in an open line the
    /// last point has no edge.
    void readChain(const json& value, const std::string& ptr, bool closed,
                   std::vector<doc::Point>& points, std::vector<doc::Edge>& edges) {
        const json& array = arrayAt(value, ptr);
        if (array.size() < (closed ? 3U : 2U)) {
            throw JsonError{ptr, closed ? "a closed contour needs at least 3 points"
                                        : "an internal line needs at least 2 points"};
        }
        for (std::size_t i = 0; i < array.size(); ++i) {
            ObjectReader e(array[i], childPointer(ptr, i));
            doc::Point p;
            p.id = claim<patterns::PointId>(e, "point");
            p.position = point(e, "at");
            if (!closed && i + 1 == array.size()) {
                for (const char* key : {"edge", "curve", "c1", "c2", "bulge"}) {
                    if (e.has(key)) {
                        e.fail(key, "the last point of an internal line has no edge after it");
                    }
                }
            } else {
                doc::Edge edge;
                edge.id = claim<patterns::EdgeId>(e, "edge");
                edge.curve = readCurve(e);
                edges.push_back(edge);
            }
            e.finish();
            points.push_back(p);
        }
    }

    void readDart(const json& value, const std::string& ptr, doc::Panel& panel) {
        ObjectReader d(value, ptr);
        doc::Dart dart;
        dart.id = claim<patterns::DartId>(d, "id");
        dart.leg1 = outlineEdge(d, "leg1", panel);
        dart.leg2 = outlineEdge(d, "leg2", panel);
        const auto leg = static_cast<std::size_t>(patterns::outlineEdgeIndex(panel, dart.leg1));
        if (leg + 1 >= panel.outline.edges.size()) {
            d.fail("leg1", "a dart's first leg must not be the outline's last edge");
        }
        if (panel.outline.edges[leg + 1].id != dart.leg2) {
            d.fail("leg2", "must be the outline edge after leg1 (id " +
                               std::to_string(panel.outline.edges[leg + 1].id.value) + ")");
        }
        d.finish();
        panel.darts.push_back(dart);
    }

    void readParts(ObjectReader& r, doc::Panel& panel) {
        forEachIn(r, "holes", [&](const json& v, const std::string& p) {
            ObjectReader h(v, p);
            doc::Hole hole;
            hole.id = claim<patterns::HoleId>(h, "id");
            readChain(h.require("contour"), h.pointerOf("contour"), true, hole.contour.points,
                      hole.contour.edges);
            h.finish();
            panel.holes.push_back(std::move(hole));
        });
        forEachIn(r, "internal_lines", [&](const json& v, const std::string& p) {
            ObjectReader l(v, p);
            doc::InternalLine line;
            line.id = claim<patterns::LineId>(l, "id");
            line.foldAngle = angleDeg(l, "fold_deg", line.foldAngle);
            readChain(l.require("points"), l.pointerOf("points"), false, line.points, line.edges);
            l.finish();
            panel.internalLines.push_back(std::move(line));
        });
        forEachIn(r, "darts", [&](const json& v, const std::string& p) { readDart(v, p, panel); });
        forEachIn(r, "notches", [&](const json& v, const std::string& p) {
            ObjectReader n(v, p);
            doc::Notch notch;
            notch.id = claim<patterns::NotchId>(n, "id");
            notch.edge = outlineEdge(n, "edge", panel);
            notch.t = parameter(n, "t", notch.t);
            n.finish();
            panel.notches.push_back(notch);
        });
        forEachIn(r, "pins", [&](const json& v, const std::string& p) { readPin(v, p, panel); });
    }

    /// `{"id", "at": [x, y] | "notch": id, "position_mm": [x, y, z], "release_s": t}`; whether
    /// the point lies inside the panel is patterns::validateGarment's check.
    void readPin(const json& value, const std::string& ptr, doc::Panel& panel) {
        ObjectReader r(value, ptr);
        doc::Pin pin;
        pin.id = claim<patterns::PinId>(r, "id");
        if (r.has("at") == r.has("notch")) {
            throw JsonError{ptr, "a pin needs either \"at\" (a point of the panel, mm) or "
                                 "\"notch\" (a notch id), not both"};
        }
        if (r.has("at")) {
            pin.point = point(r, "at");
        } else {
            pin.notch = patterns::NotchId{idValue(r, "notch")};
            if (std::none_of(panel.notches.begin(), panel.notches.end(),
                             [&](const doc::Notch& n) { return n.id == pin.notch; })) {
                r.fail("notch", "panel " + inQuotes(panel.name) + " has no notch with id " +
                                    std::to_string(pin.notch.value));
            }
        }
        if (r.has("position_mm")) {
            pin.position = r.vec3("position_mm") * 1e-3;
        }
        if (const auto release = r.optionalNumber("release_s")) {
            if (!(*release >= 0)) {
                r.fail("release_s", "must be a time of at least 0 s");
            }
            pin.releaseTime = *release;
        }
        r.finish();
        panel.pins.push_back(pin);
    }

    doc::Panel readPanel(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        doc::Panel panel;
        panel.id = claim<patterns::PanelId>(r, "id");
        std::vector<std::string> names;
        for (const doc::Panel& p : m_doc.panels) {
            names.push_back(p.name);
        }
        PanelAttributes a = readPanelAttributes(r, m_doc.materials, names);
        panel.name = std::move(a.name);
        panel.material = std::move(a.material);
        panel.side = a.side;
        panel.grainAngle = a.grainAngle;
        panel.placement = std::move(a.placement);
        panel.particleDistance = a.particleDistance;
        if (const json* sheet = r.find("sheet")) {
            panel.sheet = readSheet(*sheet, r.pointerOf("sheet"));
        }
        readChain(r.require("outline"), r.pointerOf("outline"), true, panel.outline.points,
                  panel.outline.edges);
        readParts(r, panel);
        r.finish();
        return panel;
    }

    /// `{"at_mm": [x, y], "angle_deg": a}`: where the panel lies on the pattern sheet.
    static doc::SheetPlace readSheet(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        doc::SheetPlace place;
        place.at = point(r, "at_mm");
        constexpr double FAR_LIMIT = 1000; // [m], as patterns::setSheetPlace
        if (place.at.cwiseAbs().maxCoeff() > FAR_LIMIT) {
            r.fail("at_mm", "must be within 1 km of the sheet's origin");
        }
        place.angle = angleDeg(r, "angle_deg", 0.0);
        if (!std::isfinite(place.angle)) {
            r.fail("angle_deg", "must be finite");
        }
        r.finish();
        return place;
    }

    doc::SeamRange readRange(const json& value, const std::string& ptr) {
        ObjectReader e(value, ptr);
        doc::SeamRange range;
        range.panel = patterns::PanelId{idValue(e, "panel")};
        const doc::Panel* panel = m_doc.panel(range.panel);
        if (panel == nullptr) {
            e.fail("panel", "no panel has id " + std::to_string(range.panel.value));
        }
        range.edge = outlineEdge(e, "edge", *panel);
        range.t0 = parameter(e, "t0", range.t0);
        range.t1 = parameter(e, "t1", range.t1);
        e.finish();
        return range;
    }

    doc::Seam readSeam(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        doc::Seam seam;
        seam.id = claim<patterns::SeamId>(r, "id");
        seam.name = r.string("name", "");
        seamBending(r, seam.foldAngle, seam.bendingScale);
        for (const char* sideKey : {"a", "b"}) {
            const std::string sp = r.pointerOf(sideKey);
            const json& ranges = arrayAt(r.require(sideKey), sp);
            if (ranges.empty()) {
                r.fail(sideKey, "a seam side needs at least one edge");
            }
            for (std::size_t i = 0; i < ranges.size(); ++i) {
                (sideKey[0] == 'a' ? seam.a : seam.b)
                    .push_back(readRange(ranges[i], childPointer(sp, i)));
            }
        }
        r.finish();
        return seam;
    }

    patterns::GarmentDocument& m_doc;
    /// Every id read, with the pointer of its holder.
    std::map<std::uint32_t, std::string> m_claimed;
    std::optional<std::uint32_t> m_nextId;
};

// ---------------------------------------------------------------------------------------------
// Writing

ordered_json chainJson(const std::vector<doc::Point>& points, const std::vector<doc::Edge>& edges) {
    ordered_json out = ordered_json::array();
    for (std::size_t i = 0; i < points.size(); ++i) {
        ordered_json e = ordered_json::object();
        e["point"] = points[i].id.value;
        e["at"] = pointMm(points[i].position);
        if (i < edges.size()) {
            const doc::Curve& c = edges[i].curve;
            e["edge"] = edges[i].id.value;
            e["curve"] = std::string(segmentKindName(c.kind));
            if (c.kind == SegmentKind::Quadratic || c.kind == SegmentKind::Cubic) {
                e["c1"] = pointMm(c.control1);
            }
            if (c.kind == SegmentKind::Cubic) {
                e["c2"] = pointMm(c.control2);
            }
            if (c.kind == SegmentKind::Arc) {
                e["bulge"] = number(c.bulge);
            }
        }
        out.push_back(std::move(e));
    }
    return out;
}

ordered_json panelJson(const doc::Panel& panel) {
    ordered_json out = ordered_json::object();
    out["id"] = panel.id.value;
    out["name"] = panel.name;
    out["material"] = panel.material;
    out["side"] = std::string(sideName(panel.side));
    out["grain_deg"] = deg(panel.grainAngle);
    if (panel.particleDistance > 0) { // written only when set: older files stay byte-identical
        out["particle_distance_mm"] = mm(panel.particleDistance);
    }
    if (panel.sheet) { // likewise
        ordered_json sheet = ordered_json::object();
        sheet["at_mm"] = pointMm(panel.sheet->at);
        sheet["angle_deg"] = deg(panel.sheet->angle);
        out["sheet"] = std::move(sheet);
    }
    out["outline"] = chainJson(panel.outline.points, panel.outline.edges);
    out["holes"] = ordered_json::array();
    for (const doc::Hole& hole : panel.holes) {
        ordered_json h = ordered_json::object();
        h["id"] = hole.id.value;
        h["contour"] = chainJson(hole.contour.points, hole.contour.edges);
        out["holes"].push_back(std::move(h));
    }
    out["internal_lines"] = ordered_json::array();
    for (const doc::InternalLine& line : panel.internalLines) {
        ordered_json l = ordered_json::object();
        l["id"] = line.id.value;
        l["fold_deg"] = deg(line.foldAngle);
        l["points"] = chainJson(line.points, line.edges);
        out["internal_lines"].push_back(std::move(l));
    }
    out["darts"] = ordered_json::array();
    for (const doc::Dart& dart : panel.darts) {
        out["darts"].push_back(
            {{"id", dart.id.value}, {"leg1", dart.leg1.value}, {"leg2", dart.leg2.value}});
    }
    out["notches"] = ordered_json::array();
    for (const doc::Notch& notch : panel.notches) {
        ordered_json n = ordered_json::object();
        n["id"] = notch.id.value;
        n["edge"] = notch.edge.value;
        n["t"] = number(notch.t);
        out["notches"].push_back(std::move(n));
    }
    out["placement"] = placementJson(panel.placement);
    // Written only when there are pins, so files from before pins keep their bytes.
    if (!panel.pins.empty()) {
        out["pins"] = ordered_json::array();
        for (const doc::Pin& pin : panel.pins) {
            ordered_json e = ordered_json::object();
            e["id"] = pin.id.value;
            if (pin.notch) {
                e["notch"] = pin.notch.value;
            } else {
                e["at"] = pointMm(pin.point);
            }
            if (pin.position) {
                e["position_mm"] = {mm(pin.position->x()), mm(pin.position->y()),
                                    mm(pin.position->z())};
            }
            if (std::isfinite(pin.releaseTime)) {
                e["release_s"] = number(pin.releaseTime);
            }
            out["pins"].push_back(std::move(e));
        }
    }
    return out;
}

ordered_json seamJson(const doc::Seam& seam) {
    ordered_json out = ordered_json::object();
    out["id"] = seam.id.value;
    out["name"] = seam.name;
    if (seam.foldAngle != 0) { // written when not the default, as a flat seam
        out["fold_deg"] = deg(seam.foldAngle);
    }
    if (seam.bendingScale != 1) {
        out["bending_scale"] = number(seam.bendingScale);
    }
    for (const auto* side : {&seam.a, &seam.b}) {
        ordered_json ranges = ordered_json::array();
        for (const doc::SeamRange& range : *side) {
            ordered_json e = ordered_json::object();
            e["panel"] = range.panel.value;
            e["edge"] = range.edge.value;
            e["t0"] = number(range.t0);
            e["t1"] = number(range.t1);
            ranges.push_back(std::move(e));
        }
        out[side == &seam.a ? "a" : "b"] = std::move(ranges);
    }
    return out;
}

} // namespace

void readDocumentV2(ObjectReader& root, patterns::GarmentDocument& document) {
    DocumentReader(document).read(root);
}

void writeDocumentV2(const patterns::GarmentDocument& document, ordered_json& root) {
    root["next_id"] = document.nextId;
    root["panels"] = ordered_json::array();
    for (const doc::Panel& panel : document.panels) {
        root["panels"].push_back(panelJson(panel));
    }
    root["seams"] = ordered_json::array();
    for (const doc::Seam& seam : document.seams) {
        root["seams"].push_back(seamJson(seam));
    }
}

std::string pointerInV2(const std::string& garmentPointer) {
    // Panels, seams and each panel's parts keep their order in toGarment; an outline's
    // segment i is the edge leaving its point i.
    static const std::array<std::pair<std::regex, const char*>, 5> RENAMES = {{
        {std::regex(R"(^(/panels/\d+/holes/\d+)(/|$))"), "$1/contour$2"},
        {std::regex(R"(^(/panels/\d+/internal_lines/\d+)/segments)"), "$1/points"},
        {std::regex(R"(^(/panels/\d+/darts/\d+)/leg$)"), "$1/leg1"},
        {std::regex(R"(^(/panels/\d+/notches/\d+)/segment$)"), "$1/edge"},
        {std::regex(R"(^(/seams/\d+/[ab]/\d+)/segment$)"), "$1/edge"},
    }};
    std::string out = garmentPointer;
    for (const auto& [pattern, replacement] : RENAMES) {
        out = std::regex_replace(out, pattern, replacement);
    }
    return out;
}

} // namespace atelier::io::detail
