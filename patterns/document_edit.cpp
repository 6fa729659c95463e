#include "patterns/document_edit.h"

#include "patterns/curve.h"
#include "patterns/document_edit_detail.h"
#include "patterns/mesh.h"

#include "sim/forces/continuum_bending.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>
#include <utility>

namespace atelier::patterns {

namespace detail {

template <class T> auto changeId(const Change<T>& c) {
    return c.after ? c.after->id : c.before->id;
}

/// Brings `items` from each change's before-state to its after-state: removes, replaces, then
/// inserts at the after-index in increasing order (edits never reorder what they keep).
template <class T> void applyChanges(std::vector<T>& items, const std::vector<Change<T>>& changes) {
    for (const Change<T>& c : changes) {
        if (!c.after) {
            if (const auto i = indexOfId(items, changeId(c))) {
                items.erase(items.begin() + static_cast<std::ptrdiff_t>(*i));
            }
        }
    }
    std::vector<const Change<T>*> added;
    for (const Change<T>& c : changes) {
        if (!c.after) {
            continue;
        }
        if (const auto i = indexOfId(items, changeId(c))) {
            items[*i] = *c.after;
        } else {
            added.push_back(&c);
        }
    }
    std::sort(added.begin(), added.end(),
              [](const Change<T>* x, const Change<T>* y) { return x->afterIndex < y->afterIndex; });
    for (const Change<T>* c : added) {
        const std::size_t at = std::min(c->afterIndex, items.size());
        items.insert(items.begin() + static_cast<std::ptrdiff_t>(at), *c->after);
    }
}

template <class T> Change<T> invertChange(const Change<T>& c) {
    return {c.after, c.before, c.afterIndex, c.beforeIndex};
}

/// Seams with a range on `panel` (on `edge` when given).
std::vector<SeamId> seamsOn(const GarmentDocument& d, PanelId panel, EdgeId edge) {
    std::vector<SeamId> out;
    for (const doc::Seam& s : d.seams) {
        for (const auto* side : {&s.a, &s.b}) {
            for (const doc::SeamRange& r : *side) {
                if (r.panel == panel && (!edge || r.edge == edge) &&
                    (out.empty() || out.back() != s.id)) {
                    out.push_back(s.id);
                }
            }
        }
    }
    return out;
}

Vec2* pointPosition(doc::Panel& p, PointId id) {
    int i = 0;
    if (doc::Contour* c = contourOfPoint(p, id, i)) {
        return &c->points[static_cast<std::size_t>(i)].position;
    }
    for (doc::InternalLine& l : p.internalLines) {
        for (doc::Point& pt : l.points) {
            if (pt.id == id) {
                return &pt.position;
            }
        }
    }
    return nullptr;
}

doc::Edge* anyEdge(doc::Panel& p, EdgeId id) {
    int i = 0;
    if (doc::Contour* c = contourOfEdge(p, id, i)) {
        return &c->edges[static_cast<std::size_t>(i)];
    }
    for (doc::InternalLine& l : p.internalLines) {
        for (doc::Edge& e : l.edges) {
            if (e.id == id) {
                return &e;
            }
        }
    }
    return nullptr;
}

Vec2 lerp(const Vec2& a, const Vec2& b, double t) {
    return (1 - t) * a + t * b;
}

/// The two halves of a segment split at t (their curves; the new point is pointAt(s, t)).
std::pair<doc::Curve, doc::Curve> splitCurve(const Segment& s, double t) {
    doc::Curve first, second;
    first.kind = second.kind = s.kind;
    switch (s.kind) {
    case SegmentKind::Line:
        break;
    case SegmentKind::Quadratic:
        first.control1 = lerp(s.start, s.control1, t);
        second.control1 = lerp(s.control1, s.end, t);
        break;
    case SegmentKind::Cubic: {
        const Vec2 p01 = lerp(s.start, s.control1, t), p12 = lerp(s.control1, s.control2, t);
        const Vec2 p23 = lerp(s.control2, s.end, t);
        first.control1 = p01;
        first.control2 = lerp(p01, p12, t);
        second.control1 = lerp(p12, p23, t);
        second.control2 = p23;
        break;
    }
    case SegmentKind::Arc: {
        const double sweep = 4.0 * std::atan(s.bulge);
        first.bulge = std::tan(sweep * t / 4.0);
        second.bulge = std::tan(sweep * (1 - t) / 4.0);
        break;
    }
    }
    return {first, second};
}

/// A range on an edge split at t, as ranges on the first half (`first`) and the second
/// (`second`), in the range's own direction.
std::vector<doc::SeamRange> splitRange(const doc::SeamRange& r, double t, EdgeId second) {
    const auto onFirst = [&](double a, double b) {
        return doc::SeamRange{r.panel, r.edge, a / t, b / t};
    };
    const auto onSecond = [&](double a, double b) {
        return doc::SeamRange{r.panel, second, (a - t) / (1 - t), (b - t) / (1 - t)};
    };
    const double lo = std::min(r.t0, r.t1), hi = std::max(r.t0, r.t1);
    if (hi <= t) {
        return {onFirst(r.t0, r.t1)};
    }
    if (lo >= t) {
        return {onSecond(r.t0, r.t1)};
    }
    if (r.t0 < r.t1) {
        return {onFirst(r.t0, t), onSecond(t, r.t1)};
    }
    return {onSecond(r.t0, t), onFirst(t, r.t1)};
}

bool isDartLeg(const doc::Panel& p, EdgeId e) {
    return std::any_of(p.darts.begin(), p.darts.end(),
                       [&](const doc::Dart& d) { return d.leg1 == e || d.leg2 == e; });
}

Result<std::uint32_t> splitEdgeIn(GarmentDocument& d, PanelId panelId, EdgeId edgeId, double t) {
    doc::Panel* p = d.panel(panelId);
    if (p == nullptr) {
        return editError(panelWhere(panelId), "no such panel");
    }
    int k = 0;
    doc::Contour* c = contourOfEdge(*p, edgeId, k);
    if (c == nullptr) {
        return editError(panelWhere(panelId),
                         "no outline or hole edge #" + std::to_string(edgeId.value));
    }
    if (!(t > 0 && t < 1)) {
        return editError(panelWhere(panelId), "split parameter must be within (0, 1)");
    }
    if (isDartLeg(*p, edgeId)) {
        return editError(panelWhere(panelId),
                         "edge #" + std::to_string(edgeId.value) + " is a dart leg");
    }
    const std::size_t i = static_cast<std::size_t>(k);
    const Segment s = contourSegment(*c, i);
    const auto [first, second] = splitCurve(s, t);
    const doc::Point point{d.newId<PointId>(), pointAt(s, t)};
    const doc::Edge secondEdge{d.newId<EdgeId>(), second};
    c->edges[i].curve = first;
    c->points.insert(c->points.begin() + static_cast<std::ptrdiff_t>(i) + 1, point);
    c->edges.insert(c->edges.begin() + static_cast<std::ptrdiff_t>(i) + 1, secondEdge);
    for (doc::Notch& n : p->notches) {
        if (n.edge == edgeId) {
            n = n.t <= t ? doc::Notch{n.id, edgeId, n.t / t}
                         : doc::Notch{n.id, secondEdge.id, (n.t - t) / (1 - t)};
        }
    }
    for (doc::Seam& seam : d.seams) {
        for (auto* side : {&seam.a, &seam.b}) {
            std::vector<doc::SeamRange> out;
            for (const doc::SeamRange& r : *side) {
                if (r.panel == panelId && r.edge == edgeId) {
                    const auto pieces = splitRange(r, t, secondEdge.id);
                    out.insert(out.end(), pieces.begin(), pieces.end());
                } else {
                    out.push_back(r);
                }
            }
            *side = std::move(out);
        }
    }
    return point.id.value;
}

Result<std::uint32_t> checkNewName(const GarmentDocument& d, const std::string& name,
                                   PanelId self) {
    if (name.empty()) {
        return editError(panelWhere(self), "a panel name must not be empty");
    }
    const doc::Panel* other = d.panelNamed(name);
    if (other != nullptr && other->id != self) {
        return editError(panelWhere(self), "a panel named \"" + name + "\" exists");
    }
    return 0U;
}

/// Reverses a closed contour's direction in place: points[j] = old points[(n − j) % n], edge j
/// = old edge n − 1 − j run backwards. Parameters on its edges map t → 1 − t.
void reverseContour(doc::Contour& c) {
    const std::size_t n = c.points.size();
    std::vector<doc::Point> points(n);
    std::vector<doc::Edge> edges(n);
    for (std::size_t j = 0; j < n; ++j) {
        points[j] = c.points[(n - j) % n];
        doc::Edge e = c.edges[n - 1 - j];
        std::swap(e.curve.control1, e.curve.control2);
        if (e.curve.kind == SegmentKind::Quadratic) {
            std::swap(e.curve.control1, e.curve.control2);
        }
        e.curve.bulge = -e.curve.bulge;
        edges[j] = e;
    }
    c.points = std::move(points);
    c.edges = std::move(edges);
}

void mirrorCurve(doc::Curve& c, double axis) {
    c.control1.x() = 2 * axis - c.control1.x();
    c.control2.x() = 2 * axis - c.control2.x();
    c.bulge = -c.bulge;
}

void mirrorChain(std::vector<doc::Point>& points, std::vector<doc::Edge>& edges, double axis) {
    for (doc::Point& pt : points) {
        pt.position.x() = 2 * axis - pt.position.x();
    }
    for (doc::Edge& e : edges) {
        mirrorCurve(e.curve, axis);
    }
}

std::set<EdgeId> edgeIds(const doc::Contour& c) {
    std::set<EdgeId> out;
    for (const doc::Edge& e : c.edges) {
        out.insert(e.id);
    }
    return out;
}

} // namespace detail

using namespace detail;

Edit inverse(const Edit& edit) {
    Edit out;
    out.description = edit.description;
    for (const auto& c : edit.panels) {
        out.panels.push_back(invertChange(c));
    }
    for (const auto& c : edit.seams) {
        out.seams.push_back(invertChange(c));
    }
    out.nextIdBefore = edit.nextIdAfter;
    out.nextIdAfter = edit.nextIdBefore;
    out.materialsBefore = edit.materialsAfter;
    out.materialsAfter = edit.materialsBefore;
    out.created = edit.created;
    return out;
}

void redo(GarmentDocument& d, const Edit& edit) {
    applyChanges(d.panels, edit.panels);
    applyChanges(d.seams, edit.seams);
    d.nextId = edit.nextIdAfter;
    if (edit.materialsAfter) {
        d.materials = *edit.materialsAfter;
    }
}

void undo(GarmentDocument& d, const Edit& edit) {
    redo(d, inverse(edit));
}

Result<Edit> movePoint(GarmentDocument& d, PanelId panel, PointId point, Vec2 position) {
    return record(d, "move point #" + std::to_string(point.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      Vec2* at = p != nullptr ? pointPosition(*p, point) : nullptr;
                      if (at == nullptr) {
                          return editError(panelWhere(panel),
                                           "no point #" + std::to_string(point.value));
                      }
                      if (!position.allFinite()) {
                          return editError(panelWhere(panel), "position must be finite");
                      }
                      *at = position;
                      return 0U;
                  });
}

Result<Edit> splitEdge(GarmentDocument& d, PanelId panel, EdgeId edge, double t) {
    return record(d, "split edge #" + std::to_string(edge.value), {panel}, seamsOn(d, panel, edge),
                  [&](GarmentDocument& doc) { return splitEdgeIn(doc, panel, edge, t); });
}

Result<Edit> addPoint(GarmentDocument& d, PanelId panel, EdgeId edge, double t, Vec2 position) {
    return record(d, "add point on edge #" + std::to_string(edge.value), {panel},
                  seamsOn(d, panel, edge), [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      if (!position.allFinite()) {
                          return editError(panelWhere(panel), "position must be finite");
                      }
                      auto added = splitEdgeIn(doc, panel, edge, t);
                      if (added.ok()) {
                          *pointPosition(*doc.panel(panel), PointId{added.value()}) = position;
                      }
                      return added;
                  });
}

Result<Edit> deletePoint(GarmentDocument& d, PanelId panel, PointId point) {
    return record(d, "delete point #" + std::to_string(point.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      int k = 0;
                      doc::Contour* c = p != nullptr ? contourOfPoint(*p, point, k) : nullptr;
                      if (c == nullptr) {
                          return editError(panelWhere(panel), "no outline or hole point #" +
                                                                  std::to_string(point.value));
                      }
                      const std::size_t n = c->points.size(), i = static_cast<std::size_t>(k);
                      if (n <= 3) {
                          return editError(panelWhere(panel), "a contour keeps at least 3 points");
                      }
                      const EdgeId out = c->edges[i].id, in = c->edges[(i + n - 1) % n].id;
                      for (const EdgeId e : {in, out}) {
                          if (!seamsOn(doc, panel, e).empty() || isDartLeg(*p, e)) {
                              return editError(panelWhere(panel),
                                               "edge #" + std::to_string(e.value) +
                                                   " is sewn (seam or dart); remove that first");
                          }
                      }
                      for (const doc::Notch& nt : p->notches) {
                          if (nt.edge == out) {
                              return editError(panelWhere(panel),
                                               "notch #" + std::to_string(nt.id.value) +
                                                   " is on edge #" + std::to_string(out.value));
                          }
                      }
                      c->points.erase(c->points.begin() + k);
                      c->edges.erase(c->edges.begin() + k);
                      return 0U;
                  });
}

Result<Edit> setCurve(GarmentDocument& d, PanelId panel, EdgeId edge, const doc::Curve& curve) {
    return record(d, "change curve of edge #" + std::to_string(edge.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      doc::Edge* e = p != nullptr ? anyEdge(*p, edge) : nullptr;
                      if (e == nullptr) {
                          return editError(panelWhere(panel),
                                           "no edge #" + std::to_string(edge.value));
                      }
                      if (!curve.control1.allFinite() || !curve.control2.allFinite() ||
                          !std::isfinite(curve.bulge)) {
                          return editError(panelWhere(panel), "curve handles must be finite");
                      }
                      e->curve = curve;
                      return 0U;
                  });
}

Result<Edit> addPanel(GarmentDocument& d, const Panel& drawn) {
    return record(d, "add panel \"" + drawn.name + "\"", {}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      if (auto ok = checkNewName(doc, drawn.name, PanelId{}); !ok.ok()) {
                          return ok;
                      }
                      if (drawn.outline.size() < 3) {
                          return editError("", "a panel outline needs at least 3 segments");
                      }
                      doc.panels.push_back(panelFromDrawing(doc, drawn));
                      return doc.panels.back().id.value;
                  });
}

