#include "io/scene_file.h"

#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/material_json.h"
#include "io/obj.h"
#include "io/scene_obstacles.h"

#include "sim/collision/obstacle.h"
#include "sim/simulation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <set>

namespace atelier::io {

namespace {

using detail::inQuotes;
using detail::JsonError;
using detail::nameList;
using detail::ObjectReader;
using nlohmann::json;

/// What constraints need to know about one cloth to resolve (cloth, vertex) references.
struct ClothInfo {
    std::string name;
    int offset = 0; ///< first global vertex index
    int vertexCount = 0;
    bool rectangle = false;
    int cellsX = 0;
    int cellsY = 0;
};

/// Caps on per-step loops (collision rounds, conjugate-gradient iterations), far above what
/// converges; a larger value would let one step run for hours.
constexpr long long MAX_COLLISION_ITERATIONS = 1000;
constexpr long long MAX_CG_ITERATIONS = 100'000;

class SceneParser {
  public:
    SceneParser(std::string file, std::filesystem::path baseDir, const SceneLoadOptions& options)
        : m_file(std::move(file)), m_baseDir(std::move(baseDir)), m_presets(options.presets),
          m_limits(options.limits) {}

    sim::SceneSpec parse(const json& root) {
        ObjectReader r(root, "");
        r.allow({"description", "comment"});
        r.optionalString("description");
        const std::string format = r.string("format");
        if (format != "atelier-scene") {
            r.fail("format", "expected \"atelier-scene\", found " + inQuotes(format));
        }
        const long long version = r.integer("version");
        if (version != 1) {
            r.fail("version", "unsupported version " + std::to_string(version) +
                                  " (this build reads version 1)");
        }
        readPresets(r);

        const json& cloths = detail::arrayAt(r.require("cloths"), r.pointerOf("cloths"));
        if (cloths.empty()) {
            r.fail("cloths", "a scene needs at least one cloth");
        }
        if (cloths.size() > static_cast<std::size_t>(m_limits.maxCloths)) {
            r.fail("cloths", std::to_string(cloths.size()) + " cloths, more than the limit of " +
                                 std::to_string(m_limits.maxCloths));
        }
        int offset = 0;
        for (std::size_t i = 0; i < cloths.size(); ++i) {
            readCloth(cloths[i], detail::childPointer(r.pointerOf("cloths"), i), offset);
            offset += m_scene.cloths.back().mesh.vertexCount();
        }
        if (const json* obstacles = r.find("obstacles")) {
            detail::readObstacles(*obstacles, r.pointerOf("obstacles"), m_baseDir, m_limits, m_size,
                                  m_scene.obstacles);
        }

        if (const json* pins = r.find("pins")) {
            const std::string ptr = r.pointerOf("pins");
            for (std::size_t i = 0; i < detail::arrayAt(*pins, ptr).size(); ++i) {
                readPin((*pins)[i], detail::childPointer(ptr, i));
            }
            std::sort(m_scene.pins.begin(), m_scene.pins.end());
            m_scene.pins.erase(std::unique(m_scene.pins.begin(), m_scene.pins.end()),
                               m_scene.pins.end());
            // A random (crumpled) start scatters the free vertices only: pins hold the
            // placement, or the crumpling would stretch the cloth between them for good.
            for (int pin : m_scene.pins) {
                for (const auto& [c, placed] : m_placed) {
                    const int begin = m_cloths[c].offset;
                    if (pin >= begin && pin < begin + m_cloths[c].vertexCount) {
                        m_scene.cloths[c].position.row(pin - begin) = placed.row(pin - begin);
                    }
                }
            }
        }
        if (const json* drives = r.find("drives")) {
            const std::string ptr = r.pointerOf("drives");
            for (std::size_t i = 0; i < detail::arrayAt(*drives, ptr).size(); ++i) {
                readDrive((*drives)[i], detail::childPointer(ptr, i));
            }
        }
        if (const json* seams = r.find("seams")) {
            const std::string ptr = r.pointerOf("seams");
            for (std::size_t i = 0; i < detail::arrayAt(*seams, ptr).size(); ++i) {
                readSeam((*seams)[i], detail::childPointer(ptr, i));
            }
        }
        m_scene.seamTimeConstant = r.positive("seam_time_constant", m_scene.seamTimeConstant);
        m_scene.highDampingTimeConstant =
            r.nonNegative("high_damping_time_constant", m_scene.highDampingTimeConstant);
        readGravity(r);
        if (const json* air = r.find("air")) {
            ObjectReader a(*air, r.pointerOf("air"));
            m_scene.air.enabled = a.boolean("enabled", true);
            m_scene.air.dragCoefficient = a.nonNegative("drag", m_scene.air.dragCoefficient);
            m_scene.air.wind = a.vec3("wind", m_scene.air.wind);
            a.finish();
        }
        if (const json* collision = r.find("collision")) {
            readCollision(ObjectReader(*collision, r.pointerOf("collision")));
        }
        if (const json* integrator = r.find("integrator")) {
            readIntegrator(ObjectReader(*integrator, r.pointerOf("integrator")));
        }
        m_scene.duration = r.positive("duration", m_scene.duration);
        m_scene.frameRate = r.positive("frame_rate", m_scene.frameRate);
        checkRunLength(r);
        r.finish();
        return std::move(m_scene);
    }

