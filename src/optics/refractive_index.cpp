// Parsing and printing complex refractive indices in the m = n - ik convention (see mie.h).

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "vpsim/core/error.h"
#include "vpsim/optics/mie.h"

namespace vpsim::optics {
namespace {

/// Parses the whole of `text` as a double; false if anything is left over or it is empty.
bool parseWholeNumber(const std::string& text, double& value) {
    if (text.empty()) return false;
    const char* begin = text.c_str();
    char* end = nullptr;
    value = std::strtod(begin, &end);
    return end == begin + text.size() && std::isfinite(value);
}

}  // namespace

Complex parseRefractiveIndex(const std::string& text, const std::string& what) {
    std::string s;
    for (char ch : text)
        if (ch != ' ' && ch != '\t') s += ch;
    auto malformed = [&]() {
        return InputError("cannot parse " + what + " '" + text +
                          "': expected a real number or n-ki such as 1.5 or 1.5-0.1i");
    };
    double re = 0.0, im = 0.0;
    if (parseWholeNumber(s, re)) {
        if (re <= 0.0) throw InputError(what + " must be positive, got '" + text + "'");
        return {re, 0.0};
    }
    // Split at the last sign that is not a leading sign and not an exponent sign.
    size_t split = std::string::npos;
    for (size_t i = s.size(); i-- > 1;) {
        if ((s[i] == '+' || s[i] == '-') && s[i - 1] != 'e' && s[i - 1] != 'E') {
            split = i;
            break;
        }
    }
    if (split == std::string::npos) throw malformed();
    std::string realPart = s.substr(0, split);
    std::string imagPart = s.substr(split + 1);
    const double sign = (s[split] == '-') ? -1.0 : 1.0;
    if (imagPart.empty()) throw malformed();
    if (imagPart.back() == 'i' || imagPart.back() == 'j')
        imagPart.pop_back();
    else if (imagPart.front() == 'i' || imagPart.front() == 'j')
        imagPart.erase(0, 1);
    else
        throw malformed();
    if (imagPart.empty()) imagPart = "1";  // "1.5-i"
    if (!parseWholeNumber(realPart, re) || !parseWholeNumber(imagPart, im) || im < 0.0)
        throw malformed();
    im *= sign;
    if (re <= 0.0) throw InputError(what + " must have a positive real part, got '" + text + "'");
    if (im > 0.0)
        throw InputError(what + " '" + text +
                         "' has a positive imaginary part: vpsim uses m = n - ik (absorbing "
                         "material has a negative imaginary part, e.g. 1.5-0.1i; a Bohren & "
                         "Huffman index n+ik is written n-ik here)");
    return {re, im};
}

std::string formatRefractiveIndex(Complex m) {
    char buffer[64];
    if (m.imag() == 0.0)
        std::snprintf(buffer, sizeof buffer, "%.6g", m.real());
    else
        std::snprintf(buffer, sizeof buffer, "%.6g%c%.6gi", m.real(), m.imag() < 0 ? '-' : '+',
                      std::fabs(m.imag()));
    return buffer;
}

}  // namespace vpsim::optics
