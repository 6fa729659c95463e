/// The OpenGL side of the renderer: the one file that includes GL (through libepoxy).

#include "ui/render/renderer.h"

#include "ui/render/pin_markers.h"
#include "ui/render/shaders.h"

#include "patterns/body_measure.h"

#include "sim/collision/obstacle.h"
#include "sim/mesh/vertex_normals.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace atelier::render {

namespace {

Error glError(const std::string& message) {
    return Error{"", "", "OpenGL: " + message};
}

/// Compiles and links a program; the error carries the driver's log.
Result<GLuint> buildProgram(const char* vertexSource, const char* fragmentSource) {
    const GLuint program = glCreateProgram();
    std::string log;
    for (const auto& [type, source] : {std::pair{GL_VERTEX_SHADER, vertexSource},
                                       std::pair{GL_FRAGMENT_SHADER, fragmentSource}}) {
        const GLuint shader = glCreateShader(type);
        glShaderSource(shader, 1, &source, nullptr);
        glCompileShader(shader);
        GLint ok = GL_FALSE;
        glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
        if (ok != GL_TRUE) {
            char text[2048] = {};
            glGetShaderInfoLog(shader, sizeof text, nullptr, text);
            log += text;
        }
        glAttachShader(program, shader);
        glDeleteShader(shader); // freed with the program
    }
    glLinkProgram(program);
    GLint linked = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &linked);
    if (!log.empty() || linked != GL_TRUE) {
        char text[2048] = {};
        glGetProgramInfoLog(program, sizeof text, nullptr, text);
        glDeleteProgram(program);
        return glError("shader program failed: " + log + text);
    }
    return program;
}

std::uint8_t unitToByte(float value) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f));
}

void appendColour(std::vector<std::uint8_t>& out, const Colour& c) {
    out.insert(out.end(), {unitToByte(c.r), unitToByte(c.g), unitToByte(c.b), unitToByte(c.a)});
}

/// Checks a mesh's arrays before upload; the message names the problem.
std::optional<std::string> meshProblem(const DrawMesh& mesh) {
    const auto n = mesh.positions.rows();
    if (!mesh.positions.allFinite()) {
        return "a vertex position is not finite";
    }
    if (mesh.triangles.size() > 0 &&
        (mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= n)) {
        return "a triangle index is out of range [0, " + std::to_string(n) + ")";
    }
    if (mesh.normals.rows() != 0 && mesh.normals.rows() != n) {
        return "normals: " + std::to_string(mesh.normals.rows()) + " for " + std::to_string(n) +
               " vertices";
    }
    if (!mesh.vertexColours.empty() && std::ssize(mesh.vertexColours) != n) {
        return "vertex colours: " + std::to_string(mesh.vertexColours.size()) + " for " +
               std::to_string(n) + " vertices";
    }
    if (mesh.uvs.rows() != 0 && mesh.uvs.rows() != n) {
        return "uvs: " + std::to_string(mesh.uvs.rows()) + " for " + std::to_string(n) +
               " vertices";
    }
    if (!(mesh.weavePeriodMm >= 0) || !std::isfinite(mesh.weavePeriodMm)) {
        return "weave period must be finite and >= 0";
    }
    if (!mesh.ambientOcclusion.empty() && std::ssize(mesh.ambientOcclusion) != n) {
        return "ambient occlusion: " + std::to_string(mesh.ambientOcclusion.size()) + " for " +
               std::to_string(n) + " vertices";
    }
    if (mesh.weavePeriodMm > 0 && mesh.uvs.rows() == 0) {
        return "a weave needs uvs";
    }
    if (!mesh.uvs.allFinite()) {
        return "a uv is not finite";
    }
    if (!mesh.triangleColours.empty() &&
        std::ssize(mesh.triangleColours) != mesh.triangles.rows()) {
        return "triangle colours: " + std::to_string(mesh.triangleColours.size()) + " for " +
               std::to_string(mesh.triangles.rows()) + " triangles";
    }
    return std::nullopt;
}

