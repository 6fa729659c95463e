#include "app/cli/picture.h"

#include "app/cli/commands.h"
#include "app/cli/drape.h"

#include "ui/render/headless_context.h"

#include <chrono>
#include <cstdio>
#include <iostream>

namespace atelier::app {

render::Scene garmentScene(const sim::MatX3& positions, const sim::MatX3i& triangles,
                           const std::vector<io::ObjGroup>& panels, const sim::MatX3& bodyPositions,
                           const sim::MatX3i& bodyTriangles) {
    render::Scene scene;
    render::DrawMesh garment;
    garment.kind = render::MeshKind::Garment;
    garment.positions = positions;
    garment.triangles = triangles;
    garment.colour = render::panelColour(0);
    if (panels.size() > 1) {
        garment.triangleColours.assign(static_cast<std::size_t>(triangles.rows()),
                                       render::panelColour(0));
        for (std::size_t p = 0; p < panels.size(); ++p) {
            const io::ObjGroup& g = panels[p];
            for (int t = g.firstTriangle; t < g.firstTriangle + g.triangleCount; ++t) {
                garment.triangleColours[static_cast<std::size_t>(t)] =
                    render::panelColour(static_cast<int>(p));
            }
        }
    }
    scene.meshes.push_back(std::move(garment));
    if (bodyTriangles.rows() > 0) {
        render::DrawMesh body;
        body.kind = render::MeshKind::Body;
        body.positions = bodyPositions;
        body.triangles = bodyTriangles;
        body.colour = render::bodyColour();
        scene.meshes.push_back(std::move(body));
    }
    return scene;
}

render::Scene sessionScene(const patterns::DrapeSession& session) {
    const GarmentObj obj =
        garmentObj(session.project().garment, session.mesh(), session.assembled());
    return garmentScene(session.positions(), obj.triangles, obj.options.groups,
                        session.body().vertices, session.body().triangles);
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

int writePictures(const render::Scene& scene, const std::string& out, const PictureOptions& options,
                  int code) {
    const auto start = std::chrono::steady_clock::now();
    auto context = render::HeadlessContext::create();
    if (!context.ok()) {
        std::cerr << "error: cannot draw " << out << ": " << context.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    auto renderer = render::Renderer::create();
    if (!renderer.ok()) {
        std::cerr << "error: cannot draw " << out << ": " << renderer.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    if (auto set = renderer.value()->setScene(scene); !set.ok()) {
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
        auto image = renderer.value()->render(one);
        if (!image.ok()) {
            std::cerr << "error: cannot draw " << path.string() << ": " << image.error().toString()
                      << "\n";
            return EXIT_RUN_FAILED;
        }
        if (auto written = io::writePng(path, image.value()); !written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            return EXIT_RUN_FAILED;
        }
    }
    std::fprintf(stderr, "render: %zu picture%s %dx%d in %.2f s (%s)\n", views.size(),
                 views.size() == 1 ? "" : "s", options.render.width, options.render.height,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                 renderer.value()->description().c_str());
    return code;
}

int writeThumbnail(const render::Scene& scene, const std::string& out, int code) {
    PictureOptions options;
    options.render.width = 256;
    options.render.height = 256;
    options.render.view = render::View::ThreeQuarter;
    return writePictures(scene, out, options, code);
}

} // namespace atelier::app
