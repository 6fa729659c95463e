#include "json_mutator.h"

#include "fuzz_case.h"

#include <algorithm>
#include <cctype>
#include <set>
#include <utility>

namespace atelier::fuzz {

namespace {

using Json = nlohmann::ordered_json;
using Pointer = Json::json_pointer;

/// A serialized document larger than this keeps its remaining raw fragments out (`0` instead):
/// a case stays a few megabytes at most.
constexpr std::size_t MAX_TEXT_BYTES = 16u << 20;

/// Raw text that stands in the document as a marker string until it is serialized: duplicate
/// keys, invalid UTF-8, numbers beyond double, deep nesting.
class RawText {
  public:
    std::string marker(std::string text) {
        m_texts.push_back(std::move(text));
        return "\x01\x02raw" + std::to_string(m_texts.size() - 1) + "\x02";
    }

    /// `dumped` with every marker replaced by its text, the latest first (a fragment may hold
    /// an earlier marker).
    std::string expand(std::string dumped) const {
        for (std::size_t i = m_texts.size(); i-- > 0;) {
            const std::string needle = "\"\\u0001\\u0002raw" + std::to_string(i) + "\\u0002\"";
            std::string out;
            std::size_t from = 0;
            for (std::size_t at; (at = dumped.find(needle, from)) != std::string::npos;) {
                const bool fits = out.size() + dumped.size() + m_texts[i].size() < MAX_TEXT_BYTES;
                out.append(dumped, from, at - from).append(fits ? m_texts[i] : "0");
                from = at + needle.size();
            }
            out.append(dumped, from, std::string::npos);
            dumped = std::move(out);
        }
        return dumped;
    }

