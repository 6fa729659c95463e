#include "io/project_file.h"

#include "patterns/mesh.h"

#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/material_json.h"
#include "io/materials.h"

#include "sim/simulation.h"

#include <array>
#include <cmath>
#include <limits>
#include <set>

namespace atelier::io {

namespace {

using detail::JsonError;
using detail::ObjectReader;
using nlohmann::json;
using nlohmann::ordered_json;
using patterns::Segment;
using patterns::SegmentKind;
using patterns::Vec2;

constexpr double PI = 3.14159265358979323846;
/// Body measurements above this are taken for a unit mistake (millimetres or centimetres).
constexpr double MAX_MEASUREMENT_M = 3.0;
/// Millimetre and degree values are rounded to 1 / STEPS_PER_UNIT on save.
constexpr double STEPS_PER_UNIT = 1e6;
/// Beyond this magnitude [mm or deg] values are written unrounded (the rounding would no
/// longer be exact in double precision).
constexpr double MAX_ROUNDED = 1e8;

constexpr std::array<std::pair<SegmentKind, std::string_view>, 4> SEGMENT_KINDS = {{
    {SegmentKind::Line, "line"},
    {SegmentKind::Quadratic, "quadratic"},
    {SegmentKind::Cubic, "cubic"},
    {SegmentKind::Arc, "arc"},
}};
constexpr std::array<sim::IntegratorKind, 5> INTEGRATORS = {
    sim::IntegratorKind::Euler, sim::IntegratorKind::Midpoint, sim::IntegratorKind::Rk4,
    sim::IntegratorKind::Rk45, sim::IntegratorKind::ImplicitEuler};
constexpr std::array<sim::StretchModel, 3> MODELS = {
    sim::StretchModel::Springs, sim::StretchModel::Volino, sim::StretchModel::Fem};

std::string inQuotes(std::string_view s) { return json(std::string(s)).dump(); }

template <class Enum, std::size_t N>
std::string nameList(const std::array<Enum, N>& values, std::string_view (*toName)(Enum)) {
    std::string out;
    for (const Enum v : values) {
        out += (out.empty() ? "" : ", ") + inQuotes(toName(v));
    }
    return out;
}

std::string segmentKindList() {
    std::string out;
    for (const auto& [kind, name] : SEGMENT_KINDS) {
        out += (out.empty() ? "" : ", ") + inQuotes(name);
    }
    return out;
}

bool sameParameters(const sim::Material& a, const sim::Material& b) {
    return a.density == b.density && a.stretchWeft == b.stretchWeft &&
           a.stretchWarp == b.stretchWarp && a.shear == b.shear && a.poisson == b.poisson &&
           a.bending == b.bending && a.damping == b.damping &&
           a.staticFriction == b.staticFriction && a.kineticFriction == b.kineticFriction &&
           a.plasticYieldAngle == b.plasticYieldAngle && a.plasticRate == b.plasticRate;
}

// ---------------------------------------------------------------------------------------------
// Reading

// Unit conversions, chosen so that whole values come out exact (10 mm → 0.01, 90° → π/2).
double metresFromMm(double mm) { return mm / 1000.0; }
double radiansFromDeg(double deg) { return deg / 180.0 * PI; }

enum class Range { Any, NonNegative, Positive };

/// A length `key` in millimetres, in metres; exactly `fallback` [m] when absent.
double lengthMm(ObjectReader& r, std::string_view key, double fallback, Range range) {
    if (!r.has(key)) {
        r.find(key);
        return fallback;
    }
    switch (range) {
    case Range::Positive:
        return metresFromMm(r.positive(key));
    case Range::NonNegative:
        return metresFromMm(r.nonNegative(key, 0));
    case Range::Any:
        break;
    }
    return metresFromMm(r.number(key));
}

/// An angle `key` in degrees, in radians; exactly `fallback` [rad] when absent.
double angleDeg(ObjectReader& r, std::string_view key, double fallback) {
    const auto deg = r.optionalNumber(key);
    return deg ? radiansFromDeg(*deg) : fallback;
}

/// [x, y] in millimetres at `pointer`, in metres.
Vec2 pointAt(const json& value, const std::string& pointer) {
    const auto finiteNumber = [](const json& v) {
        return v.is_number() && std::isfinite(v.get<double>());
    };
    if (!value.is_array() || value.size() != 2 || !finiteNumber(value[0]) ||
        !finiteNumber(value[1])) {
        throw JsonError{pointer, "must be an array of two finite numbers"};
    }
    return Vec2(metresFromMm(value[0].get<double>()), metresFromMm(value[1].get<double>()));
}

Vec2 point(ObjectReader& r, std::string_view key) {
    return pointAt(r.require(key), r.pointerOf(key));
}

/// A non-negative index that fits an int.
int index(ObjectReader& r, std::string_view key) {
    const long long n = r.integer(key);
    if (n < 0 || n > std::numeric_limits<int>::max()) {
        r.fail(key, "must be a non-negative integer (found " + std::to_string(n) + ")");
    }
    return static_cast<int>(n);
}

/// A curve parameter in [0, 1].
double parameter(ObjectReader& r, std::string_view key, double fallback) {
    const double t = r.number(key, fallback);
    if (t < 0 || t > 1) {
        r.fail(key, "must be in [0, 1] (found " + json(t).dump() + ")");
    }
    return t;
}

/// A non-empty string.
std::string name(ObjectReader& r, std::string_view key) {
    std::string s = r.string(key);
    if (s.empty()) {
        r.fail(key, "must not be empty");
    }
    return s;
}

/// One segment `{"kind": {...}}`; `open` segments (internal lines) carry their end ("to").
Segment readSegment(const json& value, const std::string& pointer, bool open) {
    ObjectReader r(value, pointer);
    if (value.size() != 1) {
        r.fail("expected an object with one key, the segment kind (" + segmentKindList() +
               "), found " + std::to_string(value.size()) + " keys");
    }
    const std::string kindName = value.begin().key();
    Segment s;
    bool known = false;
    for (const auto& [kind, kindKey] : SEGMENT_KINDS) {
        if (kindName == kindKey) {
            s.kind = kind;
            known = true;
        }
    }
    if (!known) {
        r.fail(kindName, "unknown segment kind " + inQuotes(kindName) + " (expected one of " +
                             segmentKindList() + ")");
    }
    ObjectReader g(r.require(kindName), r.pointerOf(kindName));
    s.start = point(g, "from");
    if (open) {
        s.end = point(g, "to");
    }
    if (s.kind == SegmentKind::Quadratic || s.kind == SegmentKind::Cubic) {
        s.control1 = point(g, "c1");
    }
    if (s.kind == SegmentKind::Cubic) {
        s.control2 = point(g, "c2");
    }
    if (s.kind == SegmentKind::Arc) {
        s.bulge = g.number("bulge");
    }
    g.finish();
    r.finish();
    return s;
}

/// A closed loop: each segment ends where the next starts, the last where the first starts.
patterns::Loop readLoop(const json& value, const std::string& pointer) {
    const json& array = detail::arrayAt(value, pointer);
    if (array.empty()) {
        throw JsonError{pointer, "a closed loop needs at least one segment"};
    }
    patterns::Loop loop;
    for (std::size_t i = 0; i < array.size(); ++i) {
        loop.push_back(readSegment(array[i], detail::childPointer(pointer, i), false));
    }
    for (std::size_t i = 0; i < loop.size(); ++i) {
        loop[i].end = loop[(i + 1) % loop.size()].start;
    }
    return loop;
}

class ProjectParser {
  public:
    /// `ordered` is the same document as `root` with its key order (for the measurements).
    ProjectParser(const json& root, const ordered_json& ordered)
        : m_root(root), m_ordered(ordered) {}

