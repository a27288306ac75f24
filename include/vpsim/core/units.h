#pragma once
/// @file
/// Physical quantities in config files and on the command line.
/// Inside vpsim every value is in the base units mm, s, mJ (so power in mW = mJ/s, dose in
/// mJ/mm^2, attenuation in 1/mm) and angles in radians. Inputs may be plain numbers (already in
/// base units) or strings with units: "50 um", "10 mW", "78 mJ/cm^2", "84 /cm", "1 m/s", "30 deg".

#include <string>

#include <nlohmann/json_fwd.hpp>

namespace vpsim {

/// Exponents of the base dimensions length (mm), time (s), energy (mJ) and angle (rad).
struct Dimension {
    int length = 0, time = 0, energy = 0, angle = 0;
    bool operator==(const Dimension& o) const {
        return length == o.length && time == o.time && energy == o.energy && angle == o.angle;
    }
    bool operator!=(const Dimension& o) const { return !(*this == o); }
    /// Human name such as "length" or "dose (energy/area)".
    std::string describe() const;
    /// Base unit spelled out, e.g. "mm", "mJ/mm^2", "1/mm".
    std::string baseUnit() const;
};

namespace dim {
constexpr Dimension DIMENSIONLESS{0, 0, 0, 0};
constexpr Dimension LENGTH{1, 0, 0, 0};
constexpr Dimension AREA{2, 0, 0, 0};
constexpr Dimension TIME{0, 1, 0, 0};
constexpr Dimension ENERGY{0, 0, 1, 0};
constexpr Dimension POWER{0, -1, 1, 0};
constexpr Dimension DOSE{-2, 0, 1, 0};            ///< mJ/mm^2
constexpr Dimension INVERSE_DOSE{2, 0, -1, 0};    ///< mm^2/mJ (the FPP rate constant K)
constexpr Dimension IRRADIANCE{-2, -1, 1, 0};     ///< mW/mm^2
constexpr Dimension INVERSE_LENGTH{-1, 0, 0, 0};  ///< 1/mm (attenuation coefficients)
constexpr Dimension SPEED{1, -1, 0, 0};           ///< mm/s
constexpr Dimension ACCELERATION{1, -2, 0, 0};    ///< mm/s^2
constexpr Dimension ANGLE{0, 0, 0, 1};            ///< rad
}  // namespace dim

/// Largest magnitude of any quantity in base units: nothing physical in mm, s, mJ comes near it,
/// and it keeps products of a few quantities far from overflow.
constexpr double MAX_QUANTITY_MAGNITUDE = 1e18;

/// A parsed value in base units with its dimension.
struct Quantity {
    double value = 0.0;
    Dimension dimension;
};

/// Parses "78 mJ/cm^2" into base units without checking the dimension.
/// @throw InputError when the number or a unit is not understood.
Quantity parseQuantity(const std::string& text);

/// Parses text and converts to base units of the expected dimension. A bare number is taken as
/// already in base units.
/// @param key,file used only to name the input in error messages
/// @throw InputError on a malformed string or a unit of the wrong dimension
double parseQuantity(const std::string& text, Dimension expected, const std::string& key = "",
                     const std::string& file = "");

/// Same for a JSON value, which may be a number (base units) or a string with units.
/// @throw InputError when the value is neither, or the dimension is wrong
double quantityFromJson(const nlohmann::json& value, Dimension expected,
                        const std::string& key = "", const std::string& file = "");

}  // namespace vpsim
