#include "io/garmentcode.h"

#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/materials.h"

#include "patterns/curve.h"
#include "patterns/document.h"
#include "patterns/mesh.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <utility>

namespace atelier::io {

namespace {

using detail::arrayAt;
using detail::childPointer;
using detail::inQuotes;
using detail::JsonError;
using detail::numberAt;
using detail::typeName;
using nlohmann::json;
using patterns::Segment;
using patterns::SegmentKind;
using sim::Vec2;
using sim::Vec3;

/// Sleeves: panels whose centre is farther than this from the garment's middle in x [m].
constexpr double ARM_OFFSET = 0.3;
/// Sleeves start this far down the arm from the shoulder joint [m]: with their top at the
/// joint, the shirt_mean specification's sleeves started 4.5 mm inside the body at 10 mm, and
/// at 20 mm its seams closed at 1.42 s instead of 0.58 s.
constexpr double SLEEVE_DROP = 0.03;
/// A stitch whose sides' lengths differ by more than this fraction of the longer one warns.
constexpr double STITCH_LENGTH_RATIO = 0.2;

/// `text` with `//` and `/* */` comments outside strings replaced by spaces (newlines kept, so
/// that line and column numbers stay right).
std::string withoutComments(std::string_view text) {
    std::string out(text);
    bool inString = false;
    for (std::size_t i = 0; i < out.size(); ++i) {
        const char c = out[i];
        if (inString) {
            if (c == '\\') {
                ++i;
            } else if (c == '"') {
                inString = false;
            }
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == '/' && i + 1 < out.size() && out[i + 1] == '/') {
            for (; i < out.size() && out[i] != '\n'; ++i) {
                out[i] = ' ';
            }
        } else if (c == '/' && i + 1 < out.size() && out[i + 1] == '*') {
            const std::size_t close = out.find("*/", i + 2);
            const std::size_t stop = close == std::string::npos ? out.size() : close + 2;
            for (std::size_t k = i; k < stop; ++k) {
                if (out[k] != '\n') {
                    out[k] = ' ';
                }
            }
            i = stop - 1;
        }
    }
    return out;
}

[[noreturn]] void fail(const std::string& pointer, std::string message) {
    throw JsonError{pointer.empty() ? "/" : pointer, std::move(message)};
}

const json& member(const json& object, const std::string& pointer, const char* key) {
    if (!object.is_object()) {
        fail(pointer, "expected an object, found " + typeName(object));
    }
    const auto it = object.find(key);
    if (it == object.end()) {
        fail(pointer, std::string("missing \"") + key + "\"");
    }
    return *it;
}

Vec2 vec2At(const json& value, const std::string& pointer) {
    if (!value.is_array() || value.size() != 2) {
        fail(pointer, "must be an array of two finite numbers, found " + typeName(value));
    }
    return {numberAt(value[0], childPointer(pointer, 0)),
            numberAt(value[1], childPointer(pointer, 1))};
}

/// One panel as the specification gives it, in metres.
struct SpecPanel {
    std::string name;
    std::string pointer;
    std::vector<Vec2> vertices;
    std::vector<std::pair<int, int>> endpoints; ///< per edge
    std::vector<Segment> edges;                 ///< per edge, in its direction [m]
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Vec3 translation = Vec3::Zero(); ///< [m]
    bool reversed = false;           ///< its loop is clockwise: our outline runs backward

