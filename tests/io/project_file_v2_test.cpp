// Version 2 of the project format: the garment document with its ids. Version-1 files migrate
// (every sample meshes the same after save and reload), version 2 round-trips byte for byte,
// and bad ids and references name their JSON pointer.
#include "io/project_file.h"
#include "io/temp_dir.h"

#include "patterns/document.h"
#include "patterns/mesh.h"

#include "source_paths.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

namespace atelier::io {
namespace {

using nlohmann::json;

/// A version-1 project with every kind of object: curves of each kind, a hole, an internal
/// line of two segments, a dart, a notch, a seam of each direction.
const char* const V1 = R"({"format": "atelier-project", "version": 1, "name": "top",
  "materials": [{"name": "shell", "fabric": "cotton"}],
  "panels": [
    {"name": "front", "material": "shell", "grain_deg": 80,
     "outline": [
       {"line": {"from": [-200, 0]}}, {"line": {"from": [200, 0]}},
       {"cubic": {"from": [200, 400], "c1": [150, 450], "c2": [100, 500]}},
       {"line": {"from": [50, 500]}}, {"line": {"from": [0, 420]}},
       {"quadratic": {"from": [-50, 500], "c1": [-150, 520]}},
       {"arc": {"from": [-200, 400], "bulge": 0.1}}],
     "holes": [[{"line": {"from": [-20, 180]}}, {"line": {"from": [-20, 220]}},
                {"line": {"from": [20, 220]}}, {"line": {"from": [20, 180]}}]],
     "internal_lines": [{"fold_deg": 45.5, "segments": [
       {"line": {"from": [-100, 100], "to": [-100, 300]}},
       {"quadratic": {"from": [-100, 300], "to": [-60, 340], "c1": [-100, 340]}}]}],
     "darts": [{"leg": 3}], "notches": [{"segment": 0, "t": 0.25}],
     "placement": {"slot": "torso_front", "offset_mm": [10.5, -20]}},
    {"name": "back", "material": "shell", "side": "back",
     "outline": [{"line": {"from": [-200, 0]}}, {"line": {"from": [200, 0]}},
                 {"line": {"from": [200, 400]}}, {"line": {"from": [-200, 400]}}]}],
  "seams": [{"name": "side", "a": [{"panel": "front", "segment": 1}],
             "b": [{"panel": "back", "segment": 3, "t0": 1, "t1": 0}]}]})";

Result<patterns::Project> parseShirtV2(const std::string& text) {
    return parseProject(text, "shirt.atelier");
}

/// The version-2 text of V1, as JSON to take apart.
json v2Json() {
    return json::parse(formatProject(parseShirtV2(V1).value()));
}

TEST(ProjectFileV2, Version1MigratesWithIdsAndReferences) {
    const auto v1 = parseShirtV2(V1);
    ASSERT_TRUE(v1.ok()) << v1.error().toString();
    EXPECT_EQ(v1.value().version, 1);
    ASSERT_TRUE(patterns::checkDocument(v1.value().document).ok());
    const std::string text = formatProject(v1.value());
    EXPECT_EQ(text.rfind("{\n  \"format\": \"atelier-project\",\n  \"version\": 2,\n", 0), 0U);
    const json doc = json::parse(text);
    const json& front = doc["panels"][0];
    const json& back = doc["panels"][1];
    // Each corner once, with the edge leaving it.
    EXPECT_EQ(front["outline"].size(), 7U);
    EXPECT_EQ(front["outline"][2]["curve"], "cubic");
    EXPECT_EQ(front["outline"][2]["c2"], json::parse("[100, 500]"));
    EXPECT_EQ(front["outline"][6]["bulge"], 0.1);
    EXPECT_EQ(front["holes"][0]["contour"].size(), 4U);
    const json& line = front["internal_lines"][0]["points"];
    ASSERT_EQ(line.size(), 3U);
    EXPECT_FALSE(line[2].contains("edge"));
    EXPECT_EQ(line[1]["curve"], "quadratic");
    // References by id.
    EXPECT_EQ(front["darts"][0]["leg1"], front["outline"][3]["edge"]);
    EXPECT_EQ(front["darts"][0]["leg2"], front["outline"][4]["edge"]);
    EXPECT_EQ(front["notches"][0]["edge"], front["outline"][0]["edge"]);
    EXPECT_EQ(doc["seams"][0]["a"][0]["panel"], front["id"]);
    EXPECT_EQ(doc["seams"][0]["a"][0]["edge"], front["outline"][1]["edge"]);
    EXPECT_EQ(doc["seams"][0]["b"][0]["panel"], back["id"]);
    EXPECT_EQ(doc["seams"][0]["b"][0]["edge"], back["outline"][3]["edge"]);
    EXPECT_EQ(doc["next_id"], v1.value().document.nextId);
}

