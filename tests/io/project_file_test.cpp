#include "io/materials.h"
#include "io/project_file.h"
#include "io/temp_dir.h"

#include "source_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <numbers>
#include <random>

namespace atelier::io {
namespace {

using nlohmann::json;
using patterns::Segment;
using patterns::SegmentKind;

constexpr double RAD_PER_DEG = std::numbers::pi / 180.0;

/// A project using every feature of the format (millimetres and degrees, as in files).
const char* const FULL = R"({
  "format": "atelier-project",
  "version": 1,
  "name": "test top",
  "body": {"base": "male", "measurements": {"waist": 0.82, "bust": 0.96, "hip": 1.01}},
  "materials": [
    {"name": "shell", "fabric": "jersey-knit"},
    {"name": "lining", "density_kg_per_m2": 0.08, "stretch_weft_n_per_m": 1500,
     "stretch_warp_n_per_m": 2500, "shear_n_per_m": 300, "bending_n_m": 2e-6}
  ],
  "panels": [
    {
      "name": "front",
      "material": "shell",
      "side": "back",
      "grain_deg": 80,
      "outline": [
        {"line": {"from": [-200, 0]}},
        {"line": {"from": [200, 0]}},
        {"cubic": {"from": [200, 400], "c1": [150, 450], "c2": [100, 500]}},
        {"line": {"from": [50, 500]}},
        {"line": {"from": [0, 420]}},
        {"quadratic": {"from": [-50, 500], "c1": [-150, 520]}},
        {"arc": {"from": [-200, 400], "bulge": 0.1}}
      ],
      "holes": [[
        {"line": {"from": [-20, 180]}},
        {"line": {"from": [-20, 220]}},
        {"line": {"from": [20, 220]}},
        {"line": {"from": [20, 180]}}
      ]],
      "internal_lines": [
        {"fold_deg": 45.5, "segments": [
          {"line": {"from": [-100, 100], "to": [-100, 300]}},
          {"quadratic": {"from": [-100, 300], "to": [-60, 340], "c1": [-100, 340]}}
        ]}
      ],
      "darts": [{"leg": 3}],
      "notches": [{"segment": 0, "t": 0.25}, {"segment": 1}],
      "placement": {"slot": "torso_front", "offset_mm": [10.5, -20], "rotation_deg": 5,
                    "clearance_mm": 15}
    },
    {
      "name": "back",
      "material": "lining",
      "outline": [
        {"line": {"from": [-200, 0]}},
        {"line": {"from": [200, 0]}},
        {"line": {"from": [200, 400]}},
        {"line": {"from": [-200, 400]}}
      ],
      "placement": {"slot": "torso_back"}
    }
  ],
  "seams": [
    {"name": "side", "a": [{"panel": "front", "segment": 1, "t0": 0, "t1": 1}],
     "b": [{"panel": "back", "segment": 3, "t0": 1, "t1": 0}]},
    {"name": "hem", "a": [{"panel": "front", "segment": 0}],
     "b": [{"panel": "back", "segment": 0, "t0": 0.5, "t1": 1},
           {"panel": "back", "segment": 0, "t0": 0, "t1": 0.5}]}
  ],
  "ease_tolerance_mm": 7.5,
  "simulation": {"particle_distance_mm": 12.5, "model": "volino", "integrator": "rk45",
                 "dt_s": 0.002, "cloth_thickness_mm": 1.5, "self_collision": false,
                 "body_thickness_mm": 3, "body_static_friction": 0.6,
                 "body_kinetic_friction": 0.35, "seam_time_constant_s": 0.05,
                 "seam_weld_distance_mm": 0.5, "rest_kinetic_energy_j": 1e-7,
                 "rest_duration_s": 0.3, "time_limit_s": 8}
})";

/// The smallest project, and its canonical text (every key, defaults filled in).
const char* const MINIMAL = R"({"format": "atelier-project", "version": 1,
  "materials": [{"name": "m", "fabric": "cotton"}],
  "panels": [{"name": "p", "material": "m", "outline": [
    {"line": {"from": [0, 0]}}, {"line": {"from": [100, 0]}}, {"line": {"from": [0, 100]}}]}]})";
const char* const MINIMAL_CANONICAL = R"({
  "format": "atelier-project",
  "version": 2,
  "name": "",
  "body": {
    "base": "female",
    "measurements": {}
  },
  "materials": [
    {
      "name": "m",
      "fabric": "cotton"
    }
  ],
  "next_id": 8,
  "panels": [
    {
      "id": 1,
      "name": "p",
      "material": "m",
      "side": "front",
      "grain_deg": 90,
      "outline": [
        {
          "point": 2,
          "at": [
            0,
            0
          ],
          "edge": 3,
          "curve": "line"
        },
        {
          "point": 4,
          "at": [
            100,
            0
          ],
          "edge": 5,
          "curve": "line"
        },
        {
          "point": 6,
          "at": [
            0,
            100
          ],
          "edge": 7,
          "curve": "line"
        }
      ],
      "holes": [],
      "internal_lines": [],
      "darts": [],
      "notches": [],
      "placement": {
        "slot": "",
        "offset_mm": [
          0,
          0
        ],
        "rotation_deg": 0,
        "clearance_mm": 20
      }
    }
  ],
  "seams": [],
  "ease_tolerance_mm": 5,
  "simulation": {
    "particle_distance_mm": 10,
    "model": "fem",
    "integrator": "implicit-euler",
    "dt_s": 0.0033333333333333335,
    "cg_tolerance": 0.001,
    "linear_solver": "block-jacobi",
    "cloth_thickness_mm": 2,
    "self_collision": true,
    "body_thickness_mm": 2,
    "body_static_friction": 0.5,
    "body_kinetic_friction": 0.4,
    "seam_time_constant_s": 0.004,
    "seam_stiffness_n_per_m2": 16000,
    "seam_weld_distance_mm": 1,
    "seam_reach_mm": 10,
    "seam_route_clearance_mm": 10,
    "sewing_time_s": 0.3,
    "sewing_friction_scale": 0,
    "closing_time_s": 0.3,
    "rest_kinetic_energy_j": 1e-08,
    "rest_duration_s": 0.2,
    "time_limit_s": 5
  }
}
)";

