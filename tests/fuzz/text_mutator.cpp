#include "text_mutator.h"

#include <sstream>

namespace atelier::fuzz {

namespace {

std::vector<std::string> splitLines(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) {
        lines.push_back(line);
    }
    return lines;
}

std::vector<std::string> splitWords(const std::string& line) {
    std::vector<std::string> words;
    std::istringstream in(line);
    for (std::string w; in >> w;) {
        words.push_back(w);
    }
    return words;
}

std::string joinWords(const std::vector<std::string>& words) {
    std::string out;
    for (const std::string& w : words) {
        if (!out.empty()) {
            out += ' ';
        }
        out += w;
    }
    return out;
}

/// Indices of the lines whose first word is `statement`.
std::vector<std::size_t> linesOf(const std::vector<std::string>& lines,
                                 const std::string& statement) {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const std::vector<std::string> words = splitWords(lines[i]);
        if (!words.empty() && words[0] == statement) {
            out.push_back(i);
        }
    }
    return out;
}

/// A face corner (`v`, `v/vt`, `v//vn`, `v/vt/vn`) with its vertex index replaced.
std::string oddCorner(const std::string& corner, std::size_t vertexCount, Rng& rng) {
    const std::vector<std::string> indices = {
        "0",
        "-1000000",
        "2147483647",
        "2147483648",
        "99999999999",
        std::to_string(vertexCount + 1),
        std::to_string(-static_cast<long long>(vertexCount) - 1),
        "abc",
        "1e3",
        ""};
    const std::size_t slash = corner.find('/');
    const std::string rest = slash == std::string::npos ? "" : corner.substr(slash);
    return rng.pick(indices) + rest;
}

std::string mutateFace(std::vector<std::string>& lines, Rng& rng) {
    const std::vector<std::size_t> faces = linesOf(lines, "f");
    if (faces.empty()) {
        return "obj: no face";
    }
    const std::size_t at = rng.pick(faces);
    std::vector<std::string> words = splitWords(lines[at]);
    const std::string where = "obj: line " + std::to_string(at + 1) + ": ";
    if (words.size() < 2) {
        lines[at] = "f 1 1 1";
        return where + "degenerate face";
    }
    switch (rng.below(3)) {
    case 0: {
        const std::size_t k = 1 + rng.below(words.size() - 1);
        words[k] = oddCorner(words[k], linesOf(lines, "v").size(), rng);
        lines[at] = joinWords(words);
        return where + "corner -> " + words[k];
    }
    case 1: {
        const std::vector<std::string> corners(words.begin() + 1, words.end());
        while (words.size() < 1001) {
            words.push_back(rng.pick(corners));
        }
        lines[at] = joinWords(words);
        return where + "face of 1000 corners";
    }
    default:
        words.resize(1 + rng.below(std::min<std::size_t>(words.size(), 3)));
        lines[at] = joinWords(words);
        return where + "face of " + std::to_string(words.size() - 1) + " corners";
    }
}

std::string mutateCoordinate(std::vector<std::string>& lines, Rng& rng) {
    std::vector<std::size_t> vertices = linesOf(lines, "v");
    const std::vector<std::size_t> uvs = linesOf(lines, "vt");
    vertices.insert(vertices.end(), uvs.begin(), uvs.end());
    if (vertices.empty()) {
        return "obj: no vertex";
    }
    const std::size_t at = rng.pick(vertices);
    std::vector<std::string> words = splitWords(lines[at]);
    const std::string where = "obj: line " + std::to_string(at + 1) + ": ";
    if (words.size() < 2 || rng.chance(20)) {
        words.resize(std::min<std::size_t>(words.size(), 2));
        lines[at] = joinWords(words);
        return where + "one coordinate";
    }
    static const std::vector<std::string> values = {
        "nan", "inf", "-inf", "1e300", "1e400", "-0", "0x1p3", "1e-320", "-1e300", "1,5", "--1"};
    const std::size_t k = 1 + rng.below(words.size() - 1);
    words[k] = rng.pick(values);
    lines[at] = joinWords(words);
    return where + "coordinate -> " + words[k];
}