    patterns::Project parse() {
        ObjectReader r(m_root, "");
        const std::string format = r.string("format");
        if (format != "atelier-project") {
            r.fail("format", "expected \"atelier-project\", found " + inQuotes(format));
        }
        const long long version = r.integer("version");
        if (version > PROJECT_FORMAT_VERSION) {
            r.fail("version", "version " + std::to_string(version) +
                                  " was written by a newer Atelier (this build reads version " +
                                  std::to_string(PROJECT_FORMAT_VERSION) + ")");
        }
        if (version < 1) {
            r.fail("version", "unsupported version " + std::to_string(version) +
                                  " (this build reads version " +
                                  std::to_string(PROJECT_FORMAT_VERSION) + ")");
        }
        m_project.version = static_cast<int>(version);
        m_project.name = r.string("name", "");
        m_project.garment.name = m_project.name;
        if (const json* body = r.find("body")) {
            readBody(*body, r.pointerOf("body"));
        }
        if (const json* materials = r.find("materials")) {
            const std::string ptr = r.pointerOf("materials");
            for (std::size_t i = 0; i < detail::arrayAt(*materials, ptr).size(); ++i) {
                readMaterial((*materials)[i], detail::childPointer(ptr, i));
            }
        }
        if (const json* panels = r.find("panels")) {
            const std::string ptr = r.pointerOf("panels");
            for (std::size_t i = 0; i < detail::arrayAt(*panels, ptr).size(); ++i) {
                readPanel((*panels)[i], detail::childPointer(ptr, i));
            }
        }
        if (const json* seams = r.find("seams")) {
            const std::string ptr = r.pointerOf("seams");
            for (std::size_t i = 0; i < detail::arrayAt(*seams, ptr).size(); ++i) {
                readSeam((*seams)[i], detail::childPointer(ptr, i));
            }
        }
        m_project.garment.easeTolerance = lengthMm(r, "ease_tolerance_mm",
                                                   m_project.garment.easeTolerance,
                                                   Range::NonNegative);
        if (const json* simulation = r.find("simulation")) {
            readSimulation(*simulation, r.pointerOf("simulation"));
        }
        r.finish();
        return std::move(m_project);
    }

