#include "io/project_file.h"

#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/project_json.h"

#include "patterns/curve.h"
#include "patterns/mesh.h"

#include <cmath>
#include <limits>

namespace atelier::io {

namespace {

using detail::inQuotes;
using detail::JsonError;
using detail::ObjectReader;
using nlohmann::json;
using nlohmann::ordered_json;
using patterns::Segment;
using patterns::SegmentKind;

/// The oldest version this build reads (version 1 is migrated through patterns::fromGarment).
constexpr int OLDEST_PROJECT_FORMAT_VERSION = 1;

// ---------------------------------------------------------------------------------------------
// Version 1: a patterns::Garment with panels and segments by index, seams by panel name.

/// A non-negative index that fits an int.
int index(ObjectReader& r, std::string_view key) {
    const long long n = r.integer(key);
    if (n < 0 || n > std::numeric_limits<int>::max()) {
        r.fail(key, "must be a non-negative integer (found " + std::to_string(n) + ")");
    }
    return static_cast<int>(n);
}

/// One segment `{"kind": {...}}`; `open` segments (internal lines) carry their end ("to").
Segment readSegment(const json& value, const std::string& pointer, bool open) {
    ObjectReader r(value, pointer);
    if (value.size() != 1) {
        r.fail("expected an object with one key, the segment kind (" + detail::segmentKindList() +
               "), found " + std::to_string(value.size()) + " keys");
    }
    const std::string kindName = value.begin().key();
    Segment s;
    const auto kind = detail::segmentKindFromName(kindName);
    if (!kind) {
        r.fail(kindName, "unknown segment kind " + inQuotes(kindName) + " (expected one of " +
                             detail::segmentKindList() + ")");
    }
    s.kind = *kind;
    ObjectReader g(r.require(kindName), r.pointerOf(kindName));
    s.start = detail::point(g, "from");
    if (open) {
        s.end = detail::point(g, "to");
    }
    if (s.kind == SegmentKind::Quadratic || s.kind == SegmentKind::Cubic) {
        s.control1 = detail::point(g, "c1");
    }
    if (s.kind == SegmentKind::Cubic) {
        s.control2 = detail::point(g, "c2");
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

patterns::InternalLine readInternalLineV1(const json& value, const std::string& ptr) {
    ObjectReader l(value, ptr);
    patterns::InternalLine line;
    line.foldAngle = detail::angleDeg(l, "fold_deg", line.foldAngle);
    const std::string sp = l.pointerOf("segments");
    const json& segments = detail::arrayAt(l.require("segments"), sp);
    if (segments.empty()) {
        l.fail("segments", "an internal line needs at least one segment");
    }
    for (std::size_t k = 0; k < segments.size(); ++k) {
        line.path.push_back(readSegment(segments[k], detail::childPointer(sp, k), true));
    }
    l.finish();
    return line;
}

patterns::Panel readPanelV1(const json& value, const std::string& ptr,
                            const patterns::Garment& garment) {
    ObjectReader r(value, ptr);
    std::vector<std::string> names;
    for (const patterns::Panel& p : garment.panels) {
        names.push_back(p.name);
    }
    const detail::PanelAttributes a = detail::readPanelAttributes(r, garment.materials, names);
    patterns::Panel panel;
    panel.name = a.name;
    panel.material = a.material;
    panel.side = a.side;
    panel.grainAngle = a.grainAngle;
    panel.placement = a.placement;
    panel.particleDistance = a.particleDistance;
    panel.outline = readLoop(r.require("outline"), r.pointerOf("outline"));
    detail::forEachIn(r, "holes", [&](const json& v, const std::string& p) {
        panel.holes.push_back(readLoop(v, p));
    });
    detail::forEachIn(r, "internal_lines", [&](const json& v, const std::string& p) {
        panel.internalLines.push_back(readInternalLineV1(v, p));
    });
    detail::forEachIn(r, "darts", [&](const json& v, const std::string& p) {
        ObjectReader d(v, p);
        panel.darts.push_back({index(d, "leg")});
        d.finish();
    });
    detail::forEachIn(r, "notches", [&](const json& v, const std::string& p) {
        ObjectReader n(v, p);
        patterns::Notch notch;
        notch.segment = index(n, "segment");
        if (notch.segment >= static_cast<int>(panel.outline.size())) {
            n.fail("segment", "no segment " + std::to_string(notch.segment) +
                                  " in the outline (it has " +
                                  std::to_string(panel.outline.size()) + ")");
        }
        notch.t = detail::parameter(n, "t", notch.t);
        n.finish();
        panel.notches.push_back(notch);
    });
    r.finish();
    return panel;
}

patterns::Seam readSeamV1(const json& value, const std::string& ptr) {
    ObjectReader r(value, ptr);
    patterns::Seam seam;
    seam.name = r.string("name", "");
    detail::seamBending(r, seam.foldAngle, seam.bendingScale);
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
            edge.t0 = detail::parameter(e, "t0", edge.t0);
            edge.t1 = detail::parameter(e, "t1", edge.t1);
            e.finish();
            out.push_back(std::move(edge));
        }
    }
    r.finish();
    return seam;
}

/// Panels and seams of a version-1 file into `garment`, whose materials are read.
void readGarmentV1(ObjectReader& r, patterns::Garment& garment) {
    detail::forEachIn(r, "panels", [&](const json& v, const std::string& p) {
        garment.panels.push_back(readPanelV1(v, p, garment));
    });
    detail::forEachIn(r, "seams", [&](const json& v, const std::string& p) {
        garment.seams.push_back(readSeamV1(v, p));
    });
}

// ---------------------------------------------------------------------------------------------
// Every version

int readVersion(ObjectReader& r) {
    const std::string format = r.string("format");
    if (format != "atelier-project") {
        r.fail("format", "expected \"atelier-project\", found " + inQuotes(format));
    }
    const long long version = r.integer("version");
    if (version > PROJECT_FORMAT_VERSION) {
        r.fail("version", "version " + std::to_string(version) +
                              " was written by a newer Atelier (this build reads versions " +
                              std::to_string(OLDEST_PROJECT_FORMAT_VERSION) + " to " +
                              std::to_string(PROJECT_FORMAT_VERSION) + ")");
    }
    if (version < OLDEST_PROJECT_FORMAT_VERSION) {
        r.fail("version", "unsupported version " + std::to_string(version) +
                              " (this build reads versions " +
                              std::to_string(OLDEST_PROJECT_FORMAT_VERSION) + " to " +
                              std::to_string(PROJECT_FORMAT_VERSION) + ")");
    }
    return static_cast<int>(version);
}

/// The project as read, before its garment is checked: version 1 fills `garment`, version 2
/// `document`. `ordered` is the same document as `root` with its key order (measurements).
patterns::Project readProject(const json& root, const ordered_json& ordered) {
    ObjectReader r(root, "");
    patterns::Project project;
    project.version = readVersion(r);
    project.name = r.string("name", "");
    if (const json* body = r.find("body")) {
        project.body = detail::readBody(*body, ordered.at("body"), r.pointerOf("body"));
    }
    std::vector<patterns::GarmentMaterial> materials;
    detail::forEachIn(r, "materials", [&](const json& v, const std::string& p) {
        materials.push_back(detail::readMaterial(v, p, materials));
    });
    double easeTolerance = patterns::Garment{}.easeTolerance;
    easeTolerance =
        detail::lengthMm(r, "ease_tolerance_mm", easeTolerance, detail::Range::NonNegative);
    if (project.version == 1) {
        project.garment.name = project.name;
        project.garment.materials = std::move(materials);
        project.garment.easeTolerance = easeTolerance;
        readGarmentV1(r, project.garment);
    } else {
        project.document.name = project.name;
        project.document.materials = std::move(materials);
        project.document.easeTolerance = easeTolerance;
        detail::readDocumentV2(r, project.document);
    }
    if (const json* simulation = r.find("simulation")) {
        project.drape = detail::readSimulation(*simulation, r.pointerOf("simulation"));
    }
    r.finish();
    return project;
}

/// Checks the garment of a project as read and fills the other representation: a version-1
/// garment becomes a document (ids handed out in file order) and is kept as read, so that it
/// drapes as before; a version-2 document gives the garment. Geometry issues
/// (patterns::validateGarment) come at their JSON pointer.
Result<void> completeProject(patterns::Project& project, const std::string& file) {
    if (project.version == 1) {
        if (const auto issues = patterns::validateGarment(project.garment); !issues.empty()) {
            return Error{file, issues.front().where, issues.front().message};
        }
        project.document = patterns::fromGarment(project.garment);
        return {};
    }
    if (auto checked = patterns::checkDocument(project.document); !checked.ok()) {
        return Error{file, "", checked.error().message};
    }
    project.garment = patterns::toGarment(project.document);
    if (const auto issues = patterns::validateGarment(project.garment); !issues.empty()) {
        return Error{file, detail::pointerInV2(issues.front().where), issues.front().message};
    }
    return {};
}

/// The drape within the limits: steps (time limit over the step) and triangles (estimated
/// from the panels' areas and outlines, patterns::estimateGarmentMesh).
Result<void> checkDrapeSize(const patterns::Project& project, const std::string& file,
                            const Limits& limits) {
    const patterns::DrapeSettings& d = project.drape;
    const auto text = [](double v) { return json(v).dump(); };
    const double steps = d.timeLimit / d.dt;
    if (!(steps <= static_cast<double>(limits.maxSteps))) {
        return Error{file, "/simulation/time_limit_s",
                     "time_limit_s / dt_s is " + text(steps) + " steps, more than the limit of " +
                         std::to_string(limits.maxSteps)};
    }
    const long triangles =
        patterns::estimateGarmentMesh(project.garment, d.particleDistance).triangles;
    if (triangles > limits.maxGarmentTriangles) {
        return Error{file, "/simulation/particle_distance_mm",
                     "the panels at this particle distance make about " +
                         std::to_string(triangles) + " triangles, more than the limit of " +
                         std::to_string(limits.maxGarmentTriangles)};
    }
    for (const auto& [key, value] : {std::pair{"cloth_thickness_mm", d.clothThickness},
                                     std::pair{"body_thickness_mm", d.bodyThickness}}) {
        if (value > limits.maxThickness) {
            return Error{file, std::string("/simulation/") + key,
                         "must be at most " + text(1000 * limits.maxThickness) + " mm (" +
                             THICKNESS_LIMIT + "; found " + text(1000 * value) + ")"};
        }
    }
    return {};
}

} // namespace

Result<patterns::Project> parseProject(std::string_view text, const std::string& file,
                                       const Limits& limits) {
    const std::string textCopy(text);
    auto parsed = detail::parseJson(textCopy, file, limits.maxJsonDepth);
    if (!parsed.ok()) {
        return parsed.error();
    }
    // The same document again, keeping key order (measurements are an ordered list).
    const ordered_json ordered = ordered_json::parse(textCopy);
    patterns::Project project;
    try {
        project = readProject(parsed.value(), ordered);
    } catch (const JsonError& e) {
        return Error{file, e.where, e.message};
    }
    if (auto complete = completeProject(project, file); !complete.ok()) {
        return complete.error();
    }
    if (auto size = checkDrapeSize(project, file, limits); !size.ok()) {
        return size.error();
    }
    return project;
}

Result<patterns::Project> loadProject(const std::filesystem::path& path, const Limits& limits) {
    auto text = readFile(path, limits.maxJsonBytes);
    if (!text.ok()) {
        return text.error();
    }
    auto project = parseProject(text.value(), path.string(), limits);
    if (!project.ok()) {
        return project;
    }
    if (const std::string& mesh = project.value().body.meshPath; !mesh.empty()) {
        const std::filesystem::path resolved = path.parent_path() / mesh;
        std::error_code ec;
        if (!std::filesystem::exists(resolved, ec)) {
            return Error{path.string(), "/body/mesh", "body mesh not found: " + resolved.string()};
        }
        if (!std::filesystem::is_regular_file(resolved, ec)) {
            return Error{path.string(), "/body/mesh",
                         "body mesh is not a regular file: " + resolved.string()};
        }
    }
    return project;
}

std::string formatProject(const patterns::Project& project) {
    const patterns::GarmentDocument& document = project.document;
    ordered_json root = ordered_json::object();
    root["format"] = "atelier-project";
    root["version"] = PROJECT_FORMAT_VERSION;
    root["name"] = project.name;
    root["body"] = detail::bodyJson(project.body);
    root["materials"] = ordered_json::array();
    for (const patterns::GarmentMaterial& material : document.materials) {
        root["materials"].push_back(detail::materialJson(material));
    }
    detail::writeDocumentV2(document, root);
    root["ease_tolerance_mm"] = detail::mm(document.easeTolerance);
    root["simulation"] = detail::simulationJson(project.drape);
    // Invalid UTF-8 in a name is replaced rather than thrown on.
    return root.dump(2, ' ', false, ordered_json::error_handler_t::replace) + "\n";
}

Result<void> saveProject(const std::filesystem::path& path, const patterns::Project& project) {
    return writeFileAtomically(path, formatProject(project));
}

} // namespace atelier::io
