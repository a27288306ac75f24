#include "vpsim/core/units.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim {
namespace {

struct UnitDef {
    double toBase;
    Dimension dimension;
};

const std::map<std::string, UnitDef>& unitTable() {
    static const std::map<std::string, UnitDef> table = {
        {"m", {1e3, dim::LENGTH}},
        {"cm", {10.0, dim::LENGTH}},
        {"mm", {1.0, dim::LENGTH}},
        {"um", {1e-3, dim::LENGTH}},
        {"\xC2\xB5m", {1e-3, dim::LENGTH}},
        {"\xCE\xBCm", {1e-3, dim::LENGTH}},
        {"nm", {1e-6, dim::LENGTH}},
        {"s", {1.0, dim::TIME}},
        {"ms", {1e-3, dim::TIME}},
        {"us", {1e-6, dim::TIME}},
        {"\xC2\xB5s", {1e-6, dim::TIME}},
        {"ns", {1e-9, dim::TIME}},
        {"min", {60.0, dim::TIME}},
        {"h", {3600.0, dim::TIME}},
        {"J", {1e3, dim::ENERGY}},
        {"mJ", {1.0, dim::ENERGY}},
        {"uJ", {1e-3, dim::ENERGY}},
        {"\xC2\xB5J", {1e-3, dim::ENERGY}},
        {"W", {1e3, dim::POWER}},
        {"kW", {1e6, dim::POWER}},
        {"mW", {1.0, dim::POWER}},
        {"uW", {1e-3, dim::POWER}},
        {"\xC2\xB5W", {1e-3, dim::POWER}},
        {"rad", {1.0, dim::ANGLE}},
        {"deg", {M_PI / 180.0, dim::ANGLE}},
        {"%", {0.01, dim::DIMENSIONLESS}},
    };
    return table;
}

Dimension scaled(Dimension d, int power) {
    return {d.length * power, d.time * power, d.energy * power, d.angle * power};
}

Dimension combined(Dimension a, Dimension b) {
    return {a.length + b.length, a.time + b.time, a.energy + b.energy, a.angle + b.angle};
}

std::string trim(const std::string& s) {
    size_t b = s.find_first_not_of(" \t");
    size_t e = s.find_last_not_of(" \t");
    return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

/// One factor such as "cm^2", "cm2", "mm^-1" or "1". Multiplies into factor/dimension.
void applyFactor(const std::string& token, int sign, const std::string& text, double& factor,
                 Dimension& dimension) {
    if (token.empty() || token == "1") return;
    size_t caret = token.find('^');
    std::string symbol = token, exponentText;
    if (caret != std::string::npos) {
        symbol = token.substr(0, caret);
        exponentText = token.substr(caret + 1);
    } else {
        size_t digits = token.size();
        while (digits > 0 && std::isdigit(static_cast<unsigned char>(token[digits - 1]))) --digits;
        if (digits < token.size() && digits > 0 && token.size() - digits == 1) {
            symbol = token.substr(0, digits);
            exponentText = token.substr(digits);
        }
    }
    int exponent = 1;
    if (!exponentText.empty()) {
        char* end = nullptr;
        long parsed = std::strtol(exponentText.c_str(), &end, 10);
        if (*end != '\0' || parsed == 0 || std::abs(parsed) > 4)
            throw InputError("bad unit exponent in " + quoteUser(text));
        exponent = static_cast<int>(parsed);
    }
    auto it = unitTable().find(symbol);
    if (it == unitTable().end())
        throw InputError("unknown unit " + quoteUser(symbol) + " in " + quoteUser(text));
    factor *= std::pow(it->second.toBase, sign * exponent);
    dimension = combined(dimension, scaled(it->second.dimension, sign * exponent));
}

void applyProduct(const std::string& part, int sign, const std::string& text, double& factor,
                  Dimension& dimension) {
    size_t start = 0;
    while (start <= part.size()) {
        size_t star = part.find('*', start);
        std::string token =
            trim(part.substr(start, star == std::string::npos ? std::string::npos : star - start));
        applyFactor(token, sign, text, factor, dimension);
        if (star == std::string::npos) break;
        start = star + 1;
    }
}

}  // namespace

std::string Dimension::describe() const {
    if (*this == dim::DIMENSIONLESS) return "dimensionless";
    if (*this == dim::LENGTH) return "length";
    if (*this == dim::AREA) return "area";
    if (*this == dim::TIME) return "time";
    if (*this == dim::ENERGY) return "energy";
    if (*this == dim::POWER) return "power";
    if (*this == dim::DOSE) return "dose (energy/area)";
    if (*this == dim::INVERSE_DOSE) return "inverse dose (area/energy)";
    if (*this == dim::IRRADIANCE) return "irradiance (power/area)";
    if (*this == dim::INVERSE_LENGTH) return "inverse length";
    if (*this == dim::SPEED) return "speed";
    if (*this == dim::ACCELERATION) return "acceleration";
    if (*this == dim::ANGLE) return "angle";
    return baseUnit();
}

std::string Dimension::baseUnit() const {
    std::string numerator, denominator;
    auto add = [&](const char* unit, int power) {
        if (power == 0) return;
        std::string& side = power > 0 ? numerator : denominator;
        if (!side.empty()) side += "*";
        side += unit;
        if (std::abs(power) != 1) side += "^" + std::to_string(std::abs(power));
    };
    add("mJ", energy);
    add("mm", length);
    add("s", time);
    add("rad", angle);
    if (numerator.empty()) numerator = "1";
    return denominator.empty() ? numerator : numerator + "/" + denominator;
}

Quantity parseQuantity(const std::string& rawText) {
    std::string text = trim(rawText);
    // Decimal only: strtod would also read "0x10" as 16, "inf" and "nan".
    const size_t length = decimalPrefixLength(text);
    if (length == 0)
        throw InputError("expected a number with optional unit (decimal digits only), got " +
                         quoteUser(text));
    const double number = std::strtod(text.substr(0, length).c_str(), nullptr);
    if (!std::isfinite(number)) throw InputError("value is not finite: " + quoteUser(text));
    std::string units = trim(text.substr(length));
    Quantity quantity{number, dim::DIMENSIONLESS};
    if (units.empty()) {
        if (!(std::fabs(number) <= MAX_QUANTITY_MAGNITUDE))
            throw InputError("value " + quoteUser(text) + " is out of range (beyond +-1e18)");
        return quantity;
    }
    double factor = 1.0;
    Dimension dimension;
    size_t slash = units.find('/');
    applyProduct(units.substr(0, slash), +1, text, factor, dimension);
    while (slash != std::string::npos) {
        size_t next = units.find('/', slash + 1);
        applyProduct(units.substr(slash + 1,
                                  next == std::string::npos ? std::string::npos : next - slash - 1),
                     -1, text, factor, dimension);
        slash = next;
    }
    quantity.value = number * factor;
    quantity.dimension = dimension;
    if (!(std::fabs(quantity.value) <= MAX_QUANTITY_MAGNITUDE))
        throw InputError("value " + quoteUser(text) + " is out of range (beyond +-1e18 " +
                         dimension.baseUnit() + ")");
    return quantity;
}

double parseQuantity(const std::string& text, Dimension expected, const std::string& key,
                     const std::string& file) {
    Quantity quantity;
    try {
        quantity = parseQuantity(text);
    } catch (const InputError& e) {
        throw InputError(e.reason(), file, key);
    }
    const bool bareNumber = parseDecimal(trim(text)).has_value();
    if (bareNumber) return quantity.value;
    if (quantity.dimension != expected)
        throw InputError("expected " + expected.describe() + " (e.g. in " + expected.baseUnit() +
                             "), got " + quantity.dimension.describe() + " from " +
                             quoteUser(trim(text)),
                         file, key);
    return quantity.value;
}

double quantityFromJson(const nlohmann::json& value, Dimension expected, const std::string& key,
                        const std::string& file) {
    if (value.is_number()) {
        double number = value.get<double>();
        if (!std::isfinite(number)) throw InputError("value is not finite", file, key);
        return number;
    }
    if (value.is_string()) return parseQuantity(value.get<std::string>(), expected, key, file);
    throw InputError("expected a number (in " + expected.baseUnit() +
                         ") or a string with units, got " + std::string(value.type_name()),
                     file, key);
}

}  // namespace vpsim
