/// `atelier-cli render-batch LIST|FOLDER --out DIR`: pictures of many draped garments (OBJs
/// from `drape --out`) or projects, several views each, and a contact sheet of them all, drawn
/// with one headless context and renderer (made once: the bulk of a single picture's time).
/// A failed item is reported and shown in its cells; the others go on.

#include "app/cli/commands.h"
#include "app/cli/drape.h"
#include "app/cli/limits_option.h"
#include "app/cli/picture.h"

#include "ui/render/contact_sheet.h"

#include "io/atomic_file.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace atelier::app {

namespace {

constexpr long MAX_SHEET_SIDE = 16384; ///< of the contact sheet (1 GiB of RGBA at most) [pixels]

struct RenderBatchOptions {
    std::string input;
    std::string out;
    std::string views = "front,back,left,three-quarter";
    std::string size = "512x512";
    int sheetColumns = 0; ///< 0 = one row per item (as many columns as views)
    int sheetCell = 256;  ///< longer side of a sheet cell's picture [pixels]
    std::string overlay;
    std::string background = "white";
    double strainRangePct = 10;
    double weaveMm = 0;            ///< --weave [mm]
    bool ambientOcclusion = false; ///< --ambient-occlusion
    bool noPins = false;           ///< --no-pins
    double contactThicknessMm = -1;
    int threads = 0;
    double timeLimit = -1;
    double particleDistanceMm = -1;
    std::vector<std::string> limits;
};

/// One input: a draped OBJ or a project.
struct Item {
    std::string name; ///< the file's stem, made unique ("-2", "-3", ...)
    std::filesystem::path path;
};

bool isItemFile(const std::filesystem::path& path) {
    const std::string name = path.filename().string();
    if (name.ends_with(".body.obj") || name.ends_with(".obstacles.obj")) {
        return false;
    }
    return path.extension() == ".obj" || path.extension() == ".atelier";
}

/// The items of a folder (its draped OBJs and projects, by name) or of a list file (one path a
/// line, relative to the list's folder; blank lines and `#` comments skipped). The error, or
/// an empty list, is bad input.
Result<std::vector<Item>> gatherItems(const std::filesystem::path& input,
                                      const io::Limits& limits) {
    std::vector<std::filesystem::path> paths;
    if (std::filesystem::is_directory(input)) {
        std::error_code ec;
        for (const auto& entry : std::filesystem::directory_iterator(input, ec)) {
            if (entry.is_regular_file() && isItemFile(entry.path())) {
                paths.push_back(entry.path());
            }
        }
        if (ec) {
            return Error{input.string(), "", ec.message()};
        }
        std::sort(paths.begin(), paths.end());
    } else {
        auto text = io::readFile(input, limits.maxJsonBytes);
        if (!text.ok()) {
            return text.error();
        }
        std::istringstream lines(text.value());
        std::string line;
        while (std::getline(lines, line)) {
            const auto first = line.find_first_not_of(" \t\r");
            if (first == std::string::npos || line[first] == '#') {
                continue;
            }
            const auto last = line.find_last_not_of(" \t\r");
            const std::filesystem::path path = line.substr(first, last - first + 1);
            paths.push_back(path.is_absolute() ? path : input.parent_path() / path);
        }
    }
    if (paths.empty()) {
        return Error{input.string(), "", "no draped OBJ or project to draw"};
    }
    std::vector<Item> items;
    std::map<std::string, int> seen;
    for (const auto& path : paths) {
        std::string name = path.stem().string();
        if (const int n = ++seen[name]; n > 1) {
            name += "-" + std::to_string(n);
        }
        items.push_back({name, path});
    }
    return items;
}

/// The views of `--views` (comma-separated names), or the message of what is wrong.
std::optional<std::string> parseViews(const std::string& text, std::vector<render::View>& out) {
    std::stringstream in(text);
    std::string name;
    while (std::getline(in, name, ',')) {
        const auto view = render::viewFromName(name);
        if (!view) {
            return "--views: '" + name +
                   "' is not one of front, back, left, right, three-quarter, top";
        }
        out.push_back(*view);
    }
    if (out.empty()) {
        return "--views: no view given";
    }
    return std::nullopt;
}

std::optional<std::string> parseOptions(const RenderBatchOptions& o, PictureOptions& pictures,
                                        std::vector<render::View>& views) {
    int width = 0;
    int height = 0;
    char rest = 0;
    if (std::sscanf(o.size.c_str(), "%dx%d%c", &width, &height, &rest) != 2 || width < 1 ||
        height < 1 || width > MAX_SIDE || height > MAX_SIDE) {
        return "--size: '" + o.size + "' is not WIDTHxHEIGHT with sides in [1, " +
               std::to_string(MAX_SIDE) + "]";
    }
    pictures.render.width = width;
    pictures.render.height = height;
    if (auto problem = parseViews(o.views, views)) {
        return problem;
    }
    const auto overlay = overlayFromName(o.overlay);
    if (!overlay) {
        return "--overlay: '" + o.overlay + "' is not " + OVERLAY_NAMES;
    }
    pictures.overlay = *overlay;
    pictures.render.wireframe = *overlay == Overlay::Wireframe;
    pictures.strainRange = o.strainRangePct / 100;
    pictures.weavePeriodMm = o.weaveMm;
    pictures.ambientOcclusion = o.ambientOcclusion;
    pictures.render.pins = !o.noPins;
    if (o.contactThicknessMm > 0) {
        pictures.contactThickness = o.contactThicknessMm / 1000;
    }
    if (!render::parseColour(o.background, pictures.render.background)) {
        return "--background: '" + o.background +
               "' is not #RRGGBB, #RRGGBBAA, white, black, grey or transparent";
    }
    return std::nullopt;
}

std::filesystem::path picturePath(const std::filesystem::path& dir, const Item& item,
                                  render::View view) {
    return dir / (item.name + "-" + std::string(render::viewName(view)) + ".png");
}

/// The garment of an item: the OBJ read, or the project draped. The message on failure.
std::optional<DrapedGarment> loadItem(const Item& item, const RenderBatchOptions& o,
                                      const io::Limits& limits, PictureOptions& pictures,
                                      std::string& problem) {
    if (item.path.extension() != ".atelier") {
        return readDrapedObj(item.path, limits, true, &problem);
    }
    DrapeOptions drape;
    drape.project = item.path.string();
    drape.threads = o.threads;
    drape.timeLimit = o.timeLimit;
    drape.particleDistanceMm = o.particleDistanceMm;
    drape.limits = o.limits;
    std::optional<DrapedGarment> garment;
    const int code = runDrape(drape, [&](const patterns::DrapeSession& session, int c) {
        garment = sessionGarment(session);
        if (o.contactThicknessMm < 0) {
            const patterns::DrapeSettings& settings = session.project().drape;
            pictures.contactThickness = settings.clothThickness + settings.bodyThickness;
        }
        return c;
    });
    if (code != EXIT_OK) {
        problem = item.path.string() + ": the drape failed (exit code " + std::to_string(code) +
                  "; its messages are above)";
        return std::nullopt;
    }
    return garment;
}

int runRenderBatch(const RenderBatchOptions& o) {
    const auto start = std::chrono::steady_clock::now();
    PictureOptions pictures;
    std::vector<render::View> views;
    if (auto problem = parseOptions(o, pictures, views)) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    const std::optional<io::Limits> limits = limitsOrReport(o.limits);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    auto gathered = gatherItems(o.input, *limits);
    if (!gathered.ok()) {
        std::cerr << inputErrorText(gathered.error());
        return EXIT_BAD_INPUT;
    }
    const std::vector<Item>& items = gathered.value();
    const std::filesystem::path dir = o.out;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) {
        std::cerr << "error: --out: " << dir.string() << ": "
                  << (ec ? ec.message() : "not a folder") << "\n";
        return EXIT_BAD_INPUT;
    }
    const std::filesystem::path sheetPath = dir / "contact-sheet.png";
    std::vector<NamedPath> inputs = {{"LIST", o.input}};
    std::vector<NamedPath> outputs = {{"--out (contact sheet)", sheetPath}};
    for (const Item& item : items) {
        inputs.push_back({"item " + item.name, item.path});
        for (const render::View view : views) {
            outputs.push_back({"--out (" + item.name + ")", picturePath(dir, item, view)});
        }
    }
    if (auto problem = checkOutputs(inputs, outputs)) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }

    const int cellSide = std::max(o.sheetCell, 16);
    const double cellScale =
        std::min(1.0, double(cellSide) / std::max(pictures.render.width, pictures.render.height));
    const int cellWidth = std::max(1, int(pictures.render.width * cellScale + 0.5));
    const int cellHeight = std::max(1, int(pictures.render.height * cellScale + 0.5));
    render::SheetOptions sheet;
    const auto cellCount = static_cast<long>(items.size() * views.size());
    sheet.columns = static_cast<int>(
        std::min<long>(o.sheetColumns > 0 ? o.sheetColumns : long(views.size()), cellCount));
    sheet.cellWidth = cellWidth;
    sheet.cellHeight = cellHeight;
    sheet.labelLines = 2; // the item's name, then the view
    if (pictures.render.background.a >= 1.0f) {
        sheet.background = pictures.render.background;
    }
    // The sheet is one picture in memory and in a PNG: refuse one past MAX_SHEET_SIDE.
    const long rows = (cellCount + sheet.columns - 1) / sheet.columns;
    const long sheetWidth = sheet.gap + long(sheet.columns) * (cellWidth + sheet.gap);
    const long sheetHeight =
        sheet.gap + rows * (cellHeight + render::sheetLabelHeight(sheet) + sheet.gap);
    if (sheetWidth > MAX_SHEET_SIDE || sheetHeight > MAX_SHEET_SIDE) {
        std::cerr << "error: the contact sheet would be " << sheetWidth << "x" << sheetHeight
                  << " pixels, more than " << MAX_SHEET_SIDE
                  << " a side: fewer items, a smaller --sheet-cell or other --sheet-columns\n";
        return EXIT_BAD_INPUT;
    }

    auto drawing = startDrawing();
    if (!drawing.ok()) {
        std::cerr << "error: cannot draw " << dir.string() << ": " << drawing.error().toString()
                  << "\n";
        return EXIT_RUN_FAILED;
    }
    render::Renderer& renderer = *drawing.value().renderer;

    std::vector<render::SheetCell> cells;
    int failed = 0;
    for (const Item& item : items) {
        std::string problem;
        PictureOptions itemPictures = pictures;
        std::optional<DrapedGarment> garment = loadItem(item, o, *limits, itemPictures, problem);
        std::vector<io::RgbaImage> images;
        if (garment) {
            auto scene = pictureScene(*garment, itemPictures);
            auto set = scene.ok() ? renderer.setScene(scene.value()) : Result<void>(scene.error());
            if (!set.ok()) {
                problem = item.path.string() + ": " + set.error().toString();
            }
            for (std::size_t v = 0; problem.empty() && v < views.size(); ++v) {
                render::RenderOptions one = itemPictures.render;
                one.view = views[v];
                auto image = renderer.render(one);
                if (!image.ok()) {
                    problem = item.path.string() + ": " + image.error().toString();
                    break;
                }
                finishPicture(image.value(), itemPictures);
                if (auto written = io::writePng(picturePath(dir, item, views[v]), image.value());
                    !written.ok()) {
                    problem = written.error().toString();
                    break;
                }
                images.push_back(cellScale < 1.0
                                     ? render::resizeImage(image.value(), cellWidth, cellHeight)
                                     : std::move(image).value());
            }
        }
        if (!problem.empty()) {
            ++failed;
            std::cerr << "error: " << problem << "\n";
        }
        for (std::size_t v = 0; v < views.size(); ++v) {
            render::SheetCell cell;
            cell.label = item.name + "\n" + std::string(render::viewName(views[v]));
            if (problem.empty()) {
                cell.picture = std::move(images[v]);
            } else {
                cell.message = problem;
            }
            cells.push_back(std::move(cell));
        }
    }

    if (auto written = io::writePng(sheetPath, render::contactSheet(cells, sheet)); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    std::fprintf(stderr,
                 "render-batch: %zu items x %zu views %dx%d and %s in %.2f s (%d failed; %s)\n",
                 items.size(), views.size(), pictures.render.width, pictures.render.height,
                 sheetPath.filename().string().c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                 failed, renderer.description().c_str());
    return failed > 0 ? EXIT_RUN_FAILED : EXIT_OK;
}

} // namespace

