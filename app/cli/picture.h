#pragma once
/// Pictures from the command line: the scene of a draped garment (one colour per panel) and
/// its body, and PNG files of one view or of every view, drawn headless (EGL).

#include "app/cli/preflight.h"

#include "ui/render/renderer.h"

#include "io/obj.h"

#include "patterns/drape_session.h"

#include <filesystem>
#include <string>
#include <vector>

namespace atelier::app {

/// The scene of a garment (each group a panel, in panelColour order; no groups = one panel)
/// and, when `bodyTriangles` has rows, its body.
render::Scene garmentScene(const sim::MatX3& positions, const sim::MatX3i& triangles,
                           const std::vector<io::ObjGroup>& panels,
                           const sim::MatX3& bodyPositions = {},
                           const sim::MatX3i& bodyTriangles = {});

/// The scene of a drape session's garment as it is now, and its body.
render::Scene sessionScene(const patterns::DrapeSession& session);

/// What to draw and where.
struct PictureOptions {
    render::RenderOptions render;
    bool allViews = false; ///< one picture per view, OUT-VIEW.png
};

/// The files writePictures writes for `out`: `out` itself, or with allViews
/// `STEM-front.png`, `STEM-back.png`, ... beside it (each named for checkOutputs).
std::vector<NamedPath> picturePaths(const std::string& out, bool allViews);

/// Draws `scene` headless and writes the pictures (atomically). Prints the error on stderr
/// (a missing EGL or OpenGL driver says what to install) and returns `code`, or
/// EXIT_RUN_FAILED when a picture could not be made or written.
int writePictures(const render::Scene& scene, const std::string& out, const PictureOptions& options,
                  int code);

/// The drape's thumbnail: a 256×256 three-quarter picture on white.
int writeThumbnail(const render::Scene& scene, const std::string& out, int code);

} // namespace atelier::app