    Vec3 world(const Vec2& p) const { return rotation * Vec3(p.x(), p.y(), 0) + translation; }
    Vec3 centroid() const {
        Vec3 c = Vec3::Zero();
        for (const Vec2& p : vertices) {
            c += world(p);
        }
        return c / static_cast<double>(vertices.size());
    }
    /// The normal of the panel's loop (counter-clockwise around it) in 3D: where its outside
    /// faces in their convention.
    Vec3 normal() const { return reversed ? Vec3(-rotation.col(2)) : Vec3(rotation.col(2)); }
    /// Index of spec edge `e` in our outline.
    int segmentOf(int e) const { return reversed ? static_cast<int>(edges.size()) - 1 - e : e; }
};

struct Context {
    double unitsInMeter = 100;
    bool relative = true;
    const Limits* limits = nullptr;
    std::vector<std::string> warnings;
};

std::string edgeName(const SpecPanel& panel, std::size_t e) {
    return "panel " + inQuotes(panel.name) + ": edge " + std::to_string(e);
}

/// A point given in the edge's frame (x along the chord start → end, y the chord turned a
/// quarter counter-clockwise, both in chord lengths) or, with absolute coordinates, as is.
Vec2 controlPoint(const Vec2& c, const Vec2& start, const Vec2& end, const Context& ctx) {
    if (!ctx.relative) {
        return c / ctx.unitsInMeter;
    }
    const Vec2 along = end - start;
    const Vec2 across(-along.y(), along.x());
    return start + c.x() * along + c.y() * across;
}

/// A number as JSON writes it (`100`, `0.25`), for messages.
std::string num(double v) {
    return json(v).dump();
}

/// A length in whole millimetres (`312 mm`), for messages.
std::string millimetres(double metres) {
    return std::to_string(std::lround(metres * 1000)) + " mm";
}

void checkCoordinate(const Vec2& p, const std::string& pointer, const Context& ctx) {
    if (!(p.cwiseAbs().maxCoeff() <= ctx.limits->maxSceneCoordinate)) {
        fail(pointer, "coordinate beyond " + num(ctx.limits->maxSceneCoordinate) +
                          " m after units_in_meter " + num(ctx.unitsInMeter) +
                          " (the limit scene-coordinate-m)");
    }
}

/// The segment of one edge from `start` to `end` [m].
Segment readCurvature(const json& curvature, const std::string& pointer, const Vec2& start,
                      const Vec2& end, const SpecPanel& panel, std::size_t e, Context& ctx) {
    Segment s;
    s.start = start;
    s.end = end;
    if (curvature.is_array()) {
        // The older dataset: one control point of a quadratic Bézier.
        s.kind = SegmentKind::Quadratic;
        s.control1 = controlPoint(vec2At(curvature, pointer), start, end, ctx);
        checkCoordinate(s.control1, pointer, ctx);
        return s;
    }
    if (!curvature.is_object()) {
        fail(pointer, "must be an array [x, y] or an object {\"type\", \"params\"}, found " +
                          typeName(curvature));
    }
    const json& type = member(curvature, pointer, "type");
    const std::string typePointer = childPointer(pointer, "type");
    if (!type.is_string()) {
        fail(typePointer, "must be a string, found " + typeName(type));
    }
    const std::string kind = type.get<std::string>();
    const std::string paramsPointer = childPointer(pointer, "params");
    const json& params = member(curvature, pointer, "params");
    if (!params.is_array()) {
        fail(paramsPointer, "must be an array, found " + typeName(params));
    }
    auto controls = [&](std::size_t n) {
        if (params.size() != n) {
            fail(paramsPointer, "a " + kind + " curve needs " + std::to_string(n) +
                                    " control point" + (n == 1 ? "" : "s") + ", found " +
                                    std::to_string(params.size()));
        }
        std::vector<Vec2> out;
        for (std::size_t i = 0; i < n; ++i) {
            const std::string p = childPointer(paramsPointer, i);
            out.push_back(controlPoint(vec2At(params[i], p), start, end, ctx));
            checkCoordinate(out.back(), p, ctx);
        }
        return out;
    };
    if (kind == "quadratic") {
        s.kind = SegmentKind::Quadratic;
        s.control1 = controls(1)[0];
    } else if (kind == "cubic") {
        const std::vector<Vec2> c = controls(2);
        s.kind = SegmentKind::Cubic;
        s.control1 = c[0];
        s.control2 = c[1];
    } else if (kind == "circle") {
        // [radius, large_arc, right]: radius in pattern units; the arc bulges to the right of
        // the edge's direction when `right` is true.
        if (params.size() != 3) {
            fail(paramsPointer, "a circle arc needs [radius, large_arc, right], found " +
                                    std::to_string(params.size()) + " values");
        }
        const double radius =
            numberAt(params[0], childPointer(paramsPointer, 0)) / ctx.unitsInMeter;
        auto flag = [&](std::size_t i) {
            const json& v = params[i];
            if (v.is_boolean()) {
                return v.get<bool>();
            }
            return numberAt(v, childPointer(paramsPointer, i)) != 0;
        };
        const bool largeArc = flag(1);
        const bool right = flag(2);
        const double chord = (end - start).norm();
        double half = 0.5 * chord / std::max(radius, 1e-300);
        if (!(radius > 0)) {
            fail(childPointer(paramsPointer, 0), "the radius must be > 0");
        }
        if (half > 1) {
            ctx.warnings.push_back(edgeName(panel, e) + ": circle radius " +
                                   std::to_string(radius) + " m is shorter than half the chord (" +
                                   std::to_string(0.5 * chord) + " m); imported as a half circle");
            half = 1;
        }
        const double small = 2 * std::asin(half);
        const double sweep = largeArc ? 2 * std::numbers::pi - small : small;
        s.kind = SegmentKind::Arc;
        // Positive bulge: counter-clockwise from start to end, i.e. bulging to the right.
        s.bulge = (right ? 1.0 : -1.0) * std::tan(sweep / 4);
    } else {
        ctx.warnings.push_back(edgeName(panel, e) + ": curvature type " + inQuotes(kind) +
                               " is not supported (quadratic, cubic, circle); imported straight");
    }
    return s;
}

SpecPanel readPanel(const std::string& name, const json& value, const std::string& pointer,
                    Context& ctx) {
    SpecPanel panel;
    panel.name = name;
    panel.pointer = pointer;
    if (!value.is_object()) {
        fail(pointer, "expected an object, found " + typeName(value));
    }
    for (const auto& [key, _] : value.items()) {
        if (key != "vertices" && key != "edges" && key != "translation" && key != "rotation") {
            ctx.warnings.push_back("panel " + inQuotes(name) + ": key " + inQuotes(key) +
                                   " ignored");
        }
    }
    const std::string vp = childPointer(pointer, "vertices");
    const json& vertices = arrayAt(member(value, pointer, "vertices"), vp);
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const std::string p = childPointer(vp, i);
        panel.vertices.push_back(vec2At(vertices[i], p) / ctx.unitsInMeter);
        checkCoordinate(panel.vertices.back(), p, ctx);
    }
    if (panel.vertices.size() < 2) {
        fail(vp,
             "a panel needs at least 2 vertices, found " + std::to_string(panel.vertices.size()));
    }
    const std::string ep = childPointer(pointer, "edges");
    const json& edges = arrayAt(member(value, pointer, "edges"), ep);
    if (edges.size() < 2) {
        fail(ep, "a panel needs at least 2 edges, found " + std::to_string(edges.size()));
    }
    const auto nv = static_cast<long long>(panel.vertices.size());
    for (std::size_t e = 0; e < edges.size(); ++e) {
        const std::string p = childPointer(ep, e);
        const json& edge = edges[e];
        const std::string endsPointer = childPointer(p, "endpoints");
        const json& ends = member(edge, p, "endpoints");
        if (!ends.is_array() || ends.size() != 2) {
            fail(endsPointer, "must be an array of two vertex indices, found " + typeName(ends));
        }
        std::array<int, 2> idx{};
        for (std::size_t k = 0; k < 2; ++k) {
            const long long i = detail::integerAt(ends[k], childPointer(endsPointer, k));
            if (i < 0 || i >= nv) {
                fail(childPointer(endsPointer, k), "vertex " + std::to_string(i) +
                                                       " does not exist (the panel has " +
                                                       std::to_string(nv) + ")");
            }
            idx[k] = static_cast<int>(i);
        }
        if (idx[0] == idx[1]) {
            fail(endsPointer, "an edge must join two different vertices");
        }
        if (e > 0 && panel.endpoints.back().second != idx[0]) {
            fail(endsPointer, "edge " + std::to_string(e) + " starts at vertex " +
                                  std::to_string(idx[0]) + " but edge " + std::to_string(e - 1) +
                                  " ends at vertex " +
                                  std::to_string(panel.endpoints.back().second) +
                                  ": the edges must form one loop");
        }
        panel.endpoints.emplace_back(idx[0], idx[1]);
        const Vec2 a = panel.vertices[static_cast<std::size_t>(idx[0])];
        const Vec2 b = panel.vertices[static_cast<std::size_t>(idx[1])];
        Segment s;
        s.start = a;
        s.end = b;
        for (const auto& [key, _] : edge.items()) {
            if (key != "endpoints" && key != "curvature") {
                ctx.warnings.push_back(edgeName(panel, e) + ": key " + inQuotes(key) + " ignored");
            }
        }
        if (const auto c = edge.find("curvature"); c != edge.end()) {
            s = readCurvature(*c, childPointer(p, "curvature"), a, b, panel, e, ctx);
        }
        panel.edges.push_back(s);
    }
    if (panel.endpoints.back().second != panel.endpoints.front().first) {
        fail(ep, "the last edge ends at vertex " + std::to_string(panel.endpoints.back().second) +
                     ", not where the first starts (" +
                     std::to_string(panel.endpoints.front().first) + "): the loop is not closed");
    }
    const std::string tp = childPointer(pointer, "translation");
    panel.translation =
        detail::vec3At(member(value, pointer, "translation"), tp) / ctx.unitsInMeter;
    if (!(panel.translation.cwiseAbs().maxCoeff() <= ctx.limits->maxSceneCoordinate)) {
        fail(tp, "translation beyond " + num(ctx.limits->maxSceneCoordinate) +
                     " m (the limit scene-coordinate-m)");
    }
    const std::string rp = childPointer(pointer, "rotation");
    const Vec3 deg =
        value.contains("rotation") ? detail::vec3At(value.at("rotation"), rp) : Vec3(Vec3::Zero());
    if (!(deg.cwiseAbs().maxCoeff() <= 1e6)) {
        fail(rp, "rotation angles must be within ±1e6 degrees");
    }
    const Vec3 rad = deg * std::numbers::pi / 180;
    // XYZ Euler angles: about x first, then y, then z (fixed axes).
    panel.rotation =
        (Eigen::AngleAxisd(rad.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rad.y(), Vec3::UnitY()) *
         Eigen::AngleAxisd(rad.x(), Vec3::UnitX()))
            .toRotationMatrix();
    panel.reversed = patterns::loopArea(panel.edges) < 0;
    return panel;
}

Segment reversedSegment(const Segment& s) {
    Segment r = s;
    std::swap(r.start, r.end);
    if (s.kind == SegmentKind::Cubic) {
        std::swap(r.control1, r.control2);
    }
    r.bulge = -s.bulge;
    return r;
}

/// Our outline of a spec panel: counter-clockwise (reversed when the spec's loop is not).
patterns::Loop outlineOf(const SpecPanel& panel) {
    patterns::Loop loop;
    const std::size_t n = panel.edges.size();
    for (std::size_t k = 0; k < n; ++k) {
        loop.push_back(panel.reversed ? reversedSegment(panel.edges[n - 1 - k]) : panel.edges[k]);
    }
    return loop;
}

/// A seam side: spec edge `e` of `panel` from its start to its end (or backward).
patterns::SeamEdge seamEdge(const SpecPanel& panel, int e, bool backward) {
    patterns::SeamEdge s;
    s.panel = panel.name;
    s.segment = panel.segmentOf(e);
    const bool flip = backward != panel.reversed;
    s.t0 = flip ? 1.0 : 0.0;
    s.t1 = flip ? 0.0 : 1.0;
    return s;
}

/// A panel's frame on its slot: around (u) and along (v) coordinates of world points.
struct SlotFrame {
    const patterns::ArrangementSlot* slot = nullptr;
    Vec3 centre = Vec3::Zero(); ///< a point on their body part's axis [m]
    Vec3 axis = Vec3::UnitY();  ///< their body part's axis (toward the shoulder / up)
    Vec3 facing = Vec3::UnitZ();
    double vShift = 0; ///< added to along coordinates [m]
    double rho = 0.1;  ///< radius turning the panel's angle into arc length [m]
    Vec3 right() const { return axis.cross(facing); }
};

/// Places `panel` (drawn as `outline`) on its slot so that its (u, v) on the slot match its
/// world position in the specification; sets slot, side, rotation and offset.
void place(const SpecPanel& spec, const SlotFrame& f, double clearance, patterns::Panel& out,
           Context& ctx) {
    const Vec3 c = spec.centroid();
    Vec3 n = spec.normal();
    const Vec3 radial = (c - f.centre) - (c - f.centre).dot(f.axis) * f.axis;
    if (n.dot(radial) < -0.02) {
        ctx.warnings.push_back("panel " + inQuotes(spec.name) +
                               ": its edge loop runs clockwise seen from outside the body; "
                               "placed facing out");
        n = -n;
    }
    if (std::abs(n.dot(f.axis)) > 0.5) {
        ctx.warnings.push_back("panel " + inQuotes(spec.name) +
                               ": its plane is tilted more than 30° from the slot's axis; "
                               "placed as if upright");
    }
    const double phi = std::atan2(n.dot(f.right()), n.dot(f.facing));
    const Vec3 tu = std::cos(phi) * f.right() - std::sin(phi) * f.facing;
    auto uv = [&](const Vec3& x) {
        return Vec2(f.rho * phi + (x - f.centre).dot(tu), (x - f.centre).dot(f.axis) + f.vShift);
    };
    Eigen::Matrix2d m;
    m << tu.dot(spec.rotation.col(0)), tu.dot(spec.rotation.col(1)),
        f.axis.dot(spec.rotation.col(0)), f.axis.dot(spec.rotation.col(1));
    const Eigen::JacobiSVD<Eigen::Matrix2d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix2d q = svd.matrixU() * svd.matrixV().transpose();
    const bool mirrored = q.determinant() < 0;
    const Eigen::Matrix2d s = mirrored ? Eigen::Matrix2d(Eigen::Vector2d(-1, 1).asDiagonal())
                                       : Eigen::Matrix2d(Eigen::Matrix2d::Identity());
    const Eigen::Matrix2d rot = q * s;
    // U(x) ≈ q·p + u0 for the drawing point p of world point x.
    Vec2 u0 = Vec2::Zero();
    for (const Vec2& p : spec.vertices) {
        u0 += uv(spec.world(p)) - q * p;
    }
    u0 /= static_cast<double>(spec.vertices.size());
    // placementCoordinates centres the (mirrored) drawing on its bounding box's middle.
    Vec2 lo = Vec2::Constant(std::numeric_limits<double>::infinity());
    Vec2 hi = -lo;
    for (const Segment& seg : out.outline) {
        for (int k = 0; k <= 16; ++k) {
            const Vec2 p = s * patterns::pointAt(seg, k / 16.0);
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
    }
    const Vec2 middle = 0.5 * (lo + hi);
    out.side = mirrored ? patterns::PanelSide::Back : patterns::PanelSide::Front;
    out.placement.slot = f.slot->name;
    out.placement.rotation = std::atan2(rot(1, 0), rot(0, 0));
    out.placement.offset = u0 + rot * middle;
    out.placement.clearance = clearance;
}

const patterns::ArrangementSlot& slotOrFail(const patterns::Body& body, const std::string& name) {
    const patterns::ArrangementSlot* s = body.slot(name);
    if (s == nullptr) {
        fail("", "the body has no slot " + inQuotes(name) + " to place the panels on");
    }
    return *s;
}

/// Chooses slots and places every panel (panels[i] is drawn from spec[i]).
void placePanels(
    const std::vector<SpecPanel>& spec, std::vector<patterns::Panel>& panels,
    const std::vector<std::pair<std::array<std::size_t, 2>, std::array<int, 2>>>& stitches,
    const patterns::Body& body, const GarmentCodeOptions& options, Context& ctx) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    for (const SpecPanel& p : spec) {
        for (const Vec2& v : p.vertices) {
            lo = lo.cwiseMin(p.world(v));
            hi = hi.cwiseMax(p.world(v));
        }
    }
    const double midX = 0.5 * (lo.x() + hi.x());
    // Groups: 0 torso, 1 left arm (+x), 2 right arm.
    std::vector<int> group(spec.size(), 0);
    for (std::size_t i = 0; i < spec.size(); ++i) {
        const double dx = spec[i].centroid().x() - midX;
        if (std::abs(dx) > ARM_OFFSET) {
            group[i] = dx > 0 ? 1 : 2;
        }
    }
    const bool sleeves = std::any_of(group.begin(), group.end(), [](int g) { return g != 0; });
    Vec3 tlo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 thi = -tlo;
    for (std::size_t i = 0; i < spec.size(); ++i) {
        if (group[i] == 0) {
            for (const Vec2& v : spec[i].vertices) {
                tlo = tlo.cwiseMin(spec[i].world(v));
                thi = thi.cwiseMax(spec[i].world(v));
            }
        }
    }
    bool torso = options.slots == "torso";
    if (options.slots == "auto") {
        torso = sleeves || (thi.y() - tlo.y()) > 0.75 || thi.y() > 1.25;
    }
    const std::string family = torso ? "torso_" : "waist_";
    // Heights: the top of the torso panels at our shoulder line (torso) or waist (waist).
    const patterns::ArrangementSlot& front = slotOrFail(body, family + "front");
    const double anchor = torso ? front.alongMax - 0.01 : 0.0;
    const Vec3 torsoCentre(midX, 0, 0.5 * (tlo.z() + thi.z()));
    for (std::size_t i = 0; i < spec.size(); ++i) {
        if (group[i] != 0) {
            continue;
        }
        // The side the panel faces: its loop's normal (their loops run counter-clockwise
        // seen from outside), or where it lies from the axis when it lies flat.
        Vec3 d = spec[i].normal();
        if (std::abs(d.y()) > 0.7) {
            d = spec[i].centroid() - torsoCentre;
        }
        std::string side;
        Vec3 facing;
        if (std::abs(d.z()) >= std::abs(d.x())) {
            side = d.z() >= 0 ? "front" : "back";
            facing = d.z() >= 0 ? Vec3::UnitZ() : Vec3(-Vec3::UnitZ());
        } else {
            side = d.x() > 0 ? "left" : "right";
            facing = d.x() > 0 ? Vec3::UnitX() : Vec3(-Vec3::UnitX());
        }
        SlotFrame f;
        f.slot = &slotOrFail(body, family + side);
        f.centre = torsoCentre;
        f.axis = Vec3::UnitY();
        f.facing = facing;
        f.vShift = anchor - thi.y();
        f.rho = f.slot->radius + options.clearance;
        place(spec[i], f, options.clearance, panels[i], ctx);
    }
    for (int g = 1; g <= 2; ++g) {
        const double sx = g == 1 ? 1.0 : -1.0;
        const patterns::ArrangementSlot& slot = slotOrFail(body, g == 1 ? "arm_left" : "arm_right");
        // Their arm's axis: along the stitches between two panels of this arm (a sleeve's
        // seams run along the arm), else our slot's axis.
        Vec3 axis = Vec3::Zero();
        const Vec3 toShoulder(-sx, 1, 0);
        for (const auto& [p, e] : stitches) {
            if (group[p[0]] != g || group[p[1]] != g) {
                continue;
            }
            const SpecPanel& a = spec[p[0]];
            const auto& ends = a.endpoints[static_cast<std::size_t>(e[0])];
            Vec3 chord = a.world(a.vertices[static_cast<std::size_t>(ends.second)]) -
                         a.world(a.vertices[static_cast<std::size_t>(ends.first)]);
            chord.z() = 0;
            axis += chord.dot(toShoulder) < 0 ? Vec3(-chord) : chord;
        }
        if (axis.norm() < 1e-9) {
            axis = Vec3(slot.axis.x(), slot.axis.y(), 0);
        }
        if (axis.norm() < 1e-9) {
            axis = toShoulder;
        }
        axis.normalize();
        const Vec3 facing = sx * Vec3(axis.y(), -axis.x(), 0);
        const Vec3 right = axis.cross(facing);
        double fLo = std::numeric_limits<double>::infinity(), fHi = -fLo, rLo = fLo, rHi = -fLo,
               aHi = -fLo;
        bool any = false;
        for (std::size_t i = 0; i < spec.size(); ++i) {
            if (group[i] != g) {
                continue;
            }
            any = true;
            for (const Vec2& v : spec[i].vertices) {
                const Vec3 x = spec[i].world(v);
                fLo = std::min(fLo, x.dot(facing));
                fHi = std::max(fHi, x.dot(facing));
                rLo = std::min(rLo, x.dot(right));
                rHi = std::max(rHi, x.dot(right));
                aHi = std::max(aHi, x.dot(axis));
            }
        }
        if (!any) {
            continue;
        }
        SlotFrame f;
        f.slot = &slot;
        f.axis = axis;
        f.facing = facing;
        f.centre = 0.5 * (fLo + fHi) * facing + 0.5 * (rLo + rHi) * right;
        f.vShift = slot.alongMax - SLEEVE_DROP - aHi;
        // Panels facing away from the top of the arm (front and back halves of a sleeve) are
        // laid side by side around it: the radius at which their widths tile the circle.
        f.rho = std::max(slot.radius + options.clearance, (fHi - fLo) / std::numbers::pi);
        for (std::size_t i = 0; i < spec.size(); ++i) {
            if (group[i] == g) {
                place(spec[i], f, options.clearance, panels[i], ctx);
            }
        }
    }
}

GarmentCodeImport build(const json& root, const std::string& name, const patterns::Body& body,
                        const GarmentCodeOptions& options, Context& ctx) {
    if (!root.is_object()) {
        fail("", "expected an object, found " + typeName(root));
    }
    for (const auto& [key, _] : root.items()) {
        if (key != "pattern" && key != "properties" && key != "parameters" &&
            key != "parameter_order") {
            ctx.warnings.push_back("key " + inQuotes(key) + " ignored");
        }
    }
    if (const auto props = root.find("properties"); props != root.end()) {
        const std::string pp = "/properties";
        if (!props->is_object()) {
            fail(pp, "expected an object, found " + typeName(*props));
        }
        if (const auto u = props->find("units_in_meter"); u != props->end()) {
            ctx.unitsInMeter = numberAt(*u, pp + "/units_in_meter");
            if (!(ctx.unitsInMeter >= 1e-3 && ctx.unitsInMeter <= 1e6)) {
                fail(pp + "/units_in_meter", "must be within [0.001, 1e6]");
            }
        } else {
            ctx.warnings.push_back("properties: no units_in_meter; centimetres assumed (100)");
        }
        if (const auto c = props->find("curvature_coords"); c != props->end()) {
            if (!c->is_string() ||
                (c->get<std::string>() != "relative" && c->get<std::string>() != "absolute")) {
                fail(pp + "/curvature_coords", "must be \"relative\" or \"absolute\"");
            }
            ctx.relative = c->get<std::string>() == "relative";
        }
    } else {
        ctx.warnings.push_back("no properties: centimetres (units_in_meter 100) and relative "
                               "curvature coordinates assumed");
    }
    const json& pattern = member(root, "", "pattern");
    const json& panelsJson = member(pattern, "/pattern", "panels");
    if (!panelsJson.is_object()) {
        fail("/pattern/panels",
             "expected an object of panels by name, found " + typeName(panelsJson));
    }
    if (panelsJson.empty()) {
        fail("/pattern/panels", "the pattern has no panels");
    }
    // Panel order: `panel_order` where given (names it lacks follow), else by name.
    std::vector<std::string> order;
    if (const auto po = pattern.find("panel_order"); po != pattern.end()) {
        const json& list = arrayAt(*po, "/pattern/panel_order");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string p = childPointer("/pattern/panel_order", i);
            if (!list[i].is_string()) {
                fail(p, "must be a panel name, found " + typeName(list[i]));
            }
            const std::string n = list[i].get<std::string>();
            if (!panelsJson.contains(n)) {
                fail(p, "no panel named " + inQuotes(n));
            }
            if (std::find(order.begin(), order.end(), n) != order.end()) {
                fail(p, "panel " + inQuotes(n) + " is listed twice");
            }
            order.push_back(n);
        }
    }
    for (const auto& [n, _] : panelsJson.items()) {
        if (std::find(order.begin(), order.end(), n) == order.end()) {
            order.push_back(n);
        }
    }
    std::vector<SpecPanel> spec;
    std::map<std::string, std::size_t> index;
    for (const std::string& n : order) {
        if (n.empty()) {
            fail("/pattern/panels", "a panel name must not be empty");
        }
        index[n] = spec.size();
        spec.push_back(readPanel(n, panelsJson.at(n), childPointer("/pattern/panels", n), ctx));
    }

