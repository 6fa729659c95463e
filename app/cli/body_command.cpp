/// `atelier-cli body`: writes the parametric mannequin for a set of measurements.
#include "app/cli/commands.h"
#include "app/cli/interrupt.h"
#include "app/cli/limits_option.h"
#include "app/cli/preflight.h"

#include "io/atomic_file.h"
#include "io/body_file.h"
#include "io/json_text.h"
#include "io/obj.h"

#include "patterns/body_measure.h"
#include "patterns/mannequin.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

namespace atelier::app {

namespace {

struct BodyOptions {
    std::string measurements;
    std::string base = "female";
    std::string out;
    std::string report;
    std::vector<std::string> limits; ///< --limit NAME=VALUE
};

nlohmann::ordered_json vec(const sim::Vec3& v) {
    return {v.x(), v.y(), v.z()};
}

int runBody(const BodyOptions& options) {
    // A signal while the body is made (seconds; it cannot stop midway) stops the command once
    // it is made: the body is written, marked interrupted, and the exit code is 130.
    const InterruptGuard interrupts;
    if (auto problem = checkOutputs({{"--measurements", options.measurements}},
                                    {{"--out", options.out}, {"--report", options.report}})) {
        std::cerr << "error: " << *problem << "\n";
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
        nlohmann::ordered_json slots = nlohmann::ordered_json::array();
        for (const patterns::ArrangementSlot& s : m.body.slots) {
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
            slots.push_back(slot);
        }
        r["slots"] = slots;
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
        "body", "Generate the parametric mannequin for a set of measurements (OBJ)");
    cmd->add_option("--measurements,-m", options->measurements,
                    "Measurements (JSON, metres: {\"base\": \"female\", \"waist\": 0.72, ...}); "
                    "absent ones take the base's");
    cmd->add_option("--base", options->base, "Base when no measurements file is given")
        ->check(CLI::IsMember({"female", "male"}));
    cmd->add_option("--out,-o", options->out, "Body mesh (OBJ)");
    cmd->add_option("--report,-r", options->report,
                    "Report (JSON): requested and measured measurements, topology, slots");
    addLimitOption(cmd, &options->limits);
    cmd->callback([options] {
        const int code = runBody(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