Result<patterns::Project> parseShirt(const std::string& text) {
    return parseProject(text, "shirt.atelier");
}

/// FULL with the value at `pointer` replaced (or removedKeys when `value` is discarded).
std::string fullWith(const std::string& pointer, const json& value) {
    json doc = json::parse(FULL);
    if (value.is_discarded()) {
        const json::json_pointer p(pointer);
        doc.at(p.parent_pointer()).erase(p.back());
    } else {
        doc[json::json_pointer(pointer)] = value;
    }
    return doc.dump();
}

json removedKeys() {
    return json(json::value_t::discarded);
}

void expectError(const Result<patterns::Project>& result, const std::string& where,
                 const std::string& fragment, const std::string& file = "shirt.atelier") {
    ASSERT_FALSE(result.ok()) << "expected an error at " << where << " containing \"" << fragment
                              << "\"";
    EXPECT_EQ(result.error().file, file);
    EXPECT_EQ(result.error().where, where) << result.error().toString();
    EXPECT_NE(result.error().message.find(fragment), std::string::npos)
        << result.error().toString();
}

void expectPoint(const sim::Vec2& actual, double xMm, double yMm) {
    EXPECT_NEAR(actual.x(), xMm / 1000, 1e-15);
    EXPECT_NEAR(actual.y(), yMm / 1000, 1e-15);
}

/// format → parse → format gives the same text; returns the parsed project.
patterns::Project expectStableText(const std::string& text) {
    const std::string second = formatProject(parseShirt(text).value());
    const auto reparsed = parseShirt(second);
    EXPECT_TRUE(reparsed.ok()) << reparsed.error().toString();
    if (!reparsed.ok()) {
        return {};
    }
    EXPECT_EQ(formatProject(reparsed.value()), second);
    return reparsed.value();
}

