#include "patterns/document.h"

#include "patterns/mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <set>

namespace atelier::patterns {

namespace {

template <class T, class IdType> T* findById(std::vector<T>& items, IdType id) {
    const auto it =
        std::find_if(items.begin(), items.end(), [&](const T& x) { return x.id == id; });
    return it == items.end() ? nullptr : &*it;
}

template <class T, class IdType> const T* findById(const std::vector<T>& items, IdType id) {
    const auto it =
        std::find_if(items.begin(), items.end(), [&](const T& x) { return x.id == id; });
    return it == items.end() ? nullptr : &*it;
}

doc::Curve curveOf(const Segment& s) {
    doc::Curve c;
    c.kind = s.kind;
    c.control1 = s.control1;
    c.control2 = s.control2;
    c.bulge = s.bulge;
    return c;
}

doc::Contour contourFromLoop(GarmentDocument& d, const Loop& loop) {
    doc::Contour c;
    for (const Segment& s : loop) {
        c.points.push_back({d.newId<PointId>(), s.start});
        c.edges.push_back({d.newId<EdgeId>(), curveOf(s)});
    }
    return c;
}

Loop loopOf(const doc::Contour& c) {
    Loop loop;
    for (std::size_t i = 0; i < c.edges.size(); ++i) {
        loop.push_back(contourSegment(c, i));
    }
    return loop;
}

/// Splits a drawn internal line into chains whose segments join end to start.
std::vector<doc::InternalLine> linesFromDrawing(GarmentDocument& d,
                                                const patterns::InternalLine& l) {
    std::vector<doc::InternalLine> out;
    for (std::size_t k = 0; k < l.path.size(); ++k) {
        const Segment& s = l.path[k];
        if (k == 0 || !(l.path[k - 1].end == s.start)) {
            doc::InternalLine line;
            line.id = d.newId<LineId>();
            line.foldAngle = l.foldAngle;
            line.points.push_back({d.newId<PointId>(), s.start});
            out.push_back(std::move(line));
        }
        doc::InternalLine& line = out.back();
        line.edges.push_back({d.newId<EdgeId>(), curveOf(s)});
        line.points.push_back({d.newId<PointId>(), s.end});
    }
    return out;
}

void appendNumber(std::string& out, double v) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, " %.17g", v);
    out += buffer;
}

void appendVec(std::string& out, const Vec2& v) {
    appendNumber(out, v.x());
    appendNumber(out, v.y());
}

void appendText(std::string& out, const std::string& s) {
    out += " \"";
    for (const char c : s) {
        if (c == '"' || c == '\\') {
            out += '\\';
        }
        out += c == '\n' ? ' ' : c;
    }
    out += '"';
}

void appendId(std::string& out, std::uint32_t id) {
    out += " #" + std::to_string(id);
}

void dumpChain(std::string& out, const std::string& indent, const std::vector<doc::Point>& points,
               const std::vector<doc::Edge>& edges) {
    for (std::size_t i = 0; i < points.size(); ++i) {
        out += indent + "point";
        appendId(out, points[i].id.value);
        appendVec(out, points[i].position);
        out += '\n';
        if (i < edges.size()) {
            const doc::Edge& e = edges[i];
            out += indent + "edge";
            appendId(out, e.id.value);
            out += " kind " + std::to_string(static_cast<int>(e.curve.kind));
            appendVec(out, e.curve.control1);
            appendVec(out, e.curve.control2);
            appendNumber(out, e.curve.bulge);
            out += '\n';
        }
    }
}