/// Checks lines before upload; the message names the problem.
std::optional<std::string> linesProblem(const DrawLines& lines) {
    const auto n = lines.positions.rows();
    if (!lines.positions.allFinite()) {
        return "a line vertex position is not finite";
    }
    if (lines.segments.size() > 0 &&
        (lines.segments.minCoeff() < 0 || lines.segments.maxCoeff() >= n)) {
        return "a line segment index is out of range [0, " + std::to_string(n) + ")";
    }
    return std::nullopt;
}

std::vector<float> toFloats(const sim::MatX3& m) {
    std::vector<float> out(static_cast<std::size_t>(m.size()));
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = static_cast<float>(m.data()[i]);
    }
    return out;
}

/// One mesh on the GPU, with its positions and triangles kept for position updates and bounds.
struct GpuMesh {
    MeshKind kind = MeshKind::Garment;
    sim::MatX3 positions;
    sim::MatX3i triangles;
    GLuint vao = 0;
    std::array<GLuint, 6> buffers{}; ///< positions, normals, colours, indices, uvs, occlusion
    float weavePeriodMm = 0;
    /// A closed body, consistently oriented outwards: its back faces are never seen, so they
    /// are culled instead of shaded and then hidden by the depth test.
    bool cullBackFaces = false;
    GLuint triangleColourBuffer = 0; ///< texture buffer contents, or 0
    GLuint triangleColourTexture = 0;
    GLsizei indexCount = 0;

    void release() {
        glDeleteTextures(1, &triangleColourTexture);
        glDeleteBuffers(1, &triangleColourBuffer);
        glDeleteBuffers(static_cast<GLsizei>(buffers.size()), buffers.data());
        glDeleteVertexArrays(1, &vao);
    }
};

template <class T> void uploadBuffer(GLenum target, GLuint buffer, const std::vector<T>& data) {
    glBindBuffer(target, buffer);
    glBufferData(target, static_cast<GLsizeiptr>(data.size() * sizeof(T)), data.data(),
                 GL_STATIC_DRAW);
}

/// Whether the mesh is watertight, consistently oriented and encloses a positive volume (its
/// triangles counter-clockwise seen from outside).
bool closedOutwards(const sim::MatX3& positions, const sim::MatX3i& triangles) {
    if (!sim::isClosedOriented(triangles, static_cast<int>(positions.rows()))) {
        return false;
    }
    return patterns::enclosedVolume(positions, triangles) > 0; // signed: < 0 inside out
}

