#pragma once
// Reading back the SVG that io/pattern_svg writes, for its tests: a strict little XML reader
// (elements, attributes, text, comments, the five named entities and character references;
// no DTD, CDATA or processing instructions after the declaration) and a sampler of the path
// commands the writer uses (absolute M, L, Q, C, A, Z).

#include "sim/core/types.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::test {

struct XmlNode {
    std::string name;
    std::map<std::string, std::string> attributes;
    std::string text; ///< the element's own text, entities decoded
    std::vector<XmlNode> children;

    std::string attribute(const std::string& key) const {
        const auto it = attributes.find(key);
        return it == attributes.end() ? std::string() : it->second;
    }
    /// This node's descendants (not itself) named `tag`, in document order.
    void collect(const std::string& tag, std::vector<const XmlNode*>& out) const {
        for (const XmlNode& child : children) {
            if (child.name == tag) {
                out.push_back(&child);
            }
            child.collect(tag, out);
        }
    }
    std::vector<const XmlNode*> all(const std::string& tag) const {
        std::vector<const XmlNode*> out;
        collect(tag, out);
        return out;
    }
    /// The text of this element and its descendants.
    std::string allText() const {
        std::string s = text;
        for (const XmlNode& child : children) {
            s += child.allText();
        }
        return s;
    }
};

/// Parses a whole document; on malformed XML, the error with its byte offset.
class XmlReader {
  public:
    explicit XmlReader(std::string_view text) : m_s(text) {}

    std::optional<XmlNode> parse() {
        if (m_s.substr(0, 5) == "<?xml") {
            const auto end = m_s.find("?>");
            if (end == std::string_view::npos) {
                return fail("unterminated XML declaration");
            }
            m_i = end + 2;
        }
        skipMisc();
        XmlNode root;
        if (!element(root)) {
            return std::nullopt;
        }
        skipMisc();
        if (m_i != m_s.size()) {
            return fail("content after the root element");
        }
        return root;
    }
    const std::string& error() const { return m_error; }

  private:
    std::nullopt_t fail(const std::string& message) {
        if (m_error.empty()) {
            m_error = message + " at byte " + std::to_string(m_i);
        }
        return std::nullopt;
    }
    bool failed(const std::string& message) {
        fail(message);
        return false;
    }
    void skipSpace() {
        while (m_i < m_s.size() &&
               std::string_view(" \t\r\n").find(m_s[m_i]) != std::string_view::npos) {
            ++m_i;
        }
    }
    void skipMisc() {
        for (;;) {
            skipSpace();
            if (m_s.substr(m_i, 4) != "<!--") {
                return;
            }
            const auto end = m_s.find("-->", m_i + 4);
            m_i = end == std::string_view::npos ? m_s.size() : end + 3;
        }
    }
    static bool nameChar(char c, bool first) {
        return std::isalpha(static_cast<unsigned char>(c)) || c == '_' || c == ':' ||
               (!first && (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '.'));
    }
    bool name(std::string& out) {
        const std::size_t start = m_i;
        while (m_i < m_s.size() && nameChar(m_s[m_i], m_i == start)) {
            ++m_i;
        }
        out = std::string(m_s.substr(start, m_i - start));
        return !out.empty() || failed("expected a name");
    }
    /// Decodes entities in raw text; '<' is not allowed in it.
    bool decode(std::string_view raw, std::string& out) {
        for (std::size_t k = 0; k < raw.size(); ++k) {
            const char c = raw[k];
            if (c == '<') {
                return failed("'<' in text or attribute");
            }
            if (c != '&') {
                out += c;
                continue;
            }
            const auto semi = raw.find(';', k);
            if (semi == std::string_view::npos) {
                return failed("bare '&'");
            }
            const std::string_view entity = raw.substr(k + 1, semi - k - 1);
            static const std::map<std::string_view, char> named = {
                {"amp", '&'}, {"lt", '<'}, {"gt", '>'}, {"quot", '"'}, {"apos", '\''}};
            if (const auto it = named.find(entity); it != named.end()) {
                out += it->second;
            } else if (entity.size() > 1 && entity[0] == '#') {
                const bool hex = entity[1] == 'x';
                const long code = std::strtol(std::string(entity.substr(hex ? 2 : 1)).c_str(),
                                              nullptr, hex ? 16 : 10);
                if (code <= 0 || code > 127) {
                    return failed("character reference outside ASCII (not used by the writer)");
                }
                out += static_cast<char>(code);
            } else {
                return failed("unknown entity &" + std::string(entity) + ";");
            }
            k = semi;
        }
        return true;
    }
    bool element(XmlNode& node) {
        if (m_i >= m_s.size() || m_s[m_i] != '<') {
            return failed("expected '<'");
        }
        ++m_i;
        if (!name(node.name)) {
            return false;
        }
        for (;;) {
            skipSpace();
            if (m_i >= m_s.size()) {
                return failed("unterminated tag");
            }
            if (m_s.substr(m_i, 2) == "/>") {
                m_i += 2;
                return true;
            }
            if (m_s[m_i] == '>') {
                ++m_i;
                break;
            }
            std::string key;
            if (!name(key)) {
                return false;
            }
            skipSpace();
            if (m_i >= m_s.size() || m_s[m_i] != '=') {
                return failed("attribute " + key + " without a value");
            }
            ++m_i;
            skipSpace();
            if (m_i >= m_s.size() || (m_s[m_i] != '"' && m_s[m_i] != '\'')) {
                return failed("unquoted attribute " + key);
            }
            const char quote = m_s[m_i++];
            const auto end = m_s.find(quote, m_i);
            if (end == std::string_view::npos) {
                return failed("unterminated attribute " + key);
            }
            std::string value;
            if (!decode(m_s.substr(m_i, end - m_i), value)) {
                return false;
            }
            if (!node.attributes.emplace(key, value).second) {
                return failed("duplicate attribute " + key);
            }
            m_i = end + 1;
        }
        for (;;) {
            const auto lt = m_s.find('<', m_i);
            if (lt == std::string_view::npos) {
                return failed("unterminated element " + node.name);
            }
            if (!decode(m_s.substr(m_i, lt - m_i), node.text)) {
                return false;
            }
            m_i = lt;
            if (m_s.substr(m_i, 4) == "<!--") {
                skipMisc();
                continue;
            }
            if (m_s.substr(m_i, 2) == "</") {
                m_i += 2;
                std::string closing;
                if (!name(closing)) {
                    return false;
                }
                skipSpace();
                if (closing != node.name || m_i >= m_s.size() || m_s[m_i] != '>') {
                    return failed("</" + closing + "> closes <" + node.name + ">");
                }
                ++m_i;
                return true;
            }
            node.children.emplace_back();
            if (!element(node.children.back())) {
                return false;
            }
        }
    }

