#include "vpsim/core/error.h"

#include <cstdio>

namespace vpsim {
namespace {

std::string composeInputMessage(const std::string& reason, const std::string& file,
                                const std::string& key, int line) {
    std::string where = file;
    if (line > 0) where += (where.empty() ? "line " : ":") + std::to_string(line);
    if (!key.empty()) where += (where.empty() ? "" : ": ") + std::string("key '") + key + "'";
    return where.empty() ? reason : where + ": " + reason;
}

}  // namespace

InputError::InputError(const std::string& reason, const std::string& file, const std::string& key,
                       int line)
    : Error(composeInputMessage(reason, file, key, line)),
      mReason(reason),
      mFile(file),
      mKey(key),
      mLine(line) {}

GpuError::GpuError(const std::string& what, const std::string& resultName, const char* file,
                   int line)
    : Error("GPU: " + what + " failed with " + resultName + " (" + file + ":" +
            std::to_string(line) + ")"),
      mResultName(resultName) {}

std::string formatBytes(double bytes) {
    const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    int unit = 0;
    while (bytes >= 1024.0 && unit < 4) {
        bytes /= 1024.0;
        ++unit;
    }
    char text[64];
    std::snprintf(text, sizeof text, unit == 0 ? "%.0f %s" : "%.2f %s", bytes, units[unit]);
    return text;
}

}  // namespace vpsim
