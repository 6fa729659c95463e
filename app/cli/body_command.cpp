/// `atelier-cli body`: writes the parametric mannequin for a set of measurements, or imports a
/// body mesh (OBJ, FBX, glTF, COLLADA, PLY, STL), says what was detected and writes it
/// normalised.
#include "app/cli/commands.h"
#include "app/cli/interrupt.h"
#include "app/cli/limits_option.h"
#include "app/cli/preflight.h"

#include "io/atomic_file.h"
#include "io/body_file.h"
#include "io/json_text.h"
#include "io/mesh_export.h"
#include "io/mesh_import.h"
#include "io/obj.h"

#include "patterns/body_landmarks.h"
#include "patterns/body_measure.h"
#include "patterns/mannequin.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <variant>

namespace atelier::app {

namespace {

struct BodyOptions {
    std::string mesh; ///< a body mesh to import instead of making the mannequin
    std::string units = "auto";
    std::string up = "auto";
    bool reportGiven = false; ///< --report without a file: the import report on stdout
    std::string measurements;
    std::string base = "female";
    std::string out;
    std::string report;
    std::vector<std::string> limits; ///< --limit NAME=VALUE
};

nlohmann::ordered_json vec(const sim::Vec3& v) {
    return {v.x(), v.y(), v.z()};
}

nlohmann::ordered_json slotsJson(const std::vector<patterns::ArrangementSlot>& slots) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (const patterns::ArrangementSlot& s : slots) {
        nlohmann::ordered_json slot = {{"name", s.name},         {"origin", vec(s.origin)},
                                       {"axis", vec(s.axis)},    {"facing", vec(s.facing)},
                                       {"radius", s.radius},     {"along_min", s.alongMin},
                                       {"along_max", s.alongMax}};
        if (!s.profile.empty()) {
            // Per bin from along_min: the radius, and where the section is centred (leg
            // slots: the radius is measured from there, not from the axis).
            slot["profile_step"] = s.profileStep;
            slot["profile_radius"] = s.profile;
            if (!s.profileCentre.empty()) {
                nlohmann::ordered_json centres = nlohmann::ordered_json::array();
                for (const sim::Vec3& c : s.profileCentre) {
                    centres.push_back(vec(c));
                }
                slot["profile_centre"] = centres;
            }
        }
        out.push_back(slot);
    }
    return out;
}

/// The landmarks found from a body mesh's shape (heights from the floor) and its girths.
nlohmann::ordered_json landmarksJson(const patterns::BodyLandmarks& L) {
    const auto fromFloor = [&](double y) { return y - L.floorY; };
    const auto pair = [](const std::array<sim::Vec3, 2>& p) {
        return nlohmann::ordered_json{{"left", vec(p[0])}, {"right", vec(p[1])}};
    };
    return {{"height", L.height},
            {"facing", vec(L.facing)},
            {"left", vec(L.left)},
            {"torso_axis", vec(L.centre)},
            {"crotch_y", fromFloor(L.crotchY)},
            {"hip_y", fromFloor(L.hipY)},
            {"waist_y", fromFloor(L.waistY)},
            {"bust_y", fromFloor(L.bustY)},
            {"armpit_y", {fromFloor(L.armpitY[0]), fromFloor(L.armpitY[1])}},
            {"shoulder_y", fromFloor(L.shoulderY)},
            {"neck_base_y", fromFloor(L.neckBaseY)},
            {"neck_y", fromFloor(L.neckY)},
            {"shoulder_half_width", L.shoulderHalfWidth},
            {"shoulder_joint", pair(L.shoulderJoint)},
            {"wrist", pair(L.wrist)},
            {"arm_axis", pair(L.armAxis)},
            {"hip_joint", pair(L.hipJoint)},
            {"thigh_point", pair(L.thighPoint)},
            {"ankle", pair(L.ankle)},
            {"girths",
             {{"bust", L.bust},
              {"waist", L.waist},
              {"hip", L.hip},
              {"neck", L.neck},
              {"thigh", {L.thigh[0], L.thigh[1]}},
              {"upper_arm", {L.upperArm[0], L.upperArm[1]}}}}};
}

/// The landmarks and girths as text (heights from the floor) [m].
std::string landmarksText(const patterns::BodyLandmarks& L) {
    const auto h = [&](double y) { return y - L.floorY; };
    char text[2048];
    std::snprintf(
        text, sizeof text,
        "facing:            (%.3f, %.3f, %.3f)\n"
        "crotch:            %.4f m (%.3f of the height)\n"
        "hip:               %.4f m, girth %.4f m\n"
        "waist:             %.4f m, girth %.4f m\n"
        "bust:              %.4f m, girth %.4f m\n"
        "armpits:           %.4f m left, %.4f m right\n"
        "shoulders:         %.4f m, torso half-width %.4f m at the armpits\n"
        "neck base:         %.4f m\n"
        "neck:              %.4f m, girth %.4f m\n"
        "left arm:          shoulder (%.3f, %.3f, %.3f) to (%.3f, %.3f, %.3f), "
        "%.1f deg from the vertical, upper arm girth %.4f m\n"
        "right arm:         shoulder (%.3f, %.3f, %.3f) to (%.3f, %.3f, %.3f), "
        "%.1f deg from the vertical, upper arm girth %.4f m\n"
        "left leg:          hip (%.3f, %.3f, %.3f), ankle (%.3f, %.3f, %.3f), thigh girth %.4f m\n"
        "right leg:         hip (%.3f, %.3f, %.3f), ankle (%.3f, %.3f, %.3f), thigh girth "
        "%.4f m\n",
        L.facing.x(), L.facing.y(), L.facing.z(), h(L.crotchY), h(L.crotchY) / L.height, h(L.hipY),
        L.hip, h(L.waistY), L.waist, h(L.bustY), L.bust, h(L.armpitY[0]), h(L.armpitY[1]),
        h(L.shoulderY), L.shoulderHalfWidth, h(L.neckBaseY), h(L.neckY), L.neck,
        L.shoulderJoint[0].x(), L.shoulderJoint[0].y(), L.shoulderJoint[0].z(), L.wrist[0].x(),
        L.wrist[0].y(), L.wrist[0].z(),
        std::acos(std::clamp(L.armAxis[0].y(), -1.0, 1.0)) * 180 / M_PI, L.upperArm[0],
        L.shoulderJoint[1].x(), L.shoulderJoint[1].y(), L.shoulderJoint[1].z(), L.wrist[1].x(),
        L.wrist[1].y(), L.wrist[1].z(),
        std::acos(std::clamp(L.armAxis[1].y(), -1.0, 1.0)) * 180 / M_PI, L.upperArm[1],
        L.hipJoint[0].x(), L.hipJoint[0].y(), L.hipJoint[0].z(), L.ankle[0].x(), L.ankle[0].y(),
        L.ankle[0].z(), L.thigh[0], L.hipJoint[1].x(), L.hipJoint[1].y(), L.hipJoint[1].z(),
        L.ankle[1].x(), L.ankle[1].y(), L.ankle[1].z(), L.thigh[1]);
    return text;
}

/// The import report as text (stdout of `body FILE --report`).
std::string importText(const std::string& file, const io::BodyImportReport& r) {
    char text[1024];
    std::snprintf(text, sizeof text,
                  "units:             %s (%s)\n"
                  "up axis:           %s (%s)\n"
                  "height:            %.4f m (%.6g file units)\n"
                  "vertices:          %ld (%ld as read)\n"
                  "triangles:         %ld (%ld degenerate dropped)\n"
                  "holes:             %ld (%ld boundary edges)\n"
                  "non-manifold edges: %ld\n",
                  std::string(io::unitName(r.units)).c_str(), r.unitsFrom.c_str(),
                  std::string(io::axisName(r.up)).c_str(), r.upFrom.c_str(), r.height, r.fileHeight,
                  r.vertices, r.sourceVertices, r.triangles, r.droppedTriangles, r.holes,
                  r.boundaryEdges, r.nonManifoldEdges);
    return "file:              " + file + "\nformat:            " + r.format + "\n" + text;
}

/// `body FILE`: imports a body mesh, reports what was detected, writes it normalised.
int runBodyImport(const BodyOptions& options) {
    const std::optional<io::Limits> limits = limitsOrReport(options.limits);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    std::optional<io::MeshFormat> outFormat;
    if (!options.out.empty()) {
        outFormat = io::meshFormatOfPath(options.out);
        if (!outFormat) {
            std::cerr << "error: --out " << options.out
                      << ": unknown mesh format (by extension: .obj, .glb, .fbx, .ply)\n";
            return EXIT_BAD_INPUT;
        }
    }
    io::BodyImportOptions importOptions;
    importOptions.units = io::parseLengthUnit(options.units).value_or(io::LengthUnit::Auto);
    importOptions.up = io::parseUpAxis(options.up).value_or(io::UpAxis::Auto);
    auto imported = io::importBody(options.mesh, importOptions, *limits);
    if (!imported.ok()) {
        std::cerr << inputErrorText(imported.error());
        return EXIT_BAD_INPUT;
    }
    const io::ImportedBody& body = imported.value();
    const io::BodyImportReport& r = body.report;
    std::fprintf(stderr,
                 "body: %s, %s, %s up, %.3f m tall, %ld vertices, %ld triangles, %ld holes, "
                 "%ld non-manifold edges\n",
                 r.format.c_str(), std::string(io::unitName(r.units)).c_str(),
                 std::string(io::axisName(r.up)).c_str(), r.height, r.vertices, r.triangles,
                 r.holes, r.nonManifoldEdges);
    for (const std::string& w : r.warnings) {
        std::cerr << "warning: " << options.mesh << ": " << w << "\n";
    }
    const auto found = patterns::findLandmarks(body.vertices, body.triangles);
    const auto* landmarks = std::get_if<patterns::FoundLandmarks>(&found);
    if (options.reportGiven && options.report.empty()) {
        std::cout << importText(options.mesh, r)
                  << (landmarks != nullptr
                          ? landmarksText(landmarks->landmarks)
                          : "landmarks:         not found: " + std::get<std::string>(found) + "\n");
    }
    int code = EXIT_OK;
    if (outFormat) {
        io::SurfaceMesh surface;
        surface.positions = body.vertices;
        surface.triangles = body.triangles;
        surface.groups.push_back(io::ObjGroup{"body", 0, static_cast<int>(r.triangles)});
        surface.comment = "body imported from " + options.mesh + ", metres, Y up";
        auto written = io::exportMesh(options.out, surface, *outFormat);
        if (!written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            code = EXIT_RUN_FAILED;
        }
    }
    if (!options.report.empty()) {
        nlohmann::ordered_json j;
        j["file"] = options.mesh;
        j["format"] = r.format;
        j["units"] = io::unitName(r.units);
        j["units_from"] = r.unitsFrom;
        j["up"] = io::axisName(r.up);
        j["up_from"] = r.upFrom;
        j["file_height"] = r.fileHeight;
        j["height_m"] = r.height;
        j["source_vertices"] = r.sourceVertices;
        j["vertices"] = r.vertices;
        j["triangles"] = r.triangles;
        j["dropped_triangles"] = r.droppedTriangles;
        j["holes"] = r.holes;
        j["boundary_edges"] = r.boundaryEdges;
        j["non_manifold_edges"] = r.nonManifoldEdges;
        j["warnings"] = r.warnings;
        if (landmarks != nullptr) {
            j["landmarks"] = landmarksJson(landmarks->landmarks);
        } else {
            j["landmarks"] = nullptr;
            j["landmarks_problem"] = std::get<std::string>(found);
        }
        patterns::Body withSlots;
        withSlots.vertices = body.vertices;
        withSlots.triangles = body.triangles;
        if (auto problem = patterns::estimateSlots(withSlots)) {
            j["slots"] = nullptr;
            j["slots_problem"] = *problem;
        } else {
            j["slots"] = slotsJson(withSlots.slots);
        }
        auto written = io::writeFileAtomically(options.report, io::jsonText(j));
        if (!written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            code = EXIT_RUN_FAILED;
        }
    }
    return code;
}

int runBody(const BodyOptions& options) {
    // A signal while the body is made (seconds; it cannot stop midway) stops the command once
    // it is made: the body is written, marked interrupted, and the exit code is 130.
    const InterruptGuard interrupts;
    if (auto problem = checkOutputs(
            {{"--measurements", options.measurements}, {"the body mesh", options.mesh}},
            {{"--out", options.out}, {"--report", options.report}})) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    if (!options.mesh.empty()) {
        return runBodyImport(options);
    }
    if (options.reportGiven && options.report.empty()) {
        std::cerr << "error: --report needs a file for the mannequin (printing it needs a body "
                     "mesh)\n";
        return EXIT_BAD_INPUT;
    }
    patterns::BodySource source;
    source.base = options.base;
    if (!options.measurements.empty()) {
        const std::optional<io::Limits> limits = limitsOrReport(options.limits);
        if (!limits) {
            return EXIT_BAD_INPUT;
        }
        auto read = io::readMeasurementsFile(options.measurements, *limits);
        if (!read.ok()) {
            std::cerr << inputErrorText(read.error());
            return EXIT_BAD_INPUT;
        }
        source = read.value();
    }
    auto made = io::makeBody(source, options.measurements);
    if (!made.ok()) {
        std::cerr << "error: " << made.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }
    const patterns::Mannequin& m = made.value();
    const patterns::MeshTopology topo = patterns::meshTopology(m.body.vertices, m.body.triangles);
    std::fprintf(
        stderr, "body: %s, %ld triangles, %s (Euler characteristic %ld), generated in %.2f s\n",
        source.base.c_str(), static_cast<long>(m.body.triangles.rows()),
        topo.watertight() ? "watertight" : "NOT watertight", topo.eulerCharacteristic, m.seconds);
    nlohmann::ordered_json requested = nlohmann::ordered_json::object();
    nlohmann::ordered_json measured = nlohmann::ordered_json::object();
    for (const auto& [name, member] : patterns::measurementFields()) {
        requested[std::string(name)] = m.requested.*member;
        measured[std::string(name)] = m.measured.*member;
        std::fprintf(stderr, "  %-15s requested %.4f m  measured %.4f m\n",
                     std::string(name).c_str(), m.requested.*member, m.measured.*member);
    }
    int code = EXIT_OK;
    if (InterruptGuard::interrupted()) {
        std::cerr << "body: interrupted (" << InterruptGuard::signalName()
                  << "); writing the body made\n";
        code = EXIT_CANCELLED;
    }
    if (!options.out.empty()) {
        io::ObjWriteOptions obj;
        obj.comment = "Atelier mannequin (" + source.base + "), metres, Y up, facing +z";
        obj.groups.push_back(io::ObjGroup{"body", 0, static_cast<int>(m.body.triangles.rows())});
        auto written = io::writeObj(options.out, m.body.vertices, m.body.triangles, obj);
        if (!written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            code = EXIT_RUN_FAILED;
        }
    }
    if (!options.report.empty()) {
        nlohmann::ordered_json r;
        r["base"] = source.base;
        r["interrupted"] = InterruptGuard::interrupted();
        r["vertices"] = m.body.vertices.rows();
        r["triangles"] = m.body.triangles.rows();
        r["watertight"] = topo.watertight();
        r["euler_characteristic"] = topo.eulerCharacteristic;
        r["volume_m3"] = patterns::enclosedVolume(m.body.vertices, m.body.triangles);
        r["seconds"] = m.seconds;
        r["requested"] = requested;
        r["measured"] = measured;
        r["slots"] = slotsJson(m.body.slots);
        // What findLandmarks finds on the mannequin's mesh alone (as on an imported body).
        const auto found = patterns::findLandmarks(m.body.vertices, m.body.triangles);
        if (const auto* landmarks = std::get_if<patterns::FoundLandmarks>(&found)) {
            r["landmarks_found"] = landmarksJson(landmarks->landmarks);
        } else {
            r["landmarks_found"] = nullptr;
            r["landmarks_problem"] = std::get<std::string>(found);
        }
        auto written = io::writeFileAtomically(options.report, io::jsonText(r));
        if (!written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            code = EXIT_RUN_FAILED;
        }
    }
    return code;
}

} // namespace

