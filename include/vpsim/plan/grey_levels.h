#pragma once
/// @file
/// A projector's grey-level calibration (seed 001 Section 3.3, Fig. 6): the irradiance at the
/// resin for each 8-bit grey level, measured at a few levels and interpolated linearly, and the
/// exposure time of a layer, so a pixel's dose is irradiance(grey) x exposure time. Grey 0 is
/// dark; levels below the first calibrated one give no usable light (dose 0). Doses are
/// quantised to the grey level whose dose is nearest.
/// Config (machine section): "grey_levels": [[150, "12.2 mW/cm^2"], [255, 0.27], ...] with
/// irradiance in mW/mm^2 unless a unit is given, and "exposure_time": "5 s".
/// Units: irradiance mW/mm^2, time s, dose mJ/mm^2.

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

namespace vpsim {
class ConfigNode;
}

namespace vpsim::plan {

class GreyLevels {
public:
    /// @param points (grey, irradiance mW/mm^2), grey strictly increasing in 1..255, irradiance
    ///        strictly increasing and > 0 @param exposureTime s (> 0)
    /// @throw InputError on an empty, unordered or out-of-range table or a bad time
    GreyLevels(std::vector<std::pair<int, double>> points, double exposureTime);

    double exposureTime() const { return mExposureTime; }
    const std::vector<std::pair<int, double>>& points() const { return mPoints; }
    /// Irradiance (mW/mm^2) of a grey level: 0 below the first point, linear between points,
    /// the last point's value above it.
    double irradiance(int grey) const;
    /// Dose (mJ/mm^2) a pixel of this grey level delivers in one exposure.
    double dose(int grey) const {
        return mDose[std::size_t(grey < 0 ? 0 : grey > 255 ? 255 : grey)];
    }
    /// Largest dose (grey 255), mJ/mm^2.
    double maxDose() const { return mDose[255]; }
    /// Smallest non-null dose (the first calibrated grey), mJ/mm^2.
    double minDose() const;
    /// The grey level whose dose is nearest to `dose` (0 for dose <= 0; 255 above the top).
    uint8_t quantise(double dose) const;

private:
    std::vector<std::pair<int, double>> mPoints;
    double mExposureTime;
    std::array<double, 256> mDose{};
};

/// Reads `grey_levels` and `exposure_time` from a machine section.
/// @throw InputError naming the file and key when missing or invalid
GreyLevels greyLevelsFromConfig(const ConfigNode& machine);

}  // namespace vpsim::plan
