#include "patterns/curve.h"
#include "patterns/document_edit.h"
#include "patterns/document_edit_detail.h"
#include "patterns/mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

// Edits of a panel's marks: pins, notches, internal lines, darts and the grain line.

namespace atelier::patterns {

using namespace detail;

Result<Edit> addPin(GarmentDocument& d, PanelId panel, const doc::Pin& pin) {
    return record(
        d, "pin panel #" + std::to_string(panel.value), {panel}, {},
        [&](GarmentDocument& doc) -> Result<std::uint32_t> {
            doc::Panel* p = doc.panel(panel);
            if (p == nullptr) {
                return editError(panelWhere(panel), "no such panel");
            }
            if (pin.notch) {
                if (std::none_of(p->notches.begin(), p->notches.end(),
                                 [&](const doc::Notch& n) { return n.id == pin.notch; })) {
                    return editError(panelWhere(panel),
                                     "no notch #" + std::to_string(pin.notch.value));
                }
            } else {
                GarmentDocument one;
                one.panels.push_back(*p);
                if (!insidePanel(toGarment(one).panels.front(), pin.point)) {
                    return editError(panelWhere(panel), "the pin's point is not inside the panel");
                }
            }
            if ((pin.position && !(pin.position->cwiseAbs().maxCoeff() <= MAX_PIN_POSITION)) ||
                !(pin.releaseTime >= 0)) {
                return editError(panelWhere(panel),
                                 "a pin's position must be within 10 m of the "
                                 "body's origin and its release time at least 0");
            }
            doc::Pin added = pin;
            added.id = doc.newId<PinId>();
            p->pins.push_back(added);
            return added.id.value;
        });
}

Result<Edit> removePin(GarmentDocument& d, PanelId panel, PinId pin) {
    return record(
        d, "unpin #" + std::to_string(pin.value), {panel}, {},
        [&](GarmentDocument& doc) -> Result<std::uint32_t> {
            doc::Panel* p = doc.panel(panel);
            if (p == nullptr) {
                return editError(panelWhere(panel), "no such panel");
            }
            if (std::erase_if(p->pins, [&](const doc::Pin& q) { return q.id == pin; }) == 0) {
                return editError(panelWhere(panel), "no pin #" + std::to_string(pin.value));
            }
            return 0U;
        });
}

namespace {

/// `panel` alone as the mesher's panel (for inside tests).
Panel garmentPanel(const doc::Panel& panel) {
    GarmentDocument one;
    one.panels.push_back(panel);
    return toGarment(one).panels.front();
}

/// Whether the straight line from `a` to `b` lies inside the panel (sampled every few mm and
/// at least 16 times, ends included).
bool lineInside(const Panel& panel, const Vec2& a, const Vec2& b) {
    const int n = std::max(16, static_cast<int>(std::ceil((b - a).norm() / 0.002)));
    for (int k = 0; k <= n; ++k) {
        if (!insidePanel(panel, a + (b - a) * (static_cast<double>(k) / n))) {
            return false;
        }
    }
    return true;
}

doc::InternalLine* internalLine(doc::Panel& p, LineId id) {
    auto it = std::find_if(p.internalLines.begin(), p.internalLines.end(),
                           [&](const doc::InternalLine& l) { return l.id == id; });
    return it == p.internalLines.end() ? nullptr : &*it;
}

Result<std::uint32_t> checkFoldAngle(PanelId panel, double angle) {
    if (!(std::abs(angle) < M_PI)) {
        return editError(panelWhere(panel), "a fold angle must be within (-pi, pi) rad (found " +
                                                std::to_string(angle) + ")");
    }
    return 0U;
}

} // namespace

Result<Edit> addNotch(GarmentDocument& d, PanelId panel, EdgeId edge, double t) {
    return record(d, "add notch on edge #" + std::to_string(edge.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      if (outlineEdgeIndex(*p, edge) < 0) {
                          return editError(panelWhere(panel),
                                           "no outline edge #" + std::to_string(edge.value));
                      }
                      if (!(t >= 0 && t <= 1)) {
                          return editError(panelWhere(panel),
                                           "a notch's curve parameter must be within [0, 1]");
                      }
                      const doc::Notch notch{doc.newId<NotchId>(), edge, t};
                      p->notches.push_back(notch);
                      return notch.id.value;
                  });
}

Result<Edit> removeNotch(GarmentDocument& d, PanelId panel, NotchId notch) {
    return record(d, "remove notch #" + std::to_string(notch.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      for (const doc::Pin& pin : p->pins) {
                          if (pin.notch == notch) {
                              return editError(panelWhere(panel),
                                               "pin #" + std::to_string(pin.id.value) +
                                                   " holds notch #" + std::to_string(notch.value));
                          }
                      }
                      if (std::erase_if(p->notches,
                                        [&](const doc::Notch& n) { return n.id == notch; }) == 0) {
                          return editError(panelWhere(panel),
                                           "no notch #" + std::to_string(notch.value));
                      }
                      return 0U;
                  });
}

Result<Edit> addInternalLine(GarmentDocument& d, PanelId panel, const std::vector<Vec2>& points,
                             double foldAngle) {
    return record(
        d, "add internal line to panel #" + std::to_string(panel.value), {panel}, {},
        [&](GarmentDocument& doc) -> Result<std::uint32_t> {
            doc::Panel* p = doc.panel(panel);
            if (p == nullptr) {
                return editError(panelWhere(panel), "no such panel");
            }
            if (points.size() < 2) {
                return editError(panelWhere(panel), "an internal line needs at least 2 points");
            }
            if (auto fold = checkFoldAngle(panel, foldAngle); !fold.ok()) {
                return fold;
            }
            const Panel shape = garmentPanel(*p);
            for (std::size_t k = 0; k < points.size(); ++k) {
                if (!points[k].allFinite()) {
                    return editError(panelWhere(panel), "an internal line's points must be finite");
                }
                if (k > 0 && (points[k] - points[k - 1]).norm() < 1e-4) {
                    return editError(panelWhere(panel),
                                     "an internal line's consecutive points must be apart");
                }
                if (k > 0 ? !lineInside(shape, points[k - 1], points[k])
                          : !insidePanel(shape, points[k])) {
                    return editError(panelWhere(panel),
                                     "an internal line must lie inside the panel");
                }
            }
            doc::InternalLine line;
            line.id = doc.newId<LineId>();
            line.foldAngle = foldAngle;
            for (const Vec2& at : points) {
                line.points.push_back({doc.newId<PointId>(), at});
            }
            for (std::size_t k = 0; k + 1 < points.size(); ++k) {
                line.edges.push_back({doc.newId<EdgeId>(), doc::Curve{}});
            }
            p->internalLines.push_back(std::move(line));
            return p->internalLines.back().id.value;
        });
}

Result<Edit> removeInternalLine(GarmentDocument& d, PanelId panel, LineId line) {
    return record(d, "remove internal line #" + std::to_string(line.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      if (std::erase_if(p->internalLines, [&](const doc::InternalLine& l) {
                              return l.id == line;
                          }) == 0) {
                          return editError(panelWhere(panel),
                                           "no internal line #" + std::to_string(line.value));
                      }
                      return 0U;
                  });
}

Result<Edit> setFoldAngle(GarmentDocument& d, PanelId panel, LineId line, double angle) {
    return record(d, "fold internal line #" + std::to_string(line.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      doc::InternalLine* l = p != nullptr ? internalLine(*p, line) : nullptr;
                      if (l == nullptr) {
                          return editError(panelWhere(panel),
                                           "no internal line #" + std::to_string(line.value));
                      }
                      if (auto fold = checkFoldAngle(panel, angle); !fold.ok()) {
                          return fold;
                      }
                      l->foldAngle = angle;
                      return 0U;
                  });
}

Result<Edit> addDart(GarmentDocument& d, PanelId panel, EdgeId edge, double t, double width,
                     double depth) {
    return record(
        d, "add dart on edge #" + std::to_string(edge.value), {panel}, seamsOn(d, panel, edge),
        [&](GarmentDocument& doc) -> Result<std::uint32_t> {
            doc::Panel* p = doc.panel(panel);
            if (p == nullptr) {
                return editError(panelWhere(panel), "no such panel");
            }
            const int k = outlineEdgeIndex(*p, edge);
            if (k < 0) {
                return editError(panelWhere(panel),
                                 "no outline edge #" + std::to_string(edge.value));
            }
            if (!(width > 0) || !(depth > 0) || !std::isfinite(width) || !std::isfinite(depth)) {
                return editError(panelWhere(panel), "a dart's width and depth must be positive");
            }
            if (!(t > 0 && t < 1)) {
                return editError(panelWhere(panel), "a dart's centre must be within (0, 1)");
            }
            const Panel shape = garmentPanel(*p);
            const Segment s = contourSegment(p->outline, static_cast<std::size_t>(k));
            const double length = arcLength(s), centre = arcLength(s, 0, t);
            if (!(centre - width / 2 > 1e-4 && centre + width / 2 < length - 1e-4)) {
                return editError(panelWhere(panel), "the dart is wider than its edge allows");
            }
            const double t0 = parameterAtLength(s, 0, 1, centre - width / 2);
            const double t1 = parameterAtLength(s, 0, 1, centre + width / 2);
            // Split at t0 (edge keeps its id up to A), then the second half at t1 (A → B is the
            // new edge, B → on another new one), then A → B in the middle for the tip.
            auto a = splitEdgeIn(doc, panel, edge, t0);
            if (!a.ok()) {
                return a;
            }
            p = doc.panel(panel);
            const EdgeId middle = p->outline.edges[static_cast<std::size_t>(k) + 1].id;
            auto b = splitEdgeIn(doc, panel, middle, (t1 - t0) / (1 - t0));
            if (!b.ok()) {
                return b;
            }
            if (!seamsOn(doc, panel, middle).empty() ||
                std::any_of(p->notches.begin(), p->notches.end(),
                            [&](const doc::Notch& n) { return n.edge == middle; })) {
                return editError(panelWhere(panel),
                                 "the dart would cut a seam or a notch on edge #" +
                                     std::to_string(edge.value));
            }
            auto tip = splitEdgeIn(doc, panel, middle, 0.5);
            if (!tip.ok()) {
                return tip;
            }
            const std::size_t i = static_cast<std::size_t>(k) + 1; // leg1 = A → tip
            const Vec2 pa = p->outline.points[i].position, pb = p->outline.points[i + 2].position;
            const Vec2 chord = pb - pa;
            // The outline runs counter-clockwise, so the inside is to the left of its direction.
            const Vec2 inward = Vec2(-chord.y(), chord.x()).normalized();
            const Vec2 at = 0.5 * (pa + pb) + depth * inward;
            p->outline.points[i + 1].position = at;
            p->outline.edges[i].curve = doc::Curve{};
            p->outline.edges[i + 1].curve = doc::Curve{};
            if (!lineInside(shape, pa + 1e-3 * (at - pa), at) ||
                !lineInside(shape, at, pb + 1e-3 * (at - pb))) {
                return editError(panelWhere(panel), "the dart's tip must lie inside the panel");
            }
            const doc::Dart dart{doc.newId<DartId>(), p->outline.edges[i].id,
                                 p->outline.edges[i + 1].id};
            p->darts.push_back(dart);
            return dart.id.value;
        });
}

namespace {

/// The outline indices of a dart's first base point (its first leg's start), tip and second
/// base point; nullopt when its legs are not consecutive outline edges.
std::optional<std::array<std::size_t, 3>> dartPoints(const doc::Panel& p, const doc::Dart& dart) {
    const int k1 = outlineEdgeIndex(p, dart.leg1), k2 = outlineEdgeIndex(p, dart.leg2);
    const auto n = static_cast<int>(p.outline.points.size());
    if (k1 < 0 || k2 < 0 || n < 4 || k2 != (k1 + 1) % n) {
        return std::nullopt;
    }
    return std::array<std::size_t, 3>{static_cast<std::size_t>(k1), static_cast<std::size_t>(k2),
                                      static_cast<std::size_t>((k2 + 1) % n)};
}

} // namespace

std::optional<DartSize> dartSize(const doc::Panel& panel, DartId dart) {
    const auto it = std::find_if(panel.darts.begin(), panel.darts.end(),
                                 [&](const doc::Dart& x) { return x.id == dart; });
    const auto at = it == panel.darts.end() ? std::nullopt : dartPoints(panel, *it);
    if (!at) {
        return std::nullopt;
    }
    const Vec2 a = panel.outline.points[(*at)[0]].position;
    const Vec2 tip = panel.outline.points[(*at)[1]].position;
    const Vec2 b = panel.outline.points[(*at)[2]].position;
    return DartSize{(b - a).norm(), (tip - 0.5 * (a + b)).norm()};
}

Result<Edit> setDartSize(GarmentDocument& d, PanelId panel, DartId dart, double width,
                         double depth) {
    return record(
        d, "resize dart #" + std::to_string(dart.value), {panel}, {},
        [&](GarmentDocument& doc) -> Result<std::uint32_t> {
            doc::Panel* p = doc.panel(panel);
            if (p == nullptr) {
                return editError(panelWhere(panel), "no such panel");
            }
            const auto it = std::find_if(p->darts.begin(), p->darts.end(),
                                         [&](const doc::Dart& x) { return x.id == dart; });
            const auto at = it == p->darts.end() ? std::nullopt : dartPoints(*p, *it);
            if (!at) {
                return editError(panelWhere(panel), "no dart #" + std::to_string(dart.value));
            }
            if (!(width > 0) || !(depth > 0) || !std::isfinite(width) || !std::isfinite(depth)) {
                return editError(panelWhere(panel), "a dart's width and depth must be positive");
            }
            auto& points = p->outline.points;
            const std::size_t n = points.size();
            const auto [ia, itip, ib] = *at;
            const Vec2 a = points[ia].position, tip = points[itip].position;
            const Vec2 b = points[ib].position;
            const Vec2 middle = 0.5 * (a + b), along = (b - a).normalized();
            // The bases slide along the chord about its middle; each must stay short of the far
            // end of the outline edge it shares (which keeps its curve handles, as movePoint).
            const Vec2 a2 = middle - 0.5 * width * along, b2 = middle + 0.5 * width * along;
            const Vec2 before = points[(ia + n - 1) % n].position;
            const Vec2 after = points[(ib + 1) % n].position;
            if ((a2 - before).dot(a - before) < 1e-4 * (a - before).norm() ||
                (b2 - after).dot(b - after) < 1e-4 * (b - after).norm()) {
                return editError(panelWhere(panel), "the dart is wider than its edge allows");
            }
            // The tip keeps its direction from the chord's middle.
            const Vec2 tip2 = middle + depth * (tip - middle).normalized();
            // Inside the panel as it would be without the dart, as addDart checks.
            doc::Panel closed = *p;
            closed.darts.clear();
            closed.outline.points.erase(closed.outline.points.begin() +
                                        static_cast<std::ptrdiff_t>(itip));
            closed.outline.edges.erase(closed.outline.edges.begin() +
                                       static_cast<std::ptrdiff_t>(itip));
            closed.outline.edges[(itip + n - 2) % (n - 1)].curve = doc::Curve{};
            const Panel shape = garmentPanel(closed);
            if (!lineInside(shape, a2 + 1e-3 * (tip2 - a2), tip2) ||
                !lineInside(shape, tip2, b2 + 1e-3 * (tip2 - b2))) {
                return editError(panelWhere(panel), "the dart's tip must lie inside the panel");
            }
            points[ia].position = a2;
            points[itip].position = tip2;
            points[ib].position = b2;
            return 0U;
        });
}

Result<Edit> removeDart(GarmentDocument& d, PanelId panel, DartId dart) {
    return record(
        d, "remove dart #" + std::to_string(dart.value), {panel}, {},
        [&](GarmentDocument& doc) -> Result<std::uint32_t> {
            doc::Panel* p = doc.panel(panel);
            if (p == nullptr) {
                return editError(panelWhere(panel), "no such panel");
            }
            auto it = std::find_if(p->darts.begin(), p->darts.end(),
                                   [&](const doc::Dart& x) { return x.id == dart; });
            if (it == p->darts.end()) {
                return editError(panelWhere(panel), "no dart #" + std::to_string(dart.value));
            }
            const doc::Dart found = *it;
            for (const EdgeId leg : {found.leg1, found.leg2}) {
                const bool notched =
                    std::any_of(p->notches.begin(), p->notches.end(),
                                [&](const doc::Notch& n) { return n.edge == leg; });
                if (!seamsOn(doc, panel, leg).empty() || notched) {
                    return editError(panelWhere(panel), "edge #" + std::to_string(leg.value) +
                                                            " of the dart has a seam or notch");
                }
            }
            const int k = outlineEdgeIndex(*p, found.leg2);
            if (k < 0 || p->outline.points.size() <= 3) {
                return editError(panelWhere(panel), "the dart's outline is too small to remove it");
            }
            p->darts.erase(it);
            const std::size_t i = static_cast<std::size_t>(k);
            // Point i is the tip, edge i the second leg: both go, the first leg runs on to the
            // second leg's end.
            p->outline.points.erase(p->outline.points.begin() + static_cast<std::ptrdiff_t>(i));
            p->outline.edges.erase(p->outline.edges.begin() + static_cast<std::ptrdiff_t>(i));
            p->outline.edges[i - 1].curve = doc::Curve{};
            return 0U;
        });
}

Result<Edit> setGrainAngle(GarmentDocument& d, PanelId panel, double angle) {
    return record(d, "set grain of panel #" + std::to_string(panel.value), {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      if (!std::isfinite(angle)) {
                          return editError(panelWhere(panel), "a grain angle must be finite");
                      }
                      double a = std::remainder(angle, 2 * M_PI);
                      if (a <= -M_PI) {
                          a += 2 * M_PI;
                      }
                      p->grainAngle = a;
                      return 0U;
                  });
}

Result<Edit> setSheetPlace(GarmentDocument& d, PanelId panel,
                           std::optional<doc::SheetPlace> place) {
    return record(d, "move panel #" + std::to_string(panel.value) + " on the sheet", {panel}, {},
                  [&](GarmentDocument& doc) -> Result<std::uint32_t> {
                      doc::Panel* p = doc.panel(panel);
                      if (p == nullptr) {
                          return editError(panelWhere(panel), "no such panel");
                      }
                      if (place) {
                          constexpr double FAR = 1000; // [m]
                          if (!place->at.allFinite() || place->at.cwiseAbs().maxCoeff() > FAR ||
                              !std::isfinite(place->angle)) {
                              return editError(panelWhere(panel),
                                               "a sheet place must be finite and within 1 km");
                          }
                          place->angle = std::remainder(place->angle, 2 * M_PI);
                          if (place->angle <= -M_PI) {
                              place->angle += 2 * M_PI;
                          }
                      }
                      p->sheet = place;
                      return 0U;
                  });
}

} // namespace atelier::patterns