  private:
    void readBody(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        patterns::BodySource& body = m_project.body;
        if (r.has("mesh")) {
            for (const char* key : {"base", "measurements"}) {
                if (r.has(key)) {
                    r.fail(key, "a body is either a mesh or a base with measurements, not both");
                }
            }
            body.meshPath = name(r, "mesh");
            r.finish();
            return;
        }
        body.base = r.string("base", body.base);
        if (body.base != "female" && body.base != "male") {
            r.fail("base", "unknown body base " + inQuotes(body.base) +
                               " (expected \"female\" or \"male\")");
        }
        if (const json* measurements = r.find("measurements")) {
            const std::string mp = r.pointerOf("measurements");
            ObjectReader m(*measurements, mp);
            // File order, from the order-keeping copy of the document.
            for (const auto& [key, unused] : m_ordered.at("body").at("measurements").items()) {
                if (key.empty()) {
                    m.fail(key, "a measurement needs a name");
                }
                const double v = m.number(key);
                if (!(v > 0) || v > MAX_MEASUREMENT_M) {
                    m.fail(key, "must be a length in metres in (0, " +
                                    json(MAX_MEASUREMENT_M).dump() + "] (found " + json(v).dump() +
                                    ")");
                }
                body.measurements.emplace_back(key, v);
            }
            m.finish();
        }
        r.finish();
    }

    void readMaterial(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        patterns::GarmentMaterial material;
        material.name = name(r, "name");
        for (const patterns::GarmentMaterial& other : m_project.garment.materials) {
            if (other.name == material.name) {
                r.fail("name", "another material is already named " + inQuotes(material.name));
            }
        }
        if (const auto fabric = r.optionalString("fabric")) {
            const MaterialPresets& presets = builtinMaterialPresets();
            const auto it = presets.find(*fabric);
            if (it == presets.end()) {
                std::string names;
                for (const auto& [presetName, unused] : presets) {
                    names += (names.empty() ? "" : ", ") + inQuotes(presetName);
                }
                r.fail("fabric", "unknown fabric preset " + inQuotes(*fabric) + " (presets: " +
                                     names + ")");
            }
            material.material = it->second;
        } else {
            // Documentation keys that readMaterial skips would be lost on save: refuse them.
            for (const char* key : {"source", "description"}) {
                if (r.has(key)) {
                    r.fail(key, "unknown key " + inQuotes(key) +
                                    " (a project material is {\"name\", \"fabric\"} or "
                                    "{\"name\", material parameters})");
                }
            }
            material.material = sim::Material{};
            material.material.name = material.name;
            detail::readMaterial(r, material.material, false);
        }
        r.finish();
        m_project.garment.materials.push_back(std::move(material));
    }

