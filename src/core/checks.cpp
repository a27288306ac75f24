#include "vpsim/core/checks.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "vpsim/core/error.h"

namespace vpsim {

void requirePositive(double value, const std::string& what) {
    if (value > 0.0 && std::isfinite(value)) return;
    std::ostringstream reason;
    reason << what << " must be positive and finite, got " << value;
    throw InputError(reason.str());
}

double positiveQuantity(const ConfigNode& node, const std::string& key, Dimension dimension,
                        std::optional<double> fallback) {
    double value =
        fallback ? node.quantity(key, dimension, *fallback) : node.quantity(key, dimension);
    if (!(value > 0.0) || !std::isfinite(value))
        throw node.error(key, "must be positive and finite");
    return value;
}

std::string resolvePath(const ConfigNode& node, const std::string& key) {
    std::filesystem::path path = node.string(key);
    if (path.is_relative()) path = std::filesystem::path(node.file()).parent_path() / path;
    if (!std::filesystem::exists(path)) throw node.error(key, "file not found: " + path.string());
    return path.string();
}

}  // namespace vpsim
