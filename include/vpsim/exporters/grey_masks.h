#pragma once
/// @file
/// Greyscale masks as a projector shows them: each pixel's dose mapped to a grey level through
/// the projector's calibration (plan::GreyLevels), and 8-bit PNG encoding (libpng). Shared by
/// the SL1 and PNG-stack exporters.

#include <cstdint>
#include <vector>

#include "vpsim/core/key_table.h"
#include "vpsim/plan/grey_levels.h"
#include "vpsim/plan/scan_plan.h"

namespace vpsim::exporters {

/// Grey level of every pixel of a mask (row-major, as the mask). @throw InputError on a
/// negative or non-finite dose, or one above the calibration's top by more than 0.5 %
std::vector<uint8_t> maskToGrey(const plan::MaskImage& mask, const plan::GreyLevels& levels);

/// 8-bit greyscale PNG of an image, in memory. @throw InputError when libpng fails
std::vector<uint8_t> encodePngGrey(int width, int height, const std::vector<uint8_t>& grey);

/// The projector calibration keys of the mask exporters, as in the machine section:
/// grey_levels ([[grey, irradiance], ...]) and exposure_time (s per layer), both required.
KeyTable greyLevelKeyTable();
/// @throw InputError naming the key
plan::GreyLevels greyLevelsFromKeys(const KeyReader& keys);

}  // namespace vpsim::exporters