Result<Edit> removePanel(GarmentDocument& d, PanelId panel) {
    return record(d, "remove panel #" + std::to_string(panel.value), {panel}, seamsOn(d, panel),
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      const auto i = indexOfId(doc.panels, panel);
                      if (!i) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      for (const SeamId s : seamsOn(doc, panel)) {
                          doc.seams.erase(doc.seams.begin() +
                                          static_cast<std::ptrdiff_t>(*indexOfId(doc.seams, s)));
                      }
                      doc.panels.erase(doc.panels.begin() + static_cast<std::ptrdiff_t>(*i));
                      return 0U;
                  });
}

Result<Edit> addSeam(GarmentDocument& d, std::string name, std::vector<doc::SeamRange> a,
                     std::vector<doc::SeamRange> b) {
    return record(
        d, "add seam \"" + name + "\"", {}, {}, [&](GarmentDocument& doc) -> Result<std::uint32_t> {
            if (a.empty() || b.empty()) {
                return editError("seam \"" + name + "\"", "each side needs a range");
            }
            for (const auto* side : {&a, &b}) {
                for (const doc::SeamRange& r : *side) {
                    const doc::Panel* p = doc.panel(r.panel);
                    if (p == nullptr || outlineEdgeIndex(*p, r.edge) < 0) {
                        return editError("seam \"" + name + "\"",
                                         "no outline edge #" + std::to_string(r.edge.value) +
                                             " on panel #" + std::to_string(r.panel.value));
                    }
                    if (!(r.t0 >= 0 && r.t0 <= 1 && r.t1 >= 0 && r.t1 <= 1) ||
                        std::abs(r.t1 - r.t0) < 1e-6) {
                        return editError("seam \"" + name + "\"",
                                         "range parameters must be distinct, within [0, 1]");
                    }
                }
            }
            doc.seams.push_back({doc.newId<SeamId>(), name, a, b});
            return doc.seams.back().id.value;
        });
}

