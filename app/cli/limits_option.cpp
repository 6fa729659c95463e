#include "app/cli/limits_option.h"

#include "io/scene_file.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <type_traits>

namespace atelier::app {

namespace {

/// One limit: its name on the command line, what it bounds, and its field.
struct LimitEntry {
    const char* name;
    const char* what;
    std::function<double(const io::Limits&)> get;
    std::function<void(io::Limits&, double)> set;
    bool integer = true;
};

template <typename T> LimitEntry entry(const char* name, const char* what, T io::Limits::*field) {
    return LimitEntry{name, what, [field](const io::Limits& l) { return double(l.*field); },
                      [field](io::Limits& l, double v) { l.*field = static_cast<T>(v); },
                      std::is_integral_v<T>};
}

const std::vector<LimitEntry>& entries() {
    static const std::vector<LimitEntry> all = {
        entry("json-bytes", "largest JSON file read (scene, project, fabrics) [bytes]",
              &io::Limits::maxJsonBytes),
        entry("mesh-bytes",
              "largest mesh or DXF pattern file read (OBJ cloth, obstacle, body) [bytes]",
              &io::Limits::maxMeshBytes),
        entry("json-depth", "deepest nesting of JSON arrays and objects",
              &io::Limits::maxJsonDepth),
        entry("body-extent-m", "longest side of a body mesh or OBJ obstacle [m]",
              &io::Limits::maxBodyExtent),
        entry("body-vertices", "vertices of a body mesh read through assimp (FBX, glTF, ...)",
              &io::Limits::maxBodyVertices),
        entry("scene-coordinate-m", "farthest cloth or obstacle point from the origin [m]",
              &io::Limits::maxSceneCoordinate),
        entry("thickness-m", "thickest contact layer of a cloth or obstacle [m]",
              &io::Limits::maxThickness),
        entry("cloths", "cloths in a scene", &io::Limits::maxCloths),
        entry("obstacles", "obstacles in a scene", &io::Limits::maxObstacles),
        entry("scene-vertices", "vertices of a scene's cloths and obstacles",
              &io::Limits::maxSceneVertices),
        entry("scene-triangles", "triangles of a scene's cloths and obstacles",
              &io::Limits::maxSceneTriangles),
        entry("frame-rate", "output frames per second of a scene", &io::Limits::maxFrameRate),
        entry("frames", "output frames of a scene (duration x frame_rate)", &io::Limits::maxFrames),
        entry("steps", "steps the nominal step asks for (duration / dt)", &io::Limits::maxSteps),
        entry("garment-triangles", "triangles a project's garment is estimated to mesh into",
              &io::Limits::maxGarmentTriangles),
    };
    return all;
}

std::string names() {
    std::string out;
    for (const LimitEntry& e : entries()) {
        out += (out.empty() ? "" : ", ") + std::string(e.name);
    }
    return out;
}

} // namespace

void addLimitOption(CLI::App* cmd, std::vector<std::string>* raw) {
    cmd->add_option("--limit", *raw,
                    "Raise or lower a bound on the input, NAME=VALUE (repeatable; "
                    "`atelier-cli limits` lists them)")
        ->type_name("NAME=VALUE");
}

Result<io::Limits> limitsFrom(const std::vector<std::string>& raw) {
    io::Limits limits;
    for (const std::string& item : raw) {
        const std::size_t eq = item.find('=');
        const std::string name = item.substr(0, eq);
        const LimitEntry* found = nullptr;
        for (const LimitEntry& e : entries()) {
            found = name == e.name ? &e : found;
        }
        if (eq == std::string::npos || found == nullptr) {
            return Error{"", "--limit",
                         "\"" + item + "\": expected NAME=VALUE with NAME one of " + names()};
        }
        const std::string text = item.substr(eq + 1);
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        const bool whole = !found->integer || value == std::floor(value);
        if (text.empty() || end != text.c_str() + text.size() || !(value > 0) ||
            !std::isfinite(value) || !whole || value > 9.0e15) {
            return Error{"", "--limit",
                         "\"" + item + "\": the value must be a positive " +
                             (found->integer ? "whole number" : "number")};
        }
        found->set(limits, value);
    }
    return limits;
}

std::optional<io::Limits> limitsOrReport(const std::vector<std::string>& raw) {
    auto limits = limitsFrom(raw);
    if (!limits.ok()) {
        std::fprintf(stderr, "error: %s\n", limits.error().toString().c_str());
        return std::nullopt;
    }
    return limits.value();
}

std::string inputErrorText(const Error& error) {
    std::string text = "error: " + error.toString() + "\n";
    if (text.find("the limit of") != std::string::npos ||
        text.find("the limit is") != std::string::npos) {
        text += "(`atelier-cli limits` lists the limits; --limit NAME=VALUE changes one)\n";
    }
    return text;
}

std::optional<sim::SceneSpec> loadSceneOrReport(const std::string& path,
                                                const std::vector<std::string>& rawLimits) {
    const std::optional<io::Limits> limits = limitsOrReport(rawLimits);
    if (!limits) {
        return std::nullopt;
    }
    io::SceneLoadOptions load;
    load.limits = *limits;
    auto loaded = io::loadScene(path, load);
    if (!loaded.ok()) {
        std::fputs(inputErrorText(loaded.error()).c_str(), stderr);
        return std::nullopt;
    }
    return std::move(loaded).value();
}

void addLimitsCommand(CLI::App& app) {
    CLI::App* cmd = app.add_subcommand(
        "limits", "The bounds Atelier holds input files to, and their --limit names");
    cmd->callback([] {
        const io::Limits defaults;
        for (const LimitEntry& e : entries()) {
            std::printf("%-20s %-14.10g %s\n", e.name, e.get(defaults), e.what);
        }
    });
}

} // namespace atelier::app
