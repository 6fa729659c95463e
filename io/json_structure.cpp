// What nlohmann's parser does not check, found by one pass over the text before it runs:
// nesting depth (its recursive parser and destructor would overflow the stack on a file
// nested 200,000 levels deep) and keys held twice by one object (it keeps the last silently).
// Syntax errors are left to the parser, which names them better.
#include "io/json_reader.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace atelier::io::detail {

namespace {

/// One array or object open at the scan's position.
struct Frame {
    bool object = false;
    std::size_t index = 0;                   ///< arrays: the element being read
    std::string key;                         ///< objects: the member being read
    std::map<std::string, std::size_t> keys; ///< objects: each key read, at its byte offset
};

/// The pointer of the innermost open array or object: the members and elements leading to it.
std::string pointerOf(const std::vector<Frame>& stack) {
    std::string out;
    for (std::size_t i = 0; i + 1 < stack.size(); ++i) {
        out = stack[i].object ? childPointer(out, stack[i].key) : childPointer(out, stack[i].index);
    }
    return out.empty() ? "/" : out;
}

/// The end of the string starting with the quote at `begin` (the offset of its closing
/// quote), or npos when it does not end.
std::size_t stringEnd(std::string_view text, std::size_t begin) {
    for (std::size_t i = begin + 1; i < text.size(); ++i) {
        if (text[i] == '\\') {
            ++i;
        } else if (text[i] == '"') {
            return i;
        }
    }
    return std::string_view::npos;
}

/// The text of a JSON string token with its escapes decoded; nullopt when they are invalid.
std::optional<std::string> decodedString(std::string_view token) {
    if (token.find('\\') == std::string_view::npos) {
        return std::string(token.substr(1, token.size() - 2));
    }
    try {
        return nlohmann::json::parse(token).get<std::string>();
    } catch (const nlohmann::json::exception&) {
        return std::nullopt;
    }
}

} // namespace

std::optional<Error> checkJsonStructure(std::string_view text, const std::string& file,
                                        int maxDepth) {
    std::vector<Frame> stack;
    bool expectKey = false;
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '"') {
            const std::size_t end = stringEnd(text, i);
            if (end == std::string_view::npos) {
                return std::nullopt;
            }
            if (expectKey && !stack.empty() && stack.back().object) {
                auto key = decodedString(text.substr(i, end - i + 1));
                if (!key) {
                    return std::nullopt;
                }
                Frame& frame = stack.back();
                const auto [first, inserted] = frame.keys.emplace(*key, i);
                if (!inserted) {
                    return Error{file, lineColumn(text, i),
                                 "duplicate key " + inQuotes(*key) + " in the object at " +
                                     pointerOf(stack) + " (first at " +
                                     lineColumn(text, first->second) + ")"};
                }
                frame.key = std::move(*key);
                expectKey = false;
            }
            i = end;
        } else if (c == '{' || c == '[') {
            if (static_cast<int>(stack.size()) >= maxDepth) {
                return Error{file, lineColumn(text, i),
                             "nested deeper than " + std::to_string(maxDepth) +
                                 " arrays and objects"};
            }
            stack.push_back(Frame{c == '{', 0, {}, {}});
            expectKey = c == '{';
        } else if (c == '}' || c == ']') {
            if (stack.empty()) {
                return std::nullopt;
            }
            stack.pop_back();
            expectKey = false;
        } else if (c == ',' && !stack.empty()) {
            expectKey = stack.back().object;
            ++stack.back().index;
        }
    }
    return std::nullopt;
}

} // namespace atelier::io::detail