TEST(ProjectFile, FullProjectValues) {
    const auto parsed = parseShirt(FULL);
    ASSERT_TRUE(parsed.ok()) << parsed.error().toString();
    const patterns::Project& p = parsed.value();
    EXPECT_EQ(p.version, 1);
    EXPECT_EQ(p.name, "test top");
    EXPECT_EQ(p.garment.name, "test top");

    EXPECT_EQ(p.body.base, "male");
    EXPECT_TRUE(p.body.meshPath.empty());
    ASSERT_EQ(p.body.measurements.size(), 3U);
    // File order, not alphabetical.
    EXPECT_EQ(p.body.measurements[0].first, "waist");
    EXPECT_DOUBLE_EQ(p.body.measurements[0].second, 0.82);
    EXPECT_EQ(p.body.measurements[1].first, "bust");
    EXPECT_EQ(p.body.measurements[2].first, "hip");
    EXPECT_DOUBLE_EQ(p.body.measurements[2].second, 1.01);

    const patterns::Garment& g = p.garment;
    ASSERT_EQ(g.materials.size(), 2U);
    EXPECT_EQ(g.materials[0].name, "shell");
    const sim::Material& jersey = builtinMaterialPresets().at("jersey-knit");
    EXPECT_EQ(g.materials[0].material.name, "jersey-knit");
    EXPECT_DOUBLE_EQ(g.materials[0].material.density, jersey.density);
    EXPECT_DOUBLE_EQ(g.materials[0].material.stretchWarp, jersey.stretchWarp);
    EXPECT_EQ(g.materials[1].name, "lining");
    EXPECT_DOUBLE_EQ(g.materials[1].material.density, 0.08);
    EXPECT_DOUBLE_EQ(g.materials[1].material.stretchWeft, 1500);
    EXPECT_DOUBLE_EQ(g.materials[1].material.stretchWarp, 2500);
    EXPECT_DOUBLE_EQ(g.materials[1].material.shear, 300);
    EXPECT_DOUBLE_EQ(g.materials[1].material.bending, 2e-6);
    EXPECT_DOUBLE_EQ(g.materials[1].material.poisson, sim::Material{}.poisson); // default

    ASSERT_EQ(g.panels.size(), 2U);
    const patterns::Panel& front = g.panels[0];
    EXPECT_EQ(front.name, "front");
    EXPECT_EQ(front.material, "shell");
    EXPECT_EQ(front.side, patterns::PanelSide::Back);
    EXPECT_NEAR(front.grainAngle, 80 * RAD_PER_DEG, 1e-15);
    ASSERT_EQ(front.outline.size(), 7U);
    EXPECT_EQ(front.outline[0].kind, SegmentKind::Line);
    expectPoint(front.outline[0].start, -200, 0);
    expectPoint(front.outline[0].end, 200, 0);
    const Segment& cubic = front.outline[2];
    EXPECT_EQ(cubic.kind, SegmentKind::Cubic);
    expectPoint(cubic.start, 200, 400);
    expectPoint(cubic.control1, 150, 450);
    expectPoint(cubic.control2, 100, 500);
    expectPoint(cubic.end, 50, 500);
    const Segment& quadratic = front.outline[5];
    EXPECT_EQ(quadratic.kind, SegmentKind::Quadratic);
    expectPoint(quadratic.control1, -150, 520);
    expectPoint(quadratic.end, -200, 400);
    const Segment& arc = front.outline[6];
    EXPECT_EQ(arc.kind, SegmentKind::Arc);
    EXPECT_DOUBLE_EQ(arc.bulge, 0.1);
    expectPoint(arc.end, -200, 0); // the last segment closes the loop

    ASSERT_EQ(front.holes.size(), 1U);
    ASSERT_EQ(front.holes[0].size(), 4U);
    expectPoint(front.holes[0][3].start, 20, 180);
    expectPoint(front.holes[0][3].end, -20, 180);

    ASSERT_EQ(front.internalLines.size(), 1U);
    const patterns::InternalLine& line = front.internalLines[0];
    EXPECT_NEAR(line.foldAngle, 45.5 * RAD_PER_DEG, 1e-15);
    ASSERT_EQ(line.path.size(), 2U);
    expectPoint(line.path[0].start, -100, 100);
    expectPoint(line.path[0].end, -100, 300);
    EXPECT_EQ(line.path[1].kind, SegmentKind::Quadratic);
    expectPoint(line.path[1].end, -60, 340);
    expectPoint(line.path[1].control1, -100, 340);

    ASSERT_EQ(front.darts.size(), 1U);
    EXPECT_EQ(front.darts[0].leg, 3);
    ASSERT_EQ(front.notches.size(), 2U);
    EXPECT_EQ(front.notches[0].segment, 0);
    EXPECT_DOUBLE_EQ(front.notches[0].t, 0.25);
    EXPECT_EQ(front.notches[1].segment, 1);
    EXPECT_DOUBLE_EQ(front.notches[1].t, 0.5); // default

    EXPECT_EQ(front.placement.slot, "torso_front");
    expectPoint(front.placement.offset, 10.5, -20);
    EXPECT_NEAR(front.placement.rotation, 5 * RAD_PER_DEG, 1e-15);
    EXPECT_NEAR(front.placement.clearance, 0.015, 1e-15);

    // The second panel takes the defaults.
    const patterns::Panel& back = g.panels[1];
    const patterns::Panel defaults;
    EXPECT_EQ(back.side, defaults.side);
    EXPECT_DOUBLE_EQ(back.grainAngle, defaults.grainAngle);
    EXPECT_TRUE(back.holes.empty() && back.internalLines.empty() && back.darts.empty() &&
                back.notches.empty());
    EXPECT_EQ(back.placement.slot, "torso_back");
    EXPECT_DOUBLE_EQ(back.placement.clearance, defaults.placement.clearance);
    EXPECT_DOUBLE_EQ(back.placement.rotation, 0);

    ASSERT_EQ(g.seams.size(), 2U);
    EXPECT_EQ(g.seams[0].name, "side");
    ASSERT_EQ(g.seams[0].b.size(), 1U);
    EXPECT_EQ(g.seams[0].b[0].panel, "back");
    EXPECT_EQ(g.seams[0].b[0].segment, 3);
    EXPECT_DOUBLE_EQ(g.seams[0].b[0].t0, 1);
    EXPECT_DOUBLE_EQ(g.seams[0].b[0].t1, 0);
    ASSERT_EQ(g.seams[1].b.size(), 2U);
    EXPECT_DOUBLE_EQ(g.seams[1].a[0].t0, 0); // defaults
    EXPECT_DOUBLE_EQ(g.seams[1].a[0].t1, 1);
    EXPECT_DOUBLE_EQ(g.seams[1].b[1].t1, 0.5);
    EXPECT_NEAR(g.easeTolerance, 0.0075, 1e-15);

    const patterns::DrapeSettings& d = p.drape;
    EXPECT_NEAR(d.particleDistance, 0.0125, 1e-15);
    EXPECT_EQ(d.model, sim::StretchModel::Volino);
    EXPECT_EQ(d.integrator, sim::IntegratorKind::Rk45);
    EXPECT_DOUBLE_EQ(d.dt, 0.002);
    EXPECT_NEAR(d.clothThickness, 0.0015, 1e-15);
    EXPECT_FALSE(d.selfCollision);
    EXPECT_NEAR(d.bodyThickness, 0.003, 1e-15);
    EXPECT_DOUBLE_EQ(d.bodyStaticFriction, 0.6);
    EXPECT_DOUBLE_EQ(d.bodyKineticFriction, 0.35);
    EXPECT_DOUBLE_EQ(d.seamTimeConstant, 0.05);
    EXPECT_NEAR(d.seamWeldDistance, 0.0005, 1e-15);
    EXPECT_DOUBLE_EQ(d.restKineticEnergy, 1e-7);
    EXPECT_DOUBLE_EQ(d.restDuration, 0.3);
    EXPECT_DOUBLE_EQ(d.timeLimit, 8);
}

TEST(ProjectFile, MinimalProjectGetsDefaultsAndCanonicalText) {
    const auto parsed = parseShirt(MINIMAL);
    ASSERT_TRUE(parsed.ok()) << parsed.error().toString();
    // Absent keys take the defaults exactly.
    const patterns::DrapeSettings defaults;
    const patterns::DrapeSettings& d = parsed.value().drape;
    EXPECT_EQ(d.particleDistance, defaults.particleDistance);
    EXPECT_EQ(d.model, defaults.model);
    EXPECT_EQ(d.integrator, defaults.integrator);
    EXPECT_EQ(d.dt, defaults.dt);
    EXPECT_EQ(d.clothThickness, defaults.clothThickness);
    EXPECT_EQ(d.selfCollision, defaults.selfCollision);
    EXPECT_EQ(d.bodyThickness, defaults.bodyThickness);
    EXPECT_EQ(d.bodyStaticFriction, defaults.bodyStaticFriction);
    EXPECT_EQ(d.bodyKineticFriction, defaults.bodyKineticFriction);
    EXPECT_EQ(d.seamTimeConstant, defaults.seamTimeConstant);
    EXPECT_EQ(d.seamWeldDistance, defaults.seamWeldDistance);
    EXPECT_EQ(d.restKineticEnergy, defaults.restKineticEnergy);
    EXPECT_EQ(d.restDuration, defaults.restDuration);
    EXPECT_EQ(d.timeLimit, defaults.timeLimit);
    EXPECT_EQ(parsed.value().garment.easeTolerance, patterns::Garment{}.easeTolerance);
    const patterns::Panel& panel = parsed.value().garment.panels.at(0);
    EXPECT_EQ(panel.grainAngle, patterns::Panel{}.grainAngle);
    EXPECT_EQ(panel.placement.clearance, patterns::Placement{}.clearance);
    EXPECT_EQ(parsed.value().body.base, "female");
    EXPECT_EQ(formatProject(parsed.value()), MINIMAL_CANONICAL);

    // The canonical text reads back to the same values: whole millimetres and degrees
    // convert exactly.
    const auto canonical = parseShirt(MINIMAL_CANONICAL);
    ASSERT_TRUE(canonical.ok()) << canonical.error().toString();
    EXPECT_EQ(canonical.value().drape.particleDistance, defaults.particleDistance);
    EXPECT_EQ(canonical.value().drape.seamWeldDistance, defaults.seamWeldDistance);
    EXPECT_EQ(canonical.value().garment.easeTolerance, patterns::Garment{}.easeTolerance);
    EXPECT_EQ(canonical.value().garment.panels.at(0).grainAngle, patterns::Panel{}.grainAngle);
    EXPECT_EQ(canonical.value().garment.panels.at(0).placement.clearance,
              patterns::Placement{}.clearance);
    EXPECT_EQ(canonical.value().drape.dt, defaults.dt);
    expectStableText(MINIMAL_CANONICAL);
}