std::string editLines(std::vector<std::string>& lines, Rng& rng) {
    if (lines.empty()) {
        lines.emplace_back("f 1 2 3");
        return "obj: a face and no vertex";
    }
    const std::size_t at = rng.below(lines.size());
    const std::string where = "obj: line " + std::to_string(at + 1) + ": ";
    switch (rng.below(4)) {
    case 0: {
        static const std::vector<std::size_t> counts = {100, 100000};
        const std::size_t count = rng.pick(counts);
        lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at), count - 1, lines[at]);
        return where + "repeated " + std::to_string(count) + " times";
    }
    case 1:
        lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(at));
        return where + "deleted";
    case 2: {
        const std::size_t other = rng.below(lines.size());
        std::swap(lines[at], lines[other]);
        return where + "swapped with line " + std::to_string(other + 1);
    }
    default:
        static const std::vector<std::string> statements = {"g",     "o", "g \x01\n", "vt 0.5",
                                                            "v 1 2", "f", "s off"};
        lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at), rng.pick(statements));
        return where + "statement inserted";
    }
}

/// A DXF group: its code line and value line (the code's index in `lines`, always even).
std::string mutateDxfLines(std::vector<std::string>& lines, Rng& rng) {
    if (lines.size() < 2) {
        lines = {"0", "SECTION", "2", "BLOCKS", "0", "BLOCK"};
        return "dxf: a BLOCKS section that never ends";
    }
    const std::size_t groups = lines.size() / 2;
    const std::size_t at = 2 * rng.below(groups);
    const std::string where = "dxf: line " + std::to_string(at + 1) + ": ";
    const std::size_t roll = rng.below(100);
    if (roll < 45) {
        // A value of a coordinate, bulge or flag group.
        std::vector<std::size_t> numeric;
        for (std::size_t i = 0; i + 1 < lines.size(); i += 2) {
            const std::string code = splitWords(lines[i]).empty() ? "" : splitWords(lines[i])[0];
            if (code == "10" || code == "20" || code == "11" || code == "21" || code == "42" ||
                code == "70" || code == "90") {
                numeric.push_back(i + 1);
            }
        }
        if (numeric.empty()) {
            return "dxf: no numeric group";
        }
        static const std::vector<std::string> values = {
            "nan",    "inf", "-inf", "1e300", "1e400", "-0",    "0x1p3", "1e-320",
            "-1e300", "1,5", "--1",  "",      "+7",    "65537", "1e9",   "-1"};
        const std::size_t v = rng.pick(numeric);
        lines[v] = rng.pick(values);
        return "dxf: line " + std::to_string(v + 1) + ": value -> " + lines[v];
    }
    if (roll < 70) {
        switch (rng.below(3)) {
        case 0:
            lines.erase(lines.begin() + static_cast<std::ptrdiff_t>(at),
                        lines.begin() + static_cast<std::ptrdiff_t>(at + 2));
            return where + "group deleted";
        case 1: {
            const std::size_t length = 2 * (1 + rng.below(std::min<std::size_t>(groups, 12)));
            const std::size_t end = std::min(at + length, lines.size());
            const std::vector<std::string> piece(lines.begin() + static_cast<std::ptrdiff_t>(at),
                                                 lines.begin() + static_cast<std::ptrdiff_t>(end));
            static const std::vector<std::size_t> counts = {100, 20000};
            const std::size_t count = rng.pick(counts);
            for (std::size_t k = 0; k < count; ++k) {
                lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at), piece.begin(),
                             piece.end());
            }
            return where + std::to_string(piece.size() / 2) + " groups repeated " +
                   std::to_string(count) + " times";
        }
        default: {
            const std::size_t other = 2 * rng.below(groups);
            std::swap(lines[at], lines[other]);
            std::swap(lines[at + 1], lines[other + 1]);
            return where + "swapped with the group at line " + std::to_string(other + 1);
        }
        }
    }
    static const std::vector<std::vector<std::string>> inserts = {
        {"0", "VERTEX", "10", "1", "20", "2"},
        {"0", "SEQEND"},
        {"0", "POLYLINE", "8", "1"},
        {"0", "ENDBLK"},
        {"0", "BLOCK"},
        {"0", "ENDSEC"},
        {"0", "EOF"},
        {"70", "1"},
        {"8", "4"},
        {"0", "LWPOLYLINE", "8", "1", "20", "3"},
        {"999", "x"},
        {"0", "SECTION"},
        {"1", "Units: ENGLISH"},
        {"x"}};
    const std::vector<std::string>& insert = rng.pick(inserts);
    lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(at), insert.begin(), insert.end());
    return where + "inserted " + insert[0] + (insert.size() > 1 ? " " + insert[1] : "");
}

} // namespace

