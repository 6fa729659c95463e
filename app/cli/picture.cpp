#include "app/cli/picture.h"

#include "app/cli/commands.h"
#include "app/cli/drape.h"
#include "app/cli/limits_option.h"

#include "ui/render/ambient_occlusion.h"
#include "ui/render/overlays.h"

#include "sim/constraints/kinematic.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>

namespace atelier::app {

namespace {

/// The scene of a garment (each group a panel, in panelColour order; no groups = one panel)
/// and, when it has one, its body.
render::Scene garmentScene(const DrapedGarment& g) {
    render::Scene scene;
    render::DrawMesh garment;
    garment.kind = render::MeshKind::Garment;
    garment.positions = g.positions;
    garment.triangles = g.triangles;
    garment.colour = render::panelColour(0);
    if (g.panels.size() > 1) {
        garment.triangleColours.assign(static_cast<std::size_t>(g.triangles.rows()),
                                       render::panelColour(0));
        for (std::size_t p = 0; p < g.panels.size(); ++p) {
            const io::ObjGroup& group = g.panels[p];
            for (int t = group.firstTriangle; t < group.firstTriangle + group.triangleCount; ++t) {
                garment.triangleColours[static_cast<std::size_t>(t)] =
                    render::panelColour(static_cast<int>(p));
            }
        }
    }
    scene.meshes.push_back(std::move(garment));
    scene.pins = g.pins;
    if (g.bodyTriangles.rows() > 0) {
        render::DrawMesh body;
        body.kind = render::MeshKind::Body;
        body.positions = g.bodyPositions;
        body.triangles = g.bodyTriangles;
        body.colour = render::bodyColour();
        scene.meshes.push_back(std::move(body));
    }
    return scene;
}

/// Each triangle's panel (|F|).
std::vector<int> trianglePanels(const DrapedGarment& g) {
    std::vector<int> panel(static_cast<std::size_t>(g.triangles.rows()), 0);
    for (std::size_t p = 0; p < g.panels.size(); ++p) {
        const io::ObjGroup& group = g.panels[p];
        for (int t = group.firstTriangle; t < group.firstTriangle + group.triangleCount; ++t) {
            panel[static_cast<std::size_t>(t)] = static_cast<int>(p);
        }
    }
    return panel;
}

/// Median edge length of the garment [m] (0 without triangles).
double medianEdge(const DrapedGarment& g) {
    std::vector<double> lengths;
    lengths.reserve(static_cast<std::size_t>(g.triangles.rows()));
    for (Eigen::Index t = 0; t < g.triangles.rows(); ++t) {
        lengths.push_back(
            (g.positions.row(g.triangles(t, 0)) - g.positions.row(g.triangles(t, 1))).norm());
    }
    if (lengths.empty()) {
        return 0;
    }
    std::nth_element(lengths.begin(), lengths.begin() + std::ssize(lengths) / 2, lengths.end());
    return lengths[lengths.size() / 2];
}

/// Red for cloth inside the body, amber for cloth closer than the contact thickness, green for
/// cloth resting in the contact layer above it.
constexpr render::Colour NEAR_COLOUR{0.95f, 0.70f, 0.20f, 1.0f};
constexpr render::Colour RESTING_COLOUR{0.35f, 0.72f, 0.45f, 1.0f};
constexpr render::Colour INSIDE_COLOUR{0.85f, 0.05f, 0.10f, 1.0f};
constexpr render::Colour CLEAR_COLOUR{0.80f, 0.82f, 0.85f, 1.0f};

} // namespace

std::optional<Overlay> overlayFromName(std::string_view name) {
    if (name.empty()) {
        return Overlay::None;
    }
    for (const auto& [text, overlay] :
         {std::pair{"wireframe", Overlay::Wireframe}, std::pair{"strain", Overlay::Strain},
          std::pair{"seams", Overlay::Seams}, std::pair{"contact", Overlay::Contact}}) {
        if (name == text) {
            return overlay;
        }
    }
    return std::nullopt;
}

DrapedGarment sessionGarment(const patterns::DrapeSession& session) {
    const GarmentObj obj =
        garmentObj(session.project().garment, session.mesh(), session.assembled());
    DrapedGarment g;
    g.positions = session.positions();
    g.triangles = obj.triangles;
    g.panels = obj.options.groups;
    g.uvs = obj.options.uvs;
    g.bodyPositions = session.body().vertices;
    g.bodyTriangles = session.body().triangles;
    // Pins still holding (a released pin no longer marks the cloth).
    const patterns::AssembledGarment& assembled = session.assembled();
    const double time = session.simulation() != nullptr ? session.simulation()->time() : 0.0;
    std::vector<int> held;
    for (const patterns::HeldPin& pin : assembled.pins) {
        if (sim::driveActive(pin.hold, time) && pin.hold.vertex < g.positions.rows()) {
            held.push_back(pin.hold.vertex);
        }
    }
    g.pins.resize(static_cast<Eigen::Index>(held.size()), 3);
    for (std::size_t k = 0; k < held.size(); ++k) {
        g.pins.row(static_cast<Eigen::Index>(k)) = g.positions.row(held[k]);
    }
    // Seam edges: boundary edges of a panel whose two ends are sewn by one seam (or dart).
    const patterns::GarmentMesh& mesh = session.mesh();
    const std::vector<int>& offsets = session.assembled().panelOffsets;
    std::map<int, std::set<int>> seamsAt; // global vertex → seams sewing it
    for (std::size_t k = 0; k < mesh.seamPairs.size(); ++k) {
        for (const patterns::VertexRef& v : mesh.seamPairs[k]) {
            seamsAt[offsets[static_cast<std::size_t>(v.panel)] + v.vertex].insert(
                mesh.seamOfPair[k]);
        }
    }
    std::map<std::pair<int, int>, int> uses;
    for (Eigen::Index t = 0; t < g.triangles.rows(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const int a = g.triangles(t, k);
            const int b = g.triangles(t, (k + 1) % 3);
            ++uses[{std::min(a, b), std::max(a, b)}];
        }
    }
    std::vector<std::pair<int, int>> seams;
    for (const auto& [edge, count] : uses) {
        const auto a = seamsAt.find(edge.first);
        const auto b = seamsAt.find(edge.second);
        if (count != 1 || a == seamsAt.end() || b == seamsAt.end()) {
            continue;
        }
        if (std::any_of(a->second.begin(), a->second.end(),
                        [&](int s) { return b->second.count(s) > 0; })) {
            seams.push_back(edge);
        }
    }
    g.seams.resize(static_cast<Eigen::Index>(seams.size()), 2);
    for (std::size_t k = 0; k < seams.size(); ++k) {
        g.seams.row(static_cast<Eigen::Index>(k)) << seams[k].first, seams[k].second;
    }
    return g;
}

std::optional<DrapedGarment> readDrapedObj(const std::filesystem::path& path,
                                           const io::Limits& limits, bool quiet,
                                           std::string* error) {
    const auto fail = [&](const Error& e) -> std::optional<DrapedGarment> {
        if (!quiet) {
            std::cerr << inputErrorText(e);
        }
        if (error != nullptr) {
            *error = e.toString();
        }
        return std::nullopt;
    };
    auto garment = io::readObj(path, limits.maxMeshBytes);
    if (!garment.ok()) {
        return fail(garment.error());
    }
    DrapedGarment g;
    io::ObjMesh& obj = garment.value();
    g.positions = std::move(obj.positions);
    g.triangles = std::move(obj.triangles);
    g.panels = std::move(obj.groups);
    g.uvs = std::move(obj.uvs);
    const std::filesystem::path bodyFile = drapedBodyPath(path);
    if (std::filesystem::is_regular_file(bodyFile)) {
        auto body = io::readObj(bodyFile, limits.maxMeshBytes);
        if (!body.ok()) {
            return fail(body.error());
        }
        g.bodyPositions = std::move(body.value().positions);
        g.bodyTriangles = std::move(body.value().triangles);
    }
    return g;
}

Result<render::Scene> pictureScene(const DrapedGarment& garment, const PictureOptions& options) {
    render::Scene scene = garmentScene(garment);
    render::DrawMesh& cloth = scene.meshes.front();
    if (options.weavePeriodMm > 0) {
        if (garment.uvs.rows() != garment.positions.rows()) {
            return Error{"", "", "--weave: the garment has no pattern UVs (vt) to draw it through"};
        }
        cloth.uvs = garment.uvs;
        cloth.weavePeriodMm = options.weavePeriodMm;
    }
    switch (options.overlay) {
    case Overlay::None:
    case Overlay::Wireframe:
        break;
    case Overlay::Strain: {
        if (garment.uvs.rows() != garment.positions.rows()) {
            return Error{"", "",
                         "--overlay strain: the garment has no pattern UVs (vt) to "
                         "measure its strain against"};
        }
        cloth.triangleColours = render::strainColours(
            render::triangleStrain(garment.positions, garment.triangles, garment.uvs),
            options.strainRange);
        break;
    }
    case Overlay::Seams: {
        render::DrawLines lines;
        lines.positions = garment.positions;
        lines.segments =
            garment.seams.rows() > 0
                ? garment.seams
                : render::seamEdgesByPosition(garment.positions, garment.triangles,
                                              trianglePanels(garment), 0.25 * medianEdge(garment));
        std::fprintf(stderr, "render: %ld seam edges (%s)\n",
                     static_cast<long>(lines.segments.rows()),
                     garment.seams.rows() > 0 ? "sewn" : "found by position");
        lines.colour = {0.10f, 0.10f, 0.12f, 1.0f};
        lines.widthPx = std::max(2.0f, static_cast<float>(options.render.height) / 256.0f);
        scene.lines.push_back(std::move(lines));
        break;
    }
    case Overlay::Contact: {
        if (garment.bodyTriangles.rows() == 0) {
            return Error{"", "", "--overlay contact: there is no body to measure against"};
        }
        // Cloth deeper inside than 10 cm reads as far (the search stops there); no drape that
        // came to rest is that deep.
        const sim::VecX d =
            render::bodyDistances(garment.positions, garment.bodyPositions, garment.bodyTriangles,
                                  std::max(0.1, options.contactThickness));
        cloth.triangleColours.assign(static_cast<std::size_t>(garment.triangles.rows()),
                                     CLEAR_COLOUR);
        for (Eigen::Index t = 0; t < garment.triangles.rows(); ++t) {
            double nearest = d[garment.triangles(t, 0)];
            for (int k = 1; k < 3; ++k) {
                nearest = std::min(nearest, d[garment.triangles(t, k)]);
            }
            auto& c = cloth.triangleColours[static_cast<std::size_t>(t)];
            if (nearest < 0) {
                c = INSIDE_COLOUR;
            } else if (nearest < options.contactThickness) {
                c = NEAR_COLOUR;
            } else if (nearest < (1 + options.contactLayer) * options.contactThickness) {
                c = RESTING_COLOUR;
            }
        }
        break;
    }
    }
    if (options.ambientOcclusion) {
        std::vector<std::vector<float>> visibility = render::ambientOcclusion(scene);
        for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
            scene.meshes[m].ambientOcclusion = std::move(visibility[m]);
        }
    }
    return scene;
}

