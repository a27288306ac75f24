#include "commands.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/text.h"

namespace vpsim::cli {

std::vector<std::pair<std::string, CommandSetup>>& commandRegistry() {
    static std::vector<std::pair<std::string, CommandSetup>> registry;
    return registry;
}

CommandRegistration::CommandRegistration(const std::string& name, CommandSetup setup) {
    commandRegistry().emplace_back(name, std::move(setup));
}

std::shared_ptr<gpu::Context> Globals::gpu() const {
    if (!mGpuResolved) {
        gpu::ContextOptions options;
        options.device = device;
        options.validation = validation;
        mGpu = gpu::contextForBackend(gpu::parseBackend(backend), options);
        mGpuResolved = true;
    }
    return mGpu;
}

uint64_t parseCount(const std::string& text, uint64_t max, const std::string& option) {
    // Decimal only ("1e6" is fine; "0x10", "inf" and "nan" are not counts).
    const std::optional<double> n = parseDecimal(text);
    if (!n || !(*n >= 1) || *n > double(max) || *n != std::floor(*n))
        throw InputError(option + ": expected a whole number from 1 to " + std::to_string(max) +
                         ", got " + quoteUser(text));
    return uint64_t(*n);
}

void printJson(const nlohmann::json& value) {
    std::cout << value.dump(2) << std::endl;
}

}  // namespace vpsim::cli