Result<Edit> removeSeam(GarmentDocument& d, SeamId seam) {
    return record(d, "remove seam #" + std::to_string(seam.value), {}, {seam},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      const auto i = indexOfId(doc.seams, seam);
                      if (!i) {
                          return editError("seam #" + std::to_string(seam.value), "no such seam");
                      }
                      doc.seams.erase(doc.seams.begin() + static_cast<std::ptrdiff_t>(*i));
                      return 0U;
                  });
}

Result<Edit> reverseSeam(GarmentDocument& d, SeamId seam) {
    return record(d, "reverse seam #" + std::to_string(seam.value), {}, {seam},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Seam* s = doc.seam(seam);
                      if (s == nullptr) {
                          return editError("seam #" + std::to_string(seam.value), "no such seam");
                      }
                      std::reverse(s->b.begin(), s->b.end());
                      for (doc::SeamRange& r : s->b) {
                          std::swap(r.t0, r.t1);
                      }
                      return 0U;
                  });
}

Result<Edit> setSeamBending(GarmentDocument& d, SeamId seam, double foldAngle,
                            double bendingScale) {
    return record(d, "set the bending of seam #" + std::to_string(seam.value), {}, {seam},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      const std::string where = "seam #" + std::to_string(seam.value);
                      doc::Seam* s = doc.seam(seam);
                      if (s == nullptr) {
                          return editError(where, "no such seam");
                      }
                      if (!(std::abs(foldAngle) < std::numbers::pi)) {
                          return editError(where, "a fold angle must be within (-pi, pi) rad");
                      }
                      if (!(bendingScale >= 0) || !std::isfinite(bendingScale)) {
                          return editError(where,
                                           "a bending scale must be finite and not negative");
                      }
                      s->foldAngle = foldAngle;
                      s->bendingScale = bendingScale;
                      return 0U;
                  });
}