  private:
    /// Frame rate, frames and steps within the limits: each is a loop the run goes round.
    void checkRunLength(ObjectReader& r) const {
        const auto text = [](double v) { return json(v).dump(); };
        if (m_scene.frameRate > m_limits.maxFrameRate) {
            r.fail("frame_rate", "must be at most " + text(m_limits.maxFrameRate) +
                                     " frames per second (found " + text(m_scene.frameRate) + ")");
        }
        const double frames = m_scene.duration * m_scene.frameRate;
        if (!(frames <= static_cast<double>(m_limits.maxFrames))) {
            r.fail("duration", "duration × frame_rate is " + text(frames) +
                                   " frames, more than the limit of " +
                                   std::to_string(m_limits.maxFrames));
        }
        const double steps = m_scene.duration / m_scene.integrator.dt;
        if (!(steps <= static_cast<double>(m_limits.maxSteps))) {
            r.fail("duration", "duration / integrator dt is " + text(steps) +
                                   " steps, more than the limit of " +
                                   std::to_string(m_limits.maxSteps));
        }
    }

    void readPresets(ObjectReader& r) {
        if (const auto materialsFile = r.optionalString("materials_file")) {
            if (m_presets.empty()) {
                auto loaded = loadMaterialPresets(m_baseDir / *materialsFile, m_limits);
                if (!loaded.ok()) {
                    detail::failWith(r.pointerOf("materials_file"), loaded.error());
                }
                m_presets = std::move(loaded).value();
            }
        }
        if (m_presets.empty()) {
            m_presets = builtinMaterialPresets();
        }
    }

    static std::string nameRef(const MaterialPresets& presets) {
        std::string out;
        for (const auto& [name, material] : presets) {
            out += (out.empty() ? "" : ", ") + inQuotes(name);
        }
        return out;
    }

    sim::Material preset(const std::string& name, const std::string& pointer) const {
        const auto it = m_presets.find(name);
        if (it == m_presets.end()) {
            throw JsonError{pointer, "unknown material preset " + inQuotes(name) +
                                         " (presets: " + nameRef(m_presets) + ")"};
        }
        return it->second;
    }