TEST(ProjectFile, FormatParseFormatIsByteIdentical) {
    const patterns::Project first = parseShirt(FULL).value();
    const std::string text = formatProject(first);
    EXPECT_EQ(text.rfind("{\n  \"format\": \"atelier-project\",\n  \"version\": 2,\n", 0), 0U);
    EXPECT_EQ(text.back(), '\n');
    const patterns::Project second = expectStableText(text);
    // Preset written back by name, inline material with its full parameters.
    const json doc = json::parse(text);
    EXPECT_EQ(doc["materials"][0], json::parse(R"({"name": "shell", "fabric": "jersey-knit"})"));
    EXPECT_EQ(doc["materials"][1].size(), 12U);
    EXPECT_EQ(doc["materials"][1]["density_kg_per_m2"], 0.08);
    // Outline points in millimetres, angles in degrees.
    EXPECT_EQ(doc["panels"][0]["outline"][2]["c2"], json::parse("[100, 500]"));
    EXPECT_EQ(doc["panels"][0]["grain_deg"], 80);
    EXPECT_EQ(doc["panels"][0]["internal_lines"][0]["fold_deg"], 45.5);
    EXPECT_EQ(doc["panels"][0]["placement"]["offset_mm"], json::parse("[10.5, -20]"));
    // Keys in the documented order.
    std::vector<std::string> keys;
    const nlohmann::ordered_json ordered = nlohmann::ordered_json::parse(text);
    for (const auto& [key, unused] : ordered.items()) {
        keys.push_back(key);
    }
    EXPECT_EQ(keys,
              (std::vector<std::string>{"format", "version", "name", "body", "materials", "next_id",
                                        "panels", "seams", "ease_tolerance_mm", "simulation"}));
    // Values survive the trip.
    EXPECT_EQ(second.body.measurements, first.body.measurements);
    EXPECT_EQ(second.garment.materials[1].material.density, 0.08);
    EXPECT_NEAR(second.garment.panels[0].grainAngle, first.garment.panels[0].grainAngle, 1e-15);
}

// A fabric's stiffening law is written with its material and read back the same; a preset
// given one is no longer the preset, so it is written in full.
TEST(ProjectFile, AStiffeningStretchLawSurvivesTheTrip) {
    patterns::Project project = parseShirt(FULL).value();
    sim::Material& lining = project.document.materials[1].material;
    lining.stretchKnee = 0.05;
    lining.stretchWeftBeyond = 6000;
    sim::Material& shell = project.document.materials[0].material;
    shell.stretchKnee = 0.03;
    shell.stretchWarpBeyond = 4 * shell.stretchWarp;
    const std::string text = formatProject(project);
    const json doc = json::parse(text);
    EXPECT_EQ(doc["materials"][1]["stretch_knee_strain"], 0.05);
    EXPECT_EQ(doc["materials"][1]["stretch_weft_beyond_n_per_m"], 6000);
    EXPECT_FALSE(doc["materials"][1].contains("stretch_warp_beyond_n_per_m"));
    EXPECT_FALSE(doc["materials"][0].contains("fabric"));
    const patterns::Project back = expectStableText(text);
    EXPECT_EQ(back.garment.materials[1].material.stretchKnee, 0.05);
    EXPECT_EQ(back.garment.materials[1].material.stretchWeftBeyond, 6000);
    EXPECT_EQ(back.garment.materials[1].material.stretchWarpBeyond, 0);
    EXPECT_EQ(back.garment.materials[0].material.stretchWarpBeyond, shell.stretchWarpBeyond);
}

TEST(ProjectFile, SaveLoadSaveOnDiskIsByteIdentical) {
    const test::TempDir dir;
    const auto first = parseShirt(FULL);
    ASSERT_TRUE(first.ok()) << first.error().toString();
    const auto saved = saveProject(dir / "a.atelier", first.value());
    ASSERT_TRUE(saved.ok()) << saved.error().toString();
    const auto loaded = loadProject(dir / "a.atelier");
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    ASSERT_TRUE(saveProject(dir / "b.atelier", loaded.value()).ok());
    const std::string a = test::readText(dir / "a.atelier");
    EXPECT_FALSE(a.empty());
    EXPECT_EQ(a, test::readText(dir / "b.atelier"));
    EXPECT_EQ(a, formatProject(first.value()));
}