Result<Edit> mirrorPanel(GarmentDocument& d, PanelId panel) {
    return record(d, "mirror panel #" + std::to_string(panel.value), {panel}, seamsOn(d, panel),
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      double lo = p->outline.points.front().position.x(), hi = lo;
                      for (const doc::Point& pt : p->outline.points) {
                          lo = std::min(lo, pt.position.x());
                          hi = std::max(hi, pt.position.x());
                      }
                      const double axis = 0.5 * (lo + hi);
                      std::set<EdgeId> reversed = edgeIds(p->outline);
                      mirrorChain(p->outline.points, p->outline.edges, axis);
                      reverseContour(p->outline);
                      for (doc::Hole& h : p->holes) {
                          mirrorChain(h.contour.points, h.contour.edges, axis);
                          reverseContour(h.contour);
                          const auto ids = edgeIds(h.contour);
                          reversed.insert(ids.begin(), ids.end());
                      }
                      for (doc::InternalLine& l : p->internalLines) {
                          mirrorChain(l.points, l.edges, axis);
                      }
                      for (doc::Dart& dart : p->darts) {
                          std::swap(dart.leg1, dart.leg2);
                      }
                      for (doc::Notch& n : p->notches) {
                          n.t = 1 - n.t;
                      }
                      for (doc::Pin& pin : p->pins) {
                          pin.point.x() = 2 * axis - pin.point.x();
                      }
                      p->grainAngle = M_PI - p->grainAngle;
                      for (doc::Seam& s : doc.seams) {
                          for (auto* side : {&s.a, &s.b}) {
                              for (doc::SeamRange& r : *side) {
                                  if (r.panel == panel && reversed.count(r.edge) != 0) {
                                      r.t0 = 1 - r.t0;
                                      r.t1 = 1 - r.t1;
                                  }
                              }
                          }
                      }
                      return 0U;
                  });
}