std::string mutateDxf(const std::string& text, Rng& rng, std::vector<std::string>& notes) {
    std::vector<std::string> lines = splitLines(text);
    notes.push_back(mutateDxfLines(lines, rng));
    std::string out;
    for (const std::string& line : lines) {
        out += line + '\n';
    }
    return out;
}

std::string mutateBytes(std::string text, Rng& rng, std::vector<std::string>& notes) {
    const std::size_t n = text.size();
    const std::size_t at = n == 0 ? 0 : rng.below(n);
    const std::string where = "bytes: offset " + std::to_string(at) + ": ";
    static const std::vector<std::string> tokens = {
        "{",    "}",     "[", "]",  "\"", "\\",    ",",    ":",   std::string(1, '\0'),    "\xff",
        "\xc3", "1e999", "-", "/*", "\n", "\"\\u", "null", "tru", "0000000000000000000001"};
    switch (n == 0 ? 2 : rng.below(6)) {
    case 0:
        text.resize(at);
        notes.push_back(where + "truncated");
        break;
    case 1: {
        const std::size_t flips = 1 + rng.below(8);
        for (std::size_t k = 0; k < flips; ++k) {
            text[rng.below(n)] ^= static_cast<char>(1u << rng.below(8));
        }
        notes.push_back("bytes: " + std::to_string(flips) + " bits flipped");
        break;
    }
    case 2: {
        const std::string token = rng.pick(tokens);
        text.insert(at, token);
        notes.push_back(where + "inserted " + std::to_string(token.size()) + " bytes");
        break;
    }
    case 3: {
        const std::size_t length = 1 + rng.below(std::min<std::size_t>(n - at, 64));
        text.erase(at, length);
        notes.push_back(where + std::to_string(length) + " bytes deleted");
        break;
    }
    case 4: {
        const std::size_t length = 1 + rng.below(std::min<std::size_t>(n - at, 64));
        const std::string piece = text.substr(at, length);
        for (std::size_t k = 0; k < 16; ++k) {
            text.insert(at, piece);
        }
        notes.push_back(where + std::to_string(length) + " bytes repeated 16 times");
        break;
    }
    default:
        text[at] = static_cast<char>(rng.below(256));
        notes.push_back(where + "byte replaced");
        break;
    }
    return text;
}

std::string mutateObj(const std::string& text, Rng& rng, std::vector<std::string>& notes) {
    std::vector<std::string> lines = splitLines(text);
    const std::size_t roll = rng.below(100);
    notes.push_back(roll < 40   ? mutateFace(lines, rng)
                    : roll < 70 ? mutateCoordinate(lines, rng)
                                : editLines(lines, rng));
    std::string out;
    for (const std::string& line : lines) {
        out += line + '\n';
    }
    return out;
}

} // namespace atelier::fuzz
