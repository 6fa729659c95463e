#include "io/obj.h"

#include "io/atomic_file.h"

#include "sim/mesh/vertex_normals.h"

#include <Eigen/Geometry>

#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <string_view>
#include <utility>

namespace atelier::io {

namespace {

/// Splits off the next whitespace-separated token of `s`.
std::string_view nextToken(std::string_view& s) {
    std::size_t b = 0;
    while (b < s.size() && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) {
        ++b;
    }
    std::size_t e = b;
    while (e < s.size() && s[e] != ' ' && s[e] != '\t' && s[e] != '\r') {
        ++e;
    }
    const std::string_view token = s.substr(b, e - b);
    s.remove_prefix(e);
    return token;
}

bool parseDouble(std::string_view token, double& out) {
    if (!token.empty() && token.front() == '+') {
        token.remove_prefix(1);
    }
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), out);
    return ec == std::errc() && ptr == token.data() + token.size();
}

bool parseInt(std::string_view token, long& out) {
    if (!token.empty() && token.front() == '+') {
        token.remove_prefix(1);
    }
    const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), out);
    return ec == std::errc() && ptr == token.data() + token.size() && !token.empty();
}

struct Corner {
    int v = -1;  ///< 0-based position index
    int vt = -1; ///< 0-based texture index, -1 = none
};

class ObjParser {
  public:
    explicit ObjParser(std::string file) : m_file(std::move(file)) {}

