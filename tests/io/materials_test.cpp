#include "io/materials.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

namespace atelier::io {
namespace {

const std::string FABRICS = std::string(ATELIER_SOURCE_DIR) + "/assets/materials/fabrics.json";

TEST(Materials, BundledPresetsLoadAndArePositive) {
    const auto presets = loadMaterialPresets(FABRICS);
    ASSERT_TRUE(presets.ok()) << presets.error().toString();
    for (const char* name : {"cotton", "denim", "silk", "jersey-knit", "leather", "polyester"}) {
        ASSERT_EQ(presets.value().count(name), 1U) << name;
    }
    for (const auto& [name, m] : presets.value()) {
        SCOPED_TRACE(name);
        EXPECT_EQ(m.name, name);
        EXPECT_GT(m.density, 0);
        EXPECT_GT(m.stretchWeft, 0);
        EXPECT_GT(m.stretchWarp, 0);
        EXPECT_GT(m.shear, 0);
        EXPECT_GT(m.bending, 0);
        EXPECT_GT(m.damping, 0);
        EXPECT_GT(m.staticFriction, 0);
        EXPECT_GT(m.kineticFriction, 0);
        EXPECT_GE(m.poisson, 0);
        EXPECT_LT(m.poisson * m.poisson * m.stretchWarp / m.stretchWeft, 1)
            << "orthotropic Poisson ratios must keep the stiffness positive definite";
        // Plausible ranges for garment fabrics (SI).
        EXPECT_LT(m.density, 2.0);
        EXPECT_LE(m.stretchWarp, 1e5);
        EXPECT_LE(m.bending, 1e-3);
    }
    const auto& p = presets.value();
    EXPECT_GT(p.at("denim").density, p.at("cotton").density);
    EXPECT_LT(p.at("jersey-knit").stretchWeft, p.at("cotton").stretchWeft);
    EXPECT_GT(p.at("leather").bending, p.at("silk").bending);
}

TEST(Materials, BuiltInCopyMatchesTheAssetFile) {
    const auto presets = loadMaterialPresets(FABRICS);
    ASSERT_TRUE(presets.ok());
    const MaterialPresets& builtin = builtinMaterialPresets();
    ASSERT_EQ(builtin.size(), presets.value().size());
    for (const auto& [name, m] : presets.value()) {
        ASSERT_EQ(builtin.count(name), 1U) << name;
        EXPECT_EQ(builtin.at(name).density, m.density);
        EXPECT_EQ(builtin.at(name).stretchWarp, m.stretchWarp);
        EXPECT_EQ(builtin.at(name).bending, m.bending);
    }
}

std::string presetFile(const std::string& fields) {
    return R"({"format": "atelier-fabrics", "version": 1, "presets": {"x": {)" + fields + "}}}";
}

const std::string ALL_FIELDS =
    R"("density_kg_per_m2": 0.1, "stretch_weft_n_per_m": 1000, "stretch_warp_n_per_m": 1000,
       "shear_n_per_m": 100, "poisson": 0.3, "bending_n_m": 1e-5, "damping_s": 0.001,
       "static_friction": 0.5, "kinetic_friction": 0.4)";

TEST(Materials, ErrorsNameTheJsonPath) {
    ASSERT_TRUE(parseMaterialPresets(presetFile(ALL_FIELDS), "f.json").ok());

    auto bad = parseMaterialPresets(presetFile(ALL_FIELDS + R"(, "densty": 1)"), "f.json");
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().where, "/presets/x/densty");
    EXPECT_NE(bad.error().message.find("unknown key"), std::string::npos);

    std::string negative = ALL_FIELDS;
    negative.replace(negative.find("0.1"), 3, "-0.1");
    bad = parseMaterialPresets(presetFile(negative), "f.json");
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().toString().substr(0, 34), "f.json: /presets/x/density_kg_per_");
    EXPECT_NE(bad.error().message.find("positive"), std::string::npos);

    bad = parseMaterialPresets(presetFile(R"("density_kg_per_m2": 0.1)"), "f.json");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("missing"), std::string::npos);

    bad = parseMaterialPresets(presetFile(R"("density_kg_per_m2": "heavy")"), "f.json");
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().where, "/presets/x/density_kg_per_m2");

    bad = parseMaterialPresets("{\"format\": \"atelier-fabrics\",\n \"version\": 1,,}", "f.json");
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().where.substr(0, 6), "line 2");
}

// The stiffening stretch law: optional keys, read as given; a modulus beyond the knee below the
// small-strain one is refused at its path.
TEST(Materials, TheStiffeningLawIsOptionalAndMustStiffen) {
    auto plain = parseMaterialPresets(presetFile(ALL_FIELDS), "f.json");
    ASSERT_TRUE(plain.ok());
    EXPECT_EQ(plain.value().at("x").stretchKnee, 0.0);
    EXPECT_EQ(plain.value().at("x").stretchWeftBeyond, 0.0);
    auto stiff = parseMaterialPresets(presetFile(ALL_FIELDS + R"(, "stretch_knee_strain": 0.04,
                   "stretch_weft_beyond_n_per_m": 5000, "stretch_warp_beyond_n_per_m": 8000)"),
                                      "f.json");
    ASSERT_TRUE(stiff.ok()) << stiff.error().toString();
    EXPECT_EQ(stiff.value().at("x").stretchKnee, 0.04);
    EXPECT_EQ(stiff.value().at("x").stretchWeftBeyond, 5000.0);
    EXPECT_EQ(stiff.value().at("x").stretchWarpBeyond, 8000.0);
    auto softer = parseMaterialPresets(
        presetFile(ALL_FIELDS +
                   R"(, "stretch_knee_strain": 0.04, "stretch_warp_beyond_n_per_m": 500)"),
        "f.json");
    ASSERT_FALSE(softer.ok());
    EXPECT_EQ(softer.error().where, "/presets/x/stretch_warp_beyond_n_per_m");
    EXPECT_NE(softer.error().message.find("must not be below stretch_warp_n_per_m"),
              std::string::npos)
        << softer.error().message;
    auto knee =
        parseMaterialPresets(presetFile(ALL_FIELDS + R"(, "stretch_knee_strain": 1.5)"), "f.json");
    ASSERT_FALSE(knee.ok());
    EXPECT_EQ(knee.error().where, "/presets/x/stretch_knee_strain");
}

} // namespace
} // namespace atelier::io