    void readCloth(const json& value, const std::string& ptr, int offset) {
        ObjectReader r(value, ptr);
        r.allow({"description"});
        r.optionalString("description");
        sim::ClothSpec cloth;
        ClothInfo info;
        cloth.name = r.string("name", "cloth" + std::to_string(m_scene.cloths.size()));
        for (const ClothInfo& other : m_cloths) {
            if (other.name == cloth.name) {
                r.fail("name", "another cloth is already named " + inQuotes(cloth.name));
            }
        }
        info.name = cloth.name;
        info.offset = offset;

        // Mesh: rest shape and topology, and for OBJ the default 3D positions.
        sim::MatX2 rest;
        sim::MatX3i triangles;
        sim::MatX3 objPositions;
        {
            ObjectReader m(r.require("mesh"), r.pointerOf("mesh"));
            const std::string type = m.string("type");
            if (type == "rectangle") {
                sim::RectangleOptions rect;
                rect.width = m.positive("width", rect.width);
                rect.height = m.positive("height", rect.height);
                if (const json* cells = m.find("cells")) {
                    const std::string cp = m.pointerOf("cells");
                    if (!cells->is_array() || cells->size() != 2) {
                        m.fail("cells", "expected [cells along x, cells along y], found " +
                                            detail::typeName(*cells));
                    }
                    const long long nx = detail::integerAt((*cells)[0], cp + "/0");
                    const long long ny = detail::integerAt((*cells)[1], cp + "/1");
                    if (nx < 1 || ny < 1) {
                        m.fail("cells", "cell counts must be at least 1");
                    }
                    // In floating point: (nx + 1)(ny + 1) may not fit 64 bits.
                    const double vertices =
                        (static_cast<double>(nx) + 1) * (static_cast<double>(ny) + 1);
                    if (vertices > static_cast<double>(m_limits.maxSceneVertices)) {
                        m.fail("cells", "a grid of " + std::to_string(nx) + " × " +
                                            std::to_string(ny) + " cells has " +
                                            json(vertices).dump() +
                                            " vertices, more than the limit of " +
                                            std::to_string(m_limits.maxSceneVertices));
                    }
                    rect.cellsX = static_cast<int>(nx);
                    rect.cellsY = static_cast<int>(ny);
                }
                const std::string tri = m.string("triangulation", "regular");
                if (tri == "regular") {
                    rect.triangulation = sim::Triangulation::Regular;
                } else if (tri == "irregular") {
                    rect.triangulation = sim::Triangulation::Irregular;
                } else {
                    m.fail("triangulation", "unknown triangulation " + inQuotes(tri) +
                                                " (expected \"regular\" or \"irregular\")");
                }
                const long long seed = m.integer("seed", 1);
                if (seed < 0 || seed > std::numeric_limits<std::uint32_t>::max()) {
                    m.fail("seed", "must be in [0, 2^32)");
                }
                rect.seed = static_cast<std::uint32_t>(seed);
                sim::makeRectangle(rect, rest, triangles);
                info.rectangle = true;
                info.cellsX = rect.cellsX;
                info.cellsY = rect.cellsY;
            } else if (type == "obj") {
                const std::string path = m.string("path");
                const double uvScale = m.positive("uv_scale", 1.0);
                auto obj = readObj(m_baseDir / path, m_limits.maxMeshBytes);
                if (!obj.ok()) {
                    detail::failWith(m.pointerOf("path"), obj.error());
                }
                ObjMesh& mesh = obj.value();
                if (mesh.uvs.rows() == 0) {
                    m.fail("path", path + ": has no texture coordinates (vt); the rest shape "
                                          "of a cloth comes from its UVs [m]");
                }
                rest = mesh.uvs * uvScale;
                triangles = std::move(mesh.triangles);
                objPositions = std::move(mesh.positions);
            } else {
                m.fail("type", "unknown mesh type " + inQuotes(type) +
                                   " (expected \"rectangle\" or \"obj\")");
            }
            m.finish();
            if (auto message = sim::buildClothMesh(rest, triangles, cloth.mesh)) {
                throw JsonError{m.pointer(), *message};
            }
        }
        info.vertexCount = cloth.mesh.vertexCount();
        m_size.add(info.vertexCount, cloth.mesh.triangles.rows(), m_limits, r.pointerOf("mesh"));

        // Initial positions: placement of the rest shape, or the OBJ's own positions.
        const json* placement = r.find("placement");
        if (placement != nullptr || objPositions.rows() == 0) {
            static const json EMPTY = json::object();
            ObjectReader p(placement != nullptr ? *placement : EMPTY, r.pointerOf("placement"));
            const sim::Vec3 origin = p.vec3("origin", sim::Vec3::Zero());
            const sim::Vec3 u = p.vec3("u_axis", sim::Vec3::UnitX());
            const sim::Vec3 v = p.vec3("v_axis", sim::Vec3::UnitY());
            if (u.norm() < 1e-12) {
                p.fail("u_axis", "must not be zero");
            }
            if (v.norm() < 1e-12) {
                p.fail("v_axis", "must not be zero");
            }
            const sim::Vec3 un = u.normalized();
            const sim::Vec3 vn = v.normalized();
            if (un.cross(vn).norm() < 1e-6) {
                p.fail("v_axis", "must not be parallel to u_axis");
            }
            p.finish();
            cloth.position.resize(info.vertexCount, 3);
            for (int i = 0; i < info.vertexCount; ++i) {
                cloth.position.row(i) =
                    (origin + cloth.mesh.rest(i, 0) * un + cloth.mesh.rest(i, 1) * vn).transpose();
            }
        } else {
            cloth.position = objPositions;
        }
        if (const json* initial = r.find("initial")) {
            ObjectReader in(*initial, r.pointerOf("initial"));
            const std::string type = in.string("type");
            if (type != "random") {
                in.fail("type",
                        "unknown initial state " + inQuotes(type) + " (expected \"random\")");
            }
            const double amplitude = in.positive("amplitude");
            const long long seed = in.integer("seed", 1);
            if (seed < 0 || seed > std::numeric_limits<std::uint32_t>::max()) {
                in.fail("seed", "must be in [0, 2^32)");
            }
            in.finish();
            // mt19937 is specified exactly by the standard: the same seed gives the same start
            // on every platform (unlike std::uniform_real_distribution).
            std::mt19937 rng(static_cast<std::uint32_t>(seed));
            m_placed[m_scene.cloths.size()] = cloth.position;
            for (int i = 0; i < info.vertexCount; ++i) {
                for (int k = 0; k < 3; ++k) {
                    const double unit = static_cast<double>(rng()) / 4294967296.0; // [0, 1)
                    cloth.position(i, k) += amplitude * (2.0 * unit - 1.0);
                }
            }
        }
        detail::checkCoordinates(cloth.position, m_limits, ptr, "the cloth's positions");
        if (const json* velocity = r.find("velocity")) {
            const sim::Vec3 v0 = detail::vec3At(*velocity, r.pointerOf("velocity"));
            cloth.velocity = sim::MatX3(info.vertexCount, 3);
            cloth.velocity.rowwise() = v0.transpose();
        }

        // Material: a preset name, or an object (optionally based on a preset) of overrides.
        {
            const json& material = r.require("material");
            const std::string mp = r.pointerOf("material");
            if (material.is_string()) {
                cloth.material = preset(material.get<std::string>(), mp);
            } else if (material.is_object()) {
                ObjectReader mr(material, mp);
                if (const auto base = mr.optionalString("preset")) {
                    cloth.material = preset(*base, mr.pointerOf("preset"));
                } else {
                    cloth.material = sim::Material{};
                }
                cloth.material.name = mr.string("name", cloth.material.name);
                detail::readMaterial(mr, cloth.material, false);
                mr.finish();
            } else {
                throw JsonError{mp, "expected a preset name or an object, found " +
                                        detail::typeName(material)};
            }
        }
        {
            const std::string model = r.string("model", "fem");
            const auto kind = sim::stretchModelFromName(model);
            if (!kind) {
                r.fail("model", "unknown model " + inQuotes(model) + " (expected one of " +
                                    nameList(sim::STRETCH_MODELS, &sim::stretchModelName) + ")");
            }
            cloth.model = *kind;
        }
        cloth.crossSprings = r.boolean("cross_springs", cloth.crossSprings);
        if (cloth.crossSprings && cloth.model != sim::StretchModel::Springs) {
            r.fail("cross_springs", "cross springs exist only in the \"springs\" model");
        }
        cloth.bending = r.boolean("bending", cloth.bending);
        if (const auto model = r.optionalString("bending_model")) {
            const auto m = sim::bendingModelFromName(*model);
            if (!m) {
                r.fail("bending_model", "unknown bending model " + inQuotes(*model) +
                                            " (expected \"continuum\" or \"hinge\")");
            }
            cloth.bendingModel = *m;
        }
        cloth.plasticity = r.boolean("plasticity", cloth.plasticity);
        if (cloth.plasticity && !(cloth.material.plasticYieldAngle > 0)) {
            r.fail("plasticity", "plasticity needs a material with plastic_yield_angle_rad > 0");
        }
        cloth.thickness = r.nonNegativeAtMost("thickness", cloth.thickness, m_limits.maxThickness,
                                              THICKNESS_LIMIT);
        cloth.selfCollision = r.boolean("self_collision", cloth.selfCollision);
        if (const json* folds = r.find("folds")) {
            // Per-edge rest fold angles: [{"vertices": [a, b], "angle_deg": 90}, ...].
            const std::string foldsPtr = r.pointerOf("folds");
            const json& list = detail::arrayAt(*folds, foldsPtr);
            cloth.restAngles = sim::VecX::Zero(cloth.mesh.hinges.rows());
            for (std::size_t k = 0; k < list.size(); ++k) {
                ObjectReader fr(list[k], detail::childPointer(foldsPtr, k));
                const json& ends =
                    detail::arrayAt(fr.require("vertices"), fr.pointerOf("vertices"));
                if (ends.size() != 2 || !ends[0].is_number_integer() ||
                    !ends[1].is_number_integer()) {
                    fr.fail("vertices", "must be two vertex indices of an interior edge");
                }
                const int a = ends[0].get<int>();
                const int b = ends[1].get<int>();
                const double angleDeg = fr.number("angle_deg");
                if (!(std::abs(angleDeg) < 180.0)) {
                    fr.fail("angle_deg", "must be strictly between -180 and 180");
                }
                fr.finish();
                int hinge = -1;
                for (int h = 0; h < cloth.mesh.hinges.rows(); ++h) {
                    const int u = cloth.mesh.hinges(h, 0);
                    const int v = cloth.mesh.hinges(h, 1);
                    if ((u == a && v == b) || (u == b && v == a)) {
                        hinge = h;
                        break;
                    }
                }
                if (hinge < 0) {
                    fr.fail("vertices", "(" + std::to_string(a) + ", " + std::to_string(b) +
                                            ") is not an interior edge of this cloth");
                }
                cloth.restAngles[hinge] = angleDeg * 3.14159265358979323846 / 180.0;
            }
        }
        r.finish();
        m_cloths.push_back(info);
        m_scene.cloths.push_back(std::move(cloth));
    }