void dumpPanel(std::string& out, const doc::Panel& p) {
    out += "panel";
    appendId(out, p.id.value);
    appendText(out, p.name);
    appendText(out, p.material);
    out += p.side == PanelSide::Back ? " back" : " front";
    appendNumber(out, p.grainAngle);
    appendNumber(out, p.particleDistance);
    out += "\n  placement";
    appendText(out, p.placement.slot);
    appendVec(out, p.placement.offset);
    appendNumber(out, p.placement.rotation);
    appendNumber(out, p.placement.clearance);
    if (p.sheet) {
        out += "\n  sheet";
        appendVec(out, p.sheet->at);
        appendNumber(out, p.sheet->angle);
    }
    out += "\n  outline\n";
    dumpChain(out, "    ", p.outline.points, p.outline.edges);
    for (const doc::Hole& h : p.holes) {
        out += "  hole";
        appendId(out, h.id.value);
        out += '\n';
        dumpChain(out, "    ", h.contour.points, h.contour.edges);
    }
    for (const doc::InternalLine& l : p.internalLines) {
        out += "  line";
        appendId(out, l.id.value);
        appendNumber(out, l.foldAngle);
        out += '\n';
        dumpChain(out, "    ", l.points, l.edges);
    }
    for (const doc::Dart& d : p.darts) {
        out += "  dart";
        appendId(out, d.id.value);
        appendId(out, d.leg1.value);
        appendId(out, d.leg2.value);
        out += '\n';
    }
    for (const doc::Notch& n : p.notches) {
        out += "  notch";
        appendId(out, n.id.value);
        appendId(out, n.edge.value);
        appendNumber(out, n.t);
        out += '\n';
    }
    for (const doc::Pin& pin : p.pins) {
        out += "  pin";
        appendId(out, pin.id.value);
        appendVec(out, pin.point);
        appendId(out, pin.notch.value);
        if (pin.position) {
            appendNumber(out, pin.position->x());
            appendNumber(out, pin.position->y());
            appendNumber(out, pin.position->z());
        }
        appendNumber(out, pin.releaseTime);
        out += '\n';
    }
}

} // namespace

Segment segmentOf(const doc::Curve& c, const Vec2& start, const Vec2& end) {
    Segment s;
    s.kind = c.kind;
    s.start = start;
    s.end = end;
    s.control1 = c.control1;
    s.control2 = c.control2;
    s.bulge = c.bulge;
    return s;
}

doc::Panel* GarmentDocument::panel(PanelId id) {
    return findById(panels, id);
}
const doc::Panel* GarmentDocument::panel(PanelId id) const {
    return findById(panels, id);
}
doc::Seam* GarmentDocument::seam(SeamId id) {
    return findById(seams, id);
}
const doc::Seam* GarmentDocument::seam(SeamId id) const {
    return findById(seams, id);
}

const doc::Panel* GarmentDocument::panelNamed(const std::string& panelName) const {
    const auto it = std::find_if(panels.begin(), panels.end(),
                                 [&](const doc::Panel& p) { return p.name == panelName; });
    return it == panels.end() ? nullptr : &*it;
}

int outlineEdgeIndex(const doc::Panel& panel, EdgeId edge) {
    const auto& edges = panel.outline.edges;
    const auto it =
        std::find_if(edges.begin(), edges.end(), [&](const doc::Edge& e) { return e.id == edge; });
    return it == edges.end() ? -1 : static_cast<int>(it - edges.begin());
}

/// The contour of `panel` (outline or a hole) whose `items` (points or edges) hold `id`, with
/// its position there in `index`; null when none does.
template <class Id, class Items>
doc::Contour* contourHolding(doc::Panel& panel, Id id, int& index, Items items) {
    auto search = [&](doc::Contour& c) {
        const auto& list = items(c);
        for (std::size_t i = 0; i < list.size(); ++i) {
            if (list[i].id == id) {
                index = static_cast<int>(i);
                return true;
            }
        }
        return false;
    };
    if (search(panel.outline)) {
        return &panel.outline;
    }
    for (doc::Hole& h : panel.holes) {
        if (search(h.contour)) {
            return &h.contour;
        }
    }
    return nullptr;
}

doc::Contour* contourOfPoint(doc::Panel& panel, PointId point, int& index) {
    return contourHolding(
        panel, point, index, [](doc::Contour & c) -> auto& { return c.points; });
}

doc::Contour* contourOfEdge(doc::Panel& panel, EdgeId edge, int& index) {
    return contourHolding(
        panel, edge, index, [](doc::Contour & c) -> auto& { return c.edges; });
}

Segment contourSegment(const doc::Contour& contour, std::size_t i) {
    const std::size_t n = contour.points.size();
    return segmentOf(contour.edges[i].curve, contour.points[i].position,
                     contour.points[(i + 1) % n].position);
}