TEST(ProjectFileV2, SaveLoadSaveIsByteIdenticalAndKeepsTheDocument) {
    const test::TempDir dir;
    const auto v1 = parseShirtV2(V1);
    ASSERT_TRUE(v1.ok()) << v1.error().toString();
    ASSERT_TRUE(saveProject(dir / "a.atelier", v1.value()).ok());
    const auto loaded = loadProject(dir / "a.atelier");
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    EXPECT_EQ(loaded.value().version, 2);
    ASSERT_TRUE(saveProject(dir / "b.atelier", loaded.value()).ok());
    EXPECT_EQ(test::readText(dir / "a.atelier"), test::readText(dir / "b.atelier"));
    // Whole millimetres read back exactly: the same document, ids and next id included.
    EXPECT_EQ(patterns::dumpDocument(loaded.value().document),
              patterns::dumpDocument(v1.value().document));
    EXPECT_EQ(patterns::dumpDocument(patterns::fromGarment(loaded.value().garment)),
              patterns::dumpDocument(patterns::fromGarment(v1.value().garment)));
}

TEST(ProjectFileV2, AnEditedDocumentRoundTripsWithItsIds) {
    // Ids that are not in file order, a gap in them, and a next id above the largest.
    json doc = v2Json();
    doc["panels"][1]["id"] = 500;
    doc["seams"][0]["b"][0]["panel"] = 500;
    doc["next_id"] = 900;
    const auto parsed = parseShirtV2(doc.dump());
    ASSERT_TRUE(parsed.ok()) << parsed.error().toString();
    EXPECT_EQ(parsed.value().document.nextId, 900U);
    EXPECT_EQ(parsed.value().document.panels[1].id.value, 500U);
    EXPECT_EQ(parsed.value().garment.seams[0].b[0].panel, "back");
    const std::string text = formatProject(parsed.value());
    EXPECT_EQ(formatProject(parseShirtV2(text).value()), text);
    // Without next_id, the next id is above the largest.
    doc.erase("next_id");
    const auto noNext = parseShirtV2(doc.dump());
    ASSERT_TRUE(noNext.ok()) << noNext.error().toString();
    EXPECT_EQ(noNext.value().document.nextId, 501U);
}

TEST(ProjectFileV2, ASeamsFoldAndBendingScaleRoundTripAndBadValuesNameTheirPath) {
    json doc = v2Json();
    EXPECT_FALSE(doc["seams"][0].contains("fold_deg")) << "a flat seam's default is not written";
    EXPECT_FALSE(doc["seams"][0].contains("bending_scale"));
    doc["seams"][0]["fold_deg"] = 30;
    doc["seams"][0]["bending_scale"] = 3;
    const auto parsed = parseShirtV2(doc.dump());
    ASSERT_TRUE(parsed.ok()) << parsed.error().toString();
    EXPECT_NEAR(parsed.value().document.seams[0].foldAngle, std::numbers::pi / 6, 1e-15);
    EXPECT_EQ(parsed.value().document.seams[0].bendingScale, 3.0);
    EXPECT_NEAR(parsed.value().garment.seams[0].foldAngle, std::numbers::pi / 6, 1e-15);
    EXPECT_EQ(parsed.value().garment.seams[0].bendingScale, 3.0);
    const json again = json::parse(formatProject(parsed.value()));
    EXPECT_EQ(again["seams"][0]["fold_deg"], 30);
    EXPECT_EQ(again["seams"][0]["bending_scale"], 3);
    for (const auto& [key, value] : {std::pair{"fold_deg", 180.0}, {"bending_scale", -1.0}}) {
        json bad = doc;
        bad["seams"][0][key] = value;
        const auto refused = parseShirtV2(bad.dump());
        ASSERT_FALSE(refused.ok()) << key;
        EXPECT_NE(refused.error().toString().find(std::string("/seams/0/") + key),
                  std::string::npos)
            << refused.error().toString();
    }
}