    const ClothInfo& clothRef(ObjectReader& r, std::string_view key) const {
        const json& ref = r.require(key);
        if (ref.is_string()) {
            for (const ClothInfo& c : m_cloths) {
                if (c.name == ref.get<std::string>()) {
                    return c;
                }
            }
            std::string names;
            for (const ClothInfo& c : m_cloths) {
                names += (names.empty() ? "" : ", ") + inQuotes(c.name);
            }
            r.fail(key, "no cloth named " + inQuotes(ref.get<std::string>()) +
                            " (cloths: " + names + ")");
        }
        const long long index = detail::integerAt(ref, r.pointerOf(key));
        if (index < 0 || index >= static_cast<long long>(m_cloths.size())) {
            r.fail(key, "cloth index " + std::to_string(index) + " out of range [0, " +
                            std::to_string(m_cloths.size()) + ")");
        }
        return m_cloths[static_cast<std::size_t>(index)];
    }

    static int localVertex(ObjectReader& r, const ClothInfo& cloth, const json& value,
                           const std::string& pointer) {
        const long long v = detail::integerAt(value, pointer);
        if (v < 0 || v >= cloth.vertexCount) {
            throw JsonError{pointer, "vertex " + std::to_string(v) + " out of range [0, " +
                                         std::to_string(cloth.vertexCount) + ") of cloth " +
                                         inQuotes(cloth.name)};
        }
        (void)r;
        return static_cast<int>(v);
    }