TEST(ProjectFile, BodyMeshResolvedAgainstTheProjectDirectory) {
    const test::TempDir dir;
    std::filesystem::create_directories(dir / "meshes");
    const std::string text = fullWith("/body", json::parse(R"({"mesh": "meshes/body.obj"})"));
    const auto path = dir.write("shirt.atelier", text);

    // Missing: the error names the resolved path.
    const auto missing = loadProject(path);
    expectError(missing, "/body/mesh", (dir / "meshes/body.obj").string(), path.string());
    EXPECT_NE(missing.error().message.find("not found"), std::string::npos);

    // Present: loads, and is written back as a mesh body.
    dir.write("meshes/body.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const auto loaded = loadProject(path);
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    EXPECT_EQ(loaded.value().body.meshPath, "meshes/body.obj");
    EXPECT_TRUE(loaded.value().body.measurements.empty());
    ASSERT_TRUE(saveProject(dir / "again.atelier", loaded.value()).ok());
    const std::string again = test::readText(dir / "again.atelier");
    EXPECT_EQ(json::parse(again)["body"], json::parse(R"({"mesh": "meshes/body.obj"})"));
    const auto reloaded = loadProject(dir / "again.atelier");
    ASSERT_TRUE(reloaded.ok()) << reloaded.error().toString();
    EXPECT_EQ(formatProject(reloaded.value()), again);

    // parseProject has no directory and does not look for the mesh.
    EXPECT_TRUE(parseShirt(text).ok());

    // Another format with its unit and up axis given: kept, and written back.
    const auto given = parseShirt(
        fullWith("/body", json::parse(R"({"mesh": "body.fbx", "units": "cm", "up": "z"})")));
    ASSERT_TRUE(given.ok()) << given.error().toString();
    EXPECT_EQ(given.value().body.meshUnits, "cm");
    EXPECT_EQ(given.value().body.meshUp, "z");
    EXPECT_EQ(json::parse(formatProject(given.value()))["body"],
              json::parse(R"({"mesh": "body.fbx", "units": "cm", "up": "z"})"));
}

TEST(ProjectFile, SaveIntoAMissingDirectoryFails) {
    const test::TempDir dir;
    const auto saved = saveProject(dir / "no/such/dir/a.atelier", parseShirt(MINIMAL).value());
    ASSERT_FALSE(saved.ok());
    EXPECT_NE(saved.error().toString().find("a.atelier"), std::string::npos)
        << saved.error().toString();
    EXPECT_FALSE(std::filesystem::exists(dir / "no"));
}

TEST(ProjectFile, MissingFile) {
    const test::TempDir dir;
    const auto result = loadProject(dir / "nothing.atelier");
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().toString().find("nothing.atelier"), std::string::npos);
}

TEST(ProjectFile, InvalidJsonGivesLineAndColumn) {
    const std::string full = FULL;
    // Truncated in the middle of the panels.
    const auto truncated = parseShirt(full.substr(0, full.find("\"darts\"")));
    ASSERT_FALSE(truncated.ok());
    EXPECT_EQ(truncated.error().file, "shirt.atelier");
    EXPECT_EQ(truncated.error().where.rfind("line ", 0), 0U) << truncated.error().toString();
    EXPECT_NE(truncated.error().where.find(", column "), std::string::npos);
    EXPECT_NE(truncated.error().message.find("invalid JSON"), std::string::npos);

    const auto syntax = parseShirt("{\n  \"format\": \"atelier-project\",\n  \"version\": 1,,\n}");
    expectError(syntax, "line 3, column 16", "invalid JSON");

    // A number beyond double range is refused, not turned into infinity (or a crash).
    const std::string overflow = "{\n  \"format\": \"atelier-project\",\n  \"version\": 1e999\n}";
    expectError(parseShirt(overflow), "line 3, column 14", "number overflow");

    expectError(parseShirt(""), "line 1, column 1", "invalid JSON");
    expectError(parseShirt("[]"), "/", "expected an object");
}

struct BadProject {
    const char* label;
    std::string text;
    const char* where;
    const char* fragment;
};