GpuMesh upload(const DrawMesh& mesh) {
    GpuMesh gpu;
    gpu.kind = mesh.kind;
    gpu.positions = mesh.positions;
    gpu.triangles = mesh.triangles;
    gpu.cullBackFaces =
        mesh.kind == MeshKind::Body && closedOutwards(mesh.positions, mesh.triangles);
    const auto n = static_cast<std::size_t>(mesh.positions.rows());
    sim::MatX3 normals = mesh.normals;
    if (normals.rows() == 0) {
        sim::vertexNormals(mesh.positions, mesh.triangles, normals);
    }
    const std::vector<float> positions = toFloats(mesh.positions);
    const std::vector<float> normalData = toFloats(normals);
    std::vector<std::uint8_t> colours;
    colours.reserve(n * 4);
    for (std::size_t i = 0; i < n; ++i) {
        appendColour(colours, mesh.vertexColours.empty() ? mesh.colour : mesh.vertexColours[i]);
    }
    std::vector<GLuint> indices(mesh.triangles.data(),
                                mesh.triangles.data() + mesh.triangles.size());
    gpu.indexCount = static_cast<GLsizei>(indices.size());

    glGenVertexArrays(1, &gpu.vao);
    glBindVertexArray(gpu.vao);
    glGenBuffers(static_cast<GLsizei>(gpu.buffers.size()), gpu.buffers.data());
    uploadBuffer(GL_ARRAY_BUFFER, gpu.buffers[0], positions);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    uploadBuffer(GL_ARRAY_BUFFER, gpu.buffers[1], normalData);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    uploadBuffer(GL_ARRAY_BUFFER, gpu.buffers[2], colours);
    glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, 0, nullptr);
    for (GLuint a = 0; a < 3; ++a) {
        glEnableVertexAttribArray(a);
    }
    uploadBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.buffers[3], indices);
    if (mesh.uvs.rows() > 0) {
        std::vector<float> uvs(static_cast<std::size_t>(mesh.uvs.size()));
        for (std::size_t i = 0; i < uvs.size(); ++i) {
            uvs[i] = static_cast<float>(mesh.uvs.data()[i]);
        }
        uploadBuffer(GL_ARRAY_BUFFER, gpu.buffers[4], uvs);
        glVertexAttribPointer(3, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(3);
        gpu.weavePeriodMm = static_cast<float>(mesh.weavePeriodMm);
    }
    if (!mesh.ambientOcclusion.empty()) {
        uploadBuffer(GL_ARRAY_BUFFER, gpu.buffers[5], mesh.ambientOcclusion);
        glVertexAttribPointer(4, 1, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(4);
    }
    glBindVertexArray(0);

    if (!mesh.triangleColours.empty()) {
        std::vector<std::uint8_t> perTriangle;
        perTriangle.reserve(mesh.triangleColours.size() * 4);
        for (const Colour& c : mesh.triangleColours) {
            appendColour(perTriangle, c);
        }
        glGenBuffers(1, &gpu.triangleColourBuffer);
        uploadBuffer(GL_TEXTURE_BUFFER, gpu.triangleColourBuffer, perTriangle);
        glGenTextures(1, &gpu.triangleColourTexture);
        glBindTexture(GL_TEXTURE_BUFFER, gpu.triangleColourTexture);
        glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA8, gpu.triangleColourBuffer);
        glBindTexture(GL_TEXTURE_BUFFER, 0);
    }
    return gpu;
}

/// Line segments on the GPU.
struct GpuLines {
    GLuint vao = 0;
    std::array<GLuint, 2> buffers{}; ///< positions, indices
    GLsizei indexCount = 0;
    Eigen::Index vertexCount = 0;
    Colour colour;
    float widthPx = 1;

    void release() {
        glDeleteBuffers(static_cast<GLsizei>(buffers.size()), buffers.data());
        glDeleteVertexArrays(1, &vao);
    }
};

GpuLines upload(const DrawLines& lines) {
    GpuLines gpu;
    gpu.colour = lines.colour;
    gpu.widthPx = lines.widthPx;
    const std::vector<GLuint> indices(lines.segments.data(),
                                      lines.segments.data() + lines.segments.size());
    gpu.indexCount = static_cast<GLsizei>(indices.size());
    gpu.vertexCount = lines.positions.rows();
    glGenVertexArrays(1, &gpu.vao);
    glBindVertexArray(gpu.vao);
    glGenBuffers(static_cast<GLsizei>(gpu.buffers.size()), gpu.buffers.data());
    uploadBuffer(GL_ARRAY_BUFFER, gpu.buffers[0], toFloats(lines.positions));
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(0);
    uploadBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.buffers[1], indices);
    glBindVertexArray(0);
    return gpu;
}

/// A multisampled framebuffer and the single-sampled one it resolves into.
struct Targets {
    int width = 0;
    int height = 0;
    int samples = 0;
    std::array<GLuint, 2> framebuffers{};  ///< multisampled, resolved
    std::array<GLuint, 3> renderbuffers{}; ///< colour (MSAA), depth (MSAA), colour (resolved)

    void release() {
        glDeleteFramebuffers(2, framebuffers.data());
        glDeleteRenderbuffers(3, renderbuffers.data());
        *this = Targets{};
    }
};

} // namespace

/// The variants of the meshes' fragment shader (shaders::MESH_FRAGMENT), by what they draw.
enum MeshVariant : std::size_t {
    PLAIN,
    TRIANGLE_COLOURS,
    WEAVE,
    TRIANGLE_COLOURS_AND_WEAVE,
    WIRE,
    MESH_VARIANTS
};