doc::Panel panelFromDrawing(GarmentDocument& d, const Panel& drawn) {
    doc::Panel p;
    p.id = d.newId<PanelId>();
    p.name = drawn.name;
    p.outline = contourFromLoop(d, drawn.outline);
    for (const Loop& hole : drawn.holes) {
        const HoleId id = d.newId<HoleId>();
        p.holes.push_back({id, contourFromLoop(d, hole)});
    }
    for (const patterns::InternalLine& l : drawn.internalLines) {
        for (doc::InternalLine& chain : linesFromDrawing(d, l)) {
            p.internalLines.push_back(std::move(chain));
        }
    }
    const auto edgeAt = [&](int i) {
        return i >= 0 && i < static_cast<int>(p.outline.edges.size())
                   ? p.outline.edges[static_cast<std::size_t>(i)].id
                   : EdgeId{};
    };
    for (const patterns::Dart& dart : drawn.darts) {
        const DartId id = d.newId<DartId>();
        p.darts.push_back({id, edgeAt(dart.leg), edgeAt(dart.leg + 1)});
    }
    for (const patterns::Notch& n : drawn.notches) {
        const NotchId id = d.newId<NotchId>();
        p.notches.push_back({id, edgeAt(n.segment), n.t});
    }
    for (const patterns::Pin& pin : drawn.pins) {
        const PinId id = d.newId<PinId>();
        const NotchId notch = pin.notch >= 0 && pin.notch < static_cast<int>(p.notches.size())
                                  ? p.notches[static_cast<std::size_t>(pin.notch)].id
                                  : NotchId{};
        p.pins.push_back({id, pin.point, notch, pin.position, pin.releaseTime});
    }
    p.grainAngle = drawn.grainAngle;
    p.particleDistance = drawn.particleDistance;
    p.material = drawn.material;
    p.side = drawn.side;
    p.placement = drawn.placement;
    return p;
}

GarmentDocument fromGarment(const Garment& garment) {
    GarmentDocument d;
    d.name = garment.name;
    d.materials = garment.materials;
    d.easeTolerance = garment.easeTolerance;
    for (const Panel& drawn : garment.panels) {
        d.panels.push_back(panelFromDrawing(d, drawn));
    }
    const auto range = [&](const SeamEdge& e) {
        doc::SeamRange r;
        r.t0 = e.t0;
        r.t1 = e.t1;
        const int pi = garment.panelIndex(e.panel);
        if (pi >= 0) {
            const doc::Panel& p = d.panels[static_cast<std::size_t>(pi)];
            r.panel = p.id;
            if (e.segment >= 0 && e.segment < static_cast<int>(p.outline.edges.size())) {
                r.edge = p.outline.edges[static_cast<std::size_t>(e.segment)].id;
            }
        }
        return r;
    };
    for (const Seam& s : garment.seams) {
        doc::Seam seam;
        seam.id = d.newId<SeamId>();
        seam.name = s.name;
        seam.foldAngle = s.foldAngle;
        seam.bendingScale = s.bendingScale;
        std::transform(s.a.begin(), s.a.end(), std::back_inserter(seam.a), range);
        std::transform(s.b.begin(), s.b.end(), std::back_inserter(seam.b), range);
        d.seams.push_back(std::move(seam));
    }
    return d;
}