    patterns::Garment garment;
    garment.name = name;
    const auto presets = builtinMaterialPresets();
    const auto preset = presets.find(options.fabric);
    if (preset == presets.end()) {
        throw JsonError{"", "unknown fabric preset " + inQuotes(options.fabric)};
    }
    garment.materials.push_back(patterns::GarmentMaterial{"fabric", preset->second});
    for (const SpecPanel& s : spec) {
        patterns::Panel p;
        p.name = s.name;
        p.outline = outlineOf(s);
        p.material = "fabric";
        garment.panels.push_back(std::move(p));
    }

    // Stitches: two edges each; the sides run against each other (their loops both run
    // counter-clockwise seen from outside) unless the 3D positions clearly say otherwise.
    std::vector<std::pair<std::array<std::size_t, 2>, std::array<int, 2>>> stitched;
    if (const auto st = pattern.find("stitches"); st != pattern.end()) {
        const std::string sp = "/pattern/stitches";
        const json& list = arrayAt(*st, sp);
        for (std::size_t i = 0; i < list.size(); ++i) {
            const std::string p = childPointer(sp, i);
            const json& stitch = arrayAt(list[i], p);
            if (stitch.size() != 2) {
                ctx.warnings.push_back("stitch " + std::to_string(i) + ": " +
                                       std::to_string(stitch.size()) +
                                       " edges; only stitches of two edges are imported");
                continue;
            }
            std::array<std::size_t, 2> pi{};
            std::array<int, 2> ei{};
            for (std::size_t k = 0; k < 2; ++k) {
                const std::string kp = childPointer(p, k);
                const json& side = stitch[k];
                const json& pn = member(side, kp, "panel");
                if (!pn.is_string()) {
                    fail(childPointer(kp, "panel"), "must be a panel name, found " + typeName(pn));
                }
                const auto it = index.find(pn.get<std::string>());
                if (it == index.end()) {
                    fail(childPointer(kp, "panel"),
                         "no panel named " + inQuotes(pn.get<std::string>()));
                }
                pi[k] = it->second;
                const long long e =
                    detail::integerAt(member(side, kp, "edge"), childPointer(kp, "edge"));
                const auto ne = static_cast<long long>(spec[pi[k]].edges.size());
                if (e < 0 || e >= ne) {
                    fail(childPointer(kp, "edge"), "panel " + inQuotes(spec[pi[k]].name) +
                                                       " has no edge " + std::to_string(e) +
                                                       " (it has " + std::to_string(ne) + ")");
                }
                ei[k] = static_cast<int>(e);
            }
            const SpecPanel& a = spec[pi[0]];
            const SpecPanel& b = spec[pi[1]];
            const auto& ea = a.endpoints[static_cast<std::size_t>(ei[0])];
            const auto& eb = b.endpoints[static_cast<std::size_t>(ei[1])];
            auto at = [](const SpecPanel& s, int v) {
                return s.world(s.vertices[static_cast<std::size_t>(v)]);
            };
            const double same = (at(a, ea.first) - at(b, eb.first)).norm() +
                                (at(a, ea.second) - at(b, eb.second)).norm();
            const double against = (at(a, ea.first) - at(b, eb.second)).norm() +
                                   (at(a, ea.second) - at(b, eb.first)).norm();
            const bool backward = !(same < 0.5 * against);
            patterns::Seam seam;
            seam.name =
                a.name + "." + std::to_string(ei[0]) + "-" + b.name + "." + std::to_string(ei[1]);
            seam.a.push_back(seamEdge(a, ei[0], false));
            seam.b.push_back(seamEdge(b, ei[1], backward));
            const double la = patterns::arcLength(a.edges[static_cast<std::size_t>(ei[0])]);
            const double lb = patterns::arcLength(b.edges[static_cast<std::size_t>(ei[1])]);
            if (std::abs(la - lb) > STITCH_LENGTH_RATIO * std::max(la, lb)) {
                ctx.warnings.push_back(
                    "stitch " + std::to_string(i) + ": " +
                    edgeName(a, static_cast<std::size_t>(ei[0])) + " (" + millimetres(la) +
                    ") and " + edgeName(b, static_cast<std::size_t>(ei[1])) + " (" +
                    millimetres(lb) + ") differ by more than 20% in length; sewn with that ease");
            }
            garment.seams.push_back(std::move(seam));
            stitched.push_back({pi, ei});
        }
    }
    placePanels(spec, garment.panels, stitched, body, options, ctx);