TEST(ProjectFile, BadValuesNameFileAndPath) {
    const std::vector<BadProject> cases = {
        {"format", fullWith("/format", "atelier-scene"), "/format", "expected \"atelier-project\""},
        {"format missing", fullWith("/format", removedKeys()), "/",
         "missing required key \"format\""},
        {"newer version", fullWith("/version", 3), "/version", "written by a newer Atelier"},
        {"version 0", fullWith("/version", 0), "/version", "unsupported version 0"},
        {"version type", fullWith("/version", "1"), "/version", "expected an integer"},
        {"name type", fullWith("/name", 3), "/name", "expected a string, found an integer"},
        {"unknown top key", fullWith("/colour", "red"), "/colour", "unknown key \"colour\""},
        {"body base", fullWith("/body/base", "child"), "/body/base", "unknown body base"},
        {"mesh and base", fullWith("/body/mesh", "body.obj"), "/body/base", "not both"},
        {"mesh unit", fullWith("/body", json::parse(R"({"mesh": "b.glb", "units": "in"})")),
         "/body/units", "unknown mesh unit \"in\" (expected \"mm\", \"cm\" or \"m\")"},
        {"mesh up axis", fullWith("/body", json::parse(R"({"mesh": "b.glb", "up": "x"})")),
         "/body/up", "unknown up axis \"x\" (expected \"y\" or \"z\")"},
        {"measurement in mm", fullWith("/body/measurements/bust", 920), "/body/measurements/bust",
         "in metres"},
        {"measurement type", fullWith("/body/measurements/bust", "92cm"), "/body/measurements/bust",
         "expected a number"},
        {"materials type", fullWith("/materials", json::object()), "/materials",
         "expected an array"},
        {"unknown fabric", fullWith("/materials/0/fabric", "cotton-jersey"), "/materials/0/fabric",
         "unknown fabric preset \"cotton-jersey\""},
        {"zero density", fullWith("/materials/1/density_kg_per_m2", 0),
         "/materials/1/density_kg_per_m2", "must be positive"},
        {"negative density", fullWith("/materials/1/density_kg_per_m2", -0.1),
         "/materials/1/density_kg_per_m2", "must be positive"},
        {"fabric with parameters", fullWith("/materials/0/poisson", 0.3), "/materials/0/poisson",
         "unknown key"},
        {"material description", fullWith("/materials/1/description", "x"),
         "/materials/1/description", "unknown key"},
        {"duplicate material", fullWith("/materials/1/name", "shell"), "/materials/1/name",
         "already named \"shell\""},
        {"material name missing", fullWith("/materials/0/name", removedKeys()), "/materials/0",
         "missing required key \"name\""},
        {"duplicate panel", fullWith("/panels/1/name", "front"), "/panels/1/name",
         "another panel is already named \"front\""},
        {"empty panel name", fullWith("/panels/1/name", ""), "/panels/1/name", "must not be empty"},
        {"panel material", fullWith("/panels/1/material", "silk"), "/panels/1/material",
         "unknown material \"silk\" (materials: \"shell\", \"lining\")"},
        {"panel side", fullWith("/panels/0/side", "inside"), "/panels/0/side",
         "unknown side \"inside\""},
        {"grain type", fullWith("/panels/0/grain_deg", "90"), "/panels/0/grain_deg",
         "expected a number, found a string"},
        {"outline missing", fullWith("/panels/1/outline", removedKeys()), "/panels/1",
         "missing required key \"outline\""},
        {"outline empty", fullWith("/panels/1/outline", json::array()), "/panels/1/outline",
         "at least one segment"},
        {"cubic c1 short", fullWith("/panels/0/outline/2/cubic/c1", json::parse("[1]")),
         "/panels/0/outline/2/cubic/c1", "must be an array of two finite numbers"},
        {"cubic c1 string", fullWith("/panels/0/outline/2/cubic/c1", json::parse(R"(["1", 2])")),
         "/panels/0/outline/2/cubic/c1", "must be an array of two finite numbers"},
        {"cubic c2 missing", fullWith("/panels/0/outline/2/cubic/c2", removedKeys()),
         "/panels/0/outline/2/cubic", "missing required key \"c2\""},
        {"segment kind", fullWith("/panels/0/outline/1", json::parse(R"({"spline": {}})")),
         "/panels/0/outline/1/spline", "unknown segment kind \"spline\""},
        {"two kinds", fullWith("/panels/0/outline/1/arc", json::parse(R"({"from": [0, 0]})")),
         "/panels/0/outline/1", "one key"},
        {"to in a loop", fullWith("/panels/0/outline/0/line/to", json::parse("[1, 2]")),
         "/panels/0/outline/0/line/to", "unknown key \"to\""},
        {"arc bulge missing", fullWith("/panels/0/outline/6/arc/bulge", removedKeys()),
         "/panels/0/outline/6/arc", "missing required key \"bulge\""},
        {"hole point", fullWith("/panels/0/holes/0/2/line/from", json::parse("[1, null]")),
         "/panels/0/holes/0/2/line/from", "must be an array of two finite numbers"},
        {"internal line to",
         fullWith("/panels/0/internal_lines/0/segments/0/line/to", removedKeys()),
         "/panels/0/internal_lines/0/segments/0/line", "missing required key \"to\""},
        {"internal line key", fullWith("/panels/0/internal_lines/0/fold", 3),
         "/panels/0/internal_lines/0/fold", "unknown key \"fold\""},
        {"dart leg", fullWith("/panels/0/darts/0/leg", -1), "/panels/0/darts/0/leg",
         "non-negative integer"},
        {"dart leg float", fullWith("/panels/0/darts/0/leg", 1.5), "/panels/0/darts/0/leg",
         "expected an integer"},
        {"notch segment", fullWith("/panels/0/notches/0/segment", 7), "/panels/0/notches/0/segment",
         "no segment 7 in the outline (it has 7)"},
        {"notch t", fullWith("/panels/0/notches/0/t", 1.5), "/panels/0/notches/0/t",
         "must be in [0, 1]"},
        {"placement typo", fullWith("/panels/0/placement/clerance_mm", 3),
         "/panels/0/placement/clerance_mm", "unknown key \"clerance_mm\""},
        {"negative clearance", fullWith("/panels/0/placement/clearance_mm", -1),
         "/panels/0/placement/clearance_mm", "must not be negative"},
        {"offset", fullWith("/panels/0/placement/offset_mm", json::parse("[1, 2, 3]")),
         "/panels/0/placement/offset_mm", "must be an array of two finite numbers"},
        {"seam side empty", fullWith("/seams/0/a", json::array()), "/seams/0/a",
         "at least one edge"},
        {"seam panel type", fullWith("/seams/0/b/0/panel", 1), "/seams/0/b/0/panel",
         "expected a string"},
        {"seam t1", fullWith("/seams/1/b/1/t1", -0.5), "/seams/1/b/1/t1", "must be in [0, 1]"},
        {"seam key", fullWith("/seams/0/c", json::array()), "/seams/0/c", "unknown key \"c\""},
        {"ease", fullWith("/ease_tolerance_mm", -1), "/ease_tolerance_mm", "must not be negative"},
        {"model", fullWith("/simulation/model", "cloth"), "/simulation/model",
         "unknown model \"cloth\" (expected one of \"springs\", \"volino\", \"fem\")"},
        {"integrator", fullWith("/simulation/integrator", "verlet"), "/simulation/integrator",
         "unknown integrator \"verlet\""},
        {"particle distance", fullWith("/simulation/particle_distance_mm", 0),
         "/simulation/particle_distance_mm", "must be positive"},
        {"self collision", fullWith("/simulation/self_collision", 1), "/simulation/self_collision",
         "expected true or false"},
        {"simulation typo", fullWith("/simulation/dt", 0.01), "/simulation/dt",
         "unknown key \"dt\""},
    };
    for (const BadProject& c : cases) {
        SCOPED_TRACE(c.label);
        expectError(parseShirt(c.text), c.where, c.fragment);
    }
}

