#include "io/dxf_reader.h"

#include <array>
#include <charconv>
#include <cmath>
#include <optional>

namespace atelier::io {

namespace {

using sim::Vec2;

struct DxfSyntaxError {
    int line;
    std::string message;
};

[[noreturn]] void fail(int line, std::string message) {
    throw DxfSyntaxError{line, std::move(message)};
}

/// One group of the file: a code and its value, with the code's line.
struct Group {
    int code = -1;
    std::string_view value;
    int line = 0;
};

/// Reads groups one at a time, with one group of lookahead.
class Reader {
  public:
    explicit Reader(std::string_view text) : m_text(text) {
        // A UTF-8 byte order mark before the first group.
        if (m_text.substr(0, 3) == "\xEF\xBB\xBF") {
            m_text.remove_prefix(3);
        }
        advance();
    }
    bool done() const { return m_next.code < 0; }
    const Group& peek() const { return m_next; }
    Group take() {
        Group g = m_next;
        advance();
        return g;
    }

  private:
    std::optional<std::string_view> nextLine() {
        if (m_pos >= m_text.size()) {
            return std::nullopt;
        }
        const std::size_t end = m_text.find('\n', m_pos);
        const std::size_t stop = end == std::string_view::npos ? m_text.size() : end;
        std::string_view line = m_text.substr(m_pos, stop - m_pos);
        m_pos = stop + 1;
        ++m_line;
        return line;
    }
    void advance() {
        std::optional<std::string_view> code = nextLine();
        while (code && dxfTrimmed(*code).empty() && m_pos >= m_text.size()) {
            code.reset(); // trailing blank line
        }
        if (!code) {
            m_next = Group{};
            return;
        }
        const int line = m_line;
        const std::string_view c = dxfTrimmed(*code);
        int value = -1;
        const auto [end, ec] = std::from_chars(c.data(), c.data() + c.size(), value);
        if (c.empty() || ec != std::errc() || end != c.data() + c.size() || value < 0 ||
            value > 1071) {
            fail(line, "group code " + dxfShown(c) +
                           " is not a DXF group code (a whole number from 0 to 1071): is this "
                           "an ASCII DXF file?");
        }
        const std::optional<std::string_view> v = nextLine();
        if (!v) {
            fail(line, "group code " + std::to_string(value) + " has no value: the file ends");
        }
        m_next = Group{value, dxfTrimmed(*v), line};
    }

    std::string_view m_text;
    std::size_t m_pos = 0;
    int m_line = 0;
    Group m_next;
};

double number(const Group& g) {
    double v = 0;
    const std::string_view s = g.value;
    const char* begin = s.data();
    if (!s.empty() && s.front() == '+') {
        ++begin;
    }
    const auto [end, ec] = std::from_chars(begin, s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) {
        fail(g.line + 1,
             "group " + std::to_string(g.code) + ": " + dxfShown(s) + " is not a finite number");
    }
    return v;
}

int integer(const Group& g) {
    const double v = number(g);
    if (v != std::floor(v) || std::abs(v) > 1e9) {
        fail(g.line + 1, "group " + std::to_string(g.code) + ": " + dxfShown(g.value) +
                             " is not a whole number");
    }
    return static_cast<int>(v);
}

int layerNumber(std::string_view name, DxfDrawing& file) {
    int v = -1;
    const auto [end, ec] = std::from_chars(name.data(), name.data() + name.size(), v);
    if (name.empty() || ec != std::errc() || end != name.data() + name.size()) {
        if (file.otherLayers.size() < 20) {
            file.otherLayers.insert(std::string(name.substr(0, 40)));
        }
        return -1;
    }
    return v;
}

/// MTEXT's paragraph breaks and formatting codes (`\P`, `\A1;`) as plain text.
std::string plainText(std::string_view s) {
    std::string out;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (s[i] == '\\' && i + 1 < s.size()) {
            const char c = s[i + 1];
            if (c == 'P' || c == 'p') {
                out += '\n';
                ++i;
                continue;
            }
            if (std::string_view("ACFHQTWfhcpq").find(c) != std::string_view::npos) {
                const std::size_t semi = s.find(';', i);
                if (semi != std::string_view::npos) {
                    i = semi;
                    continue;
                }
            }
        }
        if (s[i] != '{' && s[i] != '}') {
            out += s[i];
        }
    }
    return out;
}

class FileReader {
  public:
    explicit FileReader(std::string_view text) : m_in(text) {}

