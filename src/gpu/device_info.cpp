// Vulkan instance creation and the device survey behind `vpsim devices`.
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include <nlohmann/json.hpp>

#include "gpu/instance.h"
#include "gpu/vulkan_internal.h"

namespace vpsim::gpu {
namespace {

/// The worker threads of a CPU driver, as llvmpipe counts them (lp_screen.c): LP_NUM_THREADS
/// where set, else the online CPUs, at most its 32 (LP_MAX_THREADS); at least the one thread
/// that runs the work when it has none.
uint32_t cpuDriverThreads() {
    long threads = sysconf(_SC_NPROCESSORS_ONLN);
    if (const char* text = std::getenv("LP_NUM_THREADS")) {
        char* end = nullptr;
        const long asked = std::strtol(text, &end, 10);
        if (end != text && *end == '\0' && asked >= 0) threads = asked;
    }
    return uint32_t(std::clamp(threads, 1L, 32L));
}

std::string deviceTypeName(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
        case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
        default: return "other";
    }
}

std::string versionText(uint32_t v) {
    return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) +
           "." + std::to_string(VK_API_VERSION_PATCH(v));
}

bool hasDeviceExtension(VkPhysicalDevice physical, const char* name) {
    uint32_t count = 0;
    vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, nullptr);
    std::vector<VkExtensionProperties> extensions(count);
    vkEnumerateDeviceExtensionProperties(physical, nullptr, &count, extensions.data());
    for (const auto& e : extensions)
        if (!std::strcmp(e.extensionName, name)) return true;
    return false;
}

}  // namespace

bool supportsAtomicFloat(VkPhysicalDevice physical) {
    if (!hasDeviceExtension(physical, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME)) return false;
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat{};
    atomicFloat.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT;
    VkPhysicalDeviceFeatures2 features{};
    features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    features.pNext = &atomicFloat;
    vkGetPhysicalDeviceFeatures2(physical, &features);
    return atomicFloat.shaderBufferFloat32AtomicAdd == VK_TRUE;
}

DeviceInfo describeDevice(VkPhysicalDevice physical, uint32_t index) {
    VkPhysicalDeviceSubgroupProperties subgroup{};
    subgroup.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
    VkPhysicalDeviceDriverProperties driver{};
    driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
    subgroup.pNext = &driver;
    VkPhysicalDeviceProperties2 properties{};
    properties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    properties.pNext = &subgroup;
    vkGetPhysicalDeviceProperties2(physical, &properties);
    const VkPhysicalDeviceLimits& limits = properties.properties.limits;

    VkPhysicalDeviceVulkan12Features features12{};
    features12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
    VkPhysicalDeviceFeatures2 features{};
    features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    features.pNext = &features12;
    vkGetPhysicalDeviceFeatures2(physical, &features);

    DeviceInfo info;
    info.index = index;
    info.name = properties.properties.deviceName;
    info.type = deviceTypeName(properties.properties.deviceType);
    info.driver = std::string(driver.driverName) + " " + driver.driverInfo;
    info.apiVersion = versionText(properties.properties.apiVersion);
    info.maxStorageBufferRange = limits.maxStorageBufferRange;
    info.maxUniformBufferRange = limits.maxUniformBufferRange;
    info.maxTexelBufferElements = limits.maxTexelBufferElements;
    for (int i = 0; i < 3; ++i) {
        info.maxWorkgroupCount[i] = limits.maxComputeWorkGroupCount[i];
        info.maxWorkgroupSize[i] = limits.maxComputeWorkGroupSize[i];
    }
    info.maxWorkgroupInvocations = limits.maxComputeWorkGroupInvocations;
    info.maxPushConstantBytes = limits.maxPushConstantsSize;
    info.maxSharedMemoryBytes = limits.maxComputeSharedMemorySize;
    info.subgroupSize = subgroup.subgroupSize;
    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(physical, &memory);
    for (uint32_t h = 0; h < memory.memoryHeapCount; ++h)
        if (memory.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            info.deviceLocalBytes =
                std::max<uint64_t>(info.deviceLocalBytes, memory.memoryHeaps[h].size);
    info.int64 = features.features.shaderInt64 == VK_TRUE;
    info.int64Atomics = features12.shaderBufferInt64Atomics == VK_TRUE;
    info.float32AtomicAdd = supportsAtomicFloat(physical);
    if (info.type == "cpu") info.hostThreads = cpuDriverThreads();

    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &familyCount, families.data());
    for (const auto& family : families)
        if ((family.queueFlags & VK_QUEUE_COMPUTE_BIT) && family.timestampValidBits > 0 &&
            limits.timestampComputeAndGraphics) {
            info.timestampPeriodNs = limits.timestampPeriod;
            break;
        }
    return info;
}

nlohmann::json DeviceInfo::toJson() const {
    return {{"index", index},
            {"name", name},
            {"type", type},
            {"driver", driver},
            {"api_version", apiVersion},
            {"max_storage_buffer_range", maxStorageBufferRange},
            {"max_uniform_buffer_range", maxUniformBufferRange},
            {"max_texel_buffer_elements", maxTexelBufferElements},
            {"max_workgroup_count", maxWorkgroupCount},
            {"max_workgroup_size", maxWorkgroupSize},
            {"max_workgroup_invocations", maxWorkgroupInvocations},
            {"max_push_constant_bytes", maxPushConstantBytes},
            {"max_shared_memory_bytes", maxSharedMemoryBytes},
            {"subgroup_size", subgroupSize},
            {"device_local_bytes", deviceLocalBytes},
            {"float32_atomic_add", float32AtomicAdd},
            {"int64", int64},
            {"int64_atomics", int64Atomics},
            {"timestamp_period_ns", timestampPeriodNs},
            {"host_threads", hostThreads}};
}

std::vector<DeviceInfo> listDevices() {
    Instance instance(false, nullptr);
    std::vector<DeviceInfo> devices;
    auto physicals = instance.physicalDevices();
    for (uint32_t i = 0; i < physicals.size(); ++i)
        devices.push_back(describeDevice(physicals[i], i));
    return devices;
}

}  // namespace vpsim::gpu
