#include "vpsim/core/text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace vpsim {
namespace {

/// Length of the valid UTF-8 sequence starting at text[i], 0 when invalid (overlong forms,
/// surrogates and code points above U+10FFFF included).
size_t utf8SequenceLength(std::string_view text, size_t i) {
    const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char lead = byte(i);
    size_t length = 0;
    unsigned minimum = 0, code = 0;
    if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2, minimum = 0x80, code = lead & 0x1Fu;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3, minimum = 0x800, code = lead & 0x0Fu;
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4, minimum = 0x10000, code = lead & 0x07u;
    } else {
        return 0;
    }
    if (i + length > text.size()) return 0;
    for (size_t k = 1; k < length; ++k) {
        if ((byte(i + k) & 0xC0u) != 0x80u) return 0;
        code = (code << 6) | (byte(i + k) & 0x3Fu);
    }
    if (code < minimum || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
    return length;
}

std::string escapeByte(unsigned char c) {
    switch (c) {
        case '\n': return "\\n";
        case '\r': return "\\r";
        case '\t': return "\\t";
        default: {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02X", unsigned(c));
            return hex;
        }
    }
}

}  // namespace

std::string escaped(std::string_view text, size_t limit) {
    std::string out;
    out.reserve(std::min(text.size(), limit) + 8);
    size_t shown = 0;
    for (size_t i = 0; i < text.size();) {
        const auto c = static_cast<unsigned char>(text[i]);
        std::string piece;
        size_t consumed = 1, width = 0;
        if (c >= 0x20 && c < 0x7F) {
            piece = std::string(1, char(c));
        } else if (c >= 0x80) {
            const size_t length = utf8SequenceLength(text, i);
            if (length > 0) {
                piece = std::string(text.substr(i, length));
                consumed = length;
                width = 1;  // one character on screen
            } else {
                piece = escapeByte(c);
            }
        } else {
            piece = escapeByte(c);
        }
        if (shown >= limit) return out + "...";
        out += piece;
        shown += width > 0 ? width : piece.size();
        i += consumed;
    }
    return out;
}

std::string quoteUser(std::string_view text, size_t limit) {
    return "'" + escaped(text, limit) + "'";
}

size_t decimalPrefixLength(std::string_view text) {
    size_t i = 0;
    const auto digit = [&](size_t k) {
        return k < text.size() && std::isdigit(static_cast<unsigned char>(text[k]));
    };
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) ++i;
    size_t digits = 0;
    while (digit(i)) ++i, ++digits;
    if (i < text.size() && text[i] == '.') {
        ++i;
        while (digit(i)) ++i, ++digits;
    }
    if (digits == 0) return 0;
    if (i < text.size() && (text[i] == 'e' || text[i] == 'E')) {
        size_t k = i + 1;
        if (k < text.size() && (text[k] == '+' || text[k] == '-')) ++k;
        if (digit(k)) {
            while (digit(k)) ++k;
            i = k;
        }
    }
    // "0x10": the digits stop at 'x'; refuse rather than read 0 and leave "x10" as a unit.
    if (i < text.size() && (text[i] == 'x' || text[i] == 'X') && i > 0 && text[i - 1] == '0')
        return 0;
    return i;
}

std::optional<double> parseDecimal(std::string_view text) {
    const size_t length = decimalPrefixLength(text);
    if (length == 0 || length != text.size()) return std::nullopt;
    const std::string copy(text);  // strtod needs a terminator
    return std::strtod(copy.c_str(), nullptr);
}

std::string htmlEscape(std::string_view text) {
    std::string out;
    out.reserve(text.size());
    for (size_t i = 0; i < text.size();) {
        const auto c = static_cast<unsigned char>(text[i]);
        size_t consumed = 1;
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default:
                if (c >= 0x80) {
                    const size_t length = utf8SequenceLength(text, i);
                    if (length > 0) {
                        out.append(text.substr(i, length));
                        consumed = length;
                    } else {
                        out += "\xEF\xBF\xBD";
                    }
                } else if (c < 0x20 && c != '\n' && c != '\t') {
                    out += "\xEF\xBF\xBD";
                } else {
                    out += char(c);
                }
        }
        i += consumed;
    }
    return out;
}

std::string asciiLower(std::string_view text) {
    std::string out(text);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

std::string formatNumber(double value, int significantDigits) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.*g", significantDigits, value);
    return buffer;
}

std::string formatQuantity(double value, std::string_view unit, int significantDigits) {
    const double magnitude = std::fabs(value);
    std::string number;
    if (!(magnitude >= 1e-4 && magnitude < 1e15)) {  // 0, tiny, huge, inf, nan: "%g" form
        number = formatNumber(value == 0.0 ? 0.0 : value, significantDigits);
    } else {
        const int decimals =
            std::max(0, significantDigits - 1 - int(std::floor(std::log10(magnitude))));
        char buffer[64];
        std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
        number = buffer;
        if (number.find('.') != std::string::npos) {
            number.erase(number.find_last_not_of('0') + 1);
            if (number.back() == '.') number.pop_back();
        }
        if (number == "-0") number = "0";
    }
    return unit.empty() ? number : number + " " + std::string(unit);
}

}  // namespace vpsim
