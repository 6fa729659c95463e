#pragma once
/// The renderer: draws a Scene into an offscreen multisampled framebuffer of any size and reads
/// back RGBA8 pixels. It needs a current OpenGL 3.3 core context (a HeadlessContext, or the
/// viewport's); GL stays inside renderer.cpp.
///
/// Look: smooth normals; a key light from the upper left, a cool fill from the right and a rim
/// from behind (fixed to the camera, so every view is lit alike), hemisphere ambient (sky
/// above, warm ground below); garments two-sided, body slightly glossy; a soft shadow on the
/// floor under the content; optionally the garment's triangles as a wireframe overlay; pinheads
/// over the picture where the scene has pins.

#include "ui/render/camera.h"
#include "ui/render/scene.h"

#include "io/png.h"

#include "sim/core/result.h"

#include <memory>
#include <string>

namespace atelier::render {

struct RenderOptions {
    int width = 1024;  ///< [pixels]
    int height = 1024; ///< [pixels]
    View view = View::ThreeQuarter;
    /// Background (alpha 0 = transparent: the PNG's alpha is 0 where nothing is drawn).
    Colour background{1.0f, 1.0f, 1.0f, 1.0f};
    bool wireframe = false;   ///< draw the garments' triangle edges over them
    bool groundShadow = true; ///< a soft shadow on the floor (y = the content's lowest point)
    int samples = 4;          ///< MSAA samples per pixel (clamped to what GL offers; 1 = none)
    bool pins = true;         ///< mark the scene's pins with pinheads (Scene::pins)
};

class Renderer {
  public:
    /// Compiles the shaders in the current context. Errors name what failed (GL version,
    /// shader log).
    static Result<std::unique_ptr<Renderer>> create();
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Uploads the scene's meshes (replacing those uploaded before); its bounds frame the views.
    /// Fails on inconsistent arrays (an index out of range, colours of the wrong count).
    Result<void> setScene(const Scene& scene);
    /// Replaces the positions (and normals) of uploaded mesh `meshIndex` and re-uploads only its
    /// vertex buffers (a viewport following a running drape): the triangles and colours stay.
    /// `positions` (|V|×3) must have the mesh's vertex count; `normals` the same, or empty for
    /// smooth normals computed from the triangles. The framing bounds follow the new positions.
    Result<void> updatePositions(int meshIndex, const sim::MatX3& positions,
                                 const sim::MatX3& normals = {});
    /// Replaces the triangle colours of uploaded mesh `meshIndex` (DrawMesh::triangleColours,
    /// (|F|), e.g. a strain map following a drape); the mesh must have been uploaded with
    /// triangle colours. Only that colour buffer is re-uploaded.
    Result<void> updateTriangleColours(int meshIndex, const std::vector<Colour>& colours);
    /// Replaces the vertex positions of uploaded lines `linesIndex` (Scene::lines' order; (|V|×3),
    /// its vertex count): lines that follow a drape (seams) re-upload positions only.
    Result<void> updateLinePositions(int linesIndex, const sim::MatX3& positions);
    /// Replaces the pinned points marked over the pictures (Scene::pins, (|P|×3) [m]).
    void setPins(const sim::MatX3& pins);
    /// The box framing the views: every uploaded mesh vertex (empty when there is none).
    const Eigen::AlignedBox3d& bounds() const;
    /// Draws the uploaded scene from `options.view` and returns the picture (top row first).
    Result<io::RgbaImage> render(const RenderOptions& options);
    /// Draws with an explicit camera.
    Result<io::RgbaImage> render(const RenderOptions& options, const Camera& camera);

    /// "OpenGL 4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string description() const;

  private:
    struct Impl;
    explicit Renderer(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> m_impl;
};

} // namespace atelier::render