    if (const std::vector<patterns::GarmentIssue> issues = patterns::validateGarment(garment);
        !issues.empty()) {
        throw JsonError{"", "the imported garment is not valid: " + issues.front().where + ": " +
                                issues.front().message};
    }
    GarmentCodeImport out;
    out.project.name = name;
    out.project.garment = garment;
    out.project.document = patterns::fromGarment(garment);
    out.project.document.name = name;
    // The samples' drape settings (assets/garments/*.atelier).
    out.project.drape.dt = 0.01;
    out.project.drape.sewingTime = 1.0;
    out.project.drape.seamWeldDistance = 0.0015;
    out.project.drape.timeLimit = 4;
    return out;
}

} // namespace

Result<GarmentCodeImport> parseGarmentCode(std::string_view text, const std::string& file,
                                           const patterns::Body& body,
                                           const GarmentCodeOptions& options,
                                           const Limits& limits) {
    const std::string name = std::filesystem::path(file).stem().string();
    auto parsed = detail::parseJson(withoutComments(text), file, limits.maxJsonDepth);
    if (!parsed.ok()) {
        return parsed.error();
    }
    Context ctx;
    ctx.limits = &limits;
    try {
        GarmentCodeImport out =
            build(parsed.value(), name.empty() ? "garment" : name, body, options, ctx);
        out.warnings = std::move(ctx.warnings);
        return out;
    } catch (const JsonError& e) {
        return Error{file, e.where, e.message};
    }
}

Result<GarmentCodeImport> importGarmentCode(const std::filesystem::path& path,
                                            const patterns::Body& body,
                                            const GarmentCodeOptions& options,
                                            const Limits& limits) {
    auto text = readFile(path, limits.maxJsonBytes);
    if (!text.ok()) {
        return text.error();
    }
    return parseGarmentCode(text.value(), path.string(), body, options, limits);
}

} // namespace atelier::io