    DxfDrawing read() {
        while (!m_in.done()) {
            const Group g = m_in.take();
            if (g.code != 0) {
                continue; // stray groups between sections
            }
            if (g.value == "EOF") {
                break;
            }
            if (g.value != "SECTION") {
                continue;
            }
            if (m_in.done() || m_in.peek().code != 2) {
                fail(g.line, "SECTION without a name (group 2)");
            }
            const Group name = m_in.take();
            if (name.value == "HEADER") {
                readHeader();
            } else if (name.value == "BLOCKS") {
                readBlocks();
            } else if (name.value == "ENTITIES") {
                readEntities(nullptr, "ENDSEC");
            } else {
                skipTo("ENDSEC", name.line);
            }
        }
        return std::move(m_file);
    }

  private:
    void skipTo(std::string_view end, int from) {
        while (!m_in.done()) {
            const Group g = m_in.take();
            if (g.code == 0 && g.value == end) {
                return;
            }
        }
        fail(from, "the file ends before " + std::string(end));
    }

    void readHeader() {
        while (!m_in.done()) {
            const Group g = m_in.take();
            if (g.code == 0 && g.value == "ENDSEC") {
                return;
            }
            if (g.code == 9 && g.value == "$INSUNITS" && !m_in.done() && m_in.peek().code == 70) {
                m_file.insUnits = integer(m_in.take());
            }
        }
        fail(0, "the file ends inside the HEADER section");
    }

    void readBlocks() {
        while (!m_in.done()) {
            const Group g = m_in.take();
            if (g.code != 0) {
                continue;
            }
            if (g.value == "ENDSEC") {
                return;
            }
            if (g.value != "BLOCK") {
                continue;
            }
            DxfBlock block;
            block.line = g.line;
            while (!m_in.done() && m_in.peek().code != 0) {
                const Group h = m_in.take();
                if (h.code == 2) {
                    block.name = std::string(h.value.substr(0, 200));
                }
            }
            readEntities(&block, "ENDBLK");
            if (!block.name.empty() && block.name.front() == '*') {
                continue; // *Model_Space, *Paper_Space
            }
            m_file.blocks.push_back(std::move(block));
        }
        fail(0, "the file ends inside the BLOCKS section");
    }

    /// Entities until `end` (ENDBLK in a block, ENDSEC in ENTITIES): shapes go to `block`, texts
    /// to the block or, outside blocks, to the style text.
    void readEntities(DxfBlock* block, std::string_view end) {
        std::optional<DxfShape> polyline; // an open POLYLINE gathering its VERTEX entities
        while (!m_in.done()) {
            const Group head = m_in.take();
            if (head.code != 0) {
                continue;
            }
            if (head.value == end) {
                if (polyline) {
                    fail(polyline->line, "POLYLINE without SEQEND");
                }
                skipRest();
                return;
            }
            if (head.value == "SEQEND") {
                skipRest();
                if (polyline) {
                    addShape(block, std::move(*polyline));
                    polyline.reset();
                }
                continue;
            }
            if (head.value == "VERTEX") {
                readVertex(head, polyline);
                continue;
            }
            if (polyline) {
                fail(head.line, std::string(head.value.substr(0, 40)) +
                                    " inside a POLYLINE (its SEQEND is missing)");
            }
            if (head.value == "POLYLINE") {
                polyline = readShapeHead(head, false);
            } else if (head.value == "LWPOLYLINE") {
                addShape(block, readLwPolyline(head));
            } else if (head.value == "LINE") {
                addShape(block, readLine(head));
            } else if (head.value == "POINT") {
                DxfShape s = readShapeHead(head, true);
                addShape(block, std::move(s));
            } else if (head.value == "TEXT" || head.value == "MTEXT") {
                std::string text = readText();
                if (block) {
                    block->texts.push_back(std::move(text));
                } else {
                    m_file.styleTexts.push_back(std::move(text));
                }
            } else {
                skipRest();
            }
        }
        fail(0, "the file ends before " + std::string(end));
    }

    void skipRest() {
        while (!m_in.done() && m_in.peek().code != 0) {
            m_in.take();
        }
    }

    void countPoint(int line, const DxfShape& s) {
        if (++m_points > DXF_MAX_POINTS) {
            fail(line, "more than " + std::to_string(DXF_MAX_POINTS) +
                           " points in the file: not a pattern this importer takes");
        }
        if (static_cast<long long>(s.points.size()) >= DXF_MAX_POLYLINE_POINTS) {
            fail(line,
                 "a polyline of more than " + std::to_string(DXF_MAX_POLYLINE_POINTS) + " points");
        }
    }

