#pragma once
// The text of an SVG figure as a reader sees it: the content of each <text> element with its
// inner markup (PLplot's <tspan>s for super- and subscripts) removed and its character references
// (PLplot writes every character as &#xNN;) decoded to UTF-8.

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace vpsim::test {

inline std::string readWhole(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

/// `text` with &#xNN; / &#NN; and the XML entities decoded (UTF-8).
inline std::string decodeXml(const std::string& text) {
    std::string out;
    for (size_t i = 0; i < text.size(); ++i) {
        const size_t end = text.find(';', i);
        if (text[i] != '&' || end == std::string::npos) {
            out += text[i];
            continue;
        }
        const std::string name = text.substr(i + 1, end - i - 1);
        unsigned long code = 0;
        if (name.size() > 1 && name[0] == '#')
            code = name[1] == 'x' ? std::stoul(name.substr(2), nullptr, 16)
                                  : std::stoul(name.substr(1));
        else
            code = name == "amp"    ? '&'
                   : name == "lt"   ? '<'
                   : name == "gt"   ? '>'
                   : name == "quot" ? '"'
                                    : '\'';
        if (code < 0x80) {
            out += char(code);
        } else if (code < 0x800) {
            out += char(0xC0 | (code >> 6)), out += char(0x80 | (code & 0x3F));
        } else {
            out += char(0xE0 | (code >> 12)), out += char(0x80 | ((code >> 6) & 0x3F));
            out += char(0x80 | (code & 0x3F));
        }
        i = end;
    }
    return out;
}

inline std::vector<std::string> svgTexts(const std::string& svg) {
    std::vector<std::string> texts;
    for (size_t at = svg.find("<text"); at != std::string::npos; at = svg.find("<text", at)) {
        const size_t open = svg.find('>', at), close = svg.find("</text>", at);
        if (open == std::string::npos || close == std::string::npos) break;
        std::string text;
        bool inTag = false;
        for (size_t i = open + 1; i < close; ++i) {
            if (svg[i] == '<') inTag = true;
            if (!inTag) text += svg[i];
            if (svg[i] == '>') inTag = false;
        }
        texts.push_back(decodeXml(text));
        at = close;
    }
    return texts;
}

/// True when some <text> of `svg` contains `part`.
inline bool hasText(const std::string& svg, const std::string& part) {
    for (const std::string& t : svgTexts(svg))
        if (t.find(part) != std::string::npos) return true;
    return false;
}

}  // namespace vpsim::test