    void readPanel(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        patterns::Panel panel;
        panel.name = name(r, "name");
        if (m_project.garment.panelIndex(panel.name) >= 0) {
            r.fail("name", "another panel is already named " + inQuotes(panel.name));
        }
        panel.material = r.string("material");
        bool knownMaterial = false;
        std::string materialNames;
        for (const patterns::GarmentMaterial& m : m_project.garment.materials) {
            knownMaterial = knownMaterial || m.name == panel.material;
            materialNames += (materialNames.empty() ? "" : ", ") + inQuotes(m.name);
        }
        if (!knownMaterial) {
            r.fail("material", "unknown material " + inQuotes(panel.material) +
                                   (materialNames.empty()
                                        ? std::string(" (the project has no materials)")
                                        : " (materials: " + materialNames + ")"));
        }
        const std::string side = r.string("side", "front");
        if (side == "front") {
            panel.side = patterns::PanelSide::Front;
        } else if (side == "back") {
            panel.side = patterns::PanelSide::Back;
        } else {
            r.fail("side", "unknown side " + inQuotes(side) + " (expected \"front\" or \"back\")");
        }
        panel.grainAngle = angleDeg(r, "grain_deg", panel.grainAngle);
        panel.outline = readLoop(r.require("outline"), r.pointerOf("outline"));
        if (const json* holes = r.find("holes")) {
            const std::string hp = r.pointerOf("holes");
            for (std::size_t i = 0; i < detail::arrayAt(*holes, hp).size(); ++i) {
                panel.holes.push_back(readLoop((*holes)[i], detail::childPointer(hp, i)));
            }
        }
        if (const json* lines = r.find("internal_lines")) {
            const std::string lp = r.pointerOf("internal_lines");
            for (std::size_t i = 0; i < detail::arrayAt(*lines, lp).size(); ++i) {
                ObjectReader l((*lines)[i], detail::childPointer(lp, i));
                patterns::InternalLine line;
                line.foldAngle = angleDeg(l, "fold_deg", line.foldAngle);
                const std::string sp = l.pointerOf("segments");
                const json& segments = detail::arrayAt(l.require("segments"), sp);
                if (segments.empty()) {
                    l.fail("segments", "an internal line needs at least one segment");
                }
                for (std::size_t k = 0; k < segments.size(); ++k) {
                    line.path.push_back(
                        readSegment(segments[k], detail::childPointer(sp, k), true));
                }
                l.finish();
                panel.internalLines.push_back(std::move(line));
            }
        }
        if (const json* darts = r.find("darts")) {
            const std::string dp = r.pointerOf("darts");
            for (std::size_t i = 0; i < detail::arrayAt(*darts, dp).size(); ++i) {
                ObjectReader d((*darts)[i], detail::childPointer(dp, i));
                panel.darts.push_back({index(d, "leg")});
                d.finish();
            }
        }
        if (const json* notches = r.find("notches")) {
            const std::string np = r.pointerOf("notches");
            for (std::size_t i = 0; i < detail::arrayAt(*notches, np).size(); ++i) {
                ObjectReader n((*notches)[i], detail::childPointer(np, i));
                patterns::Notch notch;
                notch.segment = index(n, "segment");
                if (notch.segment >= static_cast<int>(panel.outline.size())) {
                    n.fail("segment", "no segment " + std::to_string(notch.segment) +
                                          " in the outline (it has " +
                                          std::to_string(panel.outline.size()) + ")");
                }
                notch.t = parameter(n, "t", notch.t);
                n.finish();
                panel.notches.push_back(notch);
            }
        }
        if (const json* placement = r.find("placement")) {
            ObjectReader p(*placement, r.pointerOf("placement"));
            patterns::Placement& out = panel.placement;
            out.slot = p.string("slot", out.slot);
            if (const json* offset = p.find("offset_mm")) {
                out.offset = pointAt(*offset, p.pointerOf("offset_mm"));
            }
            out.rotation = angleDeg(p, "rotation_deg", out.rotation);
            out.clearance = lengthMm(p, "clearance_mm", out.clearance, Range::NonNegative);
            p.finish();
        }
        r.finish();
        m_project.garment.panels.push_back(std::move(panel));
    }

    void readSeam(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        patterns::Seam seam;
        seam.name = r.string("name", "");
        for (const char* sideKey : {"a", "b"}) {
            const std::string sp = r.pointerOf(sideKey);
            const json& edges = detail::arrayAt(r.require(sideKey), sp);
            if (edges.empty()) {
                r.fail(sideKey, "a seam side needs at least one edge");
            }
            std::vector<patterns::SeamEdge>& out = sideKey[0] == 'a' ? seam.a : seam.b;
            for (std::size_t i = 0; i < edges.size(); ++i) {
                ObjectReader e(edges[i], detail::childPointer(sp, i));
                patterns::SeamEdge edge;
                edge.panel = e.string("panel");
                edge.segment = index(e, "segment");
                edge.t0 = parameter(e, "t0", edge.t0);
                edge.t1 = parameter(e, "t1", edge.t1);
                e.finish();
                out.push_back(std::move(edge));
            }
        }
        r.finish();
        m_project.garment.seams.push_back(std::move(seam));
    }