/// The `#define` lines of each variant, in MeshVariant's order.
constexpr std::array<const char*, MESH_VARIANTS> MESH_VARIANT_DEFINES = {
    "", "#define TRIANGLE_COLOURS\n", "#define WEAVE\n",
    "#define TRIANGLE_COLOURS\n#define WEAVE\n", "#define WIRE\n"};

/// `source` with `defines` inserted after its first line (the `#version` line).
std::string withDefines(const char* source, const char* defines) {
    std::string text = source;
    const std::size_t lineEnd = text.find('\n');
    text.insert(lineEnd == std::string::npos ? text.size() : lineEnd + 1, defines);
    return text;
}

struct Renderer::Impl {
    std::array<GLuint, MESH_VARIANTS> meshPrograms{};
    GLuint groundProgram = 0;
    GLuint lineProgram = 0;
    GLuint groundVao = 0;
    GLuint groundBuffer = 0;
    std::vector<GpuMesh> meshes;
    std::vector<GpuLines> lines;
    Eigen::AlignedBox3d bounds;
    sim::MatX3 pins;               ///< marked over each picture (Scene::pins)
    Eigen::AlignedBox3d footprint; ///< the vertices in the lowest 10% of the content's height
    Targets targets;

    ~Impl() {
        releaseScene();
        targets.release();
        glDeleteBuffers(1, &groundBuffer);
        glDeleteVertexArrays(1, &groundVao);
        for (const GLuint program : meshPrograms) {
            glDeleteProgram(program);
        }
        glDeleteProgram(groundProgram);
        glDeleteProgram(lineProgram);
    }

    void releaseScene() {
        for (GpuMesh& m : meshes) {
            m.release();
        }
        meshes.clear();
        for (GpuLines& l : lines) {
            l.release();
        }
        lines.clear();
    }
    void refreshBounds();
    void drawLines(const Camera& camera);

    Result<void> prepareTargets(int width, int height, int samples);
    void drawMeshes(const Camera& camera, bool wire);
    void drawGround(const Camera& camera);
    io::RgbaImage readPixels() const;
};

Renderer::Renderer(std::unique_ptr<Impl> impl) : m_impl(std::move(impl)) {}
Renderer::~Renderer() = default;

Result<std::unique_ptr<Renderer>> Renderer::create() {
    if (!epoxy_is_desktop_gl() || epoxy_gl_version() < 33) {
        return glError("the current context is not desktop OpenGL 3.3 or newer");
    }
    auto impl = std::make_unique<Impl>();
    for (std::size_t v = 0; v < MESH_VARIANTS; ++v) {
        const std::string fragment = withDefines(shaders::MESH_FRAGMENT, MESH_VARIANT_DEFINES[v]);
        auto mesh = buildProgram(shaders::MESH_VERTEX, fragment.c_str());
        if (!mesh.ok()) {
            return mesh.error();
        }
        impl->meshPrograms[v] = mesh.value();
    }
    auto ground = buildProgram(shaders::GROUND_VERTEX, shaders::GROUND_FRAGMENT);
    if (!ground.ok()) {
        return ground.error();
    }
    impl->groundProgram = ground.value();
    auto line = buildProgram(shaders::LINE_VERTEX, shaders::LINE_FRAGMENT);
    if (!line.ok()) {
        return line.error();
    }
    impl->lineProgram = line.value();
    const std::vector<float> corners = {-1, -1, 1, -1, -1, 1, 1, 1};
    glGenVertexArrays(1, &impl->groundVao);
    glBindVertexArray(impl->groundVao);
    glGenBuffers(1, &impl->groundBuffer);
    uploadBuffer(GL_ARRAY_BUFFER, impl->groundBuffer, corners);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(0);
    glBindVertexArray(0);
    return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

std::string Renderer::description() const {
    const auto text = [](GLenum name) {
        const auto* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s != nullptr ? s : "?");
    };
    return "OpenGL " + text(GL_VERSION) + ", " + text(GL_RENDERER);
}

