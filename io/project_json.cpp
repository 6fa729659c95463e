#include "io/project_json.h"

#include "io/material_json.h"
#include "io/materials.h"

#include "patterns/mesh.h"

#include "sim/simulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace atelier::io::detail {

namespace {

using nlohmann::json;
using nlohmann::ordered_json;
using patterns::SegmentKind;
using patterns::Vec2;

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

bool sameParameters(const sim::Material& a, const sim::Material& b) {
    return a.density == b.density && a.stretchWeft == b.stretchWeft &&
           a.stretchWarp == b.stretchWarp && a.shear == b.shear && a.poisson == b.poisson &&
           a.bending == b.bending && a.bendingWeft == b.bendingWeft &&
           a.bendingWarp == b.bendingWarp && a.bendingBias == b.bendingBias &&
           a.stretchKnee == b.stretchKnee && a.stretchWeftBeyond == b.stretchWeftBeyond &&
           a.stretchWarpBeyond == b.stretchWarpBeyond && a.damping == b.damping &&
           a.staticFriction == b.staticFriction && a.kineticFriction == b.kineticFriction &&
           a.plasticYieldAngle == b.plasticYieldAngle && a.plasticRate == b.plasticRate;
}

// Unit conversions, chosen so that whole values come out exact (10 mm → 0.01, 90° → π/2).
double metresFromMm(double mm) {
    return mm / 1000.0;
}
double radiansFromDeg(double deg) {
    return deg / 180.0 * std::numbers::pi;
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

void readMeasurements(ObjectReader& r, const ordered_json& ordered, patterns::BodySource& body) {
    const json* measurements = r.find("measurements");
    if (measurements == nullptr) {
        return;
    }
    ObjectReader m(*measurements, r.pointerOf("measurements"));
    // File order, from the order-keeping copy of the document.
    for (const auto& [key, unused] : ordered.at("measurements").items()) {
        if (key.empty()) {
            m.fail(key, "a measurement needs a name");
        }
        const double v = m.number(key);
        if (!(v > 0) || v > MAX_MEASUREMENT_M) {
            m.fail(key, "must be a length in metres in (0, " + json(MAX_MEASUREMENT_M).dump() +
                            "] (found " + json(v).dump() + ")");
        }
        body.measurements.emplace_back(key, v);
    }
    m.finish();
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Reading

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

void seamBending(ObjectReader& r, double& foldAngle, double& bendingScale) {
    foldAngle = angleDeg(r, "fold_deg", foldAngle);
    if (!(std::abs(foldAngle) < std::numbers::pi)) {
        r.fail("fold_deg", "a seam's fold angle must be within (-180, 180) degrees");
    }
    bendingScale = r.nonNegative("bending_scale", bendingScale);
}

double angleDeg(ObjectReader& r, std::string_view key, double fallback) {
    const auto deg = r.optionalNumber(key);
    return deg ? radiansFromDeg(*deg) : fallback;
}

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

double parameter(ObjectReader& r, std::string_view key, double fallback) {
    const double t = r.number(key, fallback);
    if (t < 0 || t > 1) {
        r.fail(key, "must be in [0, 1] (found " + json(t).dump() + ")");
    }
    return t;
}

std::string name(ObjectReader& r, std::string_view key) {
    std::string s = r.string(key);
    if (s.empty()) {
        r.fail(key, "must not be empty");
    }
    return s;
}

std::optional<SegmentKind> segmentKindFromName(std::string_view name) {
    for (const auto& [kind, kindName] : SEGMENT_KINDS) {
        if (name == kindName) {
            return kind;
        }
    }
    return std::nullopt;
}

std::string_view segmentKindName(SegmentKind kind) {
    for (const auto& [k, name] : SEGMENT_KINDS) {
        if (k == kind) {
            return name;
        }
    }
    return "line";
}

std::string segmentKindList() {
    std::string out;
    for (const auto& [kind, name] : SEGMENT_KINDS) {
        out += (out.empty() ? "" : ", ") + inQuotes(name);
    }
    return out;
}

patterns::BodySource readBody(const json& value, const ordered_json& ordered,
                              const std::string& pointer) {
    ObjectReader r(value, pointer);
    patterns::BodySource body;
    if (r.has("mesh")) {
        for (const char* key : {"base", "measurements"}) {
            if (r.has(key)) {
                r.fail(key, "a body is either a mesh or a base with measurements, not both");
            }
        }
        body.meshPath = name(r, "mesh");
        if (r.has("units")) {
            body.meshUnits = r.string("units", "");
            if (body.meshUnits != "mm" && body.meshUnits != "cm" && body.meshUnits != "m") {
                r.fail("units", "unknown mesh unit " + inQuotes(body.meshUnits) +
                                    " (expected \"mm\", \"cm\" or \"m\")");
            }
        }
        if (r.has("up")) {
            body.meshUp = r.string("up", "");
            if (body.meshUp != "y" && body.meshUp != "z") {
                r.fail("up",
                       "unknown up axis " + inQuotes(body.meshUp) + " (expected \"y\" or \"z\")");
            }
        }
        r.finish();
        return body;
    }
    body.base = r.string("base", body.base);
    if (body.base != "female" && body.base != "male") {
        r.fail("base",
               "unknown body base " + inQuotes(body.base) + " (expected \"female\" or \"male\")");
    }
    readMeasurements(r, ordered, body);
    r.finish();
    return body;
}

patterns::GarmentMaterial readMaterial(const json& value, const std::string& pointer,
                                       const std::vector<patterns::GarmentMaterial>& existing) {
    ObjectReader r(value, pointer);
    patterns::GarmentMaterial material;
    material.name = name(r, "name");
    for (const patterns::GarmentMaterial& other : existing) {
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
            r.fail("fabric",
                   "unknown fabric preset " + inQuotes(*fabric) + " (presets: " + names + ")");
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
    return material;
}

PanelAttributes readPanelAttributes(ObjectReader& r,
                                    const std::vector<patterns::GarmentMaterial>& materials,
                                    const std::vector<std::string>& takenNames) {
    PanelAttributes a;
    a.name = name(r, "name");
    if (std::find(takenNames.begin(), takenNames.end(), a.name) != takenNames.end()) {
        r.fail("name", "another panel is already named " + inQuotes(a.name));
    }
    a.material = r.string("material");
    bool knownMaterial = false;
    std::string materialNames;
    for (const patterns::GarmentMaterial& m : materials) {
        knownMaterial = knownMaterial || m.name == a.material;
        materialNames += (materialNames.empty() ? "" : ", ") + inQuotes(m.name);
    }
    if (!knownMaterial) {
        r.fail("material",
               "unknown material " + inQuotes(a.material) +
                   (materialNames.empty() ? std::string(" (the project has no materials)")
                                          : " (materials: " + materialNames + ")"));
    }
    const std::string side = r.string("side", "front");
    if (side == "front") {
        a.side = patterns::PanelSide::Front;
    } else if (side == "back") {
        a.side = patterns::PanelSide::Back;
    } else {
        r.fail("side", "unknown side " + inQuotes(side) + " (expected \"front\" or \"back\")");
    }
    a.grainAngle = angleDeg(r, "grain_deg", a.grainAngle);
    a.particleDistance = lengthMm(r, "particle_distance_mm", 0.0, Range::NonNegative);
    if (!(a.particleDistance == 0 ||
          (a.particleDistance >= patterns::MIN_PANEL_PARTICLE_DISTANCE &&
           a.particleDistance <= patterns::MAX_PANEL_PARTICLE_DISTANCE))) {
        r.fail("particle_distance_mm", "must be 0 (the drape's) or between 1 and 1000 mm");
    }
    if (const json* placement = r.find("placement")) {
        ObjectReader p(*placement, r.pointerOf("placement"));
        patterns::Placement& out = a.placement;
        out.slot = p.string("slot", out.slot);
        if (const json* offset = p.find("offset_mm")) {
            out.offset = pointAt(*offset, p.pointerOf("offset_mm"));
            // Along a body's surface: anything farther is off every body (and an offset of
            // 9e15 m made the placement search run for ever).
            constexpr double MAX_OFFSET_M = 10.0;
            if (out.offset.cwiseAbs().maxCoeff() > MAX_OFFSET_M) {
                throw JsonError{p.pointerOf("offset_mm"),
                                "an offset beyond 10000 mm is off the body"};
            }
        }
        out.rotation = angleDeg(p, "rotation_deg", out.rotation);
        out.clearance = lengthMm(p, "clearance_mm", out.clearance, Range::NonNegative);
        p.finish();
    }
    return a;
}

patterns::DrapeSettings readSimulation(const json& value, const std::string& pointer) {
    ObjectReader r(value, pointer);
    patterns::DrapeSettings d;
    d.particleDistance = lengthMm(r, "particle_distance_mm", d.particleDistance, Range::Positive);
    if (const auto model = r.optionalString("model")) {
        const auto m = sim::stretchModelFromName(*model);
        if (!m) {
            r.fail("model", "unknown model " + inQuotes(*model) + " (expected one of " +
                                nameList(sim::STRETCH_MODELS, &sim::stretchModelName) + ")");
        }
        d.model = *m;
    }
    if (const auto model = r.optionalString("bending_model")) {
        const auto m = sim::bendingModelFromName(*model);
        if (!m) {
            r.fail("bending_model", "unknown bending model " + inQuotes(*model) +
                                        " (expected \"continuum\" or \"hinge\")");
        }
        d.bendingModel = *m;
    }
    if (const auto integrator = r.optionalString("integrator")) {
        const auto kind = sim::integratorFromName(*integrator);
        if (!kind) {
            r.fail("integrator", "unknown integrator " + inQuotes(*integrator) +
                                     " (expected one of " +
                                     nameList(sim::INTEGRATOR_KINDS, &sim::integratorName) + ")");
        }
        d.integrator = *kind;
    }
    d.dt = r.positive("dt_s", d.dt);
    d.cgTolerance = r.positive("cg_tolerance", d.cgTolerance);
    if (const auto solver = r.optionalString("linear_solver")) {
        const auto kind = sim::linearSolverFromName(*solver);
        if (!kind) {
            r.fail("linear_solver",
                   "unknown linear solver " + inQuotes(*solver) + " (expected one of " +
                       nameList(sim::LINEAR_SOLVERS, &sim::linearSolverName) + ")");
        }
        d.linearSolver = kind.value_or(d.linearSolver);
    }
    d.clothThickness = lengthMm(r, "cloth_thickness_mm", d.clothThickness, Range::Positive);
    d.selfCollision = r.boolean("self_collision", d.selfCollision);
    d.bodyThickness = lengthMm(r, "body_thickness_mm", d.bodyThickness, Range::NonNegative);
    d.bodyStaticFriction = r.nonNegative("body_static_friction", d.bodyStaticFriction);
    d.bodyKineticFriction = r.nonNegative("body_kinetic_friction", d.bodyKineticFriction);
    d.seamTimeConstant = r.positive("seam_time_constant_s", d.seamTimeConstant);
    d.seamStiffness = r.nonNegative("seam_stiffness_n_per_m2", d.seamStiffness);
    d.seamWeldDistance =
        lengthMm(r, "seam_weld_distance_mm", d.seamWeldDistance, Range::NonNegative);
    d.seamBending = r.boolean("seam_bending", d.seamBending);
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
    return d;
}

// ---------------------------------------------------------------------------------------------
// Writing

ordered_json number(double v) {
    if (v == 0) {
        return 0;
    }
    if (std::isfinite(v) && v == std::floor(v) && std::abs(v) < 9e15) {
        return static_cast<long long>(v);
    }
    return v;
}

ordered_json mm(double metres) {
    return rounded(metres * 1000.0);
}
ordered_json deg(double radians) {
    return rounded(radians / std::numbers::pi * 180.0);
}
ordered_json pointMm(const Vec2& p) {
    return ordered_json::array({mm(p.x()), mm(p.y())});
}

ordered_json bodyJson(const patterns::BodySource& source) {
    ordered_json body = ordered_json::object();
    if (!source.meshPath.empty()) {
        body["mesh"] = source.meshPath;
        if (!source.meshUnits.empty()) {
            body["units"] = source.meshUnits;
        }
        if (!source.meshUp.empty()) {
            body["up"] = source.meshUp;
        }
        return body;
    }
    body["base"] = source.base;
    ordered_json measurements = ordered_json::object();
    for (const auto& [key, value] : source.measurements) {
        measurements[key] = number(value);
    }
    body["measurements"] = std::move(measurements);
    return body;
}

ordered_json materialJson(const patterns::GarmentMaterial& material) {
    ordered_json out = ordered_json::object();
    out["name"] = material.name;
    const sim::Material& m = material.material;
    const MaterialPresets& presets = builtinMaterialPresets();
    if (const auto it = presets.find(m.name);
        it != presets.end() && sameParameters(m, it->second)) {
        out["fabric"] = m.name;
        return out;
    }
    appendMaterialFields(out, m);
    return out;
}

void appendMaterialFields(ordered_json& out, const sim::Material& m) {
    out["density_kg_per_m2"] = number(m.density);
    out["stretch_weft_n_per_m"] = number(m.stretchWeft);
    out["stretch_warp_n_per_m"] = number(m.stretchWarp);
    out["shear_n_per_m"] = number(m.shear);
    out["poisson"] = number(m.poisson);
    out["bending_n_m"] = number(m.bending);
    // Per-direction rigidities only when set: an isotropic fabric's entry stays as it was.
    for (const auto& [key, value] : {std::pair{"bending_weft_n_m", m.bendingWeft},
                                     std::pair{"bending_warp_n_m", m.bendingWarp},
                                     std::pair{"bending_bias_n_m", m.bendingBias}}) {
        if (value > 0) {
            out[key] = number(value);
        }
    }
    if (m.stretchKnee > 0) { // the stiffening law only when set, as the bending directions
        out["stretch_knee_strain"] = number(m.stretchKnee);
        for (const auto& [key, value] :
             {std::pair{"stretch_weft_beyond_n_per_m", m.stretchWeftBeyond},
              std::pair{"stretch_warp_beyond_n_per_m", m.stretchWarpBeyond}}) {
            if (value > 0) {
                out[key] = number(value);
            }
        }
    }
    out["damping_s"] = number(m.damping);
    out["static_friction"] = number(m.staticFriction);
    out["kinetic_friction"] = number(m.kineticFriction);
    out["plastic_yield_angle_rad"] = number(m.plasticYieldAngle);
    out["plastic_rate_per_s"] = number(m.plasticRate);
}

ordered_json placementJson(const patterns::Placement& placement) {
    ordered_json p = ordered_json::object();
    p["slot"] = placement.slot;
    p["offset_mm"] = pointMm(placement.offset);
    p["rotation_deg"] = deg(placement.rotation);
    p["clearance_mm"] = mm(placement.clearance);
    return p;
}

std::string_view sideName(patterns::PanelSide side) {
    return side == patterns::PanelSide::Back ? "back" : "front";
}

ordered_json simulationJson(const patterns::DrapeSettings& d) {
    ordered_json out = ordered_json::object();
    out["particle_distance_mm"] = mm(d.particleDistance);
    out["model"] = std::string(sim::stretchModelName(d.model));
    if (d.bendingModel != patterns::DrapeSettings{}.bendingModel) {
        out["bending_model"] = std::string(sim::bendingModelName(d.bendingModel));
    }
    out["integrator"] = std::string(sim::integratorName(d.integrator));
    out["dt_s"] = number(d.dt);
    out["cg_tolerance"] = number(d.cgTolerance);
    out["linear_solver"] = std::string(sim::linearSolverName(d.linearSolver));
    out["cloth_thickness_mm"] = mm(d.clothThickness);
    out["self_collision"] = d.selfCollision;
    out["body_thickness_mm"] = mm(d.bodyThickness);
    out["body_static_friction"] = number(d.bodyStaticFriction);
    out["body_kinetic_friction"] = number(d.bodyKineticFriction);
    out["seam_time_constant_s"] = number(d.seamTimeConstant);
    out["seam_stiffness_n_per_m2"] = number(d.seamStiffness);
    out["seam_weld_distance_mm"] = mm(d.seamWeldDistance);
    if (!d.seamBending) { // written when off: files of the default stay as they were
        out["seam_bending"] = false;
    }
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

} // namespace atelier::io::detail