Garment toGarment(const GarmentDocument& d) {
    Garment g;
    g.name = d.name;
    g.materials = d.materials;
    g.easeTolerance = d.easeTolerance;
    for (const doc::Panel& p : d.panels) {
        Panel out;
        out.name = p.name;
        out.outline = loopOf(p.outline);
        for (const doc::Hole& h : p.holes) {
            out.holes.push_back(loopOf(h.contour));
        }
        for (const doc::InternalLine& l : p.internalLines) {
            patterns::InternalLine line;
            line.foldAngle = l.foldAngle;
            for (std::size_t i = 0; i < l.edges.size(); ++i) {
                line.path.push_back(
                    segmentOf(l.edges[i].curve, l.points[i].position, l.points[i + 1].position));
            }
            out.internalLines.push_back(std::move(line));
        }
        for (const doc::Dart& dart : p.darts) {
            out.darts.push_back({outlineEdgeIndex(p, dart.leg1)});
        }
        for (const doc::Notch& n : p.notches) {
            out.notches.push_back({outlineEdgeIndex(p, n.edge), n.t});
        }
        for (const doc::Pin& pin : p.pins) {
            patterns::Pin drawn{pin.point, -1, pin.position, pin.releaseTime};
            for (std::size_t n = 0; n < p.notches.size() && pin.notch; ++n) {
                if (p.notches[n].id == pin.notch) {
                    drawn.notch = static_cast<int>(n);
                }
            }
            out.pins.push_back(drawn);
        }
        out.grainAngle = p.grainAngle;
        out.particleDistance = p.particleDistance;
        out.material = p.material;
        out.side = p.side;
        out.placement = p.placement;
        g.panels.push_back(std::move(out));
    }
    const auto range = [&](const doc::SeamRange& r) {
        SeamEdge e;
        e.t0 = r.t0;
        e.t1 = r.t1;
        if (const doc::Panel* p = d.panel(r.panel)) {
            e.panel = p->name;
            e.segment = outlineEdgeIndex(*p, r.edge);
        }
        return e;
    };
    for (const doc::Seam& s : d.seams) {
        Seam seam;
        seam.name = s.name;
        seam.foldAngle = s.foldAngle;
        seam.bendingScale = s.bendingScale;
        std::transform(s.a.begin(), s.a.end(), std::back_inserter(seam.a), range);
        std::transform(s.b.begin(), s.b.end(), std::back_inserter(seam.b), range);
        g.seams.push_back(std::move(seam));
    }
    return g;
}

Result<void> checkDocument(const GarmentDocument& d) {
    std::vector<Error> problems;
    const auto fail = [&](std::string where, std::string message) {
        problems.push_back({"", std::move(where), std::move(message)});
    };
    std::set<std::uint32_t> ids;
    const auto claim = [&](std::uint32_t id, const std::string& where) {
        if (id == 0 || id >= d.nextId) {
            fail(where, "id #" + std::to_string(id) + " is not below the next id");
        } else if (!ids.insert(id).second) {
            fail(where, "id #" + std::to_string(id) + " is held twice");
        }
    };
    const auto claimChain = [&](const std::vector<doc::Point>& points,
                                const std::vector<doc::Edge>& edges, const std::string& where) {
        for (const doc::Point& pt : points) {
            claim(pt.id.value, where);
        }
        for (const doc::Edge& e : edges) {
            claim(e.id.value, where);
        }
    };
    std::set<std::string> names;
    for (const doc::Panel& p : d.panels) {
        const std::string w = "panel #" + std::to_string(p.id.value);
        claim(p.id.value, w);
        if (p.name.empty() || !names.insert(p.name).second) {
            fail(w, "panel name \"" + p.name + "\" is empty or not unique");
        }
        if (!(p.particleDistance == 0 || (p.particleDistance >= MIN_PANEL_PARTICLE_DISTANCE &&
                                          p.particleDistance <= MAX_PANEL_PARTICLE_DISTANCE))) {
            fail(w, "particle distance must be 0 or between 1 and 1000 mm");
        }
        if (p.outline.points.size() < 3 || p.outline.points.size() != p.outline.edges.size()) {
            fail(w, "outline needs as many edges as points, at least 3");
        }
        claimChain(p.outline.points, p.outline.edges, w);
        for (const doc::Hole& h : p.holes) {
            claim(h.id.value, w);
            claimChain(h.contour.points, h.contour.edges, w);
            if (h.contour.points.size() < 3 || h.contour.points.size() != h.contour.edges.size()) {
                fail(w, "hole #" + std::to_string(h.id.value) +
                            " needs as many edges as points, at least 3");
            }
        }
        for (const doc::InternalLine& l : p.internalLines) {
            claim(l.id.value, w);
            claimChain(l.points, l.edges, w);
            if (l.edges.empty() || l.points.size() != l.edges.size() + 1) {
                fail(w, "line #" + std::to_string(l.id.value) + " needs one point more than edges");
            }
        }
        for (const doc::Dart& dart : p.darts) {
            claim(dart.id.value, w);
            const int leg = outlineEdgeIndex(p, dart.leg1);
            if (leg < 0 || leg + 1 >= static_cast<int>(p.outline.edges.size()) ||
                p.outline.edges[static_cast<std::size_t>(leg) + 1].id != dart.leg2) {
                fail(w, "dart #" + std::to_string(dart.id.value) +
                            ": legs are not consecutive outline edges");
            }
        }
        for (const doc::Notch& n : p.notches) {
            claim(n.id.value, w);
            if (outlineEdgeIndex(p, n.edge) < 0 || !(n.t >= 0 && n.t <= 1)) {
                fail(w, "notch #" + std::to_string(n.id.value) + ": not on an outline edge");
            }
        }
        for (const doc::Pin& pin : p.pins) {
            claim(pin.id.value, w);
            const bool notchFound =
                !pin.notch || std::any_of(p.notches.begin(), p.notches.end(),
                                          [&](const doc::Notch& n) { return n.id == pin.notch; });
            if (!notchFound || !pin.point.allFinite() ||
                (pin.position && !pin.position->allFinite()) || std::isnan(pin.releaseTime)) {
                fail(w, "pin #" + std::to_string(pin.id.value) +
                            ": not on a notch of the panel, or a value not finite");
            }
        }
    }
    for (const doc::Seam& s : d.seams) {
        const std::string w = "seam #" + std::to_string(s.id.value);
        claim(s.id.value, w);
        if (!(std::abs(s.foldAngle) < std::numbers::pi) || !(s.bendingScale >= 0) ||
            !std::isfinite(s.bendingScale)) {
            fail(w, "a seam's fold angle must be within (-pi, pi) rad and its bending scale "
                    "finite and not negative");
        }
        for (const auto* side : {&s.a, &s.b}) {
            if (side->empty()) {
                fail(w, "seam side has no ranges");
            }
            for (const doc::SeamRange& r : *side) {
                const doc::Panel* p = d.panel(r.panel);
                if (p == nullptr || outlineEdgeIndex(*p, r.edge) < 0) {
                    fail(w, "range on missing panel #" + std::to_string(r.panel.value) + " edge #" +
                                std::to_string(r.edge.value));
                } else if (!(r.t0 >= 0 && r.t0 <= 1 && r.t1 >= 0 && r.t1 <= 1)) {
                    fail(w, "range parameters must be within [0, 1]");
                }
            }
        }
    }
    if (problems.empty()) {
        return {};
    }
    Error first = problems.front();
    first.more.assign(problems.begin() + 1, problems.end());
    return first;
}