Result<void> Renderer::setScene(const Scene& scene) {
    for (std::size_t k = 0; k < scene.meshes.size(); ++k) {
        if (auto problem = meshProblem(scene.meshes[k])) {
            return Error{"", "mesh " + std::to_string(k), *problem};
        }
    }
    for (std::size_t k = 0; k < scene.lines.size(); ++k) {
        if (auto problem = linesProblem(scene.lines[k])) {
            return Error{"", "lines " + std::to_string(k), *problem};
        }
    }
    m_impl->releaseScene();
    for (const DrawMesh& mesh : scene.meshes) {
        m_impl->meshes.push_back(upload(mesh));
    }
    for (const DrawLines& lines : scene.lines) {
        m_impl->lines.push_back(upload(lines));
    }
    m_impl->pins = scene.pins;
    m_impl->refreshBounds();
    return {};
}

void Renderer::setPins(const sim::MatX3& pins) {
    m_impl->pins = pins;
}

void Renderer::Impl::refreshBounds() {
    bounds = Eigen::AlignedBox3d();
    for (const GpuMesh& mesh : meshes) {
        for (Eigen::Index i = 0; i < mesh.positions.rows(); ++i) {
            bounds.extend(mesh.positions.row(i).transpose());
        }
    }
    footprint = Eigen::AlignedBox3d();
    const double floorBand = bounds.min().y() + 0.1 * bounds.sizes().y();
    for (const GpuMesh& mesh : meshes) {
        for (Eigen::Index i = 0; i < mesh.positions.rows(); ++i) {
            if (mesh.positions(i, 1) <= floorBand) {
                footprint.extend(mesh.positions.row(i).transpose());
            }
        }
    }
}

Result<void> Renderer::updatePositions(int meshIndex, const sim::MatX3& positions,
                                       const sim::MatX3& normals) {
    if (meshIndex < 0 || meshIndex >= std::ssize(m_impl->meshes)) {
        return Error{"", "mesh " + std::to_string(meshIndex),
                     "no such mesh (" + std::to_string(m_impl->meshes.size()) + " uploaded)"};
    }
    GpuMesh& mesh = m_impl->meshes[static_cast<std::size_t>(meshIndex)];
    const auto n = mesh.positions.rows();
    std::optional<std::string> problem;
    if (positions.rows() != n) {
        problem = "positions: " + std::to_string(positions.rows()) + " for " + std::to_string(n) +
                  " vertices";
    } else if (!positions.allFinite()) {
        problem = "a vertex position is not finite";
    } else if (normals.rows() != 0 && normals.rows() != n) {
        problem = "normals: " + std::to_string(normals.rows()) + " for " + std::to_string(n) +
                  " vertices";
    }
    if (problem) {
        return Error{"", "mesh " + std::to_string(meshIndex), *problem};
    }
    mesh.positions = positions;
    sim::MatX3 smooth;
    if (normals.rows() == 0) {
        sim::vertexNormals(positions, mesh.triangles, smooth);
    }
    const std::vector<float> positionData = toFloats(positions);
    const std::vector<float> normalData = toFloats(normals.rows() == 0 ? smooth : normals);
    const auto bytes = static_cast<GLsizeiptr>(positionData.size() * sizeof(float));
    glBindBuffer(GL_ARRAY_BUFFER, mesh.buffers[0]);
    glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, positionData.data());
    glBindBuffer(GL_ARRAY_BUFFER, mesh.buffers[1]);
    glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, normalData.data());
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    m_impl->refreshBounds();
    return {};
}

