#pragma once
/// Internal to io/: what every version of the `.atelier` project format shares: units (files in
/// millimetres and degrees, rounded to 1e-6 on save), the body, materials, placement and drape
/// settings, read strictly and written in canonical form. The garment itself is version
/// specific: io/project_file.cpp reads version 1, io/project_file_v2.cpp reads and writes
/// version 2.

#include "io/json_reader.h"

#include "patterns/document.h"
#include "patterns/project.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::io::detail {

// ---------------------------------------------------------------------------------------------
// Reading (each throws JsonError at the value's JSON pointer)

enum class Range { Any, NonNegative, Positive };

/// Calls `read(element, pointer)` for each element of the array `key` of `r` (absent: none).
template <class Read> void forEachIn(ObjectReader& r, std::string_view key, Read read) {
    if (const nlohmann::json* array = r.find(key)) {
        const std::string ptr = r.pointerOf(key);
        for (std::size_t i = 0; i < arrayAt(*array, ptr).size(); ++i) {
            read((*array)[i], childPointer(ptr, i));
        }
    }
}

/// A length `key` in millimetres, in metres; exactly `fallback` [m] when absent.
double lengthMm(ObjectReader& r, std::string_view key, double fallback, Range range);
/// An angle `key` in degrees, in radians; exactly `fallback` [rad] when absent.
double angleDeg(ObjectReader& r, std::string_view key, double fallback);
/// [x, y] in millimetres at `pointer`, in metres.
patterns::Vec2 pointAt(const nlohmann::json& value, const std::string& pointer);
patterns::Vec2 point(ObjectReader& r, std::string_view key);
/// A curve parameter in [0, 1].
double parameter(ObjectReader& r, std::string_view key, double fallback);
/// A non-empty string.
std::string name(ObjectReader& r, std::string_view key);
/// A seam's bending once sewn (patterns::Seam): "fold_deg" within (−180, 180) into `foldAngle`
/// [rad] and "bending_scale" ≥ 0 into `bendingScale`, each left as it is when absent.
void seamBending(ObjectReader& r, double& foldAngle, double& bendingScale);

/// The segment kind named `name` ("line", "quadratic", "cubic", "arc").
std::optional<patterns::SegmentKind> segmentKindFromName(std::string_view name);
std::string_view segmentKindName(patterns::SegmentKind kind);
/// The kind names in quotes, for messages.
std::string segmentKindList();

/// `body`: the mannequin with measurements (in the key order of `ordered`, the same value read
/// keeping its order), or a mesh.
patterns::BodySource readBody(const nlohmann::json& value, const nlohmann::ordered_json& ordered,
                              const std::string& pointer);
/// One entry of `materials`; its name must not be one of `existing`.
patterns::GarmentMaterial readMaterial(const nlohmann::json& value, const std::string& pointer,
                                       const std::vector<patterns::GarmentMaterial>& existing);
patterns::DrapeSettings readSimulation(const nlohmann::json& value, const std::string& pointer);

/// What a panel is besides its geometry, the same in every version.
struct PanelAttributes {
    std::string name;
    std::string material;
    patterns::PanelSide side = patterns::PanelSide::Front;
    double grainAngle = patterns::Panel{}.grainAngle;
    patterns::Placement placement;
    double particleDistance = 0; ///< the panel's own [m]; 0: the drape's
};

/// Reads `name` (not one of `takenNames`), `material` (one of `materials`), `side`,
/// `grain_deg`, `placement` and `particle_distance_mm` from a panel object.
PanelAttributes readPanelAttributes(ObjectReader& r,
                                    const std::vector<patterns::GarmentMaterial>& materials,
                                    const std::vector<std::string>& takenNames);

// ---------------------------------------------------------------------------------------------
// Writing (canonical form)

/// Integral values as integers (`90`, not `90.0`), others as the shortest text that reads back
/// to the same double; -0 as 0.
nlohmann::ordered_json number(double v);
/// Metres as millimetres, radians as degrees, rounded to 1e-6 so that the text is stable.
nlohmann::ordered_json mm(double metres);
nlohmann::ordered_json deg(double radians);
nlohmann::ordered_json pointMm(const patterns::Vec2& p);

nlohmann::ordered_json bodyJson(const patterns::BodySource& source);
nlohmann::ordered_json materialJson(const patterns::GarmentMaterial& material);
/// Appends the parameter keys of `material` (material_json.h's, per-direction rigidities only
/// when set) to `out`.
void appendMaterialFields(nlohmann::ordered_json& out, const sim::Material& material);
nlohmann::ordered_json placementJson(const patterns::Placement& placement);
nlohmann::ordered_json simulationJson(const patterns::DrapeSettings& drape);
std::string_view sideName(patterns::PanelSide side);

// ---------------------------------------------------------------------------------------------
// Version 2 (io/project_file_v2.cpp)

/// Reads `next_id`, `panels` and `seams` of a version-2 project object into `document`, whose
/// materials are already read. Every id is checked (unique over the document, below
/// `next_id`), and every reference (dart legs, notch edges, seam panels and edges).
void readDocumentV2(ObjectReader& root, patterns::GarmentDocument& document);

/// Writes `next_id`, `panels` and `seams` of `document` into `root`, in that order.
void writeDocumentV2(const patterns::GarmentDocument& document, nlohmann::ordered_json& root);

/// The pointer into a version-2 file of an issue that patterns::validateGarment found in
/// `toGarment(document)` (whose pointers name version-1 keys: `segment`, `leg`, ...).
std::string pointerInV2(const std::string& garmentPointer);

} // namespace atelier::io::detail