    Result<ObjMesh> parse(std::string_view text) {
        int lineNo = 0;
        while (!text.empty()) {
            const std::size_t nl = text.find('\n');
            std::string_view line = text.substr(0, nl);
            text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
            ++lineNo;
            m_line = lineNo;
            if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
                line = line.substr(0, hash);
            }
            if (auto error = parseLine(line)) {
                return *error;
            }
        }
        return finish();
    }

  private:
    Error error(std::string message) const {
        return Error{m_file, "line " + std::to_string(m_line), std::move(message)};
    }

    std::optional<Error> readNumbers(std::string_view& rest, std::string_view what, int required,
                                     int allowed, std::array<double, 4>& out) {
        int n = 0;
        for (std::string_view token = nextToken(rest); !token.empty(); token = nextToken(rest)) {
            if (n >= allowed) {
                // Extra values (such as vertex colours after `v x y z`) are ignored.
                break;
            }
            double value = 0;
            if (!parseDouble(token, value)) {
                return error(std::string(what) + ": '" + std::string(token) + "' is not a number");
            }
            if (!std::isfinite(value)) {
                return error(std::string(what) + ": coordinate is not finite");
            }
            out[static_cast<std::size_t>(n++)] = value;
        }
        if (n < required) {
            return error(std::string(what) + ": expected " + std::to_string(required) +
                         " coordinates, found " + std::to_string(n));
        }
        return std::nullopt;
    }

    std::optional<Error> resolveIndex(std::string_view token, std::size_t count,
                                      std::string_view what, int& out) {
        long index = 0;
        if (!parseInt(token, index)) {
            return error("face: '" + std::string(token) + "' is not an index");
        }
        const long n = static_cast<long>(count);
        const long resolved = index < 0 ? n + index : index - 1;
        if (index == 0 || resolved < 0 || resolved >= n) {
            return error("face: " + std::string(what) + " index " + std::to_string(index) +
                         (n == 0 ? " but no " + std::string(what) + " is defined yet"
                                 : " out of range [1, " + std::to_string(n) + "] or [-" +
                                       std::to_string(n) + ", -1]"));
        }
        out = static_cast<int>(resolved);
        return std::nullopt;
    }

    std::optional<Error> parseLine(std::string_view line) {
        std::string_view rest = line;
        const std::string_view keyword = nextToken(rest);
        if (keyword.empty()) {
            return std::nullopt;
        }
        std::array<double, 4> values{};
        if (keyword == "v") {
            if (auto e = readNumbers(rest, "vertex", 3, 3, values)) {
                return e;
            }
            m_positions.push_back(sim::Vec3(values[0], values[1], values[2]));
        } else if (keyword == "vt") {
            if (auto e = readNumbers(rest, "texture coordinate", 1, 3, values)) {
                return e;
            }
            m_uvs.push_back(sim::Vec2(values[0], values[1]));
        } else if (keyword == "vn") {
            if (auto e = readNumbers(rest, "normal", 3, 3, values)) {
                return e;
            }
            ++m_normalCount;
        } else if (keyword == "f") {
            return parseFace(rest);
        } else if (keyword == "g" || keyword == "o") {
            std::string name(nextToken(rest));
            for (std::string_view more = nextToken(rest); !more.empty(); more = nextToken(rest)) {
                name += ' ';
                name += more;
            }
            startGroup(name.empty() ? "default" : name);
        }
        // Anything else (mtllib, usemtl, s, l, p, curves, ...) carries no triangle geometry.
        return std::nullopt;
    }

    std::optional<Error> parseFace(std::string_view rest) {
        std::vector<Corner> corners;
        for (std::string_view token = nextToken(rest); !token.empty(); token = nextToken(rest)) {
            Corner c;
            const std::size_t s1 = token.find('/');
            const std::string_view vPart = token.substr(0, s1);
            if (auto e = resolveIndex(vPart, m_positions.size(), "vertex", c.v)) {
                return e;
            }
            if (s1 != std::string_view::npos) {
                const std::string_view after = token.substr(s1 + 1);
                const std::size_t s2 = after.find('/');
                const std::string_view vtPart = after.substr(0, s2);
                if (!vtPart.empty()) {
                    if (auto e = resolveIndex(vtPart, m_uvs.size(), "texture coordinate", c.vt)) {
                        return e;
                    }
                }
                if (s2 != std::string_view::npos) {
                    int vn = 0;
                    if (auto e = resolveIndex(after.substr(s2 + 1), m_normalCount, "normal", vn)) {
                        return e;
                    }
                }
            }
            const bool hasVt = c.vt >= 0;
            if (m_faceHasVt == -1) {
                m_faceHasVt = hasVt ? 1 : 0;
            } else if (m_faceHasVt != (hasVt ? 1 : 0)) {
                return error("face: some corners have texture coordinates and some do not "
                             "(earlier faces " +
                             std::string(m_faceHasVt == 1 ? "have" : "do not have") + " them)");
            }
            corners.push_back(c);
        }
        if (corners.size() < 3) {
            return error("face: needs at least 3 vertices, found " +
                         std::to_string(corners.size()));
        }
        for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
            m_faces.push_back({corners[0], corners[i], corners[i + 1]});
        }
        return std::nullopt;
    }

    void startGroup(std::string name) {
        closeGroup();
        if (m_groups.empty() && !m_faces.empty()) {
            m_groups.push_back(ObjGroup{"default", 0, static_cast<int>(m_faces.size())});
        }
        m_openGroup = ObjGroup{std::move(name), static_cast<int>(m_faces.size()), 0};
        m_hasOpenGroup = true;
    }

    void closeGroup() {
        if (!m_hasOpenGroup) {
            return;
        }
        m_openGroup.triangleCount = static_cast<int>(m_faces.size()) - m_openGroup.firstTriangle;
        if (m_openGroup.triangleCount > 0) {
            m_groups.push_back(m_openGroup);
        }
        m_hasOpenGroup = false;
    }

    Result<ObjMesh> finish() {
        closeGroup();
        ObjMesh mesh;
        mesh.groups = std::move(m_groups);
        const int nf = static_cast<int>(m_faces.size());
        mesh.triangles.resize(nf, 3);
        if (m_faceHasVt == 1) {
            // One vertex per distinct (v, vt) pair, ordered by (v, vt).
            std::map<std::pair<int, int>, int> ids;
            for (const auto& face : m_faces) {
                for (const Corner& c : face) {
                    ids.emplace(std::make_pair(c.v, c.vt), 0);
                }
            }
            int next = 0;
            for (auto& [key, id] : ids) {
                id = next++;
            }
            mesh.positions.resize(next, 3);
            mesh.uvs.resize(next, 2);
            mesh.sourceVertex.resize(static_cast<std::size_t>(next));
            for (const auto& [key, id] : ids) {
                mesh.positions.row(id) = m_positions[static_cast<std::size_t>(key.first)];
                mesh.uvs.row(id) = m_uvs[static_cast<std::size_t>(key.second)];
                mesh.sourceVertex[static_cast<std::size_t>(id)] = key.first;
            }
            for (int f = 0; f < nf; ++f) {
                for (int k = 0; k < 3; ++k) {
                    const Corner& c =
                        m_faces[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)];
                    mesh.triangles(f, k) = ids.at({c.v, c.vt});
                }
            }
        } else {
            const int nv = static_cast<int>(m_positions.size());
            mesh.positions.resize(nv, 3);
            mesh.sourceVertex.resize(static_cast<std::size_t>(nv));
            for (int i = 0; i < nv; ++i) {
                mesh.positions.row(i) = m_positions[static_cast<std::size_t>(i)];
                mesh.sourceVertex[static_cast<std::size_t>(i)] = i;
            }
            for (int f = 0; f < nf; ++f) {
                for (int k = 0; k < 3; ++k) {
                    mesh.triangles(f, k) =
                        m_faces[static_cast<std::size_t>(f)][static_cast<std::size_t>(k)].v;
                }
            }
        }
        return mesh;
    }

    std::string m_file;
    int m_line = 0;
    std::vector<sim::Vec3> m_positions;
    std::vector<sim::Vec2> m_uvs;
    std::size_t m_normalCount = 0;
    std::vector<std::array<Corner, 3>> m_faces;
    int m_faceHasVt = -1; ///< -1 = no face yet, 0 = faces have no vt, 1 = they all have vt
    std::vector<ObjGroup> m_groups;
    ObjGroup m_openGroup;
    bool m_hasOpenGroup = false;
};