Result<void> Renderer::updateTriangleColours(int meshIndex, const std::vector<Colour>& colours) {
    const std::string where = "mesh " + std::to_string(meshIndex);
    if (meshIndex < 0 || meshIndex >= std::ssize(m_impl->meshes)) {
        return Error{"", where,
                     "no such mesh (" + std::to_string(m_impl->meshes.size()) + " uploaded)"};
    }
    const GpuMesh& mesh = m_impl->meshes[static_cast<std::size_t>(meshIndex)];
    if (mesh.triangleColourBuffer == 0) {
        return Error{"", where, "uploaded without triangle colours"};
    }
    if (std::ssize(colours) != mesh.triangles.rows()) {
        return Error{"", where,
                     "triangle colours: " + std::to_string(colours.size()) + " for " +
                         std::to_string(mesh.triangles.rows()) + " triangles"};
    }
    std::vector<std::uint8_t> bytes;
    bytes.reserve(colours.size() * 4);
    for (const Colour& c : colours) {
        appendColour(bytes, c);
    }
    glBindBuffer(GL_TEXTURE_BUFFER, mesh.triangleColourBuffer);
    glBufferSubData(GL_TEXTURE_BUFFER, 0, static_cast<GLsizeiptr>(bytes.size()), bytes.data());
    glBindBuffer(GL_TEXTURE_BUFFER, 0);
    return {};
}

Result<void> Renderer::updateLinePositions(int linesIndex, const sim::MatX3& positions) {
    const std::string where = "lines " + std::to_string(linesIndex);
    if (linesIndex < 0 || linesIndex >= std::ssize(m_impl->lines)) {
        return Error{"", where,
                     "no such lines (" + std::to_string(m_impl->lines.size()) + " uploaded)"};
    }
    const GpuLines& lines = m_impl->lines[static_cast<std::size_t>(linesIndex)];
    if (positions.rows() != lines.vertexCount) {
        return Error{"", where,
                     "positions: " + std::to_string(positions.rows()) + " for " +
                         std::to_string(lines.vertexCount) + " vertices"};
    }
    if (!positions.allFinite()) {
        return Error{"", where, "a line vertex position is not finite"};
    }
    const std::vector<float> data = toFloats(positions);
    glBindBuffer(GL_ARRAY_BUFFER, lines.buffers[0]);
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(data.size() * sizeof(float)),
                    data.data());
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    return {};
}

const Eigen::AlignedBox3d& Renderer::bounds() const {
    return m_impl->bounds;
}

Result<void> Renderer::Impl::prepareTargets(int width, int height, int samples) {
    if (targets.width == width && targets.height == height && targets.samples == samples) {
        return {};
    }
    targets.release();
    GLint maxSize = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &maxSize);
    if (width < 1 || height < 1 || width > maxSize || height > maxSize) {
        return glError("picture size " + std::to_string(width) + "x" + std::to_string(height) +
                       " out of range [1, " + std::to_string(maxSize) + "]");
    }
    glGenFramebuffers(2, targets.framebuffers.data());
    glGenRenderbuffers(3, targets.renderbuffers.data());
    const GLenum formats[3] = {GL_RGBA8, GL_DEPTH_COMPONENT24, GL_RGBA8};
    const GLenum attachments[3] = {GL_COLOR_ATTACHMENT0, GL_DEPTH_ATTACHMENT, GL_COLOR_ATTACHMENT0};
    for (int k = 0; k < 3; ++k) {
        glBindRenderbuffer(GL_RENDERBUFFER, targets.renderbuffers[k]);
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, k < 2 ? samples : 0, formats[k], width,
                                         height);
        glBindFramebuffer(GL_FRAMEBUFFER, targets.framebuffers[k < 2 ? 0 : 1]);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, attachments[k], GL_RENDERBUFFER,
                                  targets.renderbuffers[k]);
    }
    for (const GLuint fb : targets.framebuffers) {
        glBindFramebuffer(GL_FRAMEBUFFER, fb);
        if (const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
            status != GL_FRAMEBUFFER_COMPLETE) {
            char hex[16];
            std::snprintf(hex, sizeof hex, "0x%04x", status);
            targets.release();
            return glError(std::string("offscreen framebuffer incomplete (") + hex + ")");
        }
    }
    targets.width = width;
    targets.height = height;
    targets.samples = samples;
    return {};
}

