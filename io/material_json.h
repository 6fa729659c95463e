#pragma once
/// Internal to io/: the JSON fields of a material, shared by the preset file and scene files.
///
/// Keys (SI): density_kg_per_m2, stretch_weft_n_per_m, stretch_warp_n_per_m, shear_n_per_m,
/// poisson, bending_n_m, damping_s, static_friction, kinetic_friction, plastic_yield_angle_rad,
/// plastic_rate_per_s; optional bending_weft_n_m, bending_warp_n_m, bending_bias_n_m; plus "source"
/// and "description" strings, which are ignored.

#include "io/json_reader.h"

#include "sim/material.h"

namespace atelier::io::detail {

/// Reads the material keys present in `reader` into `material` (overrides); with `requireAll`
/// the mechanical keys (all but plasticity) must all be there. Throws JsonError.
void readMaterial(ObjectReader& reader, sim::Material& material, bool requireAll);

} // namespace atelier::io::detail