    static int cornerVertex(ObjectReader& r, const ClothInfo& cloth, std::string_view key) {
        const std::string corner = r.string(key);
        if (!cloth.rectangle) {
            r.fail(key, "corners are defined only for rectangle meshes; cloth " +
                            inQuotes(cloth.name) + " is not one (give a vertex)");
        }
        const int v = rectangleCorner(corner, cloth.cellsX, cloth.cellsY);
        if (v < 0) {
            r.fail(key, "unknown corner " + inQuotes(corner) +
                            " (expected \"top-left\", \"top-right\", \"bottom-left\" or "
                            "\"bottom-right\")");
        }
        return v;
    }

    /// One global vertex from `vertexKey` or `cornerKey` (exactly one of them).
    int vertexRef(ObjectReader& r, const ClothInfo& cloth, std::string_view vertexKey,
                  std::string_view cornerKey) const {
        const bool hasVertex = r.has(vertexKey);
        const bool hasCorner = r.has(cornerKey);
        if (hasVertex == hasCorner) {
            r.allow({vertexKey, cornerKey});
            r.fail("give exactly one of \"" + std::string(vertexKey) + "\" and \"" +
                   std::string(cornerKey) + "\"");
        }
        if (hasVertex) {
            return cloth.offset +
                   localVertex(r, cloth, r.require(vertexKey), r.pointerOf(vertexKey));
        }
        r.allow({vertexKey});
        return cloth.offset + cornerVertex(r, cloth, cornerKey);
    }

