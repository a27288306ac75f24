#include "commands.h"

#include <cmath>
#include <cstdlib>
#include <iostream>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"

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
    double n = 0;
    size_t used = 0;
    try {
        n = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || !(n >= 1) || n > double(max) || n != std::floor(n))
        throw InputError(option + ": expected a whole number from 1 to " + std::to_string(max) +
                         ", got '" + text + "'");
    return uint64_t(n);
}

void printJson(const nlohmann::json& value) {
    std::cout << value.dump(2) << std::endl;
}

}  // namespace vpsim::cli
