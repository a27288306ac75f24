// `vpsim devices [--json]`: the Vulkan devices and the limits that matter to vpsim.
#include <iostream>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "vpsim/core/error.h"

namespace {

void printDevices(bool json) {
    auto devices = vpsim::gpu::listDevices();
    if (json) {
        nlohmann::json list = nlohmann::json::array();
        for (const auto& d : devices) list.push_back(d.toJson());
        vpsim::cli::printJson({{"devices", list}});
        return;
    }
    if (devices.empty()) std::cout << "no Vulkan devices (the CPU path will be used)\n";
    for (const auto& d : devices) {
        std::cout << d.index << ": " << d.name << " [" << d.type << ", Vulkan " << d.apiVersion
                  << ", " << d.driver << "]\n"
                  << "   max storage buffer " << vpsim::formatBytes(double(d.maxStorageBufferRange))
                  << ", device memory " << vpsim::formatBytes(double(d.deviceLocalBytes)) << "\n"
                  << "   max workgroups " << d.maxWorkgroupCount[0] << " x "
                  << d.maxWorkgroupCount[1] << " x " << d.maxWorkgroupCount[2]
                  << ", max invocations " << d.maxWorkgroupInvocations << ", subgroup "
                  << d.subgroupSize << "\n"
                  << "   push constants " << d.maxPushConstantBytes << " B, shared memory "
                  << d.maxSharedMemoryBytes << " B\n"
                  << "   int64 " << (d.int64 ? "yes" : "no") << ", int64 atomics "
                  << (d.int64Atomics ? "yes" : "no") << ", float atomic add "
                  << (d.float32AtomicAdd ? "yes" : "no") << ", timestamps "
                  << (d.timestampPeriodNs > 0 ? "yes" : "no") << "\n";
    }
}

vpsim::cli::CommandRegistration registerDevices{
    "devices", [](CLI::App& app, const vpsim::cli::Globals&) {
        auto* command =
            app.add_subcommand("devices", "list Vulkan devices with the limits that matter");
        auto json = std::make_shared<bool>(false);
        command->add_flag("--json", *json, "print JSON");
        command->callback([json] { printDevices(*json); });
    }};

}  // namespace
