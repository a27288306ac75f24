#include "commands.h"

#include <cstdlib>
#include <iostream>

#include <nlohmann/json.hpp>

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

void printJson(const nlohmann::json& value) { std::cout << value.dump(2) << std::endl; }

} // namespace vpsim::cli
