/// `atelier-cli render INPUT --out PICTURE.png`: pictures of a draped garment (an OBJ written
/// by `drape --out`, with its body beside it as NAME.body.obj when there is one) or of a
/// project (.atelier, draped first as `drape` does), drawn headless through EGL.

#include "app/cli/commands.h"
#include "app/cli/drape.h"
#include "app/cli/limits_option.h"
#include "app/cli/picture.h"

#include "io/obj.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace atelier::app {

namespace {

/// Largest picture side [pixels]: 4096² with 4× MSAA already takes 512 MiB of buffers.
constexpr int MAX_SIDE = 4096;

struct RenderCommandOptions {
    std::string input;
    std::string out;
    std::string size = "1024x1024";
    std::string view = "three-quarter";
    std::string overlay;
    std::string background = "white";
    int threads = 0;
    double timeLimit = -1;          ///< a project's drape: time limit override [s]
    double particleDistanceMm = -1; ///< a project's drape: particle distance override [mm]
    std::vector<std::string> limits;
};

/// The render options the command line asks for, or the message of what is wrong.
std::optional<std::string> parsePictureOptions(const RenderCommandOptions& o, PictureOptions& out) {
    int width = 0;
    int height = 0;
    char rest = 0;
    if (std::sscanf(o.size.c_str(), "%dx%d%c", &width, &height, &rest) != 2 || width < 1 ||
        height < 1 || width > MAX_SIDE || height > MAX_SIDE) {
        return "--size: '" + o.size + "' is not WIDTHxHEIGHT with sides in [1, " +
               std::to_string(MAX_SIDE) + "]";
    }
    out.render.width = width;
    out.render.height = height;
    out.allViews = o.view == "all";
    if (!out.allViews) {
        const auto view = render::viewFromName(o.view);
        if (!view) {
            return "--view: '" + o.view +
                   "' is not one of front, back, left, right, three-quarter, top, all";
        }
        out.render.view = *view;
    }
    if (!o.overlay.empty() && o.overlay != "wireframe") {
        return "--overlay: '" + o.overlay + "' is not wireframe";
    }
    out.render.wireframe = o.overlay == "wireframe";
    if (!render::parseColour(o.background, out.render.background)) {
        return "--background: '" + o.background +
               "' is not #RRGGBB, #RRGGBBAA, white, black, grey or transparent";
    }
    return std::nullopt;
}

int renderProject(const RenderCommandOptions& o, const PictureOptions& pictures) {
    DrapeOptions drape;
    drape.project = o.input;
    drape.threads = o.threads;
    drape.timeLimit = o.timeLimit;
    drape.particleDistanceMm = o.particleDistanceMm;
    drape.limits = o.limits;
    drape.laterOutputs = picturePaths(o.out, pictures.allViews);
    return runDrape(drape, [&](const patterns::DrapeSession& session, int code) {
        return writePictures(sessionScene(session), o.out, pictures, code);
    });
}

int renderMesh(const RenderCommandOptions& o, const PictureOptions& pictures,
               const io::Limits& limits) {
    const std::filesystem::path bodyFile = drapedBodyPath(o.input);
    const bool withBody = std::filesystem::is_regular_file(bodyFile);
    std::vector<NamedPath> inputs = {{"input", o.input}};
    if (withBody) {
        inputs.push_back({"the input's body", bodyFile});
    }
    if (auto problem = checkOutputs(inputs, picturePaths(o.out, pictures.allViews))) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    auto garment = io::readObj(o.input, limits.maxMeshBytes);
    if (!garment.ok()) {
        std::cerr << inputErrorText(garment.error());
        return EXIT_BAD_INPUT;
    }
    io::ObjMesh body;
    if (withBody) {
        auto read = io::readObj(bodyFile, limits.maxMeshBytes);
        if (!read.ok()) {
            std::cerr << inputErrorText(read.error());
            return EXIT_BAD_INPUT;
        }
        body = std::move(read).value();
    }
    const io::ObjMesh& g = garment.value();
    std::fprintf(stderr, "render: %s: %ld triangles, %zu panels%s\n", o.input.c_str(),
                 static_cast<long>(g.triangles.rows()), std::max<std::size_t>(g.groups.size(), 1),
                 withBody ? (", body " + bodyFile.filename().string()).c_str() : "");
    return writePictures(
        garmentScene(g.positions, g.triangles, g.groups, body.positions, body.triangles), o.out,
        pictures, EXIT_OK);
}

int runRender(const RenderCommandOptions& o) {
    PictureOptions pictures;
    if (auto problem = parsePictureOptions(o, pictures)) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    const std::optional<io::Limits> limits = limitsOrReport(o.limits);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    if (std::filesystem::path(o.input).extension() == ".atelier") {
        return renderProject(o, pictures);
    }
    return renderMesh(o, pictures, *limits);
}

} // namespace

void addRenderCommand(CLI::App& app) {
    auto options = std::make_shared<RenderCommandOptions>();
    CLI::App* cmd = app.add_subcommand(
        "render", "Draw pictures of a draped garment (OBJ) or of a project (draped first)");
    cmd->add_option("input", options->input,
                    "Draped garment (OBJ from drape --out; NAME.body.obj beside it is drawn "
                    "too) or garment project (.atelier)")
        ->required();
    cmd->add_option("--out,-o", options->out, "Picture (PNG); with --view all, OUT-VIEW.png")
        ->required();
    cmd->add_option("--size", options->size, "Picture size WIDTHxHEIGHT [pixels]")
        ->capture_default_str();
    cmd->add_option("--view", options->view,
                    "front, back, left, right, three-quarter, top, or all (one picture each)")
        ->capture_default_str();
    cmd->add_option("--overlay", options->overlay, "wireframe: the garment's triangle edges");
    cmd->add_option("--background", options->background,
                    "#RRGGBB, #RRGGBBAA, white, black, grey or transparent")
        ->capture_default_str();
    cmd->add_option("--threads,-j", options->threads,
                    "Engine threads when draping a project (default: all cores)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--time-limit", options->timeLimit,
                    "Simulated time limit of a project's drape [s] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--particle-distance", options->particleDistanceMm,
                    "Mesh particle distance of a project's drape [mm] (default: the project's)")
        ->check(CLI::PositiveNumber);
    addLimitOption(cmd, &options->limits);
    cmd->callback([options] {
        const int code = runRender(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
