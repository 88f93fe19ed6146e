// Text put inside XML or HTML: the characters markup gives a meaning to, escaped.
#pragma once

#include <string>

namespace hexmesh {

// `text` with & < > " written as entities, fit for element content and quoted attributes.
inline std::string escape_markup(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (char ch : text) {
        switch (ch) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += ch;
        }
    }
    return out;
}

}  // namespace hexmesh
