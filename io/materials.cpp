#include "io/materials.h"

#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/json_text.h"
#include "io/material_json.h"
#include "io/project_json.h"

#include "sim/forces/continuum_bending.h"

#include <limits>
#include <string>
#include <tuple>

namespace atelier::io {

namespace detail {

/// The text of assets/materials/fabrics.json, generated at configure time.
extern const char* const BUILTIN_FABRICS_JSON;

void readMaterial(ObjectReader& reader, sim::Material& material, bool requireAll) {
    reader.allow({"source", "description"});
    for (const char* key : {"source", "description"}) {
        reader.optionalString(key);
    }
    auto field = [&](std::string_view key, double& target, bool positive, double max,
                     bool required) {
        if (!reader.has(key)) {
            if (required) {
                reader.require(key); // throws "missing required key"
            }
            reader.find(key);
            return;
        }
        const double v = reader.number(key);
        if (positive && !(v > 0)) {
            reader.fail(key, "must be positive (found " + nlohmann::json(v).dump() + ")");
        }
        if (!positive && v < 0) {
            reader.fail(key, "must not be negative (found " + nlohmann::json(v).dump() + ")");
        }
        if (!(v < max)) {
            reader.fail(key, "must be less than " + nlohmann::json(max).dump() + " (found " +
                                 nlohmann::json(v).dump() + ")");
        }
        target = v;
    };
    constexpr double NO_MAX = std::numeric_limits<double>::infinity();
    field("density_kg_per_m2", material.density, true, NO_MAX, requireAll);
    field("stretch_weft_n_per_m", material.stretchWeft, true, NO_MAX, requireAll);
    field("stretch_warp_n_per_m", material.stretchWarp, true, NO_MAX, requireAll);
    field("shear_n_per_m", material.shear, true, NO_MAX, requireAll);
    field("poisson", material.poisson, false, 1.0, requireAll);
    field("bending_n_m", material.bending, false, NO_MAX, requireAll);
    // Per-direction bending rigidities are optional (0 = bending_n_m).
    field("bending_weft_n_m", material.bendingWeft, false, NO_MAX, false);
    field("bending_warp_n_m", material.bendingWarp, false, NO_MAX, false);
    field("bending_bias_n_m", material.bendingBias, false, NO_MAX, false);
    if (sim::BendingRigidity rigidity; const auto why = sim::bendingRigidity(material, rigidity)) {
        reader.fail(material.bendingBias > 0 ? "bending_bias_n_m" : "bending_n_m", *why);
    }
    // The stiffening stretch law is optional (knee 0 = linear; a modulus beyond it of 0 = the
    // small-strain one).
    field("stretch_knee_strain", material.stretchKnee, false, 1.0, false);
    field("stretch_weft_beyond_n_per_m", material.stretchWeftBeyond, false, NO_MAX, false);
    field("stretch_warp_beyond_n_per_m", material.stretchWarpBeyond, false, NO_MAX, false);
    for (const auto& [key, beyond, small, name] :
         {std::tuple{"stretch_weft_beyond_n_per_m", material.stretchWeftBeyond,
                     material.stretchWeft, "stretch_weft_n_per_m"},
          std::tuple{"stretch_warp_beyond_n_per_m", material.stretchWarpBeyond,
                     material.stretchWarp, "stretch_warp_n_per_m"}}) {
        if (beyond > 0 && beyond < small) {
            reader.fail(key, "must not be below " + std::string(name) + " (found " +
                                 nlohmann::json(beyond).dump() + " < " +
                                 nlohmann::json(small).dump() +
                                 "): fabrics stiffen, they do "
                                 "not soften, beyond the knee");
        }
    }
    field("damping_s", material.damping, false, NO_MAX, requireAll);
    field("static_friction", material.staticFriction, false, NO_MAX, requireAll);
    field("kinetic_friction", material.kineticFriction, false, NO_MAX, requireAll);
    // Plasticity is optional even in presets.
    field("plastic_yield_angle_rad", material.plasticYieldAngle, false, NO_MAX, false);
    field("plastic_rate_per_s", material.plasticRate, false, NO_MAX, false);
}

} // namespace detail

Result<MaterialPresets> parseMaterialPresets(std::string_view text, const std::string& file,
                                             const Limits& limits) {
    auto parsed = detail::parseJson(std::string(text), file, limits.maxJsonDepth);
    if (!parsed.ok()) {
        return parsed.error();
    }
    try {
        detail::ObjectReader root(parsed.value(), "");
        root.allow({"comment", "units"});
        const std::string format = root.string("format");
        if (format != "atelier-fabrics") {
            root.fail("format", "expected \"atelier-fabrics\", found \"" + format + "\"");
        }
        const long long version = root.integer("version");
        if (version != 1) {
            root.fail("version", "unsupported version " + std::to_string(version) +
                                     " (this build reads version 1)");
        }
        const nlohmann::json& presets = root.require("presets");
        detail::ObjectReader presetsReader(presets, root.pointerOf("presets"));
        MaterialPresets out;
        for (const auto& [name, value] : presets.items()) {
            presetsReader.find(name);
            detail::ObjectReader reader(value, presetsReader.pointerOf(name));
            sim::Material material;
            material.name = name;
            detail::readMaterial(reader, material, true);
            reader.finish();
            out.emplace(name, material);
        }
        if (out.empty()) {
            root.fail("presets", "no presets");
        }
        root.finish();
        return out;
    } catch (const detail::JsonError& e) {
        return Error{file, e.where, e.message};
    }
}

Result<MaterialPresets> loadMaterialPresets(const std::filesystem::path& path,
                                            const Limits& limits) {
    auto text = readFile(path, limits.maxJsonBytes);
    if (!text.ok()) {
        return text.error();
    }
    return parseMaterialPresets(text.value(), path.string(), limits);
}

const MaterialPresets& builtinMaterialPresets() {
    static const MaterialPresets presets = [] {
        auto parsed = parseMaterialPresets(detail::BUILTIN_FABRICS_JSON, "fabrics.json (built in)");
        // The file is checked by the unit tests; a broken built-in copy gives no presets.
        return parsed.ok() ? parsed.value() : MaterialPresets{};
    }();
    return presets;
}

std::string presetNames(const MaterialPresets& presets) {
    std::string names;
    for (const auto& entry : presets) {
        names += (names.empty() ? "" : ", ") + entry.first;
    }
    return names;
}

std::string formatMaterialPreset(const std::string& name, const sim::Material& material,
                                 const std::string& description, const std::string& source) {
    nlohmann::ordered_json preset = nlohmann::ordered_json::object();
    preset["description"] = description;
    preset["source"] = source;
    detail::appendMaterialFields(preset, material);
    nlohmann::ordered_json root = nlohmann::ordered_json::object();
    root["format"] = "atelier-fabrics";
    root["version"] = 1;
    root["presets"][name] = std::move(preset);
    return jsonText(root);
}

} // namespace atelier::io
