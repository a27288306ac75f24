#include "vpsim/core/checks.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

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
    namespace fs = std::filesystem;
    fs::path path = node.string(key);
    if (path.empty()) throw node.error(key, "empty file name");
    if (path.is_relative()) path = fs::path(node.file()).parent_path() / path;
    // The error_code forms: a 1000-character name must be a message, not a filesystem_error.
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (ec || !fs::exists(status))
        throw node.error(
            key, "file not found: " + quoteUser(path.string()) +
                     (ec && ec != std::errc::no_such_file_or_directory ? " (" + ec.message() + ")"
                                                                       : ""));
    if (!fs::is_regular_file(status))
        throw node.error(key, "not a regular file: " + quoteUser(path.string()));
    return path.string();
}

}  // namespace vpsim
