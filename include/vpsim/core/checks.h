#pragma once
/// @file
/// The parameter checks every module repeats: positive finite numbers, in code and in config
/// sections, with one wording of the message.

#include <optional>
#include <string>

#include "vpsim/core/config.h"
#include "vpsim/core/units.h"

namespace vpsim {

/// @throw InputError "`what` must be positive and finite, got V" unless 0 < value < inf
void requirePositive(double value, const std::string& what);

/// A positive finite quantity of `dimension` read from `key` (the fallback when absent, if any).
/// @throw InputError naming the file and key when it is missing, of the wrong unit, or <= 0
double positiveQuantity(const ConfigNode& node, const std::string& key, Dimension dimension,
                        std::optional<double> fallback = std::nullopt);

/// The path in `key`, relative to the directory of the node's file when not absolute.
/// @throw InputError naming the file and key when the file does not exist
std::string resolvePath(const ConfigNode& node, const std::string& key);

}  // namespace vpsim