std::string dumpDocument(const GarmentDocument& d) {
    std::string out = "document";
    appendText(out, d.name);
    appendNumber(out, d.easeTolerance);
    out += " next #" + std::to_string(d.nextId) + '\n';
    for (const GarmentMaterial& m : d.materials) {
        out += "material";
        appendText(out, m.name);
        appendText(out, m.material.name);
        for (const double v :
             {m.material.density, m.material.stretchWeft, m.material.stretchWarp, m.material.shear,
              m.material.poisson, m.material.bending, m.material.bendingWeft,
              m.material.bendingWarp, m.material.bendingBias, m.material.stretchKnee,
              m.material.stretchWeftBeyond, m.material.stretchWarpBeyond, m.material.damping,
              m.material.staticFriction, m.material.kineticFriction, m.material.plasticYieldAngle,
              m.material.plasticRate}) {
            appendNumber(out, v);
        }
        out += '\n';
    }
    for (const doc::Panel& p : d.panels) {
        dumpPanel(out, p);
    }
    for (const doc::Seam& s : d.seams) {
        out += "seam";
        appendId(out, s.id.value);
        appendText(out, s.name);
        appendNumber(out, s.foldAngle);
        appendNumber(out, s.bendingScale);
        out += '\n';
        for (const auto* side : {&s.a, &s.b}) {
            out += side == &s.a ? "  a" : "  b";
            for (const doc::SeamRange& r : *side) {
                appendId(out, r.panel.value);
                appendId(out, r.edge.value);
                appendNumber(out, r.t0);
                appendNumber(out, r.t1);
                out += " ;";
            }
            out += '\n';
        }
    }
    return out;
}

} // namespace atelier::patterns