    std::string_view m_s;
    std::size_t m_i = 0;
    std::string m_error;
};

/// One subpath of an SVG path, sampled: every curve by `samplesPerCurve` chords, lines as
/// they are, arcs exactly on their circle.
struct SampledSubpath {
    std::vector<sim::Vec2> points;
    bool closed = false;
};

/// Samples the absolute commands M, L, Q, C, A (rx = ry, no rotation) and Z; nullopt on
/// anything else or a missing number.
inline std::optional<std::vector<SampledSubpath>> samplePath(const std::string& d,
                                                             int samplesPerCurve = 200) {
    using sim::Vec2;
    std::istringstream in(d);
    std::vector<SampledSubpath> out;
    Vec2 current = Vec2::Zero();
    auto number = [&](double& v) { return static_cast<bool>(in >> v); };
    auto point = [&](Vec2& p) { return number(p.x()) && number(p.y()); };
    char op = 0;
    while (in >> op) {
        if (op == 'Z') {
            if (out.empty()) {
                return std::nullopt;
            }
            out.back().closed = true;
            current = out.back().points.front();
            continue;
        }
        if (op != 'M' && out.empty()) {
            return std::nullopt;
        }
        if (op == 'M') {
            if (!point(current)) {
                return std::nullopt;
            }
            out.push_back({{current}, false});
        } else if (op == 'L') {
            if (!point(current)) {
                return std::nullopt;
            }
            out.back().points.push_back(current);
        } else if (op == 'Q' || op == 'C') {
            Vec2 c1, c2, end;
            if (!point(c1) || (op == 'C' && !point(c2)) || !point(end)) {
                return std::nullopt;
            }
            const Vec2 p0 = current;
            for (int k = 1; k <= samplesPerCurve; ++k) {
                const double t = static_cast<double>(k) / samplesPerCurve, u = 1 - t;
                out.back().points.push_back(op == 'Q'
                                                ? Vec2(u * u * p0 + 2 * u * t * c1 + t * t * end)
                                                : Vec2(u * u * u * p0 + 3 * u * u * t * c1 +
                                                       3 * u * t * t * c2 + t * t * t * end));
            }
            current = end;
        } else if (op == 'A') {
            double rx, ry, rotation, large, sweep;
            Vec2 end;
            if (!number(rx) || !number(ry) || !number(rotation) || !number(large) ||
                !number(sweep) || !point(end) || rx != ry || rotation != 0) {
                return std::nullopt;
            }
            // SVG 1.1 F.6.5: endpoint to centre parameterisation (no rotation, rx = ry).
            const Vec2 half = 0.5 * (current - end);
            double r = rx;
            const double lambda = half.squaredNorm() / (r * r);
            if (lambda > 1) {
                r *= std::sqrt(lambda);
            }
            const double num = r * r * r * r - r * r * half.squaredNorm();
            double coef = std::sqrt(std::max(0.0, num / (r * r * half.squaredNorm())));
            if ((large != 0) == (sweep != 0)) {
                coef = -coef;
            }
            const Vec2 cp(coef * half.y(), -coef * half.x());
            const Vec2 centre = cp + 0.5 * (current + end);
            const Vec2 u = (half - cp) / r, v = (-half - cp) / r;
            const double theta1 = std::atan2(u.y(), u.x());
            double delta = std::atan2(u.x() * v.y() - u.y() * v.x(), u.dot(v));
            if (sweep == 0 && delta > 0) {
                delta -= 2 * std::numbers::pi;
            } else if (sweep != 0 && delta < 0) {
                delta += 2 * std::numbers::pi;
            }
            for (int k = 1; k <= samplesPerCurve; ++k) {
                const double a = theta1 + delta * k / samplesPerCurve;
                out.back().points.push_back(centre + r * Vec2(std::cos(a), std::sin(a)));
            }
            out.back().points.back() = end;
            current = end;
        } else {
            return std::nullopt;
        }
    }
    return out;
}

/// Length of a sampled subpath (with its closing chord when closed).
inline double pathLength(const SampledSubpath& sub) {
    double length = 0;
    for (std::size_t i = 1; i < sub.points.size(); ++i) {
        length += (sub.points[i] - sub.points[i - 1]).norm();
    }
    if (sub.closed && sub.points.size() > 1) {
        length += (sub.points.front() - sub.points.back()).norm();
    }
    return length;
}

} // namespace atelier::test