TEST(ProjectFile, EveryPrefixOfAFileFailsCleanly) {
    // Never a crash or an exception: each truncation gives an error with a place.
    const std::string text = formatProject(parseShirt(FULL).value());
    for (std::size_t n = 0; n + 1 < text.size(); n += 7) {
        const auto result = parseShirt(text.substr(0, n));
        ASSERT_FALSE(result.ok()) << n;
        EXPECT_FALSE(result.error().where.empty()) << n;
    }
}

/// A random garment that is valid by construction: star-shaped outlines of gently curved
/// segments around the origin, a small hole and an internal line near the centre.
patterns::Project randomProject(std::mt19937& rng) {
    std::uniform_real_distribution<double> unit(0, 1);
    const auto between = [&](double lo, double hi) { return lo + (hi - lo) * unit(rng); };
    patterns::Project p;
    p.name = "random " + std::to_string(rng() % 1000);
    if (rng() % 2 == 0) {
        p.body.meshPath = "bodies/b" + std::to_string(rng() % 10) + ".obj";
    } else {
        p.body.base = rng() % 2 == 0 ? "female" : "male";
        p.body.measurements = {{"waist", between(0.5, 1.2)}, {"bust", between(0.6, 1.3)}};
    }
    p.garment.materials.push_back({"preset", builtinMaterialPresets().at("denim")});
    sim::Material inlineMaterial;
    inlineMaterial.name = "inline";
    inlineMaterial.density = between(0.05, 0.5);
    inlineMaterial.bending = between(1e-7, 1e-4);
    inlineMaterial.plasticYieldAngle = between(0, 1);
    p.garment.materials.push_back({"inline", inlineMaterial});

    const int panelCount = 2 + static_cast<int>(rng() % 3);
    for (int k = 0; k < panelCount; ++k) {
        patterns::Panel panel;
        panel.name = "panel" + std::to_string(k);
        panel.material = p.garment.materials[rng() % 2].name;
        panel.side = rng() % 2 == 0 ? patterns::PanelSide::Front : patterns::PanelSide::Back;
        panel.grainAngle = between(-std::numbers::pi, std::numbers::pi);
        const int n = 5 + static_cast<int>(rng() % 4);
        std::vector<sim::Vec2> corners;
        for (int i = 0; i < n; ++i) {
            const double angle = 2 * std::numbers::pi * (i + between(-0.2, 0.2)) / n;
            const double radius = between(0.2, 0.4);
            corners.emplace_back(radius * std::cos(angle), radius * std::sin(angle));
        }
        for (int i = 0; i < n; ++i) {
            Segment s;
            s.kind = static_cast<SegmentKind>(rng() % 4);
            s.start = corners[static_cast<std::size_t>(i)];
            s.end = corners[static_cast<std::size_t>((i + 1) % n)];
            const sim::Vec2 chord = s.end - s.start;
            const sim::Vec2 normal(chord.y(), -chord.x()); // outward for a CCW loop
            s.control1 = s.start + between(0.2, 0.45) * chord + between(0, 0.1) * normal;
            s.control2 = s.start + between(0.55, 0.8) * chord + between(0, 0.1) * normal;
            s.bulge = s.kind == SegmentKind::Arc ? between(-0.15, 0.15) : 0;
            if (s.kind == SegmentKind::Line || s.kind == SegmentKind::Arc) {
                s.control1 = s.control2 = sim::Vec2::Zero();
            } else if (s.kind == SegmentKind::Quadratic) {
                s.control2 = sim::Vec2::Zero();
            }
            panel.outline.push_back(s);
        }
        patterns::Loop hole;
        const double h = between(0.01, 0.03);
        const std::array<sim::Vec2, 4> square = {sim::Vec2(-h, -h), sim::Vec2(-h, h),
                                                 sim::Vec2(h, h), sim::Vec2(h, -h)};
        for (std::size_t i = 0; i < 4; ++i) {
            Segment s;
            s.start = square[i];
            s.end = square[(i + 1) % 4];
            hole.push_back(s);
        }
        panel.holes.push_back(hole);
        patterns::InternalLine line;
        Segment s;
        s.start = sim::Vec2(between(0.05, 0.07), between(-0.05, 0.0));
        s.end = sim::Vec2(between(0.08, 0.1), between(0.0, 0.05));
        line.path.push_back(s);
        line.foldAngle = between(-std::numbers::pi, std::numbers::pi);
        panel.internalLines.push_back(line);
        panel.notches.push_back(
            {static_cast<int>(rng() % static_cast<unsigned>(n)), between(0, 1)});
        panel.placement.slot = "slot" + std::to_string(k);
        panel.placement.offset = sim::Vec2(between(-0.3, 0.3), between(-0.3, 0.3));
        panel.placement.rotation = between(-std::numbers::pi, std::numbers::pi);
        panel.placement.clearance = between(0, 0.05);
        p.garment.panels.push_back(panel);
    }
    for (int k = 0; k + 1 < panelCount; ++k) {
        patterns::Seam seam;
        seam.name = "seam" + std::to_string(k);
        seam.a.push_back({"panel" + std::to_string(k), 0, between(0, 1), between(0, 1)});
        seam.b.push_back({"panel" + std::to_string(k + 1), 1, between(0, 1), between(0, 1)});
        p.garment.seams.push_back(seam);
    }
    p.garment.easeTolerance = between(0, 0.02);
    patterns::DrapeSettings& d = p.drape;
    d.particleDistance = between(0.003, 0.03);
    d.model = static_cast<sim::StretchModel>(rng() % 3);
    d.integrator = static_cast<sim::IntegratorKind>(rng() % 5);
    d.dt = between(1e-4, 1e-2);
    d.clothThickness = between(0.0005, 0.005);
    d.selfCollision = rng() % 2 == 0;
    d.bodyThickness = between(0, 0.005);
    d.bodyStaticFriction = between(0, 1);
    d.bodyKineticFriction = between(0, 1);
    d.seamTimeConstant = between(0.01, 0.1);
    d.seamWeldDistance = between(0, 0.002);
    d.restKineticEnergy = between(1e-10, 1e-6);
    d.restDuration = between(0, 1);
    d.timeLimit = between(1, 10);
    p.document = patterns::fromGarment(p.garment); // what is saved
    return p;
}

