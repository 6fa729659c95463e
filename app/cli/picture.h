#pragma once
/// Pictures from the command line: the scene of a draped garment (one colour per panel, or an
/// overlay's colours and lines) and its body, and PNG files of one view or of every view, drawn
/// headless (EGL).

#include "app/cli/preflight.h"

#include "ui/render/headless_context.h"
#include "ui/render/renderer.h"

#include "io/limits.h"
#include "io/obj.h"

#include "patterns/drape_session.h"

#include "sim/scene.h"

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::app {

/// What `--overlay` draws over the garment (docs/rendering.md).
enum class Overlay {
    None,
    Wireframe, ///< triangle edges
    Strain,    ///< per-triangle principal strain against the pattern UVs, with a legend
    Seams,     ///< seam lines
    Contact,   ///< garment vertices within the contact thickness of the body, or inside it
};

/// The overlay of a `--overlay` value ("wireframe", "strain", "seams", "contact"; "" = None).
std::optional<Overlay> overlayFromName(std::string_view name);
inline constexpr const char* OVERLAY_NAMES = "wireframe, strain, seams or contact";

/// A draped garment and its body, with what the overlays need.
struct DrapedGarment {
    sim::MatX3 positions;             ///< (|V|×3) [m]
    sim::MatX3i triangles;            ///< (|F|×3)
    std::vector<io::ObjGroup> panels; ///< one group per panel; empty = one panel
    sim::MatX2 uvs;    ///< (|V|×2) pattern coordinates [m] (the strain's rest shape), or empty
    sim::MatX2i seams; ///< (|E|×2) seam edges known from a project; empty = found by position
    sim::MatX3 bodyPositions;  ///< (|B|×3) [m], or empty
    sim::MatX3i bodyTriangles; ///< or empty
    sim::MatX3 pins;           ///< (|P|×3) pinned vertices [m], marked with pinheads; or empty
};

/// The garment of a drape session as it is now (seams from its sewing), and its body.
DrapedGarment sessionGarment(const patterns::DrapeSession& session);

/// Reads a draped OBJ (`drape --out`) and, when it exists, the body beside it
/// (drapedBodyPath). On an error prints it on stderr and returns nullopt.
std::optional<DrapedGarment> readDrapedObj(const std::filesystem::path& path,
                                           const io::Limits& limits, bool quiet = false,
                                           std::string* error = nullptr);

/// What to draw and where.
/// Largest picture side [pixels] of `render` and `render-batch`: 4096² with 4× MSAA already
/// takes 512 MiB of buffers.
inline constexpr int MAX_SIDE = 4096;

struct PictureOptions {
    render::RenderOptions render;
    bool allViews = false; ///< one picture per view, OUT-VIEW.png
    Overlay overlay = Overlay::None;
    double strainRange = 0.10;       ///< the strain colours saturate at ±this [-]
    double contactThickness = 0.004; ///< closer to the body than this is in contact [m]
    double weavePeriodMm = 0;        ///< a plain weave through the UVs, threads this far apart [mm]
    bool ambientOcclusion = false;   ///< darken creases and cloth near the body
    /// Cloth resting on the body sits in a layer this fraction of the thickness above it
    /// (the engine's contact springs act there: sim::ContactSolveOptions::margin) [-].
    double contactLayer = sim::ContactSolveOptions{}.margin;
};

/// The scene of `garment` with the options' overlay: panel colours, or strain colours (an
/// error when the garment has no UVs), seam lines, contact colours.
Result<render::Scene> pictureScene(const DrapedGarment& garment, const PictureOptions& options);

/// Draws what goes on top of a finished picture (the strain legend).
void finishPicture(io::RgbaImage& image, const PictureOptions& options);

/// A headless context and its renderer, made once and reused for many pictures.
struct Drawing {
    std::unique_ptr<render::HeadlessContext> context;
    std::unique_ptr<render::Renderer> renderer;
};
/// The drawing context, or the error (a missing EGL driver names the packages to install).
Result<Drawing> startDrawing();

/// The files writePictures writes for `out`: `out` itself, or with allViews
/// `STEM-front.png`, `STEM-back.png`, ... beside it (each named for checkOutputs).
std::vector<NamedPath> picturePaths(const std::string& out, bool allViews);

/// Draws `garment` headless and writes the pictures (atomically). Prints the error on stderr
/// (a missing EGL or OpenGL driver says what to install) and returns `code`, or
/// EXIT_RUN_FAILED when a picture could not be made or written (EXIT_BAD_INPUT when the
/// overlay cannot be drawn for this garment).
int writePictures(const DrapedGarment& garment, const std::string& out,
                  const PictureOptions& options, int code);

/// The drape's thumbnail: a 256×256 three-quarter picture on white.
int writeThumbnail(const DrapedGarment& garment, const std::string& out, int code);

} // namespace atelier::app