void expectSameMesh(const patterns::GarmentMesh& a, const patterns::GarmentMesh& b) {
    ASSERT_EQ(a.panels.size(), b.panels.size());
    for (std::size_t i = 0; i < a.panels.size(); ++i) {
        SCOPED_TRACE("panel " + std::to_string(i));
        EXPECT_TRUE(a.panels[i].pattern == b.panels[i].pattern);
        EXPECT_TRUE(a.panels[i].rest == b.panels[i].rest);
        EXPECT_TRUE(a.panels[i].triangles == b.panels[i].triangles);
        EXPECT_EQ(a.panels[i].lineEdges, b.panels[i].lineEdges);
        EXPECT_EQ(a.panels[i].notchVertices, b.panels[i].notchVertices);
    }
    EXPECT_EQ(a.seamPairs, b.seamPairs);
    EXPECT_EQ(a.seamOfPair, b.seamOfPair);
}

TEST(ProjectFileV2, EverySampleMigratesAndMeshesTheSame) {
    if (!std::filesystem::is_directory(test::GARMENTS_DIR)) {
        GTEST_SKIP() << "no sample garments in " << test::GARMENTS_DIR;
    }
    const test::TempDir dir;
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(test::GARMENTS_DIR)) {
        if (entry.path().extension() != ".atelier") {
            continue;
        }
        SCOPED_TRACE(entry.path().filename().string());
        const auto v1 = loadProject(entry.path());
        ASSERT_TRUE(v1.ok()) << v1.error().toString();
        EXPECT_EQ(v1.value().version, 1); // the samples stay version 1 until regenerated
        const std::filesystem::path saved = dir / entry.path().filename().string();
        ASSERT_TRUE(saveProject(saved, v1.value()).ok());
        const auto v2 = loadProject(saved);
        ASSERT_TRUE(v2.ok()) << v2.error().toString();
        EXPECT_EQ(v2.value().version, 2);
        EXPECT_EQ(formatProject(v2.value()), test::readText(saved));

        patterns::MeshOptions options;
        options.particleDistance = 0.02;
        patterns::GarmentMesh before;
        patterns::GarmentMesh after;
        ASSERT_FALSE(patterns::meshGarment(v1.value().garment, options, before).has_value());
        ASSERT_FALSE(patterns::meshGarment(v2.value().garment, options, after).has_value());
        EXPECT_GT(before.triangleCount, 0);
        expectSameMesh(before, after);
        ++count;
    }
    EXPECT_GT(count, 0);
}

/// The version-2 text of V1 with `value` at `pointer` (a discarded value removes the key).
std::string v2With(const std::string& pointer, const json& value) {
    json doc = v2Json();
    if (value.is_discarded()) {
        const json::json_pointer p(pointer);
        json& parent = doc.at(p.parent_pointer());
        if (parent.is_array()) {
            parent.erase(std::stoul(p.back()));
        } else {
            parent.erase(p.back());
        }
    } else {
        doc[json::json_pointer(pointer)] = value;
    }
    return doc.dump();
}

json removedKeysV2() {
    return json(json::value_t::discarded);
}

struct BadProjectV2 {
    const char* label;
    std::string text;
    const char* where;
    const char* fragment;
};

