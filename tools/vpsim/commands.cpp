#include "commands.h"

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>

#include <nlohmann/json.hpp>

#include "vpsim/core/error.h"
#include "vpsim/core/log.h"
#include "vpsim/core/progress.h"
#include "vpsim/core/resources.h"
#include "vpsim/core/text.h"
#include "vpsim/kernel/kernel_cache.h"

namespace vpsim::cli {

std::vector<std::pair<std::string, CommandSetup>>& commandRegistry() {
    static std::vector<std::pair<std::string, CommandSetup>> registry;
    return registry;
}

CommandRegistration::CommandRegistration(const std::string& name, CommandSetup setup) {
    commandRegistry().emplace_back(name, std::move(setup));
}

void Globals::readEnvironment() {
    auto env = [](const char* name) -> std::string {
        const char* value = std::getenv(name);
        return value ? value : "";
    };
    if (!env("VPSIM_BACKEND").empty()) backend = env("VPSIM_BACKEND");
    device = env("VPSIM_DEVICE");
    validation = !env("VPSIM_VALIDATION").empty() && env("VPSIM_VALIDATION") != "0";
    const std::string level = env("VPSIM_LOG");
    if (level == "error") setLogLevel(LogLevel::Error);
    if (level == "warn") setLogLevel(LogLevel::Warn);
    if (level == "debug") setLogLevel(LogLevel::Debug);
    cacheDirectory = kernel::defaultKernelCacheDirectory(
        std::getenv("VPSIM_CACHE_DIR"), std::getenv("XDG_CACHE_HOME"), std::getenv("HOME"));
    const std::string limit = env("VPSIM_MEMORY_LIMIT");
    memoryLimit = limit.empty() ? 0 : parseMemorySize(limit, "VPSIM_MEMORY_LIMIT");
}

RunContext Globals::hostContext() const {
    RunContext context;
    context.monteCarloOnCpuDevices = backend == "vulkan";
    context.cacheDirectory = cacheDirectory;
    context.memoryLimit = memoryLimit;
    return context;
}

RunContext Globals::runContext() const {
    RunContext context = hostContext();
    context.gpu = gpu();
    return context;
}

std::shared_ptr<cluster::Communicator> Globals::communicator() const {
    if (!mCommunicator) {
        cluster::LaunchEnvironment launch;
        launch.ompiWorldSize = std::getenv("OMPI_COMM_WORLD_SIZE");
        launch.pmiSize = std::getenv("PMI_SIZE");
        launch.pmixRank = std::getenv("PMIX_RANK");
        mCommunicator = cluster::startCommunicator(launch);
        if (!mCommunicator->isRoot()) Progress::setEnabled(false);  // one progress display
    }
    return mCommunicator;
}

void Globals::abortOtherRanks() const {
    if (mCommunicator && mCommunicator->ranks() > 1) mCommunicator->abort(1);
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

std::string optionName(const std::string& key) {
    std::string name = "--" + key;
    for (char& c : name)
        if (c == '_') c = '-';
    return name;
}

void printJson(const nlohmann::json& value) {
    std::cout << value.dump(2) << std::endl;
}

void printComponents(const nlohmann::json& list, const std::string& section) {
    for (const auto& c : list) {
        std::cout << c["name"].get<std::string>() << ": " << c["description"].get<std::string>()
                  << "\n";
        for (const auto& key : c["keys"]) {
            std::string fallback = key["required"].get<bool>() ? "required"
                                   : key["default"].is_null()  ? "no default"
                                                               : "default " + key["default"].dump();
            std::string kind = key["dimension"].get<std::string>();
            if (kind.empty()) kind = key["kind"].get<std::string>();
            std::cout << "    " << section << "." << key["name"].get<std::string>() << "  (" << kind
                      << ", " << fallback << ")  " << key["doc"].get<std::string>() << "\n";
        }
    }
}

}  // namespace vpsim::cli
