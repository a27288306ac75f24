#include "vpsim/plan/grey_levels.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "vpsim/core/config.h"
#include "vpsim/core/error.h"
#include "vpsim/core/units.h"

namespace vpsim::plan {

GreyLevels::GreyLevels(std::vector<std::pair<int, double>> points, double exposureTime)
    : mPoints(std::move(points)), mExposureTime(exposureTime) {
    if (!(exposureTime > 0.0) || !std::isfinite(exposureTime))
        throw InputError("grey levels: exposure time must be positive");
    if (mPoints.empty()) throw InputError("grey levels: the calibration table is empty");
    for (size_t i = 0; i < mPoints.size(); ++i) {
        const auto& [grey, value] = mPoints[i];
        if (grey < 1 || grey > 255)
            throw InputError("grey levels: grey " + std::to_string(grey) + " is outside 1..255");
        if (!(value > 0.0) || !std::isfinite(value))
            throw InputError("grey levels: irradiance at grey " + std::to_string(grey) +
                             " must be positive");
        if (i > 0 && (grey <= mPoints[i - 1].first || value <= mPoints[i - 1].second))
            throw InputError("grey levels: grey and irradiance must both increase along the table");
    }
    for (int g = 0; g < 256; ++g) mDose[size_t(g)] = irradiance(g) * mExposureTime;
}

double GreyLevels::irradiance(int grey) const {
    if (grey < mPoints.front().first) return 0.0;
    for (size_t i = 1; i < mPoints.size(); ++i) {
        if (grey > mPoints[i].first) continue;
        const auto& [g0, v0] = mPoints[i - 1];
        const auto& [g1, v1] = mPoints[i];
        return v0 + (v1 - v0) * double(grey - g0) / double(g1 - g0);
    }
    return mPoints.back().second;
}

double GreyLevels::minDose() const {
    return dose(mPoints.front().first);
}

uint8_t GreyLevels::quantise(double dose) const {
    if (!(dose > 0.0)) return 0;
    // mDose is non-decreasing: 0 ... 0, then strictly increasing up to the last point.
    auto it = std::lower_bound(mDose.begin(), mDose.end(), dose);
    if (it == mDose.end()) return 255;
    size_t g = size_t(it - mDose.begin());
    if (g > 0 && dose - mDose[g - 1] < *it - dose) --g;
    while (g > 0 && mDose[g - 1] == mDose[g]) --g;  // the dark levels all mean grey 0
    return uint8_t(g);
}

GreyLevels greyLevelsFromConfig(const ConfigNode& machine) {
    const nlohmann::json& table = machine.raw("grey_levels");
    const std::string key = machine.keyPath("grey_levels");
    if (!table.is_array() || table.empty())
        throw machine.error("grey_levels", "must be a non-empty array of [grey, irradiance]");
    std::vector<std::pair<int, double>> points;
    for (size_t i = 0; i < table.size(); ++i) {
        const nlohmann::json& entry = table[i];
        if (!entry.is_array() || entry.size() != 2 || !entry[0].is_number_integer())
            throw machine.error("grey_levels", "entry " + std::to_string(i) +
                                                   " must be [integer grey, irradiance]");
        points.emplace_back(entry[0].get<int>(),
                            quantityFromJson(entry[1], dim::IRRADIANCE,
                                             key + "[" + std::to_string(i) + "]", machine.file()));
    }
    const double time = machine.quantity("exposure_time", dim::TIME);
    try {
        return GreyLevels(std::move(points), time);
    } catch (const InputError& e) {
        throw machine.error("grey_levels", e.what());
    }
}

}  // namespace vpsim::plan
