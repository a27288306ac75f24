#include "vpsim/core/resources.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim {

uint64_t defaultMemoryBudget() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGESIZE);
    const uint64_t physical = pages > 0 && pageSize > 0 ? uint64_t(pages) * uint64_t(pageSize) : 0;
    // Half the memory, at most 16 GiB unless the context says more: beyond that a user size is
    // far more often a unit mistake than a wish, and the work would take hours.
    const uint64_t floor = uint64_t(256) << 20, ceiling = uint64_t(16) << 30;
    return std::max(floor, std::min(physical / 2, ceiling));
}

uint64_t memoryBudget(const RunContext& context) {
    return context.memoryLimit ? context.memoryLimit : defaultMemoryBudget();
}

std::string memoryBudgetOrigin(const RunContext& context) {
    return context.memoryLimit ? "set by VPSIM_MEMORY_LIMIT"
                               : "half the memory, at most 16 GiB; VPSIM_MEMORY_LIMIT sets it";
}

uint64_t parseMemorySize(std::string_view text, const std::string& name) {
    const auto fail = [&](const std::string& why) -> uint64_t {
        throw InputError(name + ": " + why + ", got " + quoteUser(text) +
                         " (a number of bytes with an optional K, M or G, e.g. 512M or 5G)");
    };
    // The number is decimal only (no "0x", "inf", "nan"), then at most one suffix letter.
    const size_t digits = decimalPrefixLength(text);
    if (digits == 0) return fail("expected a memory size");
    double factor = 1.0;
    std::string_view rest = text.substr(digits);
    if (!rest.empty()) {
        const char suffix = rest.front();
        if (suffix == 'K' || suffix == 'k') factor = 1024.0;
        if (suffix == 'M' || suffix == 'm') factor = 1024.0 * 1024.0;
        if (suffix == 'G' || suffix == 'g') factor = 1024.0 * 1024.0 * 1024.0;
        if (factor == 1.0 || rest.size() > 1)
            return fail("unexpected text after the number (only a K, M or G may follow it)");
    }
    const std::optional<double> value = parseDecimal(text.substr(0, digits));
    if (!value) return fail("expected a memory size");
    const double bytes = *value * factor;
    if (!(bytes >= 1.0)) return fail("expected a positive size of at least one byte");
    if (!(bytes < 9.2e18)) return fail("size out of range");
    return uint64_t(bytes);
}

void checkMemory(const RunContext& context, double bytes, const std::string& what,
                 const std::string& hint) {
    const double budget = double(memoryBudget(context));
    if (std::isfinite(bytes) && bytes <= budget) return;
    throw ResourceError(what + " would need " +
                        (std::isfinite(bytes) ? formatBytes(bytes) : std::string("unbounded")) +
                        ", more than the " + formatBytes(budget) + " allowed (" +
                        memoryBudgetOrigin(context) + "): " + hint);
}

}  // namespace vpsim
