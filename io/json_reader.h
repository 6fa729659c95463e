#pragma once
/// Internal to io/: strict reading of JSON objects with errors that name the JSON pointer.
/// Not installed, not included by public headers (the public API does not expose nlohmann).

#include "io/limits.h"
#include "io/result.h"

#include "sim/core/types.h"

#include <nlohmann/json.hpp>

#include <array>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::io::detail {

/// Thrown inside a parser and turned into an `Error` at the API boundary.
struct JsonError {
    std::string where; ///< JSON pointer
    std::string message;
};

/// Throws the error of a file read from this one (a mesh, a preset file) at `pointer`.
[[noreturn]] void failWith(const std::string& pointer, const Error& inner);

/// `base` + "/" + `key`, escaped as RFC 6901 asks (`~` → `~0`, `/` → `~1`).
std::string childPointer(const std::string& base, std::string_view key);
std::string childPointer(const std::string& base, std::size_t index);

/// The JSON type name of a value, for messages ("a string", "an array", ...).
std::string typeName(const nlohmann::json& value);

/// "line L, column C" of the byte at `offset` (0-based) in `text`.
std::string lineColumn(std::string_view text, std::size_t offset);

/// Checks what the JSON parser does not, before it runs: arrays and objects nested more than
/// `maxDepth` deep, and a key held twice by one object (naming both places and the object's
/// pointer). nullopt when neither is found; syntax errors are left to the parser.
std::optional<Error> checkJsonStructure(std::string_view text, const std::string& file,
                                        int maxDepth);

/// Parses JSON text; nesting deeper than `maxDepth`, a duplicate key, a syntax error or a
/// number too large for a double (`1e999`) becomes Error{file, "line L, column C", message}.
/// Never throws.
Result<nlohmann::json> parseJson(const std::string& text, const std::string& file,
                                 int maxDepth = Limits{}.maxJsonDepth);

/// Reads the members of one JSON object. Each accessor marks its key as known;
/// `finish()` throws for any key that no accessor asked for (catches typos).
class ObjectReader {
  public:
    /// Throws when `value` is not an object.
    ObjectReader(const nlohmann::json& value, std::string pointer);

    const std::string& pointer() const { return m_pointer; }
    std::string pointerOf(std::string_view key) const { return childPointer(m_pointer, key); }
    /// Throws JsonError at this object (or at `key` of it).
    [[noreturn]] void fail(std::string message) const;
    [[noreturn]] void fail(std::string_view key, std::string message) const;

    /// The member, or nullptr when absent; marks the key as known.
    const nlohmann::json* find(std::string_view key);
    /// The member; throws when absent.
    const nlohmann::json& require(std::string_view key);
    bool has(std::string_view key) const;
    /// Marks keys as known without reading them (comments, documentation).
    void allow(std::initializer_list<std::string_view> keys);

    /// A finite number; `std::nullopt` when absent.
    std::optional<double> optionalNumber(std::string_view key);
    double number(std::string_view key);
    double number(std::string_view key, double fallback);
    /// A finite number > 0.
    double positive(std::string_view key);
    double positive(std::string_view key, double fallback);
    /// A finite number >= 0.
    double nonNegative(std::string_view key, double fallback);
    /// A finite number in [0, max] (`what`: the limit, named in the message).
    double nonNegativeAtMost(std::string_view key, double fallback, double max,
                             std::string_view what);
    std::optional<long long> optionalInteger(std::string_view key);
    long long integer(std::string_view key);
    long long integer(std::string_view key, long long fallback);
    bool boolean(std::string_view key, bool fallback);
    std::optional<std::string> optionalString(std::string_view key);
    std::string string(std::string_view key);
    std::string string(std::string_view key, const std::string& fallback);
    /// A 3-vector [x, y, z] of finite numbers.
    sim::Vec3 vec3(std::string_view key);
    sim::Vec3 vec3(std::string_view key, const sim::Vec3& fallback);

    /// Throws for the first member that no accessor asked for.
    void finish() const;

  private:
    const nlohmann::json& m_value;
    std::string m_pointer;
    std::set<std::string, std::less<>> m_known;
};

/// A finite number at `pointer`; throws otherwise.
double numberAt(const nlohmann::json& value, const std::string& pointer);
/// An integer at `pointer`; throws otherwise.
long long integerAt(const nlohmann::json& value, const std::string& pointer);
/// [x, y, z] at `pointer`; throws otherwise.
sim::Vec3 vec3At(const nlohmann::json& value, const std::string& pointer);
/// An array at `pointer`; throws otherwise.
const nlohmann::json& arrayAt(const nlohmann::json& value, const std::string& pointer);

/// `s` as a JSON string, quoted and escaped: names in error messages. Invalid UTF-8 is
/// replaced by U+FFFD rather than thrown on.
std::string inQuotes(std::string_view s);

/// `"a", "b", "c"`: the names of an enum's values, for "expected one of" messages.
template <class Enum, std::size_t N>
std::string nameList(const std::array<Enum, N>& values, std::string_view (*toName)(Enum)) {
    std::string out;
    for (const Enum v : values) {
        out += (out.empty() ? "" : ", ") + inQuotes(toName(v));
    }
    return out;
}

} // namespace atelier::io::detail