    void readPin(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        const ClothInfo& cloth = clothRef(r, "cloth");
        const int given = static_cast<int>(r.has("vertex")) + static_cast<int>(r.has("vertices")) +
                          static_cast<int>(r.has("corner")) + static_cast<int>(r.has("edge"));
        r.allow({"vertex", "vertices", "corner", "edge"});
        if (given != 1) {
            r.fail("give exactly one of \"vertex\", \"vertices\", \"corner\" and \"edge\"");
        }
        if (r.has("vertex")) {
            m_scene.pins.push_back(
                cloth.offset + localVertex(r, cloth, r.require("vertex"), r.pointerOf("vertex")));
        } else if (r.has("vertices")) {
            const std::string vp = r.pointerOf("vertices");
            const json& list = detail::arrayAt(r.require("vertices"), vp);
            for (std::size_t i = 0; i < list.size(); ++i) {
                m_scene.pins.push_back(cloth.offset +
                                       localVertex(r, cloth, list[i], detail::childPointer(vp, i)));
            }
        } else if (r.has("corner")) {
            m_scene.pins.push_back(cloth.offset + cornerVertex(r, cloth, "corner"));
        } else {
            for (const int v : edgeVertices(r, cloth, "edge")) {
                m_scene.pins.push_back(cloth.offset + v);
            }
        }
        r.finish();
    }

    /// The local vertices of a rectangle border ("left", "right", "top", "bottom").
    static std::vector<int> edgeVertices(ObjectReader& r, const ClothInfo& cloth,
                                         std::string_view key) {
        const std::string edge = r.string(key);
        if (!cloth.rectangle) {
            r.fail(key, "edges are defined only for rectangle meshes; cloth " +
                            inQuotes(cloth.name) + " is not one");
        }
        const int nx = cloth.cellsX;
        const int ny = cloth.cellsY;
        std::vector<int> out;
        if (edge == "left" || edge == "right") {
            for (int j = 0; j <= ny; ++j) {
                out.push_back(j * (nx + 1) + (edge == "left" ? 0 : nx));
            }
        } else if (edge == "bottom" || edge == "top") {
            for (int i = 0; i <= nx; ++i) {
                out.push_back((edge == "bottom" ? 0 : ny) * (nx + 1) + i);
            }
        } else {
            r.fail(key, "unknown edge " + inQuotes(edge) +
                            " (expected \"left\", \"right\", \"top\" or \"bottom\")");
        }
        return out;
    }