    /// The groups of an entity up to the next entity: layer, flags and (for POINT) its point.
    DxfShape readShapeHead(const Group& head, bool isPoint) {
        DxfShape s;
        s.line = head.line;
        s.isPoint = isPoint;
        Vec2 p = Vec2::Zero();
        while (!m_in.done() && m_in.peek().code != 0) {
            const Group g = m_in.take();
            if (g.code == 8) {
                s.layer = layerNumber(g.value, m_file);
            } else if (g.code == 70 && !isPoint) {
                s.closed = (integer(g) & 1) != 0;
            } else if (g.code == 10 && isPoint) {
                p.x() = number(g);
            } else if (g.code == 20 && isPoint) {
                p.y() = number(g);
            }
        }
        if (isPoint) {
            countPoint(head.line, s);
            s.points.push_back(p);
            s.bulges.push_back(0);
        }
        return s;
    }

    void readVertex(const Group& head, std::optional<DxfShape>& polyline) {
        if (!polyline) {
            fail(head.line, "VERTEX outside a POLYLINE");
        }
        Vec2 p = Vec2::Zero();
        double bulge = 0;
        while (!m_in.done() && m_in.peek().code != 0) {
            const Group g = m_in.take();
            if (g.code == 10) {
                p.x() = number(g);
            } else if (g.code == 20) {
                p.y() = number(g);
            } else if (g.code == 42) {
                bulge = number(g);
            }
        }
        countPoint(head.line, *polyline);
        polyline->points.push_back(p);
        polyline->bulges.push_back(bulge);
    }

    DxfShape readLwPolyline(const Group& head) {
        DxfShape s;
        s.line = head.line;
        while (!m_in.done() && m_in.peek().code != 0) {
            const Group g = m_in.take();
            if (g.code == 8) {
                s.layer = layerNumber(g.value, m_file);
            } else if (g.code == 70) {
                s.closed = (integer(g) & 1) != 0;
            } else if (g.code == 10) {
                countPoint(g.line, s);
                s.points.emplace_back(number(g), 0.0);
                s.bulges.push_back(0);
            } else if (g.code == 20) {
                if (s.points.empty()) {
                    fail(g.line, "LWPOLYLINE: a y coordinate (group 20) before any x (group 10)");
                }
                s.points.back().y() = number(g);
            } else if (g.code == 42 && !s.points.empty()) {
                s.bulges.back() = number(g);
            }
        }
        return s;
    }

    DxfShape readLine(const Group& head) {
        DxfShape s;
        s.line = head.line;
        std::array<Vec2, 2> p{Vec2::Zero(), Vec2::Zero()};
        while (!m_in.done() && m_in.peek().code != 0) {
            const Group g = m_in.take();
            switch (g.code) {
            case 8:
                s.layer = layerNumber(g.value, m_file);
                break;
            case 10:
                p[0].x() = number(g);
                break;
            case 20:
                p[0].y() = number(g);
                break;
            case 11:
                p[1].x() = number(g);
                break;
            case 21:
                p[1].y() = number(g);
                break;
            default:
                break;
            }
        }
        for (const Vec2& q : p) {
            countPoint(head.line, s);
            s.points.push_back(q);
            s.bulges.push_back(0);
        }
        return s;
    }

    std::string readText() {
        std::string text;
        std::string tail;
        while (!m_in.done() && m_in.peek().code != 0) {
            const Group g = m_in.take();
            if (g.code == 3 && text.size() < 4096) {
                text += g.value;
            } else if (g.code == 1) {
                tail = std::string(g.value.substr(0, 4096));
            }
        }
        return plainText(text + tail);
    }

    void addShape(DxfBlock* block, DxfShape shape) {
        if (block != nullptr && shape.layer >= 0) {
            block->shapes.push_back(std::move(shape));
        }
    }

    Reader m_in;
    DxfDrawing m_file;
    long long m_points = 0;
};

} // namespace

std::string_view dxfTrimmed(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) {
        s.remove_prefix(1);
    }
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
        s.remove_suffix(1);
    }
    return s;
}

std::string dxfShown(std::string_view s) {
    std::string out = "\"";
    for (const char c : s.substr(0, 60)) {
        out += (static_cast<unsigned char>(c) < 0x20) ? '?' : c;
    }
    return out + (s.size() > 60 ? "...\"" : "\"");
}

Result<DxfDrawing> readDxfDrawing(std::string_view text, const std::string& file) {
    try {
        return FileReader(text).read();
    } catch (const DxfSyntaxError& e) {
        return Error{file, e.line > 0 ? "line " + std::to_string(e.line) : "", e.message};
    }
}

} // namespace atelier::io