Result<Edit> duplicatePanel(GarmentDocument& d, PanelId panel, std::string name) {
    return record(d, "duplicate panel #" + std::to_string(panel.value), {}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      const doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      if (auto ok = checkNewName(doc, name, PanelId{}); !ok.ok()) {
                          return ok;
                      }
                      // Through the drawing, which hands out new ids for everything.
                      GarmentDocument one;
                      one.panels.push_back(*p);
                      Panel drawn = toGarment(one).panels.front();
                      drawn.name = name;
                      doc.panels.push_back(panelFromDrawing(doc, drawn));
                      return doc.panels.back().id.value;
                  });
}

Result<Edit> renamePanel(GarmentDocument& d, PanelId panel, std::string name) {
    return record(d, "rename panel #" + std::to_string(panel.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      if (auto ok = checkNewName(doc, name, panel); !ok.ok()) {
                          return ok;
                      }
                      p->name = name;
                      return 0U;
                  });
}

Result<Edit> placePanel(GarmentDocument& d, PanelId panel, const Placement& placement) {
    return placePanels(d, {{panel, placement}});
}

Result<Edit> placePanels(GarmentDocument& d,
                         const std::vector<std::pair<PanelId, Placement>>& placements) {
    std::vector<PanelId> ids;
    for (const auto& [panel, placement] : placements) {
        ids.push_back(panel);
    }
    const std::string description = placements.size() == 1
                                        ? "place panel #" + std::to_string(ids.front().value)
                                        : "place " + std::to_string(placements.size()) + " panels";
    return record(d, description, ids, {}, [&](GarmentDocument& doc) -> Result<std::uint32_t> {
        if (placements.empty()) {
            return editError("", "no panel to place");
        }
        for (const auto& [panel, placement] : placements) {
            doc::Panel* p = doc.panel(panel);
            if (p == nullptr) {
                return editError(panelWhere(panel), "no such panel");
            }
            if (!placement.offset.allFinite() || !std::isfinite(placement.rotation) ||
                !(placement.clearance >= 0)) {
                return editError(panelWhere(panel), "placement values must be finite");
            }
            p->placement = placement;
        }
        return 0U;
    });
}