    void readDrive(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        const ClothInfo& cloth = clothRef(r, "cloth");
        const sim::ClothSpec& spec =
            m_scene.cloths[static_cast<std::size_t>(&cloth - m_cloths.data())];
        const bool relative = r.boolean("relative", false);
        std::vector<int> vertices;
        if (r.has("edge")) {
            r.allow({"vertex", "corner"});
            if (r.has("vertex") || r.has("corner")) {
                r.fail("give exactly one of \"vertex\", \"corner\" and \"edge\"");
            }
            if (!relative) {
                r.fail("edge", "an edge drive moves every vertex of the edge by the same "
                               "offset: it needs \"relative\": true");
            }
            for (const int v : edgeVertices(r, cloth, "edge")) {
                vertices.push_back(cloth.offset + v);
            }
        } else {
            r.allow({"edge"});
            vertices.push_back(vertexRef(r, cloth, "vertex", "corner"));
        }
        const std::string kp = r.pointerOf("keys");
        const json& keys = detail::arrayAt(r.require("keys"), kp);
        if (keys.empty()) {
            r.fail("keys", "a drive needs at least one key [t, x, y, z]");
        }
        sim::Drive drive;
        for (std::size_t i = 0; i < keys.size(); ++i) {
            const std::string p = detail::childPointer(kp, i);
            if (!keys[i].is_array() || keys[i].size() != 4) {
                throw JsonError{p,
                                "expected a key [t, x, y, z], found " + detail::typeName(keys[i])};
            }
            const double t = detail::numberAt(keys[i][0], p + "/0");
            const sim::Vec3 x(detail::numberAt(keys[i][1], p + "/1"),
                              detail::numberAt(keys[i][2], p + "/2"),
                              detail::numberAt(keys[i][3], p + "/3"));
            if (!drive.times.empty() && !(t > drive.times.back())) {
                throw JsonError{p + "/0", "key times must increase"};
            }
            detail::checkCoordinates(x.transpose(), m_limits, p, "the key's position");
            drive.times.push_back(t);
            drive.positions.push_back(x);
        }
        drive.releaseTime = r.number("release_time", drive.releaseTime);
        drive.followTimeConstant = r.nonNegative("follow_time_constant", drive.followTimeConstant);
        r.finish();
        for (const int v : vertices) {
            sim::Drive d = drive;
            d.vertex = v;
            if (relative) {
                const sim::Vec3 start = spec.position.row(v - cloth.offset).transpose();
                for (sim::Vec3& x : d.positions) {
                    x += start;
                }
            }
            m_scene.drives.push_back(std::move(d));
        }
    }

    void readSeam(const json& value, const std::string& ptr) {
        ObjectReader r(value, ptr);
        sim::SeamPair seam;
        seam.a = vertexRef(r, clothRef(r, "cloth_a"), "vertex_a", "corner_a");
        seam.b = vertexRef(r, clothRef(r, "cloth_b"), "vertex_b", "corner_b");
        if (seam.a == seam.b) {
            r.fail("a seam joins two different vertices; both ends are the same vertex");
        }
        r.finish();
        m_scene.seams.push_back(seam);
    }

    void readCollision(ObjectReader r) {
        sim::CollisionOptions& o = m_scene.collision;
        o.continuous = r.boolean("continuous", o.continuous);
        const long long iterations = r.integer("iterations", o.iterations);
        if (iterations < 1 || iterations > MAX_COLLISION_ITERATIONS) {
            r.fail("iterations",
                   "must be an integer in [1, " + std::to_string(MAX_COLLISION_ITERATIONS) + "]");
        }
        o.iterations = static_cast<int>(iterations);
        o.proximityFactor = r.nonNegative("proximity_factor", o.proximityFactor);
        o.extractionSpeed = r.positive("extraction_speed", o.extractionSpeed);
        o.failSafe = r.boolean("fail_safe", o.failSafe);
        o.solveContacts = r.boolean("solve_contacts", o.solveContacts);
        o.solve.stiffness = r.positive("contact_stiffness", o.solve.stiffness);
        o.solve.margin = r.positive("contact_layer", o.solve.margin);
        o.solve.slipSpeed = r.positive("friction_slip_speed", o.solve.slipSpeed);
        o.solve.selfContacts = r.boolean("solve_self_contacts", o.solve.selfContacts);
        r.finish();
    }

