#pragma once
/// Text for the XML files Atelier writes (SVG patterns and plots).

#include <string>

namespace atelier::io {

/// `text` safe in XML element text and attribute values: `&`, `<`, `>`, `"` and `'` as
/// entities; control characters XML 1.0 cannot hold, even escaped, as spaces (tab, line feed
/// and carriage return stay); bytes that are not UTF-8 (a file or panel name from anywhere) as
/// U+FFFD, so the file stays well-formed.
std::string xmlEscape(const std::string& text);

} // namespace atelier::io