/// A group name as one OBJ token: control characters, whitespace and `#` (which would end the
/// line, split the name or start a comment) become `_`; an empty name is "default".
std::string objName(std::string_view name) {
    if (name.empty()) {
        return "default";
    }
    std::string out(name);
    for (char& c : out) {
        const auto u = static_cast<unsigned char>(c);
        if (u <= 0x20 || u == 0x7f || c == '#') {
            c = '_';
        }
    }
    return out;
}

/// Appends `comment` as `# ` lines; control characters other than the line breaks become
/// spaces, so that no reader sees a statement in it.
void appendComment(std::string& out, std::string_view comment) {
    while (!comment.empty()) {
        const std::size_t nl = comment.find('\n');
        out += "# ";
        for (const char c : comment.substr(0, nl)) {
            const auto u = static_cast<unsigned char>(c);
            out += u < 0x20 || u == 0x7f ? ' ' : c;
        }
        out += '\n';
        comment.remove_prefix(nl == std::string_view::npos ? comment.size() : nl + 1);
    }
}

void appendNumber(std::string& out, double value) {
    std::array<char, 32> buffer{};
    const auto [ptr, ec] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
    out.append(buffer.data(), ec == std::errc() ? ptr : buffer.data());
}

} // namespace

Result<ObjMesh> readObj(const std::filesystem::path& path, std::uint64_t maxBytes) {
    auto text = readFile(path, maxBytes);
    if (!text.ok()) {
        return text.error();
    }
    return ObjParser(path.string()).parse(text.value());
}