  private:
    std::vector<std::string> m_texts;
};

struct Context {
    Json& doc;
    Rng& rng;
    RawText& raw;
    const std::vector<std::string>& keys;
    const std::vector<std::string>& strings;
    const std::vector<Json>& values;
};

std::string shown(const Pointer& p) {
    return p.empty() ? "/" : p.to_string();
}

/// Calls visit(pointer, node) for every node of `doc`, the root included, in document order.
template <class Visit> void forEachNode(const Json& doc, Visit visit) {
    std::vector<Pointer> stack{Pointer()};
    while (!stack.empty()) {
        const Pointer p = std::move(stack.back());
        stack.pop_back();
        const Json& node = doc.at(p);
        if (node.is_object()) {
            for (auto it = node.rbegin(); it != node.rend(); ++it) {
                stack.push_back(p / it.key());
            }
        } else if (node.is_array()) {
            for (std::size_t i = node.size(); i-- > 0;) {
                stack.push_back(p / i);
            }
        }
        visit(p, node);
    }
}

/// A node for which `accept` holds, each equally likely (one pass, one pointer kept: a
/// document of repeated arrays may have millions of nodes).
template <class Accept> std::optional<Pointer> pickNode(Context& c, Accept accept) {
    std::optional<Pointer> picked;
    std::size_t seen = 0;
    forEachNode(c.doc, [&](const Pointer& p, const Json& node) {
        if (accept(node) && c.rng.below(++seen) == 0) {
            picked = p;
        }
    });
    return picked;
}

bool isNumber(const Json& j) {
    return j.is_number();
}
bool isString(const Json& j) {
    return j.is_string();
}
bool isFilledObject(const Json& j) {
    return j.is_object() && !j.empty();
}
bool isArray(const Json& j) {
    return j.is_array();
}
bool isAny(const Json& /*j*/) {
    return true;
}

const Json& dictionaryValue(Context& c) {
    static const Json fallback = 0;
    return c.values.empty() ? fallback : c.values[c.rng.below(c.values.size())];
}

/// A number readers get wrong, in place of `old`; `text` says what was written.
Json oddNumber(Context& c, const Json& old, std::string& text) {
    const double x = old.is_number() ? old.get<double>() : 1.0;
    static const std::vector<std::string> raws = {"9223372036854775808",
                                                  "-9223372036854775809",
                                                  "18446744073709551616",
                                                  "1e400",
                                                  "-1e400",
                                                  "-0",
                                                  "NaN",
                                                  "Infinity",
                                                  "1.7976931348623157e308",
                                                  "4.9e-324",
                                                  "123456789012345678901234567890"};
    static const std::vector<double> doubles = {
        0,       -1,  1,    2,   1e300, -1e300,       1e-300,
        -1e-300, 0.5, 1e-9, 1e9, 65536, 4294967296.0, -2147483649.0};
    static const std::vector<std::int64_t> integers = {1000000000000000000LL, 9223372036854775807LL,
                                                       2147483647LL,          2147483648LL,
                                                       -2147483648LL,         1000000};
    Json out;
    switch (c.rng.below(6)) {
    case 0:
        text = c.rng.pick(raws);
        return c.raw.marker(text);
    case 1:
        out = c.rng.pick(doubles);
        break;
    case 2:
        out = c.rng.pick(integers);
        break;
    case 3: {
        static const std::vector<std::string> strings = {"nan",   "NaN", "inf", "-inf",
                                                         "1e999", "1",   "0x10"};
        out = c.rng.pick(strings);
        break;
    }
    case 4: {
        static const std::vector<double> factors = {-1, 10, 1e6, 1e-6, 1 + 1e-12};
        out = x * c.rng.pick(factors);
        break;
    }
    default:
        // Off by one: indices and counts.
        out = old.is_number_integer() ? Json(old.get<std::int64_t>() + (c.rng.chance(50) ? 1 : -1))
                                      : Json(x + (c.rng.chance(50) ? 1 : -1));
        break;
    }
    text = out.dump();
    return out;
}

/// A path readers get wrong: a device that never ends, a FIFO that never opens, a folder, the
/// case itself, outside the case's folder, too long.
Json oddPath(Context& c) {
    static const std::vector<std::string> paths = {"/dev/zero",
                                                   "/dev/urandom",
                                                   "/dev/null",
                                                   FIFO_NAME,
                                                   std::string("./") + FIFO_NAME,
                                                   "/",
                                                   ".",
                                                   "..",
                                                   "../",
                                                   "../../../../../../etc/passwd",
                                                   "",
                                                   "missing.obj",
                                                   "case.scene.json",
                                                   "case.atelier",
                                                   "fabrics.json",
                                                   "cloth.obj",
                                                   "ball.obj",
                                                   "body.obj"};
    return c.rng.chance(90) ? Json(c.rng.pick(paths)) : Json(std::string(3000, 'a') + "/b.obj");
}

bool looksLikePath(const std::string& s) {
    return s.ends_with(".obj") || s.ends_with(".json") || s.ends_with(".atelier");
}

/// A string readers get wrong, in place of `old`.
Json oddString(Context& c, const std::string& old, std::string& text) {
    static const std::vector<std::string> fixed = {
        "",        "\x01\x1f\x7f",    "a\nb\r\nc", "\t", std::string("a\0b", 3), "../", "/dev/zero",
        FIFO_NAME, "case.scene.json", "%s%n%x",    " ",  "\xc3\xa9t\xc3\xa9"};
    if (looksLikePath(old) && c.rng.chance(70)) {
        const Json out = oddPath(c);
        text = out.dump().substr(0, 60);
        return out;
    }
    Json out;
    switch (c.rng.below(8)) {
    case 0:
    case 1:
        out = c.rng.pick(fixed);
        break;
    case 2: {
        static const std::vector<std::size_t> lengths = {300, 5000, 100000};
        out = std::string(c.rng.pick(lengths), c.rng.chance(50) ? 'x' : '/');
        break;
    }
    case 3: {
        static const std::vector<std::string> raws = {"\"\xff\xfe\xc0\xaf\"", "\"a\xed\xa0\x80z\"",
                                                      "\"\\ud800\"", "\"\\u0000\"", "\"\xc3\""};
        text = c.rng.pick(raws);
        return c.raw.marker(text);
    }
    case 4:
    case 5:
        out = c.strings.empty() ? old : c.rng.pick(c.strings);
        break;
    case 6:
        out = old + old;
        break;
    default: {
        std::string s = old;
        std::transform(s.begin(), s.end(), s.begin(),
                       [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
        out = c.rng.chance(50) ? s : old.substr(0, old.size() / 2);
        break;
    }
    }
    text = out.dump(-1, ' ', false, Json::error_handler_t::replace);
    if (text.size() > 60) {
        text = text.substr(0, 40) + "...(" + std::to_string(text.size()) + " bytes)";
    }
    return out;
}

std::string mutateNumber(Context& c) {
    const auto p = pickNode(c, isNumber);
    if (!p) {
        return "no number";
    }
    std::string text;
    const Json before = c.doc.at(*p);
    c.doc.at(*p) = oddNumber(c, before, text);
    return shown(*p) + ": " + before.dump() + " -> " + text;
}

std::string mutateString(Context& c) {
    const auto p = pickNode(c, isString);
    if (!p) {
        return "no string";
    }
    std::string text;
    const std::string before = c.doc.at(*p).get<std::string>();
    c.doc.at(*p) = oddString(c, before, text);
    return shown(*p) + ": string -> " + text;
}

std::string keyAt(const Json& object, std::size_t index) {
    auto it = object.begin();
    std::advance(it, static_cast<std::ptrdiff_t>(index));
    return it.key();
}

std::string editKey(Context& c) {
    const auto p = pickNode(c, isFilledObject);
    if (!p) {
        return "no object";
    }
    Json& object = c.doc.at(*p);
    const std::string key = keyAt(object, c.rng.below(object.size()));
    switch (c.rng.below(4)) {
    case 0:
        object.erase(key);
        return shown(*p / key) + ": deleted";
    case 1: {
        // The same key again (a JSON object cannot hold it: written as raw text).
        const Json value = c.rng.chance(50) ? object[key] : dictionaryValue(c);
        object[c.raw.marker(Json(key).dump())] = value;
        return shown(*p / key) + ": duplicated with " + value.dump().substr(0, 60);
    }
    case 2: {
        const std::string added = c.keys.empty() ? "unknown" : c.rng.pick(c.keys);
        object[added] = dictionaryValue(c);
        return shown(*p / added) + ": added";
    }
    default: {
        const std::string renamed =
            c.rng.chance(50) && !c.keys.empty() ? c.rng.pick(c.keys) : key + "_";
        Json value = std::move(object[key]);
        object.erase(key);
        object[renamed] = std::move(value);
        return shown(*p / key) + ": renamed " + renamed;
    }
    }
}

std::string swapType(Context& c) {
    const auto p = pickNode(c, isAny);
    Json& node = c.doc.at(*p);
    Json replacement;
    switch (c.rng.below(8)) {
    case 0:
        replacement = nullptr;
        break;
    case 1:
        replacement = c.rng.chance(50);
        break;
    case 2:
        replacement = c.rng.chance(50) ? Json(0) : Json(1.5);
        break;
    case 3:
        replacement = c.rng.chance(50) ? "" : "x";
        break;
    case 4:
        replacement = c.rng.chance(50) ? Json::array() : Json::object();
        break;
    case 5:
        replacement = c.rng.chance(50) ? Json::array({node}) : Json::object({{"a", node}});
        break;
    default:
        replacement = dictionaryValue(c);
        break;
    }
    const std::string text = replacement.dump().substr(0, 60);
    node = std::move(replacement);
    return shown(*p) + ": replaced by " + text;
}

std::string deepNest(Context& c) {
    const auto p = pickNode(c, isAny);
    static const std::vector<std::size_t> depths = {50, 600, 5000, 100000, 1000000};
    const std::size_t depth = c.rng.pick(depths);
    const bool arrays = c.rng.chance(50);
    std::string text;
    text.reserve(depth * 6 + 64);
    for (std::size_t i = 0; i < depth; ++i) {
        text += arrays ? "[" : "{\"a\":";
    }
    Json& node = c.doc.at(*p);
    text += node.dump();
    text.append(depth, arrays ? ']' : '}');
    node = c.raw.marker(std::move(text));
    return shown(*p) + ": nested " + std::to_string(depth) + (arrays ? " arrays" : " objects");
}

std::string editArray(Context& c) {
    const auto p = pickNode(c, isArray);
    if (!p) {
        return "no array";
    }
    Json& array = c.doc.at(*p);
    const std::size_t n = array.size();
    const std::size_t op = n == 0 ? 5 : c.rng.below(7);
    const std::size_t i = n == 0 ? 0 : c.rng.below(n);
    switch (op) {
    case 0:
        array.erase(i);
        return shown(*p / i) + ": removed";
    case 1:
        array.insert(array.begin() + static_cast<std::ptrdiff_t>(c.rng.below(n + 1)),
                     Json(array[i]));
        return shown(*p / i) + ": duplicated";
    case 2:
        array = Json::array();
        return shown(*p) + ": emptied";
    case 3: {
        // Up to a megabyte of copies.
        static const std::vector<std::size_t> sizes = {100, 10000};
        const Json element = array[i];
        const std::size_t bytes = element.dump().size() + 1;
        const std::size_t size =
            std::min(c.rng.pick(sizes), std::max<std::size_t>(n, (1u << 20) / bytes));
        while (array.size() < size) {
            array.push_back(element);
        }
        return shown(*p / i) + ": repeated to " + std::to_string(size) + " elements";
    }
    case 4: {
        const std::size_t j = c.rng.below(n);
        std::swap(array[i], array[j]);
        return shown(*p) + ": swapped elements " + std::to_string(i) + ", " + std::to_string(j);
    }
    case 5:
        array.push_back(dictionaryValue(c));
        return shown(*p) + ": appended " + array.back().dump().substr(0, 60);
    default:
        std::reverse(array.begin(), array.end());
        return shown(*p) + ": reversed";
    }
}

std::string swapValues(Context& c) {
    const Pointer a = *pickNode(c, isAny);
    const Pointer b = *pickNode(c, isAny);
    const std::string sa = a.to_string();
    const std::string sb = b.to_string();
    // Neither may hold the other.
    if (sa.rfind(sb, 0) == 0 || sb.rfind(sa, 0) == 0) {
        return shown(a) + ": not swapped with " + shown(b);
    }
    std::swap(c.doc.at(a), c.doc.at(b));
    return shown(a) + ": swapped with " + shown(b);
}

std::string mutateOnce(Context& c) {
    const std::size_t roll = c.rng.below(100);
    if (roll < 25) {
        return mutateNumber(c);
    }
    if (roll < 42) {
        return mutateString(c);
    }
    if (roll < 67) {
        return editKey(c);
    }
    if (roll < 77) {
        return swapType(c);
    }
    if (roll < 87) {
        return editArray(c);
    }
    if (roll < 95) {
        return swapValues(c);
    }
    return deepNest(c);
}

} // namespace

JsonMutator::JsonMutator(const std::vector<std::string>& corpus) {
    std::set<std::string> keys;
    std::set<std::string> strings;
    constexpr std::size_t MAX_VALUE_BYTES = 2000;
    constexpr std::size_t MAX_VALUES = 4000;
    for (const std::string& text : corpus) {
        Json doc;
        try {
            doc = Json::parse(text);
        } catch (const Json::exception&) {
            continue;
        }
        forEachNode(doc, [&](const Pointer& /*p*/, const Json& node) {
            if (node.is_object()) {
                for (auto it = node.begin(); it != node.end(); ++it) {
                    keys.insert(it.key());
                }
            } else if (node.is_string()) {
                strings.insert(node.get<std::string>());
            }
            if (node.dump().size() < MAX_VALUE_BYTES) {
                m_values.push_back(node);
            }
        });
    }
    // Every file keeps a share of the dictionary: thinned evenly, not cut after the first.
    if (m_values.size() > MAX_VALUES) {
        std::vector<Json> thinned;
        for (std::size_t i = 0; i < MAX_VALUES; ++i) {
            thinned.push_back(std::move(m_values[i * m_values.size() / MAX_VALUES]));
        }
        m_values = std::move(thinned);
    }
    m_keys.assign(keys.begin(), keys.end());
    m_strings.assign(strings.begin(), strings.end());
}

std::optional<std::string> JsonMutator::mutate(std::string_view text, Rng& rng, int count,
                                               std::vector<std::string>& notes) const {
    Json doc;
    try {
        doc = Json::parse(text);
    } catch (const Json::exception&) {
        return std::nullopt;
    }
    RawText raw;
    Context c{doc, rng, raw, m_keys, m_strings, m_values};
    for (int k = 0; k < count; ++k) {
        notes.push_back(mutateOnce(c));
    }
    return raw.expand(doc.dump(2, ' ', false, Json::error_handler_t::replace));
}

} // namespace atelier::fuzz