    void readSimulation(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        patterns::DrapeSettings& d = m_project.drape;
        d.particleDistance =
            lengthMm(r, "particle_distance_mm", d.particleDistance, Range::Positive);
        if (const auto model = r.optionalString("model")) {
            const auto m = sim::stretchModelFromName(*model);
            if (!m) {
                r.fail("model", "unknown model " + inQuotes(*model) + " (expected one of " +
                                    nameList(MODELS, &sim::stretchModelName) + ")");
            }
            d.model = *m;
        }
        if (const auto integrator = r.optionalString("integrator")) {
            const auto kind = sim::integratorFromName(*integrator);
            if (!kind) {
                r.fail("integrator", "unknown integrator " + inQuotes(*integrator) +
                                         " (expected one of " +
                                         nameList(INTEGRATORS, &sim::integratorName) + ")");
            }
            d.integrator = *kind;
        }
        d.dt = r.positive("dt_s", d.dt);
        d.cgTolerance = r.positive("cg_tolerance", d.cgTolerance);
        d.clothThickness = lengthMm(r, "cloth_thickness_mm", d.clothThickness, Range::Positive);
        d.selfCollision = r.boolean("self_collision", d.selfCollision);
        d.bodyThickness =
            lengthMm(r, "body_thickness_mm", d.bodyThickness, Range::NonNegative);
        d.bodyStaticFriction = r.nonNegative("body_static_friction", d.bodyStaticFriction);
        d.bodyKineticFriction = r.nonNegative("body_kinetic_friction", d.bodyKineticFriction);
        d.seamTimeConstant = r.positive("seam_time_constant_s", d.seamTimeConstant);
        d.seamStiffness = r.nonNegative("seam_stiffness_n_per_m2", d.seamStiffness);
        d.seamWeldDistance =
            lengthMm(r, "seam_weld_distance_mm", d.seamWeldDistance, Range::NonNegative);
        d.seamReach = lengthMm(r, "seam_reach_mm", d.seamReach, Range::NonNegative);
        d.seamRouteClearance =
            lengthMm(r, "seam_route_clearance_mm", d.seamRouteClearance, Range::NonNegative);
        d.sewingTime = r.nonNegative("sewing_time_s", d.sewingTime);
        d.sewingFrictionScale = r.nonNegative("sewing_friction_scale", d.sewingFrictionScale);
        d.closingTime = r.nonNegative("closing_time_s", d.closingTime);
        d.restKineticEnergy = r.nonNegative("rest_kinetic_energy_j", d.restKineticEnergy);
        d.restDuration = r.nonNegative("rest_duration_s", d.restDuration);
        d.timeLimit = r.positive("time_limit_s", d.timeLimit);
        r.finish();
    }

