#pragma once
/// What the renderer draws: triangle meshes as arrays (a garment, a body), with their colours.
/// No GL here: a scene is plain data, built by the app layer from meshes or a drape session.

#include "sim/core/types.h"

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace atelier::render {

/// A colour with components in [0, 1], sRGB-encoded (as in a PNG), straight alpha.
struct Colour {
    float r = 0;
    float g = 0;
    float b = 0;
    float a = 1;
};

/// How a mesh is shaded.
enum class MeshKind {
    /// Cloth: two-sided (the back of the cloth is drawn in a paler, darker tone of its front
    /// colour), a soft sheen, and the wireframe overlay when asked for.
    Garment,
    /// A solid: one-sided look, a little gloss, never wireframed.
    Body,
};

/// One triangle mesh to draw.
struct DrawMesh {
    MeshKind kind = MeshKind::Garment;
    sim::MatX3 positions;  ///< (|V|×3) [m], y up
    sim::MatX3i triangles; ///< (|F|×3) 0-based; counter-clockwise seen from the front
    /// (|V|×3) unit vertex normals; empty = smooth area-weighted normals from the triangles.
    sim::MatX3 normals;
    Colour colour{0.8f, 0.8f, 0.8f, 1.0f}; ///< front colour where no colours are given below
    std::vector<Colour> triangleColours;   ///< (|F|) one colour per triangle, or empty
    std::vector<Colour> vertexColours;     ///< (|V|) interpolated colours, or empty
    /// (|V|×2) fabric coordinates [m] (the pattern UVs of a drape), or empty.
    sim::MatX2 uvs;
    /// A plain weave drawn through `uvs` (which it needs), its threads this far apart [mm]:
    /// warp along the UVs' v axis (the grain), weft along u; 0 = none. Threads finer than
    /// about two pixels fade to their average shade instead of shimmering.
    double weavePeriodMm = 0;
    /// (|V|) ambient visibility in [0, 1] (ambientOcclusion()), darkening the ambient light
    /// fully and the lamps by half; empty = 1 everywhere. Not updated by updatePositions.
    std::vector<float> ambientOcclusion;
};

/// Line segments drawn over the meshes in one flat colour (seams): depth-tested, nudged towards
/// the camera so that lines lying on a surface are not hidden by it.
struct DrawLines {
    sim::MatX3 positions; ///< (|V|×3) [m]
    sim::MatX2i segments; ///< (|S|×2) 0-based vertex pairs
    Colour colour{0.1f, 0.1f, 0.1f, 1.0f};
    float widthPx = 2.0f; ///< [pixels] (clamped to what GL offers)
};

/// Everything drawn in one picture.
struct Scene {
    std::vector<DrawMesh> meshes;
    std::vector<DrawLines> lines; ///< drawn after the meshes; not part of the framing bounds
    /// (|P|×3) pinned points [m], marked with a pinhead over the picture (pin_markers.h);
    /// not part of the framing bounds.
    sim::MatX3 pins;
};

/// The axis-aligned box around every vertex of the scene (empty when it has none).
Eigen::AlignedBox3d sceneBounds(const Scene& scene);

/// The colour of panel `index` (0, 1, ...): a palette of distinct, soft fabric tones, cycled.
Colour panelColour(int index);

/// The colour of seam `index` (0, 1, ...) in the document's order: saturated tones that stand
/// out on the panel colours, cycled. The pattern view draws each seam's two sides in it.
Colour seamColour(int index);

/// The body's colour: a light warm grey, like a dress form.
Colour bodyColour();

/// Per-vertex colours (|values|) for scalars on a blue–white–red ramp: `low` and below blue,
/// the midpoint white, `high` and above red (a non-finite value grey).
std::vector<Colour> scalarColours(const sim::VecX& values, double low, double high);

/// Parses `#RRGGBB`, `#RRGGBBAA`, `RRGGBB` or a name (`white`, `black`, `grey`/`gray`,
/// `transparent`); false when `text` is none of these.
bool parseColour(const std::string& text, Colour& out);

} // namespace atelier::render