void addRenderBatchCommand(CLI::App& app) {
    auto options = std::make_shared<RenderBatchOptions>();
    CLI::App* cmd = app.add_subcommand(
        "render-batch",
        "Draw pictures of many draped garments or projects and a contact sheet of them all");
    cmd->add_option("input", options->input,
                    "A folder of draped OBJs (drape --out; NAME.body.obj beside each is drawn "
                    "too) and projects, or a text file listing them (one a line, # comments)")
        ->required();
    cmd->add_option("--out,-o", options->out,
                    "Folder: NAME-VIEW.png per item and view, and contact-sheet.png")
        ->required();
    cmd->add_option("--views", options->views,
                    "Comma-separated: front, back, left, right, three-quarter, top")
        ->capture_default_str();
    cmd->add_option("--size", options->size, "Picture size WIDTHxHEIGHT [pixels]")
        ->capture_default_str();
    cmd->add_option("--sheet-columns", options->sheetColumns,
                    "Contact sheet cells per row (default: the number of views)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--sheet-cell", options->sheetCell,
                    "Longer side of a contact sheet cell [pixels]; larger pictures are scaled "
                    "down into it")
        ->check(CLI::Range(16, MAX_SIDE))
        ->capture_default_str();
    cmd->add_option("--overlay", options->overlay,
                    "wireframe, strain, seams or contact (as for render)");
    cmd->add_flag("--no-pins", options->noPins,
                  "Leave out the pinheads drawn where a project's pins hold the cloth");
    cmd->add_flag("--ambient-occlusion", options->ambientOcclusion,
                  "Darken creases, armpits and cloth close to the body (computed per vertex on "
                  "the CPU before drawing)");
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
                    "#RRGGBB, #RRGGBBAA, white, black, grey or transparent (the sheet stays "
                    "opaque: white under a transparent background)")
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
        const int code = runRenderBatch(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
