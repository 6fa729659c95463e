/// `atelier-cli render INPUT --out PICTURE.png`: pictures of a draped garment (an OBJ written
/// by `drape --out`, with its body beside it as NAME.body.obj when there is one) or of a
/// project (.atelier, draped first as `drape` does), drawn headless through EGL; and
/// `atelier-cli render --frames-dir DIR --out OUTDIR`: one picture per frame OBJ of a drape or
/// simulation, all framed alike.

#include "app/cli/commands.h"
#include "app/cli/drape.h"
#include "app/cli/limits_option.h"
#include "app/cli/picture.h"

#include "ui/render/camera.h"

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

struct RenderCommandOptions {
    std::string input;
    std::string out;
    std::string size = "1024x1024";
    std::string view = "three-quarter";
    std::string overlay;
    std::string background = "white";
    double strainRangePct = 10;     ///< --strain-range [%]
    double weaveMm = 0;             ///< --weave [mm]; 0 = none
    bool ambientOcclusion = false;  ///< --ambient-occlusion
    bool noPins = false;            ///< --no-pins
    double contactThicknessMm = -1; ///< --contact-thickness [mm]; < 0 = the project's or 4 mm
    std::string framesDir;          ///< --frames-dir: render every frame OBJ in it
    std::string body;               ///< --body: the body of the frames (static)
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
    const auto overlay = overlayFromName(o.overlay);
    if (!overlay) {
        return "--overlay: '" + o.overlay + "' is not " + OVERLAY_NAMES;
    }
    out.overlay = *overlay;
    out.render.wireframe = *overlay == Overlay::Wireframe;
    out.strainRange = o.strainRangePct / 100;
    out.weavePeriodMm = o.weaveMm;
    out.ambientOcclusion = o.ambientOcclusion;
    out.render.pins = !o.noPins;
    if (o.contactThicknessMm > 0) {
        out.contactThickness = o.contactThicknessMm / 1000;
    }
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
        PictureOptions withProject = pictures;
        if (o.contactThicknessMm < 0) {
            const patterns::DrapeSettings& settings = session.project().drape;
            withProject.contactThickness = settings.clothThickness + settings.bodyThickness;
        }
        return writePictures(sessionGarment(session), o.out, withProject, code);
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
    const std::optional<DrapedGarment> g = readDrapedObj(o.input, limits);
    if (!g) {
        return EXIT_BAD_INPUT;
    }
    std::fprintf(stderr, "render: %s: %ld triangles, %zu panels%s\n", o.input.c_str(),
                 static_cast<long>(g->triangles.rows()), std::max<std::size_t>(g->panels.size(), 1),
                 withBody ? (", body " + bodyFile.filename().string()).c_str() : "");
    return writePictures(*g, o.out, pictures, EXIT_OK);
}