void finishPicture(io::RgbaImage& image, const PictureOptions& options) {
    if (options.overlay == Overlay::Strain) {
        render::drawStrainLegend(image, options.strainRange);
    }
}

Result<Drawing> startDrawing() {
    auto context = render::HeadlessContext::create();
    if (!context.ok()) {
        return context.error();
    }
    auto renderer = render::Renderer::create();
    if (!renderer.ok()) {
        return renderer.error();
    }
    return Drawing{std::move(context).value(), std::move(renderer).value()};
}

namespace {

std::filesystem::path viewPath(const std::filesystem::path& out, render::View view) {
    std::filesystem::path path = out;
    const std::string extension = path.has_extension() ? path.extension().string() : ".png";
    return path.replace_filename(path.stem().string() + "-" + std::string(render::viewName(view)) +
                                 extension);
}

} // namespace

std::vector<NamedPath> picturePaths(const std::string& out, bool allViews) {
    if (!allViews) {
        return {{"--out", out}};
    }
    std::vector<NamedPath> paths;
    for (const render::View view : render::ALL_VIEWS) {
        paths.push_back(
            {"--out (view " + std::string(render::viewName(view)) + ")", viewPath(out, view)});
    }
    return paths;
}

int writePictures(const DrapedGarment& garment, const std::string& out,
                  const PictureOptions& options, int code) {
    const auto start = std::chrono::steady_clock::now();
    auto scene = pictureScene(garment, options);
    if (!scene.ok()) {
        std::cerr << "error: " << scene.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }
    auto drawing = startDrawing();
    if (!drawing.ok()) {
        std::cerr << "error: cannot draw " << out << ": " << drawing.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    render::Renderer& renderer = *drawing.value().renderer;
    if (auto set = renderer.setScene(scene.value()); !set.ok()) {
        std::cerr << "error: cannot draw " << out << ": " << set.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    std::vector<render::View> views = {options.render.view};
    if (options.allViews) {
        views.assign(render::ALL_VIEWS.begin(), render::ALL_VIEWS.end());
    }
    for (const render::View view : views) {
        render::RenderOptions one = options.render;
        one.view = view;
        const std::filesystem::path path =
            options.allViews ? viewPath(out, view) : std::filesystem::path(out);
        auto image = renderer.render(one);
        if (!image.ok()) {
            std::cerr << "error: cannot draw " << path.string() << ": " << image.error().toString()
                      << "\n";
            return EXIT_RUN_FAILED;
        }
        finishPicture(image.value(), options);
        if (auto written = io::writePng(path, image.value()); !written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            return EXIT_RUN_FAILED;
        }
    }
    std::fprintf(stderr, "render: %zu picture%s %dx%d in %.2f s (%s)\n", views.size(),
                 views.size() == 1 ? "" : "s", options.render.width, options.render.height,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                 renderer.description().c_str());
    return code;
}

int writeThumbnail(const DrapedGarment& garment, const std::string& out, int code) {
    PictureOptions options;
    options.render.width = 256;
    options.render.height = 256;
    options.render.view = render::View::ThreeQuarter;
    return writePictures(garment, out, options, code);
}

} // namespace atelier::app