    const json& m_root;
    const ordered_json& m_ordered;
    patterns::Project m_project;
};

// ---------------------------------------------------------------------------------------------
// Writing

/// A number as JSON: integral values as integers (`90`, not `90.0`), others as the shortest
/// text that reads back to the same double. -0 is written as 0.
ordered_json number(double v) {
    if (v == 0) {
        return 0;
    }
    if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 9e15) {
        return static_cast<long long>(v);
    }
    return v;
}

/// A millimetre or degree value rounded to 1e-6: reading it back (÷ 1000, × π/180)
/// and writing again gives the same value, so the text is stable.
ordered_json rounded(double v) {
    if (!std::isfinite(v) || std::abs(v) >= MAX_ROUNDED) {
        return number(v);
    }
    // N / 10⁶ is the double nearest the decimal N·10⁻⁶: its shortest text has ≤ 6 decimals.
    return number(std::round(v * STEPS_PER_UNIT) / STEPS_PER_UNIT);
}

ordered_json mm(double metres) { return rounded(metres * 1000.0); }
ordered_json deg(double radians) { return rounded(radians / PI * 180.0); }
ordered_json pointMm(const Vec2& p) { return ordered_json::array({mm(p.x()), mm(p.y())}); }

ordered_json segmentJson(const Segment& s, bool open) {
    ordered_json g = ordered_json::object();
    g["from"] = pointMm(s.start);
    if (open) {
        g["to"] = pointMm(s.end);
    }
    if (s.kind == SegmentKind::Quadratic || s.kind == SegmentKind::Cubic) {
        g["c1"] = pointMm(s.control1);
    }
    if (s.kind == SegmentKind::Cubic) {
        g["c2"] = pointMm(s.control2);
    }
    if (s.kind == SegmentKind::Arc) {
        g["bulge"] = number(s.bulge);
    }
    std::string_view kindName = "line";
    for (const auto& [kind, name] : SEGMENT_KINDS) {
        if (kind == s.kind) {
            kindName = name;
        }
    }
    ordered_json out = ordered_json::object();
    out[std::string(kindName)] = std::move(g);
    return out;
}

ordered_json segmentsJson(const std::vector<Segment>& segments, bool open) {
    ordered_json out = ordered_json::array();
    for (const Segment& s : segments) {
        out.push_back(segmentJson(s, open));
    }
    return out;
}

ordered_json materialJson(const patterns::GarmentMaterial& material) {
    ordered_json out = ordered_json::object();
    out["name"] = material.name;
    const sim::Material& m = material.material;
    const MaterialPresets& presets = builtinMaterialPresets();
    if (const auto it = presets.find(m.name); it != presets.end() && sameParameters(m, it->second)) {
        out["fabric"] = m.name;
        return out;
    }
    out["density_kg_per_m2"] = number(m.density);
    out["stretch_weft_n_per_m"] = number(m.stretchWeft);
    out["stretch_warp_n_per_m"] = number(m.stretchWarp);
    out["shear_n_per_m"] = number(m.shear);
    out["poisson"] = number(m.poisson);
    out["bending_n_m"] = number(m.bending);
    out["damping_s"] = number(m.damping);
    out["static_friction"] = number(m.staticFriction);
    out["kinetic_friction"] = number(m.kineticFriction);
    out["plastic_yield_angle_rad"] = number(m.plasticYieldAngle);
    out["plastic_rate_per_s"] = number(m.plasticRate);
    return out;
}

ordered_json panelJson(const patterns::Panel& panel) {
    ordered_json out = ordered_json::object();
    out["name"] = panel.name;
    out["material"] = panel.material;
    out["side"] = panel.side == patterns::PanelSide::Back ? "back" : "front";
    out["grain_deg"] = deg(panel.grainAngle);
    out["outline"] = segmentsJson(panel.outline, false);
    out["holes"] = ordered_json::array();
    for (const patterns::Loop& hole : panel.holes) {
        out["holes"].push_back(segmentsJson(hole, false));
    }
    out["internal_lines"] = ordered_json::array();
    for (const patterns::InternalLine& line : panel.internalLines) {
        ordered_json l = ordered_json::object();
        l["fold_deg"] = deg(line.foldAngle);
        l["segments"] = segmentsJson(line.path, true);
        out["internal_lines"].push_back(std::move(l));
    }
    out["darts"] = ordered_json::array();
    for (const patterns::Dart& dart : panel.darts) {
        out["darts"].push_back({{"leg", dart.leg}});
    }
    out["notches"] = ordered_json::array();
    for (const patterns::Notch& notch : panel.notches) {
        ordered_json n = ordered_json::object();
        n["segment"] = notch.segment;
        n["t"] = number(notch.t);
        out["notches"].push_back(std::move(n));
    }
    ordered_json p = ordered_json::object();
    p["slot"] = panel.placement.slot;
    p["offset_mm"] = pointMm(panel.placement.offset);
    p["rotation_deg"] = deg(panel.placement.rotation);
    p["clearance_mm"] = mm(panel.placement.clearance);
    out["placement"] = std::move(p);
    return out;
}

ordered_json seamJson(const patterns::Seam& seam) {
    ordered_json out = ordered_json::object();
    out["name"] = seam.name;
    for (const auto* side : {&seam.a, &seam.b}) {
        ordered_json edges = ordered_json::array();
        for (const patterns::SeamEdge& edge : *side) {
            ordered_json e = ordered_json::object();
            e["panel"] = edge.panel;
            e["segment"] = edge.segment;
            e["t0"] = number(edge.t0);
            e["t1"] = number(edge.t1);
            edges.push_back(std::move(e));
        }
        out[side == &seam.a ? "a" : "b"] = std::move(edges);
    }
    return out;
}

ordered_json simulationJson(const patterns::DrapeSettings& d) {
    ordered_json out = ordered_json::object();
    out["particle_distance_mm"] = mm(d.particleDistance);
    out["model"] = std::string(sim::stretchModelName(d.model));
    out["integrator"] = std::string(sim::integratorName(d.integrator));
    out["dt_s"] = number(d.dt);
    out["cg_tolerance"] = number(d.cgTolerance);
    out["cloth_thickness_mm"] = mm(d.clothThickness);
    out["self_collision"] = d.selfCollision;
    out["body_thickness_mm"] = mm(d.bodyThickness);
    out["body_static_friction"] = number(d.bodyStaticFriction);
    out["body_kinetic_friction"] = number(d.bodyKineticFriction);
    out["seam_time_constant_s"] = number(d.seamTimeConstant);
    out["seam_stiffness_n_per_m2"] = number(d.seamStiffness);
    out["seam_weld_distance_mm"] = mm(d.seamWeldDistance);
    out["seam_reach_mm"] = mm(d.seamReach);
    out["seam_route_clearance_mm"] = mm(d.seamRouteClearance);
    out["sewing_time_s"] = number(d.sewingTime);
    out["sewing_friction_scale"] = number(d.sewingFrictionScale);
    out["closing_time_s"] = number(d.closingTime);
    out["rest_kinetic_energy_j"] = number(d.restKineticEnergy);
    out["rest_duration_s"] = number(d.restDuration);
    out["time_limit_s"] = number(d.timeLimit);
    return out;
}

} // namespace

