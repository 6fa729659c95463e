#include "io/json_reader.h"

#include <cmath>
#include <limits>
#include <sstream>

namespace atelier::io::detail {

using nlohmann::json;

void failWith(const std::string& pointer, const Error& inner) {
    throw JsonError{pointer, inner.toString()};
}

std::string childPointer(const std::string& base, std::string_view key) {
    std::string out = base + "/";
    for (const char c : key) {
        if (c == '~') {
            out += "~0";
        } else if (c == '/') {
            out += "~1";
        } else {
            out += c;
        }
    }
    return out;
}

std::string childPointer(const std::string& base, std::size_t index) {
    return base + "/" + std::to_string(index);
}

std::string typeName(const json& value) {
    switch (value.type()) {
    case json::value_t::null:
        return "null";
    case json::value_t::boolean:
        return "a boolean";
    case json::value_t::string:
        return "a string";
    case json::value_t::array:
        return "an array";
    case json::value_t::object:
        return "an object";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
        return "an integer";
    case json::value_t::number_float:
        return "a number";
    default:
        return "an unsupported value";
    }
}

std::string lineColumn(std::string_view text, std::size_t offset) {
    int line = 1;
    std::size_t lineStart = 0;
    for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
        if (text[i] == '\n') {
            ++line;
            lineStart = i + 1;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(offset - lineStart + 1);
}

Result<json> parseJson(const std::string& text, const std::string& file, int maxDepth) {
    if (auto error = checkJsonStructure(text, file, maxDepth)) {
        return *error;
    }
    try {
        return json::parse(text);
    } catch (const json::parse_error& e) {
        std::string message = e.what();
        // "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error ..."
        if (const std::size_t s = message.find("syntax error"); s != std::string::npos) {
            message = message.substr(s);
        }
        return Error{file, lineColumn(text, e.byte == 0 ? 0 : e.byte - 1),
                     "invalid JSON: " + message};
    } catch (const json::out_of_range& e) {
        // A number too large for a double: "... number overflow parsing '1e999'". nlohmann
        // gives no position; the first occurrence of the number is the best guess.
        std::string message = e.what();
        if (const std::size_t s = message.find("] "); s != std::string::npos) {
            message = message.substr(s + 2);
        }
        std::string where;
        const std::size_t open = message.find('\'');
        const std::size_t close = message.rfind('\'');
        if (open != std::string::npos && close > open + 1) {
            if (const std::size_t at = text.find(message.substr(open + 1, close - open - 1));
                at != std::string::npos) {
                where = lineColumn(text, at);
            }
        }
        return Error{file, where, "invalid JSON: " + message};
    }
}

ObjectReader::ObjectReader(const json& value, std::string pointer)
    : m_value(value), m_pointer(std::move(pointer)) {
    if (!m_value.is_object()) {
        throw JsonError{m_pointer.empty() ? "/" : m_pointer,
                        "expected an object, found " + typeName(m_value)};
    }
}

void ObjectReader::fail(std::string message) const {
    throw JsonError{m_pointer.empty() ? "/" : m_pointer, std::move(message)};
}

void ObjectReader::fail(std::string_view key, std::string message) const {
    throw JsonError{pointerOf(key), std::move(message)};
}

const json* ObjectReader::find(std::string_view key) {
    m_known.emplace(key);
    const auto it = m_value.find(key);
    return it == m_value.end() ? nullptr : &*it;
}

const json& ObjectReader::require(std::string_view key) {
    const json* v = find(key);
    if (v == nullptr) {
        fail("missing required key \"" + std::string(key) + "\"");
    }
    return *v;
}

bool ObjectReader::has(std::string_view key) const {
    return m_value.contains(key);
}

void ObjectReader::allow(std::initializer_list<std::string_view> keys) {
    for (const std::string_view k : keys) {
        m_known.emplace(k);
    }
}

double numberAt(const json& value, const std::string& pointer) {
    if (!value.is_number()) {
        throw JsonError{pointer, "expected a number, found " + typeName(value)};
    }
    const double d = value.get<double>();
    if (!std::isfinite(d)) {
        throw JsonError{pointer, "must be finite"};
    }
    return d;
}

long long integerAt(const json& value, const std::string& pointer) {
    if (value.is_number_integer()) {
        if (value.is_number_unsigned() &&
            value.get<unsigned long long>() >
                static_cast<unsigned long long>(std::numeric_limits<long long>::max())) {
            throw JsonError{pointer, "integer too large"};
        }
        return value.get<long long>();
    }
    if (value.is_number_float()) {
        const double d = value.get<double>();
        if (std::isfinite(d) && d == std::floor(d) && std::abs(d) < 9e15) {
            return static_cast<long long>(d);
        }
    }
    throw JsonError{pointer, "expected an integer, found " + typeName(value)};
}

sim::Vec3 vec3At(const json& value, const std::string& pointer) {
    if (!value.is_array() || value.size() != 3) {
        throw JsonError{pointer,
                        "expected an array of 3 numbers [x, y, z], found " +
                            (value.is_array() ? "an array of " + std::to_string(value.size())
                                              : typeName(value))};
    }
    sim::Vec3 out;
    for (std::size_t i = 0; i < 3; ++i) {
        out[static_cast<Eigen::Index>(i)] = numberAt(value[i], childPointer(pointer, i));
    }
    return out;
}

const json& arrayAt(const json& value, const std::string& pointer) {
    if (!value.is_array()) {
        throw JsonError{pointer, "expected an array, found " + typeName(value)};
    }
    return value;
}

std::optional<double> ObjectReader::optionalNumber(std::string_view key) {
    const json* v = find(key);
    if (v == nullptr) {
        return std::nullopt;
    }
    return numberAt(*v, pointerOf(key));
}

double ObjectReader::number(std::string_view key) {
    return numberAt(require(key), pointerOf(key));
}

double ObjectReader::number(std::string_view key, double fallback) {
    return optionalNumber(key).value_or(fallback);
}

double ObjectReader::positive(std::string_view key) {
    const double d = number(key);
    if (!(d > 0)) {
        fail(key, "must be positive (found " + json(d).dump() + ")");
    }
    return d;
}

double ObjectReader::positive(std::string_view key, double fallback) {
    if (!has(key)) {
        find(key);
        return fallback;
    }
    return positive(key);
}

double ObjectReader::nonNegative(std::string_view key, double fallback) {
    const double d = number(key, fallback);
    if (d < 0) {
        fail(key, "must not be negative (found " + json(d).dump() + ")");
    }
    return d;
}

double ObjectReader::nonNegativeAtMost(std::string_view key, double fallback, double max,
                                       std::string_view what) {
    const double d = nonNegative(key, fallback);
    if (d > max) {
        fail(key, "must be at most " + json(max).dump() + " (" + std::string(what) + "; found " +
                      json(d).dump() + ")");
    }
    return d;
}

std::optional<long long> ObjectReader::optionalInteger(std::string_view key) {
    const json* v = find(key);
    if (v == nullptr) {
        return std::nullopt;
    }
    return integerAt(*v, pointerOf(key));
}

long long ObjectReader::integer(std::string_view key) {
    return integerAt(require(key), pointerOf(key));
}

long long ObjectReader::integer(std::string_view key, long long fallback) {
    return optionalInteger(key).value_or(fallback);
}

bool ObjectReader::boolean(std::string_view key, bool fallback) {
    const json* v = find(key);
    if (v == nullptr) {
        return fallback;
    }
    if (!v->is_boolean()) {
        fail(key, "expected true or false, found " + typeName(*v));
    }
    return v->get<bool>();
}

std::optional<std::string> ObjectReader::optionalString(std::string_view key) {
    const json* v = find(key);
    if (v == nullptr) {
        return std::nullopt;
    }
    if (!v->is_string()) {
        fail(key, "expected a string, found " + typeName(*v));
    }
    return v->get<std::string>();
}

std::string ObjectReader::string(std::string_view key) {
    require(key);
    return *optionalString(key);
}

std::string ObjectReader::string(std::string_view key, const std::string& fallback) {
    return optionalString(key).value_or(fallback);
}

sim::Vec3 ObjectReader::vec3(std::string_view key) {
    return vec3At(require(key), pointerOf(key));
}

sim::Vec3 ObjectReader::vec3(std::string_view key, const sim::Vec3& fallback) {
    const json* v = find(key);
    return v == nullptr ? fallback : vec3At(*v, pointerOf(key));
}

void ObjectReader::finish() const {
    for (const auto& [key, value] : m_value.items()) {
        if (m_known.find(key) == m_known.end()) {
            std::string expected;
            for (const std::string& k : m_known) {
                expected += (expected.empty() ? "" : ", ") + k;
            }
            throw JsonError{pointerOf(key),
                            "unknown key \"" + key + "\"" +
                                (expected.empty() ? "" : " (expected one of: " + expected + ")")};
        }
    }
}

std::string inQuotes(std::string_view s) {
    return nlohmann::json(std::string(s)).dump(-1, ' ', false, json::error_handler_t::replace);
}

} // namespace atelier::io::detail