void Renderer::Impl::drawMeshes(const Camera& camera, bool wire) {
    const Eigen::Matrix3f rotation = camera.view.topLeftCorner<3, 3>();
    for (const GpuMesh& m : meshes) {
        if (wire && m.kind != MeshKind::Garment) {
            continue;
        }
        const bool coloured = m.triangleColourTexture != 0;
        const bool woven = m.weavePeriodMm > 0;
        const GLuint program =
            meshPrograms[wire       ? WIRE
                         : coloured ? (woven ? TRIANGLE_COLOURS_AND_WEAVE : TRIANGLE_COLOURS)
                         : woven    ? WEAVE
                                    : PLAIN];
        glUseProgram(program);
        const auto at = [&](const char* name) { return glGetUniformLocation(program, name); };
        glUniformMatrix4fv(at("uView"), 1, GL_FALSE, camera.view.data());
        glUniformMatrix4fv(at("uProjection"), 1, GL_FALSE, camera.projection.data());
        glUniformMatrix3fv(at("uViewRotation"), 1, GL_FALSE, rotation.data());
        glUniform1i(at("uTriangleColours"), 0);
        glUniform4f(at("uWireColour"), 0.0f, 0.0f, 0.0f, 0.35f);
        glUniform1i(at("uGarment"), m.kind == MeshKind::Garment ? 1 : 0);
        glUniform1f(at("uWeavePeriodMm"), m.weavePeriodMm);
        if (m.cullBackFaces) {
            glEnable(GL_CULL_FACE);
            glCullFace(GL_BACK);
        }
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_BUFFER, m.triangleColourTexture);
        glBindVertexArray(m.vao);
        glVertexAttrib1f(4, 1.0f); // the visibility where a mesh has no occlusion array
        glDrawElements(GL_TRIANGLES, m.indexCount, GL_UNSIGNED_INT, nullptr);
        glDisable(GL_CULL_FACE);
    }
    glBindVertexArray(0);
}

void Renderer::Impl::drawLines(const Camera& camera) {
    glUseProgram(lineProgram);
    const auto at = [&](const char* name) { return glGetUniformLocation(lineProgram, name); };
    glUniformMatrix4fv(at("uView"), 1, GL_FALSE, camera.view.data());
    glUniformMatrix4fv(at("uProjection"), 1, GL_FALSE, camera.projection.data());
    // 3 mm: above the cloth a seam lies on and the seam allowance beside it, at a garment's
    // scale; a line behind the body stays hidden.
    glUniform1f(at("uTowardsCamera"), 0.003f);
    GLfloat range[2] = {1, 1};
    glGetFloatv(GL_ALIASED_LINE_WIDTH_RANGE, range);
    for (const GpuLines& l : lines) {
        glLineWidth(std::clamp(l.widthPx, range[0], range[1]));
        glUniform4f(at("uColour"), l.colour.r, l.colour.g, l.colour.b, l.colour.a);
        glBindVertexArray(l.vao);
        glDrawElements(GL_LINES, l.indexCount, GL_UNSIGNED_INT, nullptr);
    }
    glLineWidth(1);
    glBindVertexArray(0);
}

/// A soft dark ellipse on the floor under the content's footprint, drawn over what is already
/// there.
void Renderer::Impl::drawGround(const Camera& camera) {
    const Eigen::Vector3d size = footprint.sizes();
    const Eigen::Vector3d centre = footprint.center();
    const double reach = 0.25 * std::max(size.x(), size.z()) + 0.04 * bounds.sizes().y();
    glUseProgram(groundProgram);
    const auto at = [&](const char* name) { return glGetUniformLocation(groundProgram, name); };
    const Eigen::Matrix4f viewProjection = camera.projection * camera.view;
    glUniformMatrix4fv(at("uViewProjection"), 1, GL_FALSE, viewProjection.data());
    glUniform3f(at("uCentre"), static_cast<float>(centre.x()),
                static_cast<float>(bounds.min().y() - 1e-3 * bounds.sizes().norm()),
                static_cast<float>(centre.z()));
    glUniform2f(at("uHalfSize"), static_cast<float>(0.5 * size.x() + reach),
                static_cast<float>(0.5 * size.z() + reach));
    glUniform1f(at("uStrength"), 0.5f);
    glBindVertexArray(groundVao);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    glBindVertexArray(0);
}