std::vector<std::pair<PanelId, Placement>> sideBySide(const GarmentDocument& d,
                                                      const std::vector<PanelId>& panels,
                                                      const std::string& slot, double gap) {
    // Each panel's extent around the slot [lo, hi] about its own origin on it, as
    // placementCoordinates lays it: mirrored for a Back panel, centred on its box, turned.
    constexpr int SAMPLES = 8; // per outline edge
    std::vector<std::pair<PanelId, Placement>> out;
    std::vector<std::pair<double, double>> extents;
    for (const PanelId id : panels) {
        const doc::Panel* p = d.panel(id);
        if (p == nullptr || p->outline.edges.empty()) {
            continue;
        }
        std::vector<Vec2> points;
        for (std::size_t i = 0; i < p->outline.edges.size(); ++i) {
            const Segment s = contourSegment(p->outline, i);
            for (int k = 0; k < SAMPLES; ++k) {
                Vec2 q = pointAt(s, static_cast<double>(k) / SAMPLES);
                if (p->side == PanelSide::Back) {
                    q.x() = -q.x();
                }
                points.push_back(q);
            }
        }
        Vec2 lo = points.front(), hi = points.front();
        for (const Vec2& q : points) {
            lo = lo.cwiseMin(q);
            hi = hi.cwiseMax(q);
        }
        const Vec2 centre = 0.5 * (lo + hi);
        const double c = std::cos(p->placement.rotation), s = std::sin(p->placement.rotation);
        double left = std::numeric_limits<double>::infinity(), right = -left;
        for (const Vec2& q : points) {
            const double u = c * (q.x() - centre.x()) - s * (q.y() - centre.y());
            left = std::min(left, u);
            right = std::max(right, u);
        }
        Placement placement = p->placement;
        placement.slot = slot;
        out.emplace_back(id, placement);
        extents.emplace_back(left, right);
    }
    // Left to right from 0, then the whole row moved so that its middle is the slot's.
    double cursor = 0;
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i].second.offset.x() = cursor - extents[i].first;
        cursor += extents[i].second - extents[i].first + gap;
    }
    const double middle = 0.5 * (cursor - gap);
    for (auto& [id, placement] : out) {
        placement.offset.x() -= middle;
    }
    return out;
}