Result<std::string> formatObj(const sim::MatX3& positions, const sim::MatX3i& triangles,
                              const ObjWriteOptions& options) {
    const Eigen::Index nv = positions.rows();
    const Eigen::Index nf = triangles.rows();
    const bool withUvs = options.uvs.rows() > 0;
    const bool uvCorners = options.uvTriangles.rows() > 0;
    if (withUvs && !uvCorners && options.uvs.rows() != nv) {
        return Error{"", "",
                     "uvs have " + std::to_string(options.uvs.rows()) + " rows, positions " +
                         std::to_string(nv)};
    }
    if (uvCorners) {
        if (!withUvs || options.uvTriangles.rows() != nf) {
            return Error{"", "",
                         "uv triangles have " + std::to_string(options.uvTriangles.rows()) +
                             " rows, triangles " + std::to_string(nf) + " (and uvs are needed)"};
        }
        if (options.uvTriangles.minCoeff() < 0 ||
            options.uvTriangles.maxCoeff() >= options.uvs.rows()) {
            return Error{"", "", "a uv triangle's index is out of range"};
        }
    }
    for (Eigen::Index f = 0; f < nf; ++f) {
        for (int k = 0; k < 3; ++k) {
            if (triangles(f, k) < 0 || triangles(f, k) >= nv) {
                return Error{"", "",
                             "triangle " + std::to_string(f) + ": vertex index " +
                                 std::to_string(triangles(f, k)) + " out of range"};
            }
        }
    }
    for (const ObjGroup& g : options.groups) {
        if (g.firstTriangle < 0 || g.triangleCount < 0 || g.firstTriangle + g.triangleCount > nf) {
            return Error{"", "", "group '" + g.name + "' is out of the triangle range"};
        }
    }

    std::string out;
    out.reserve(static_cast<std::size_t>(nv * 90 + nf * 40));
    appendComment(out, options.comment);
    if (!options.materialLibrary.empty()) {
        out += "mtllib " + objName(options.materialLibrary) + '\n';
    }
    for (Eigen::Index i = 0; i < nv; ++i) {
        out += 'v';
        for (int k = 0; k < 3; ++k) {
            out += ' ';
            appendNumber(out, positions(i, k));
        }
        out += '\n';
    }
    if (withUvs) {
        for (Eigen::Index i = 0; i < options.uvs.rows(); ++i) {
            out += "vt ";
            appendNumber(out, options.uvs(i, 0));
            out += ' ';
            appendNumber(out, options.uvs(i, 1));
            out += '\n';
        }
    }
    if (options.normals) {
        sim::MatX3 normals;
        sim::vertexNormals(positions, triangles, normals);
        for (Eigen::Index i = 0; i < nv; ++i) {
            const sim::Vec3 n = normals.row(i);
            out += "vn";
            for (int k = 0; k < 3; ++k) {
                out += ' ';
                appendNumber(out, n[k]);
            }
            out += '\n';
        }
    }
    std::vector<const ObjGroup*> groupAt(static_cast<std::size_t>(nf), nullptr);
    for (const ObjGroup& g : options.groups) {
        if (g.triangleCount > 0) {
            groupAt[static_cast<std::size_t>(g.firstTriangle)] = &g;
        }
    }
    for (Eigen::Index f = 0; f < nf; ++f) {
        if (const ObjGroup* g = groupAt[static_cast<std::size_t>(f)]) {
            out += "g ";
            out += objName(g->name);
            out += '\n';
            if (!options.materialLibrary.empty()) {
                out += "usemtl ";
                out += objName(g->name);
                out += '\n';
            }
        }
        out += 'f';
        for (int k = 0; k < 3; ++k) {
            const std::string i = std::to_string(triangles(f, k) + 1);
            const std::string t = uvCorners ? std::to_string(options.uvTriangles(f, k) + 1) : i;
            out += ' ';
            out += i;
            if (withUvs && options.normals) {
                out += '/' + t + '/' + i;
            } else if (withUvs) {
                out += '/' + t;
            } else if (options.normals) {
                out += "//" + i;
            }
        }
        out += '\n';
    }
    return out;
}

Result<void> writeObj(const std::filesystem::path& path, const sim::MatX3& positions,
                      const sim::MatX3i& triangles, const ObjWriteOptions& options) {
    auto text = formatObj(positions, triangles, options);
    if (!text.ok()) {
        Error e = text.error();
        e.file = path.string();
        return e;
    }
    return writeFileAtomically(path, text.value());
}

} // namespace atelier::io