/// The frame OBJs of a `--frames-dir` folder (frame_NNNNN.obj, not the .obstacles.obj beside
/// them), in name order.
std::vector<std::filesystem::path> frameFiles(const std::filesystem::path& dir) {
    std::vector<std::filesystem::path> files;
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (entry.is_regular_file() && name.starts_with("frame_") && name.ends_with(".obj") &&
            !name.ends_with(".obstacles.obj")) {
            files.push_back(entry.path());
        }
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// `render --frames-dir DIR --out OUTDIR`: OUTDIR/frame_NNNNN.png for every DIR/frame_NNNNN.obj,
/// one camera for all of them (framed to the union of their bounds).
int renderFrames(const RenderCommandOptions& o, const PictureOptions& pictures,
                 const io::Limits& limits) {
    if (!std::filesystem::is_directory(o.framesDir)) {
        std::cerr << "error: --frames-dir: " << o.framesDir << ": not a folder\n";
        return EXIT_BAD_INPUT;
    }
    if (pictures.allViews) {
        std::cerr << "error: --view all: a frame sequence is drawn from one view\n";
        return EXIT_BAD_INPUT;
    }
    const std::vector<std::filesystem::path> files = frameFiles(o.framesDir);
    if (files.empty()) {
        std::cerr << "error: --frames-dir: " << o.framesDir << ": no frame_NNNNN.obj in it\n";
        return EXIT_BAD_INPUT;
    }
    const std::filesystem::path outDir = o.out;
    std::vector<NamedPath> outputs;
    for (const auto& file : files) {
        outputs.push_back({"--out", outDir / file.filename().replace_extension(".png")});
    }
    if (auto problem = checkOutputFolder({"--out", outDir}, {{"--frames-dir", o.framesDir}})) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    std::error_code ec;
    std::filesystem::create_directories(outDir, ec);
    if (ec) {
        std::cerr << "error: --out: " << outDir.string() << ": " << ec.message() << "\n";
        return EXIT_BAD_INPUT;
    }
    DrapedGarment staticBody;
    if (!o.body.empty()) {
        auto body = io::readObj(o.body, limits.maxMeshBytes);
        if (!body.ok()) {
            std::cerr << inputErrorText(body.error());
            return EXIT_BAD_INPUT;
        }
        staticBody.bodyPositions = std::move(body.value().positions);
        staticBody.bodyTriangles = std::move(body.value().triangles);
    }
    // Every frame is read first: the camera frames the union of their bounds.
    std::vector<DrapedGarment> frames;
    Eigen::AlignedBox3d bounds;
    bool movingBody = false; ///< some frame has its own obstacles OBJ
    for (const auto& file : files) {
        auto garment = io::readObj(file, limits.maxMeshBytes);
        if (!garment.ok()) {
            std::cerr << inputErrorText(garment.error());
            return EXIT_BAD_INPUT;
        }
        DrapedGarment g;
        g.positions = std::move(garment.value().positions);
        g.triangles = std::move(garment.value().triangles);
        g.panels = std::move(garment.value().groups);
        g.uvs = std::move(garment.value().uvs);
        std::filesystem::path moving = file;
        moving.replace_extension(".obstacles.obj");
        if (std::filesystem::is_regular_file(moving)) {
            auto obstacles = io::readObj(moving, limits.maxMeshBytes);
            if (!obstacles.ok()) {
                std::cerr << inputErrorText(obstacles.error());
                return EXIT_BAD_INPUT;
            }
            g.bodyPositions = std::move(obstacles.value().positions);
            g.bodyTriangles = std::move(obstacles.value().triangles);
            movingBody = true;
        } else {
            g.bodyPositions = staticBody.bodyPositions;
            g.bodyTriangles = staticBody.bodyTriangles;
        }
        for (const sim::MatX3* m : {&g.positions, &g.bodyPositions}) {
            for (Eigen::Index i = 0; i < m->rows(); ++i) {
                bounds.extend(m->row(i).transpose());
            }
        }
        frames.push_back(std::move(g));
    }
    auto drawing = startDrawing();
    if (!drawing.ok()) {
        std::cerr << "error: cannot draw " << outDir.string() << ": " << drawing.error().toString()
                  << "\n";
        return EXIT_RUN_FAILED;
    }
    render::Renderer& renderer = *drawing.value().renderer;
    const render::Camera camera =
        render::frameView(pictures.render.view, bounds,
                          double(pictures.render.width) / double(pictures.render.height));
    // Colours that follow the positions (strain, contact, seams found by position) and a
    // moving body need the whole scene each frame; otherwise only the garment's positions
    // change and go up alone (updatePositions).
    const bool positionsOnly = !movingBody && (pictures.overlay == Overlay::None ||
                                               pictures.overlay == Overlay::Wireframe);
    int updated = 0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
        const DrapedGarment& g = frames[k];
        if (k > 0 && positionsOnly && g.triangles.rows() == frames[0].triangles.rows() &&
            g.triangles == frames[0].triangles && g.panels.size() == frames[0].panels.size() &&
            renderer.updatePositions(0, g.positions).ok()) {
            ++updated;
        } else {
            auto scene = pictureScene(g, pictures);
            if (!scene.ok()) {
                std::cerr << "error: " << files[k].string() << ": " << scene.error().toString()
                          << "\n";
                return EXIT_BAD_INPUT;
            }
            if (auto set = renderer.setScene(scene.value()); !set.ok()) {
                std::cerr << "error: " << files[k].string() << ": " << set.error().toString()
                          << "\n";
                return EXIT_RUN_FAILED;
            }
        }
        auto image = renderer.render(pictures.render, camera);
        if (!image.ok()) {
            std::cerr << "error: cannot draw " << files[k].string() << ": "
                      << image.error().toString() << "\n";
            return EXIT_RUN_FAILED;
        }
        finishPicture(image.value(), pictures);
        if (auto written = io::writePng(outputs[k].path, image.value()); !written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            return EXIT_RUN_FAILED;
        }
    }
    std::fprintf(stderr, "render: %zu frames %dx%d written to %s (%d by position updates)\n",
                 frames.size(), pictures.render.width, pictures.render.height,
                 outDir.string().c_str(), updated);
    return EXIT_OK;
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
    if (!o.framesDir.empty()) {
        if (!o.input.empty()) {
            std::cerr << "error: --frames-dir: draws the frames in it; give no INPUT beside it\n";
            return EXIT_BAD_INPUT;
        }
        return renderFrames(o, pictures, *limits);
    }
    if (o.input.empty()) {
        std::cerr << "error: INPUT: a draped OBJ or a project is required (or --frames-dir)\n";
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
                    "too) or garment project (.atelier)");
    cmd->add_option("--out,-o", options->out,
                    "Picture (PNG); with --view all, OUT-VIEW.png; with --frames-dir, a folder")
        ->required();
    cmd->add_option("--frames-dir", options->framesDir,
                    "Draw every frame_NNNNN.obj of this folder (drape/simulate --frames-dir) to "
                    "OUT/frame_NNNNN.png, one camera for all");
    cmd->add_option("--body", options->body,
                    "With --frames-dir: the body OBJ drawn with every frame (frames with a "
                    "frame_NNNNN.obstacles.obj beside them use that)");
    cmd->add_option("--size", options->size, "Picture size WIDTHxHEIGHT [pixels]")
        ->capture_default_str();
    cmd->add_option("--view", options->view,
                    "front, back, left, right, three-quarter, top, or all (one picture each)")
        ->capture_default_str();
    cmd->add_option("--overlay", options->overlay,
                    "wireframe (triangle edges), strain (against the pattern UVs, with a "
                    "legend), seams (seam lines) or contact (cloth near or inside the body)");
    cmd->add_flag("--ambient-occlusion", options->ambientOcclusion,
                  "Darken creases, armpits and cloth close to the body (computed per vertex on "
                  "the CPU before drawing)");
    cmd->add_flag("--no-pins", options->noPins,
                  "Leave out the pinheads drawn where a project's pins hold the cloth");
    cmd->add_option("--weave", options->weaveMm,
                    "A plain weave drawn through the pattern UVs, threads this far apart [mm] "
                    "(warp along the UVs' v axis)")
        ->check(CLI::Range(0.05, 1000.0));
    cmd->add_option("--strain-range", options->strainRangePct,
                    "--overlay strain: the colours saturate at +-this [%]")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    cmd->add_option("--contact-thickness", options->contactThicknessMm,
                    "--overlay contact: cloth closer to the body than this is in contact [mm] "
                    "(default: a project's cloth + body thickness, else 4)")
        ->check(CLI::PositiveNumber);
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
