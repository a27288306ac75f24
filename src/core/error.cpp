#include "vpsim/core/error.h"

#include <cstdio>

#include "vpsim/core/text.h"

namespace vpsim {
namespace {

// File names and keys come from the user: escaped and cut, so that a 1000-character path or a
// key with a newline still gives one readable line. The reason quotes its own user text.
constexpr size_t FILE_LIMIT = 160, KEY_LIMIT = 120, REASON_LIMIT = 800;

std::string composeInputMessage(const std::string& rawReason, const std::string& rawFile,
                                const std::string& rawKey, int line) {
    const std::string reason = escaped(rawReason, REASON_LIMIT);
    const std::string file = escaped(rawFile, FILE_LIMIT), key = escaped(rawKey, KEY_LIMIT);
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
    if (unit > 0) return formatQuantity(bytes, units[unit], 3);
    char text[64];
    std::snprintf(text, sizeof text, "%.0f %s", bytes, units[unit]);
    return text;
}

}  // namespace vpsim