TEST(ProjectFileV2, BadIdsAndReferencesNameTheJsonPointer) {
    const json doc = v2Json();
    const json& front = doc["panels"][0];
    const json frontId = front["id"];
    const json point0 = front["outline"][0]["point"];
    const json frontEdge = front["outline"][1]["edge"];
    const json holeEdge = front["holes"][0]["contour"][0]["edge"];
    const std::string duplicatePoint =
        "duplicate id " + point0.dump() + " (already used at /panels/0/outline/0/point)";
    json twoCorners = doc["panels"][1]["outline"];
    twoCorners.erase(2);
    twoCorners.erase(2);
    const std::vector<BadProjectV2> cases = {
        {"duplicate panel id", v2With("/panels/1/id", frontId), "/panels/1/id",
         "duplicate id 1 (already used at /panels/0/id)"},
        {"duplicate point id", v2With("/panels/0/outline/1/point", point0),
         "/panels/0/outline/1/point", duplicatePoint.c_str()},
        {"id of another kind", v2With("/seams/0/id", frontEdge), "/seams/0/id", "duplicate id"},
        {"id zero", v2With("/panels/0/id", 0), "/panels/0/id", "must be an id"},
        {"id type", v2With("/panels/0/id", "1"), "/panels/0/id", "expected an integer"},
        {"id missing", v2With("/seams/0/id", removedKeysV2()), "/seams/0",
         "missing required key \"id\""},
        {"id not below next", v2With("/next_id", 5), "/panels/0/outline/1/edge",
         "id 5 is not below next_id (5)"},
        {"next id zero", v2With("/next_id", 0), "/next_id", "must be an integer in [1, "},
        {"unknown seam panel", v2With("/seams/0/a/0/panel", 999), "/seams/0/a/0/panel",
         "no panel has id 999"},
        {"seam panel is an edge", v2With("/seams/0/a/0/panel", frontEdge), "/seams/0/a/0/panel",
         "no panel has id"},
        {"missing seam edge", v2With("/seams/0/a/0/edge", 999), "/seams/0/a/0/edge",
         "panel \"front\" has no outline edge with id 999"},
        {"seam edge of another panel", v2With("/seams/0/b/0/edge", frontEdge), "/seams/0/b/0/edge",
         "panel \"back\" has no outline edge"},
        {"seam on a hole edge", v2With("/seams/0/a/0/edge", holeEdge), "/seams/0/a/0/edge",
         "has no outline edge"},
        {"seam t", v2With("/seams/0/a/0/t1", 2), "/seams/0/a/0/t1", "must be in [0, 1]"},
        {"version-1 seam key", v2With("/seams/0/a/0/segment", 1), "/seams/0/a/0/segment",
         "unknown key \"segment\""},
        {"unknown dart leg", v2With("/panels/0/darts/0/leg1", 999), "/panels/0/darts/0/leg1",
         "no outline edge with id 999"},
        {"dart legs apart", v2With("/panels/0/darts/0/leg2", front["outline"][5]["edge"]),
         "/panels/0/darts/0/leg2", "must be the outline edge after leg1"},
        {"dart on the last edge", v2With("/panels/0/darts/0/leg1", front["outline"][6]["edge"]),
         "/panels/0/darts/0/leg1", "must not be the outline's last edge"},
        {"unknown notch edge", v2With("/panels/0/notches/0/edge", 999), "/panels/0/notches/0/edge",
         "no outline edge with id 999"},
        {"unknown curve", v2With("/panels/0/outline/0/curve", "spline"),
         "/panels/0/outline/0/curve", "unknown curve \"spline\""},
        {"control point on a line", v2With("/panels/0/outline/0/c1", json::parse("[1, 2]")),
         "/panels/0/outline/0/c1", "unknown key \"c1\""},
        {"cubic without c2", v2With("/panels/0/outline/2/c2", removedKeysV2()),
         "/panels/0/outline/2", "missing required key \"c2\""},
        {"point not finite", v2With("/panels/0/outline/3/at", json::parse("[1, null]")),
         "/panels/0/outline/3/at", "must be an array of two finite numbers"},
        {"edge after a line's end", v2With("/panels/0/internal_lines/0/points/2/edge", 999),
         "/panels/0/internal_lines/0/points/2/edge", "has no edge after it"},
        {"line end missing an edge",
         v2With("/panels/0/internal_lines/0/points/1/edge", removedKeysV2()),
         "/panels/0/internal_lines/0/points/1", "missing required key \"edge\""},
        {"outline too short", v2With("/panels/1/outline", twoCorners), "/panels/1/outline",
         "at least 3 points"},
        {"hole without contour", v2With("/panels/0/holes/0/contour", removedKeysV2()),
         "/panels/0/holes/0", "missing required key \"contour\""},
        {"duplicate panel name", v2With("/panels/1/name", "front"), "/panels/1/name",
         "another panel is already named \"front\""},
    };
    for (const BadProjectV2& c : cases) {
        SCOPED_TRACE(c.label);
        const auto result = parseShirtV2(c.text);
        ASSERT_FALSE(result.ok());
        EXPECT_EQ(result.error().file, "shirt.atelier");
        EXPECT_EQ(result.error().where, c.where) << result.error().toString();
        EXPECT_NE(result.error().message.find(c.fragment), std::string::npos)
            << result.error().toString();
    }
}

