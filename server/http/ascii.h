// Header values compared as HTTP compares them: names, media types and schemes are
// case-insensitive ASCII (RFC 9110, sections 5.1, 8.3.1 and 4.2.3).
#pragma once

#include <string>
#include <string_view>

namespace caustic::server {

/// `text` with ASCII letters lower-cased; other bytes as they are.
inline std::string asciiLower(std::string_view text) {
    std::string lower(text);
    for (char& c : lower)
        if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    return lower;
}

}  // namespace caustic::server