void expectNear(const sim::Vec2& a, const sim::Vec2& b, double tolerance) {
    EXPECT_NEAR(a.x(), b.x(), tolerance);
    EXPECT_NEAR(a.y(), b.y(), tolerance);
}

TEST(ProjectFile, RandomProjectsRoundTripToTheSameText) {
    std::mt19937 rng(20261123);
    // Rounding to 1e-6 mm and 1e-6 deg on save.
    constexpr double METRES = 1e-9 * 0.5 + 1e-15;
    constexpr double RADIANS = 1e-6 * RAD_PER_DEG * 0.5 + 1e-15;
    for (int trial = 0; trial < 60; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const patterns::Project original = randomProject(rng);
        const std::string text = formatProject(original);
        const auto parsed = parseShirt(text);
        ASSERT_TRUE(parsed.ok()) << parsed.error().toString();
        const std::string again = formatProject(parsed.value());
        ASSERT_EQ(again, text);

        const patterns::Project& p = parsed.value();
        EXPECT_EQ(p.name, original.name);
        EXPECT_EQ(p.body.meshPath, original.body.meshPath);
        EXPECT_EQ(p.body.measurements, original.body.measurements);
        ASSERT_EQ(p.garment.materials.size(), 2U);
        EXPECT_EQ(p.garment.materials[0].material.name, "denim");
        EXPECT_EQ(p.garment.materials[1].material.density,
                  original.garment.materials[1].material.density);
        EXPECT_EQ(p.garment.materials[1].material.plasticYieldAngle,
                  original.garment.materials[1].material.plasticYieldAngle);
        ASSERT_EQ(p.garment.panels.size(), original.garment.panels.size());
        for (std::size_t k = 0; k < p.garment.panels.size(); ++k) {
            const patterns::Panel& a = p.garment.panels[k];
            const patterns::Panel& b = original.garment.panels[k];
            EXPECT_EQ(a.side, b.side);
            EXPECT_EQ(a.material, b.material);
            EXPECT_NEAR(a.grainAngle, b.grainAngle, RADIANS);
            ASSERT_EQ(a.outline.size(), b.outline.size());
            for (std::size_t i = 0; i < a.outline.size(); ++i) {
                EXPECT_EQ(a.outline[i].kind, b.outline[i].kind);
                expectNear(a.outline[i].start, b.outline[i].start, METRES);
                expectNear(a.outline[i].end, b.outline[i].end, METRES);
                expectNear(a.outline[i].control1, b.outline[i].control1, METRES);
                expectNear(a.outline[i].control2, b.outline[i].control2, METRES);
                EXPECT_EQ(a.outline[i].bulge, b.outline[i].bulge);
            }
            expectNear(a.internalLines[0].path[0].end, b.internalLines[0].path[0].end, METRES);
            EXPECT_NEAR(a.internalLines[0].foldAngle, b.internalLines[0].foldAngle, RADIANS);
            EXPECT_EQ(a.notches[0].t, b.notches[0].t);
            expectNear(a.placement.offset, b.placement.offset, METRES);
            EXPECT_NEAR(a.placement.rotation, b.placement.rotation, RADIANS);
            EXPECT_NEAR(a.placement.clearance, b.placement.clearance, METRES);
        }
        EXPECT_EQ(p.garment.seams[0].a[0].t0, original.garment.seams[0].a[0].t0);
        EXPECT_NEAR(p.drape.particleDistance, original.drape.particleDistance, METRES);
        EXPECT_EQ(p.drape.dt, original.drape.dt);
        EXPECT_EQ(p.drape.model, original.drape.model);
        EXPECT_EQ(p.drape.integrator, original.drape.integrator);
        EXPECT_EQ(p.drape.selfCollision, original.drape.selfCollision);
        EXPECT_EQ(p.drape.restKineticEnergy, original.drape.restKineticEnergy);
    }
}

TEST(ProjectFile, MillimetreValuesRoundedToMicrometres) {
    // Values with more than six decimals are rounded on the first save, then stay put.
    std::string text = MINIMAL;
    text.replace(text.find("[100, 0]"), 8, "[100.12345678901, 0.1]");
    const auto parsed = parseShirt(text);
    ASSERT_TRUE(parsed.ok()) << parsed.error().toString();
    const std::string formatted = formatProject(parsed.value());
    const json doc = json::parse(formatted);
    EXPECT_EQ(doc["panels"][0]["outline"][1]["at"][0].dump(), "100.123457");
    EXPECT_EQ(doc["panels"][0]["outline"][1]["at"][1].dump(), "0.1");
    expectStableText(formatted);
}

TEST(ProjectFile, EverySampleRoundTrips) {
    if (!std::filesystem::is_directory(test::GARMENTS_DIR)) {
        GTEST_SKIP() << "no sample garments in " << test::GARMENTS_DIR;
    }
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(test::GARMENTS_DIR)) {
        if (entry.path().extension() != ".atelier") {
            continue;
        }
        SCOPED_TRACE(entry.path().string());
        const auto loaded = loadProject(entry.path());
        ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
        EXPECT_FALSE(loaded.value().garment.panels.empty());
        expectStableText(formatProject(loaded.value()));
        ++count;
    }
    EXPECT_GT(count, 0);
}

} // namespace
} // namespace atelier::io
