#include "vpsim/core/resources.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>

#include "vpsim/core/error.h"

namespace vpsim {
namespace {

uint64_t parseLimit(const char* text) {
    char* end = nullptr;
    const double value = std::strtod(text, &end);
    double factor = 1.0;
    if (end && (*end == 'K' || *end == 'k')) factor = 1024.0;
    if (end && (*end == 'M' || *end == 'm')) factor = 1024.0 * 1024.0;
    if (end && (*end == 'G' || *end == 'g')) factor = 1024.0 * 1024.0 * 1024.0;
    if (!(value > 0) || !std::isfinite(value * factor)) return 0;
    return uint64_t(value * factor);
}

}  // namespace

uint64_t memoryBudget() {
    if (const char* text = std::getenv("VPSIM_MEMORY_LIMIT")) {
        if (const uint64_t limit = parseLimit(text)) return limit;
    }
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
    const uint64_t physical = pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : 0;
    // Half the memory, at most 16 GiB unless VPSIM_MEMORY_LIMIT says more: beyond that a user
    // size is far more often a unit mistake than a wish, and the work would take hours.
    const uint64_t floor = uint64_t(256) << 20, ceiling = uint64_t(16) << 30;
    return std::max(floor, std::min(physical / 2, ceiling));
}

void checkMemory(double bytes, const std::string& what, const std::string& hint) {
    const double budget = double(memoryBudget());
    if (std::isfinite(bytes) && bytes <= budget) return;
    throw ResourceError(
        what + " would need " +
        (std::isfinite(bytes) ? formatBytes(bytes) : std::string("unbounded")) +
        ", more than the " + formatBytes(budget) +
        " allowed (half the memory, at most 16 GiB; VPSIM_MEMORY_LIMIT sets it): " + hint);
}

}  // namespace vpsim