io::RgbaImage Renderer::Impl::readPixels() const {
    io::RgbaImage image(targets.width, targets.height);
    std::vector<std::uint8_t> raw(image.pixels.size());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, targets.framebuffers[1]);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, targets.width, targets.height, GL_RGBA, GL_UNSIGNED_BYTE, raw.data());
    const std::size_t stride = std::size_t(targets.width) * 4;
    for (int y = 0; y < targets.height; ++y) {
        // GL's rows go bottom up; the framebuffer holds premultiplied colour.
        const std::uint8_t* from = raw.data() + std::size_t(targets.height - 1 - y) * stride;
        std::uint8_t* to = image.at(0, y);
        for (std::size_t i = 0; i < stride; i += 4) {
            const int alpha = from[i + 3];
            for (std::size_t k = 0; k < 3; ++k) {
                to[i + k] = alpha == 255 || alpha == 0
                                ? from[i + k]
                                : static_cast<std::uint8_t>(
                                      std::min(255, (from[i + k] * 255 + alpha / 2) / alpha));
            }
            to[i + 3] = from[i + 3];
        }
    }
    return image;
}

Result<io::RgbaImage> Renderer::render(const RenderOptions& options) {
    const double aspect = static_cast<double>(std::max(options.width, 1)) /
                          static_cast<double>(std::max(options.height, 1));
    return render(options, frameView(options.view, m_impl->bounds, aspect));
}

Result<io::RgbaImage> Renderer::render(const RenderOptions& options, const Camera& camera) {
    GLint maxSamples = 1;
    glGetIntegerv(GL_MAX_SAMPLES, &maxSamples);
    const int samples = std::clamp(options.samples, 1, std::max(maxSamples, 1));
    if (auto prepared = m_impl->prepareTargets(options.width, options.height, samples);
        !prepared.ok()) {
        return prepared.error();
    }
    glBindFramebuffer(GL_FRAMEBUFFER, m_impl->targets.framebuffers[0]);
    glViewport(0, 0, options.width, options.height);
    const Colour& bg = options.background; // cleared premultiplied, as blending leaves it
    glClearColor(bg.r * bg.a, bg.g * bg.a, bg.b * bg.a, bg.a);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    if (samples > 1) {
        glEnable(GL_MULTISAMPLE);
    }
    glEnable(GL_POLYGON_OFFSET_FILL); // the wireframe's lines win the depth test
    glPolygonOffset(1.0f, 1.0f);
    m_impl->drawMeshes(camera, false);
    glDisable(GL_POLYGON_OFFSET_FILL);

    glEnable(GL_BLEND);
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    if (options.groundShadow && !m_impl->bounds.isEmpty()) {
        m_impl->drawGround(camera);
    }
    if (options.wireframe) {
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        m_impl->drawMeshes(camera, true);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
    if (!m_impl->lines.empty()) {
        m_impl->drawLines(camera);
    }
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);

    glBindFramebuffer(GL_READ_FRAMEBUFFER, m_impl->targets.framebuffers[0]);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, m_impl->targets.framebuffers[1]);
    glBlitFramebuffer(0, 0, options.width, options.height, 0, 0, options.width, options.height,
                      GL_COLOR_BUFFER_BIT, GL_NEAREST);
    io::RgbaImage image = m_impl->readPixels();
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (const GLenum error = glGetError(); error != GL_NO_ERROR) {
        char hex[16];
        std::snprintf(hex, sizeof hex, "0x%04x", error);
        return glError(std::string("drawing failed (GL error ") + hex + ")");
    }
    if (options.pins && m_impl->pins.rows() > 0) {
        drawPinMarkers(image, camera, m_impl->pins);
    }
    return image;
}

} // namespace atelier::render