void addBodyCommand(CLI::App& app) {
    auto options = std::make_shared<BodyOptions>();
    CLI::App* cmd = app.add_subcommand(
        "body", "Generate the parametric mannequin for a set of measurements (OBJ), or import "
                "a body mesh and say what was detected");
    CLI::Option* mesh = cmd->add_option(
        "mesh", options->mesh,
        "A body mesh to import (OBJ, FBX, glTF .gltf/.glb, COLLADA .dae, PLY, STL): "
        "triangulated, welded, normalised to metres, Y up, standing on y = 0");
    cmd->add_option("--units", options->units,
                    "The mesh's unit (default: from its height, ~1700 mm, ~170 cm, ~1.7 m)")
        ->check(CLI::IsMember({"auto", "mm", "cm", "m"}))
        ->needs(mesh);
    cmd->add_option("--up", options->up,
                    "The mesh's up axis (default: from its metadata and bounding box)")
        ->check(CLI::IsMember({"auto", "y", "z"}))
        ->needs(mesh);
    cmd->add_option("--measurements,-m", options->measurements,
                    "Measurements (JSON, metres: {\"base\": \"female\", \"waist\": 0.72, ...}); "
                    "absent ones take the base's")
        ->excludes(mesh);
    cmd->add_option("--base", options->base, "Base when no measurements file is given")
        ->check(CLI::IsMember({"female", "male"}));
    cmd->add_option("--out,-o", options->out,
                    "Body mesh (mannequin: OBJ; an imported mesh: .obj, .glb, .fbx or .ply)");
    cmd->add_option("--report,-r", options->report,
                    "Report (JSON): requested and measured measurements, topology, slots, the "
                    "landmarks found from the mesh's shape; for an imported mesh what was "
                    "detected (units, up axis, height, counts, holes, non-manifold edges) and its "
                    "landmarks and girths, printed on stdout when no file is given")
        ->expected(0, 1);
    addLimitOption(cmd, &options->limits);
    cmd->callback([options, cmd] {
        options->reportGiven = cmd->count("--report") > 0;
        const int code = runBody(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