Result<Edit> setPanelParticleDistance(GarmentDocument& d, PanelId panel, double distance) {
    return record(d, "particle distance of panel #" + std::to_string(panel.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      if (!(distance == 0 || (distance >= MIN_PANEL_PARTICLE_DISTANCE &&
                                              distance <= MAX_PANEL_PARTICLE_DISTANCE))) {
                          return editError(panelWhere(panel),
                                           "a particle distance must be 0 (the drape's) or "
                                           "between 1 and 1000 mm");
                      }
                      p->particleDistance = distance;
                      return 0U;
                  });
}

Result<Edit> setPanelMaterial(GarmentDocument& d, PanelId panel, std::string material) {
    return record(
        d, "fabric of panel #" + std::to_string(panel.value), {panel}, {},
        [&](GarmentDocument& doc) -> Result<std::uint32_t> {
            doc::Panel* p = doc.panel(panel);
            if (p == nullptr) {
                return editError(panelWhere(panel), "no such panel");
            }
            if (std::none_of(doc.materials.begin(), doc.materials.end(),
                             [&](const GarmentMaterial& m) { return m.name == material; })) {
                return editError(panelWhere(panel),
                                 "no fabric \"" + material + "\" in the document");
            }
            p->material = std::move(material);
            return 0U;
        });
}

Result<Edit> setMaterial(GarmentDocument& d, const GarmentMaterial& material) {
    const std::string where = "fabric \"" + material.name + "\"";
    if (material.name.empty()) {
        return editError("fabric", "a fabric name must not be empty");
    }
    const sim::Material& m = material.material;
    struct Rule {
        const char* name;
        double value;
        bool positive;
        double below;
    };
    constexpr double ANY = std::numeric_limits<double>::infinity();
    for (const Rule& r :
         {Rule{"density", m.density, true, ANY}, Rule{"weft stretch", m.stretchWeft, true, ANY},
          Rule{"warp stretch", m.stretchWarp, true, ANY}, Rule{"shear", m.shear, true, ANY},
          Rule{"Poisson's ratio", m.poisson, false, 1}, Rule{"bending", m.bending, false, ANY},
          Rule{"weft bending", m.bendingWeft, false, ANY},
          Rule{"warp bending", m.bendingWarp, false, ANY},
          Rule{"bias bending", m.bendingBias, false, ANY},
          Rule{"stretch knee strain", m.stretchKnee, false, 1},
          Rule{"weft stretch beyond the knee", m.stretchWeftBeyond, false, ANY},
          Rule{"warp stretch beyond the knee", m.stretchWarpBeyond, false, ANY},
          Rule{"damping", m.damping, false, ANY},
          Rule{"static friction", m.staticFriction, false, ANY},
          Rule{"kinetic friction", m.kineticFriction, false, ANY},
          Rule{"plastic yield angle", m.plasticYieldAngle, false, ANY},
          Rule{"plastic rate", m.plasticRate, false, ANY}}) {
        const bool sign = r.positive ? r.value > 0 : r.value >= 0;
        if (!std::isfinite(r.value) || !sign || !(r.value < r.below)) {
            return editError(where, std::string(r.name) + " must be " +
                                        (r.positive ? "positive" : "at least 0") +
                                        (r.below < ANY ? " and below 1" : "") + " (found " +
                                        std::to_string(r.value) + ")");
        }
    }
    if (sim::BendingRigidity rigidity; const auto why = sim::bendingRigidity(m, rigidity)) {
        return editError(where, *why);
    }
    Edit edit;
    edit.description = where;
    edit.nextIdBefore = d.nextId;
    edit.nextIdAfter = d.nextId;
    edit.materialsBefore = d.materials;
    auto same = std::find_if(d.materials.begin(), d.materials.end(),
                             [&](const GarmentMaterial& g) { return g.name == material.name; });
    if (same != d.materials.end()) {
        same->material = material.material;
    } else {
        d.materials.push_back(material);
    }
    edit.materialsAfter = d.materials;
    return edit;
}

} // namespace atelier::patterns