Result<patterns::Project> parseProject(std::string_view text, const std::string& file) {
    const std::string textCopy(text);
    auto parsed = detail::parseJson(textCopy, file);
    if (!parsed.ok()) {
        return parsed.error();
    }
    // The same document again, keeping key order (measurements are an ordered list).
    const ordered_json ordered = ordered_json::parse(textCopy);
    patterns::Project project;
    try {
        project = ProjectParser(parsed.value(), ordered).parse();
    } catch (const JsonError& e) {
        return Error{file, e.where, e.message};
    }
    // Geometry and references: the first problem, at its JSON path.
    if (const auto issues = patterns::validateGarment(project.garment); !issues.empty()) {
        return Error{file, issues.front().where, issues.front().message};
    }
    return project;
}

Result<patterns::Project> loadProject(const std::filesystem::path& path) {
    auto text = readFile(path);
    if (!text.ok()) {
        return text.error();
    }
    auto project = parseProject(text.value(), path.string());
    if (!project.ok()) {
        return project;
    }
    if (const std::string& mesh = project.value().body.meshPath; !mesh.empty()) {
        const std::filesystem::path resolved = path.parent_path() / mesh;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(resolved, ec)) {
            return Error{path.string(), "/body/mesh",
                         "body mesh not found: " + resolved.string()};
        }
    }
    return project;
}

std::string formatProject(const patterns::Project& project) {
    ordered_json root = ordered_json::object();
    root["format"] = "atelier-project";
    root["version"] = PROJECT_FORMAT_VERSION;
    root["name"] = project.name;
    ordered_json body = ordered_json::object();
    if (!project.body.meshPath.empty()) {
        body["mesh"] = project.body.meshPath;
    } else {
        body["base"] = project.body.base;
        ordered_json measurements = ordered_json::object();
        for (const auto& [key, value] : project.body.measurements) {
            measurements[key] = number(value);
        }
        body["measurements"] = std::move(measurements);
    }
    root["body"] = std::move(body);
    root["materials"] = ordered_json::array();
    for (const patterns::GarmentMaterial& material : project.garment.materials) {
        root["materials"].push_back(materialJson(material));
    }
    root["panels"] = ordered_json::array();
    for (const patterns::Panel& panel : project.garment.panels) {
        root["panels"].push_back(panelJson(panel));
    }
    root["seams"] = ordered_json::array();
    for (const patterns::Seam& seam : project.garment.seams) {
        root["seams"].push_back(seamJson(seam));
    }
    root["ease_tolerance_mm"] = mm(project.garment.easeTolerance);
    root["simulation"] = simulationJson(project.drape);
    // Invalid UTF-8 in a name is replaced rather than thrown on.
    return root.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

Result<void> saveProject(const std::filesystem::path& path, const patterns::Project& project) {
    return writeFileAtomically(path, formatProject(project));
}

} // namespace atelier::io
