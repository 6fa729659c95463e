#include "patterns/fabric_fit.h"

#include "sim/core/types.h"
#include "sim/forces/continuum_bending.h"

#include <cmath>
#include <numbers>
#include <string>

namespace atelier::patterns {

namespace {

Error measurementError(const std::string& key, const std::string& message) {
    return Error{"", key, message};
}

bool positive(const std::optional<double>& v) {
    return !v || (std::isfinite(*v) && *v > 0);
}

} // namespace

double rigidityOfBendingLength(double c, double density) {
    return density * sim::STANDARD_GRAVITY * c * c * c;
}

double bendingLengthOf(double rigidity, double density) {
    return std::cbrt(rigidity / (density * sim::STANDARD_GRAVITY));
}

StripResponse biasTensile(const sim::Material& m) {
    const double s1 = 1.0 / m.stretchWeft;
    const double s2 = 1.0 / m.stretchWarp;
    const double s6 = 1.0 / m.shear;
    const double e45 = 4.0 / (s1 + s2 + s6 - 2.0 * m.poisson * s1);
    return {e45, e45 * (0.5 * m.poisson * s1 - 0.25 * (s1 + s2 - s6))};
}

Result<sim::Material> fitFabric(const LabFabric& lab, const sim::Material& base) {
    if (!(std::isfinite(lab.density) && lab.density > 0)) {
        return measurementError("density", "must be a positive areal density [kg/m²]");
    }
    const struct {
        const char* key;
        const std::optional<double>& value;
    } all[] = {{"bending_length_weft", lab.bendingLengthWeft},
               {"bending_length_warp", lab.bendingLengthWarp},
               {"bending_length_bias", lab.bendingLengthBias},
               {"bending_weft", lab.bendingWeft},
               {"bending_warp", lab.bendingWarp},
               {"bending_bias", lab.bendingBias},
               {"tensile_weft", lab.tensileWeft},
               {"tensile_warp", lab.tensileWarp},
               {"tensile_bias", lab.tensileBias}};
    for (const auto& m : all) {
        if (!positive(m.value)) {
            return measurementError(m.key, "must be positive");
        }
    }
    if (lab.poisson && !(std::isfinite(*lab.poisson) && *lab.poisson >= 0 && *lab.poisson < 1)) {
        return measurementError("poisson", "must be in [0, 1)");
    }
    sim::Material m = base;
    m.density = lab.density;
    // B per direction: from the bending length, or as measured; 0 = not measured.
    const auto rigidity = [&](const char* key, const std::optional<double>& length,
                              const std::optional<double>& b, double& out) -> std::optional<Error> {
        if (length && b) {
            return measurementError(key, "give a bending length or a rigidity, not both");
        }
        out = length ? rigidityOfBendingLength(*length, lab.density) : b.value_or(0.0);
        return std::nullopt;
    };
    double bWeft = 0;
    double bWarp = 0;
    double bBias = 0;
    if (auto e = rigidity("bending_weft", lab.bendingLengthWeft, lab.bendingWeft, bWeft)) {
        return *e;
    }
    if (auto e = rigidity("bending_warp", lab.bendingLengthWarp, lab.bendingWarp, bWarp)) {
        return *e;
    }
    if (auto e = rigidity("bending_bias", lab.bendingLengthBias, lab.bendingBias, bBias)) {
        return *e;
    }
    if (bWeft > 0 || bWarp > 0) {
        // The isotropic value (the hinge model's, and the one a project shows) is the geometric
        // mean of the two thread directions; one direction alone is taken for both.
        const double one = bWeft > 0 ? bWeft : bWarp;
        const double other = bWarp > 0 ? bWarp : bWeft;
        m.bending = std::sqrt(one * other);
        m.bendingWeft = bWeft > 0 && bWarp > 0 ? bWeft : 0;
        m.bendingWarp = bWeft > 0 && bWarp > 0 ? bWarp : 0;
        m.bendingBias = 0; // the base's bias rigidity belongs to its own weft and warp
    }
    if (bBias > 0) {
        m.bendingBias = bBias;
    }
    sim::BendingRigidity plate;
    if (auto e = sim::bendingRigidity(m, plate)) {
        return measurementError("bending_bias", *e);
    }
    if (lab.tensileWeft) {
        m.stretchWeft = *lab.tensileWeft;
    }
    if (lab.tensileWarp) {
        m.stretchWarp = *lab.tensileWarp;
    }
    if (lab.poisson) {
        m.poisson = *lab.poisson;
    }
    if (m.poisson * m.poisson * m.stretchWarp / m.stretchWeft >= 1.0) {
        return measurementError("poisson", "ν₁₂·ν₂₁ must be below 1 (ν₂₁ = ν₁₂·E₂/E₁)");
    }
    if (lab.tensileBias) {
        const double inverseShear = 4.0 / *lab.tensileBias - 1.0 / m.stretchWeft -
                                    1.0 / m.stretchWarp + 2.0 * m.poisson / m.stretchWeft;
        if (!(inverseShear > 0)) {
            return measurementError("tensile_bias",
                                    "stiffer than the weft and warp stiffness allow: a bias strip "
                                    "is at most as stiff as 4/(1/E1 + 1/E2 - 2 nu12/E1)");
        }
        m.shear = 1.0 / inverseShear;
    }
    return m;
}

Result<FabricFigures> fabricFigures(const sim::Material& m) {
    sim::BendingRigidity plate;
    if (auto e = sim::bendingRigidity(m, plate)) {
        return measurementError("bending", *e);
    }
    if (!(m.density > 0) || !(m.stretchWeft > 0) || !(m.stretchWarp > 0) || !(m.shear > 0)) {
        return measurementError("", "density, stretch and shear must be positive");
    }
    FabricFigures f;
    f.bendingWeft = plate.weft;
    f.bendingWarp = plate.warp;
    f.bendingBias = sim::stripRigidity(plate, std::numbers::pi / 4);
    f.bendingLengthWeft = bendingLengthOf(f.bendingWeft, m.density);
    f.bendingLengthWarp = bendingLengthOf(f.bendingWarp, m.density);
    f.bendingLengthBias = bendingLengthOf(f.bendingBias, m.density);
    f.tensileBias = biasTensile(m).stretch;
    return f;
}

} // namespace atelier::patterns
