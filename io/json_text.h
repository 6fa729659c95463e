#pragma once
/// JSON text for the files Atelier writes (reports, benchmark figures).

#include <nlohmann/json.hpp>

#include <string>

namespace atelier::io {

/// `json` as text, 2-space indented, with a final newline. Strings that are not UTF-8 (a file
/// name from a file system that allows any byte) have their invalid bytes written as U+FFFD
/// instead of making the dump throw, so a report is never lost to its paths.
template <class Json> std::string jsonText(const Json& json) {
    return json.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

} // namespace atelier::io