TEST(ProjectFileV2, GeometryIssuesNameVersion2Pointers) {
    // A hole corner on top of the next one: validateGarment's issue, at the hole's contour.
    const json corner = v2Json()["panels"][0]["holes"][0]["contour"][2]["at"];
    const auto result = parseShirtV2(v2With("/panels/0/holes/0/contour/1/at", corner));
    ASSERT_FALSE(result.ok());
    EXPECT_EQ(result.error().where.rfind("/panels/0/holes/0/contour/", 0), 0U)
        << result.error().toString();
}

TEST(ProjectFileV2, APanelsOwnParticleDistanceRoundTripsAndBadOnesNameTheirPointer) {
    json doc = v2Json();
    doc["panels"][1]["particle_distance_mm"] = 12.5;
    const auto read = parseShirtV2(doc.dump());
    ASSERT_TRUE(read.ok()) << read.error().toString();
    EXPECT_DOUBLE_EQ(read.value().document.panels[1].particleDistance, 0.0125);
    EXPECT_DOUBLE_EQ(read.value().garment.panels[1].particleDistance, 0.0125);
    EXPECT_EQ(read.value().document.panels[0].particleDistance, 0.0);
    const std::string saved = formatProject(read.value());
    EXPECT_EQ(formatProject(parseShirtV2(saved).value()), saved);
    EXPECT_EQ(json::parse(saved)["panels"][1]["particle_distance_mm"], 12.5);
    EXPECT_FALSE(json::parse(saved)["panels"][0].contains("particle_distance_mm"))
        << "a panel at the drape's distance is saved as before";
    for (const json& value : {json(0.5), json(-3), json(2000)}) {
        json d = doc;
        d["panels"][1]["particle_distance_mm"] = value;
        const auto bad = parseShirtV2(d.dump());
        ASSERT_FALSE(bad.ok()) << value.dump();
        EXPECT_NE(bad.error().toString().find("/panels/1/particle_distance_mm"), std::string::npos)
            << bad.error().toString();
    }
}

TEST(ProjectFileV2, APanelsSheetPlaceRoundTripsAndBadOnesNameTheirPointer) {
    json doc = v2Json();
    doc["panels"][1]["sheet"] = json::parse(R"({"at_mm": [450, -120.5], "angle_deg": -90})");
    const auto read = parseShirtV2(doc.dump());
    ASSERT_TRUE(read.ok()) << read.error().toString();
    const auto& sheet = read.value().document.panels[1].sheet;
    ASSERT_TRUE(sheet);
    EXPECT_EQ(sheet->at, patterns::Vec2(0.45, -0.1205));
    EXPECT_NEAR(sheet->angle, -std::numbers::pi / 2, 1e-15);
    EXPECT_FALSE(read.value().document.panels[0].sheet);
    const std::string saved = formatProject(read.value());
    EXPECT_EQ(formatProject(parseShirtV2(saved).value()), saved);
    EXPECT_FALSE(json::parse(saved)["panels"][0].contains("sheet"))
        << "a panel laid out by the view is saved as before";
    for (const char* bad :
         {R"({"at_mm": [1, 2, 3]})", R"({"at_mm": [2e6, 0]})",
          R"({"at_mm": [0, 0], "angle_deg": "x"})", R"({"at_mm": [0, 0], "turn": 1})"}) {
        json d = doc;
        d["panels"][1]["sheet"] = json::parse(bad);
        const auto refused = parseShirtV2(d.dump());
        ASSERT_FALSE(refused.ok()) << bad;
        EXPECT_NE(refused.error().toString().find("/panels/1/sheet"), std::string::npos)
            << refused.error().toString();
    }
}