    void readGravity(ObjectReader& r) {
        const json* gravity = r.find("gravity");
        if (gravity == nullptr) {
            return;
        }
        if (gravity->is_boolean()) {
            m_scene.gravity = gravity->get<bool>();
        } else {
            m_scene.gravity = true;
            m_scene.gravityVector = detail::vec3At(*gravity, r.pointerOf("gravity"));
        }
    }

    void readIntegrator(ObjectReader r) {
        sim::IntegratorOptions& o = m_scene.integrator;
        const std::string type = r.string("type", std::string(sim::integratorName(o.kind)));
        const auto kind = sim::integratorFromName(type);
        if (!kind) {
            r.fail("type", "unknown integrator " + inQuotes(type) + " (expected one of " +
                               nameList(sim::INTEGRATOR_KINDS, &sim::integratorName) + ")");
        }
        o.kind = *kind;
        o.dt = r.positive("dt", o.dt);
        o.tolerance = r.positive("tolerance", o.tolerance);
        o.minDt = r.positive("min_dt", o.minDt);
        o.maxDt = r.positive("max_dt", o.maxDt);
        o.growth = r.positive("growth", o.growth);
        o.cgTolerance = r.positive("cg_tolerance", o.cgTolerance);
        const long long cgMax = r.integer("cg_max_iterations", o.cgMaxIterations);
        if (cgMax < 1 || cgMax > MAX_CG_ITERATIONS) {
            r.fail("cg_max_iterations",
                   "must be an integer in [1, " + std::to_string(MAX_CG_ITERATIONS) + "]");
        }
        o.cgMaxIterations = static_cast<int>(cgMax);
        if (const auto solver = r.optionalString("linear_solver")) {
            const auto kind = sim::linearSolverFromName(*solver);
            if (!kind) {
                r.fail("linear_solver",
                       "unknown linear solver " + inQuotes(*solver) + " (expected one of " +
                           nameList(sim::LINEAR_SOLVERS, &sim::linearSolverName) + ")");
            }
            o.linearSolver = kind.value_or(o.linearSolver);
        }
        if (!(o.growth > 1)) {
            r.fail("growth", "must be greater than 1");
        }
        if (o.minDt > o.maxDt) {
            r.fail("min_dt", "must not exceed max_dt");
        }
        if (o.dt < o.minDt) {
            r.fail("dt", "must not be below min_dt");
        }
        r.finish();
    }

    std::string m_file;
    std::filesystem::path m_baseDir;
    MaterialPresets m_presets;
    const Limits& m_limits;
    detail::SceneSize m_size;
    sim::SceneSpec m_scene;
    std::vector<ClothInfo> m_cloths;
    std::map<std::size_t, sim::MatX3> m_placed; ///< cloth index → positions before a random start
};

} // namespace

int rectangleCorner(std::string_view corner, int cellsX, int cellsY) {
    const int top = cellsY * (cellsX + 1);
    if (corner == "bottom-left") {
        return 0;
    }
    if (corner == "bottom-right") {
        return cellsX;
    }
    if (corner == "top-left") {
        return top;
    }
    if (corner == "top-right") {
        return top + cellsX;
    }
    return -1;
}

Result<sim::SceneSpec> parseScene(std::string_view text, const std::string& file,
                                  const std::filesystem::path& baseDir,
                                  const SceneLoadOptions& options) {
    auto parsed = detail::parseJson(std::string(text), file, options.limits.maxJsonDepth);
    if (!parsed.ok()) {
        return parsed.error();
    }
    sim::SceneSpec scene;
    try {
        scene = SceneParser(file, baseDir, options).parse(parsed.value());
    } catch (const JsonError& e) {
        return Error{file, e.where, e.message};
    }
    if (options.validate) {
        if (auto message = sim::Simulation::validate(scene)) {
            return Error{file, "", *message};
        }
    }
    return scene;
}

Result<sim::SceneSpec> loadScene(const std::filesystem::path& path,
                                 const SceneLoadOptions& options) {
    auto text = readFile(path, options.limits.maxJsonBytes);
    if (!text.ok()) {
        return text.error();
    }
    return parseScene(text.value(), path.string(), path.parent_path(), options);
}

} // namespace atelier::io