TEST(ProjectFileV2, PinsRoundTripAndBadPinsNameTheirPointer) {
    json doc = v2Json();
    const json notch = doc["panels"][0]["notches"][0]["id"];
    doc["panels"][1]["pins"] = json::parse(R"([{"id": 900, "at": [-200, 400]},
        {"id": 901, "at": [0, 200], "position_mm": [10, 1200.5, 150], "release_s": 1.5}])");
    doc["panels"][0]["pins"] = json::array({{{"id", 902}, {"notch", notch}}});
    doc["next_id"] = 903;
    const auto read = parseShirtV2(doc.dump());
    ASSERT_TRUE(read.ok()) << read.error().toString();
    const patterns::Project& p = read.value();
    ASSERT_EQ(p.document.panels[1].pins.size(), 2U);
    const patterns::doc::Pin& moving = p.document.panels[1].pins[1];
    EXPECT_EQ(moving.id.value, 901U);
    EXPECT_EQ(moving.point, patterns::Vec2(0, 0.2));
    ASSERT_TRUE(moving.position.has_value());
    EXPECT_NEAR((*moving.position - sim::Vec3(0.01, 1.2005, 0.15)).norm(), 0, 1e-12);
    EXPECT_EQ(moving.releaseTime, 1.5);
    EXPECT_FALSE(std::isfinite(p.document.panels[1].pins[0].releaseTime));
    EXPECT_EQ(p.document.panels[0].pins[0].notch.value, notch.get<std::uint32_t>());
    ASSERT_EQ(p.garment.panels[0].pins.size(), 1U);
    EXPECT_EQ(p.garment.panels[0].pins[0].notch, 0);
    // Save, load, save: the same bytes; pins only where a panel has them.
    const std::string saved = formatProject(p);
    EXPECT_EQ(formatProject(parseShirtV2(saved).value()), saved);
    EXPECT_EQ(json::parse(saved)["panels"][1]["pins"], doc["panels"][1]["pins"]);
    EXPECT_FALSE(json::parse(formatProject(parseShirtV2(V1).value()))["panels"][0].contains("pins"))
        << "a project without pins is saved as before";

    const auto bad = [&](const std::string& pointer, const json& value) {
        json d = doc;
        d[json::json_pointer(pointer)] = value;
        return parseShirtV2(d.dump());
    };
    const std::vector<std::tuple<const char*, Result<patterns::Project>, const char*, const char*>>
        cases = {
            {"point outside", bad("/panels/1/pins/0/at", json::parse("[-300, 400]")),
             "/panels/1/pins/0/at", "pin point (-300, 400) mm is not inside panel \"back\""},
            {"unknown notch", bad("/panels/0/pins/0/notch", 999), "/panels/0/pins/0/notch",
             "panel \"front\" has no notch with id 999"},
            {"point and notch", bad("/panels/0/pins/0/at", json::parse("[0, 10]")),
             "/panels/0/pins/0", "either \"at\""},
            {"neither", bad("/panels/1/pins/0", json::parse(R"({"id": 900})")), "/panels/1/pins/0",
             "either \"at\""},
            {"negative release", bad("/panels/1/pins/1/release_s", -1),
             "/panels/1/pins/1/release_s", "at least 0"},
            {"position not a point", bad("/panels/1/pins/1/position_mm", json::parse("[1, 2]")),
             "/panels/1/pins/1/position_mm", ""},
            {"position too far", bad("/panels/1/pins/1/position_mm", json::parse("[0, 2e7, 0]")),
             "/panels/1/pins/1/position_mm", "within 10 m of the body's origin"},
            {"duplicate id", bad("/panels/1/pins/1/id", 900), "/panels/1/pins/1/id",
             "duplicate id 900"},
            {"unknown key", bad("/panels/1/pins/1/panel", 1), "/panels/1/pins/1/panel",
             "unknown key"},
        };
    for (const auto& [label, result, where, fragment] : cases) {
        SCOPED_TRACE(label);
        ASSERT_FALSE(result.ok());
        EXPECT_EQ(result.error().where, where) << result.error().toString();
        EXPECT_NE(result.error().message.find(fragment), std::string::npos)
            << result.error().toString();
    }
}

} // namespace
} // namespace atelier::io
