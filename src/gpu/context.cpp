#include <chrono>
#include <cstdlib>
#include <cstring>

#include "gpu/instance.h"
#include "gpu/vulkan_internal.h"
#include "vpsim/core/log.h"

namespace vpsim::gpu {
namespace {

int devicePreference(const DeviceInfo& info) {
    if (info.type == "discrete") return 0;
    if (info.type == "integrated") return 1;
    if (info.type == "virtual") return 2;
    if (info.type == "cpu") return 3;
    return 4;
}

/// Picks a device by index, by name part, or (empty selector) hardware first.
uint32_t chooseDevice(const std::vector<DeviceInfo>& devices, const std::string& selector) {
    if (devices.empty())
        throw GpuError(
            "no Vulkan device found; install mesa-vulkan-drivers (lavapipe) or use --backend cpu");
    if (selector.empty()) {
        uint32_t best = 0;
        for (uint32_t i = 1; i < devices.size(); ++i)
            if (devicePreference(devices[i]) < devicePreference(devices[best])) best = i;
        return best;
    }
    std::string names;
    for (const auto& d : devices)
        names += (names.empty() ? "" : ", ") + std::to_string(d.index) + ": " + d.name;
    char* end = nullptr;
    unsigned long index = std::strtoul(selector.c_str(), &end, 10);
    if (*end == '\0') {
        if (index < devices.size()) return uint32_t(index);
        throw GpuError("device index " + selector + " does not exist (devices: " + names + ")");
    }
    for (const auto& d : devices)
        if (d.name.find(selector) != std::string::npos) return d.index;
    throw GpuError("no Vulkan device name contains '" + selector + "' (devices: " + names + ")");
}

}  // namespace

GpuError makeGpuError(const char* what, VkResult result, const char* file, int line) {
    return GpuError(what, resultName(result), file, line);
}

void throwGpuError(const char* what, VkResult result, const char* file, int line) {
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
        throw ResourceError(std::string("GPU memory exhausted (") + resultName(result) + " in " +
                            what + ")");
    throw makeGpuError(what, result, file, line);
}

Context::Context() : mImpl(std::make_unique<Impl>()) {}

std::shared_ptr<Context> Context::create(const ContextOptions& options) {
    std::shared_ptr<Context> context(new Context());
    Impl& c = *context->mImpl;
    c.validation = options.validation;
    c.stagedTransfers = options.stagedTransfers;
    Instance instance(c.validation, &c);
    std::vector<DeviceInfo> devices;
    auto physicals = instance.physicalDevices();
    for (uint32_t i = 0; i < physicals.size(); ++i)
        devices.push_back(describeDevice(physicals[i], i));
    const std::string& selector = options.device;
    uint32_t chosen = chooseDevice(devices, selector);
    instance.release(c.instance, c.messenger);
    c.physical = physicals[chosen];
    c.info = devices[chosen];
    if (!options.int64) c.info.int64 = c.info.int64Atomics = false;
    vkGetPhysicalDeviceMemoryProperties(c.physical, &c.memory);

    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(c.physical, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(c.physical, &familyCount, families.data());
    c.queueFamily = UINT32_MAX;
    for (uint32_t i = 0; i < familyCount && c.queueFamily == UINT32_MAX; ++i)
        if (families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) c.queueFamily = i;
    if (c.queueFamily == UINT32_MAX)
        throw GpuError("device '" + c.info.name + "' has no compute queue");
    if (families[c.queueFamily].timestampValidBits == 0) c.info.timestampPeriodNs = 0.0;

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queueInfo{};
    queueInfo.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
    queueInfo.queueFamilyIndex = c.queueFamily;
    queueInfo.queueCount = 1;
    queueInfo.pQueuePriorities = &priority;

    // Enable only what the device has; shaders that need a feature check DeviceInfo first.
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomicFloat{};
    atomicFloat.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT;
    atomicFloat.shaderBufferFloat32AtomicAdd = c.info.float32AtomicAdd ? VK_TRUE : VK_FALSE;
    VkPhysicalDeviceVulkan12Features features12{};
    features12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
    features12.shaderBufferInt64Atomics = c.info.int64Atomics ? VK_TRUE : VK_FALSE;
    features12.pNext = c.info.float32AtomicAdd ? &atomicFloat : nullptr;
    VkPhysicalDeviceFeatures2 features{};
    features.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
    features.pNext = &features12;
    features.features.shaderInt64 = c.info.int64 ? VK_TRUE : VK_FALSE;
    std::vector<const char*> extensions;
    if (c.info.float32AtomicAdd) extensions.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);

    VkDeviceCreateInfo deviceInfo{};
    deviceInfo.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
    deviceInfo.pNext = &features;
    deviceInfo.queueCreateInfoCount = 1;
    deviceInfo.pQueueCreateInfos = &queueInfo;
    deviceInfo.enabledExtensionCount = uint32_t(extensions.size());
    deviceInfo.ppEnabledExtensionNames = extensions.data();
    VK_CHECK(vkCreateDevice(c.physical, &deviceInfo, nullptr, &c.device));
    vkGetDeviceQueue(c.device, c.queueFamily, 0, &c.queue);

    VkCommandPoolCreateInfo poolInfo{};
    poolInfo.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = c.queueFamily;
    VK_CHECK(vkCreateCommandPool(c.device, &poolInfo, nullptr, &c.commandPool));
    VkFenceCreateInfo fenceInfo{};
    fenceInfo.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    VK_CHECK(vkCreateFence(c.device, &fenceInfo, nullptr, &c.fence));
    if (c.info.timestampPeriodNs > 0) {
        VkQueryPoolCreateInfo queryInfo{};
        queryInfo.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
        queryInfo.queryType = VK_QUERY_TYPE_TIMESTAMP;
        queryInfo.queryCount = 2;
        VK_CHECK(vkCreateQueryPool(c.device, &queryInfo, nullptr, &c.timestampPool));
    }
    logDebug("Vulkan device: " + c.info.name + (c.validation ? " (validation on)" : ""));
    return context;
}

Context::~Context() {
    Impl& c = *mImpl;
    if (c.device != VK_NULL_HANDLE) {
        vkDeviceWaitIdle(c.device);
        if (c.timestampPool) vkDestroyQueryPool(c.device, c.timestampPool, nullptr);
        if (c.fence) vkDestroyFence(c.device, c.fence, nullptr);
        if (c.commandPool) vkDestroyCommandPool(c.device, c.commandPool, nullptr);
        vkDestroyDevice(c.device, nullptr);
    }
    if (c.instance != VK_NULL_HANDLE) {
        destroyMessenger(c.instance, c.messenger);
        vkDestroyInstance(c.instance, nullptr);
    }
}

const DeviceInfo& Context::info() const {
    return mImpl->info;
}
uint64_t Context::validationMessageCount() const {
    return mImpl->validationMessages.load();
}
bool Context::validationEnabled() const {
    return mImpl->validation;
}
std::string Context::lastValidationMessage() const {
    std::lock_guard<std::mutex> lock(mImpl->mutex);
    return mImpl->lastMessage;
}

int Context::Impl::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const {
    for (uint32_t i = 0; i < memory.memoryTypeCount; ++i)
        if ((typeBits & (1u << i)) && (memory.memoryTypes[i].propertyFlags & required) == required)
            return int(i);
    return -1;
}

VkCommandBuffer Context::Impl::beginOneOff() {
    VkCommandBufferAllocateInfo allocate{};
    allocate.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    allocate.commandPool = commandPool;
    allocate.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    allocate.commandBufferCount = 1;
    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateCommandBuffers(device, &allocate, &commandBuffer));
    VkCommandBufferBeginInfo begin{};
    begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(commandBuffer, &begin));
    return commandBuffer;
}

void Context::Impl::endOneOffAndWait(VkCommandBuffer commandBuffer) {
    // Make device writes visible to the host before it maps or reads back.
    VkMemoryBarrier barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(commandBuffer,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0, nullptr);
    VK_CHECK(vkEndCommandBuffer(commandBuffer));
    VkSubmitInfo submit{};
    submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &commandBuffer;
    {
        std::lock_guard<std::mutex> lock(mutex);
        VK_CHECK(vkResetFences(device, 1, &fence));
        VK_CHECK(vkQueueSubmit(queue, 1, &submit, fence));
        VK_CHECK(vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX));
    }
    vkFreeCommandBuffers(device, commandPool, 1, &commandBuffer);
}

Recorder Context::beginRecording() {
    auto impl = std::make_shared<Recorder::Impl>();
    impl->context = mImpl.get();
    impl->commandBuffer = mImpl->beginOneOff();
    impl->hasTimestamps = mImpl->timestampPool != VK_NULL_HANDLE;
    if (impl->hasTimestamps) {
        vkCmdResetQueryPool(impl->commandBuffer, mImpl->timestampPool, 0, 2);
        vkCmdWriteTimestamp(impl->commandBuffer, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT,
                            mImpl->timestampPool, 0);
    }
    return Recorder(impl);
}

double Context::submitRecorded(Recorder& recorder) {
    Recorder::Impl& r = recorder.impl();
    if (r.hasTimestamps)
        vkCmdWriteTimestamp(r.commandBuffer, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT,
                            mImpl->timestampPool, 1);
    auto start = std::chrono::steady_clock::now();
    VkCommandBuffer commandBuffer = r.commandBuffer;
    r.commandBuffer = VK_NULL_HANDLE;
    mImpl->endOneOffAndWait(commandBuffer);
    double hostMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!r.hasTimestamps) return hostMs;
    uint64_t stamps[2] = {0, 0};
    VK_CHECK(vkGetQueryPoolResults(mImpl->device, mImpl->timestampPool, 0, 2, sizeof stamps, stamps,
                                   sizeof(uint64_t),
                                   VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    return double(stamps[1] - stamps[0]) * mImpl->info.timestampPeriodNs * 1e-6;
}

Backend parseBackend(const std::string& text) {
    if (text == "auto") return Backend::Auto;
    if (text == "vulkan") return Backend::Vulkan;
    if (text == "cpu") return Backend::Cpu;
    throw InputError("--backend must be auto, vulkan or cpu, got '" + text + "'");
}

std::string toString(Backend backend) {
    switch (backend) {
        case Backend::Vulkan: return "vulkan";
        case Backend::Cpu: return "cpu";
        default: return "auto";
    }
}

std::shared_ptr<Context> monteCarloContext(const RunContext& context) {
    if (!context.gpu) return nullptr;
    return context.gpu->info().isHardware() || context.monteCarloOnCpuDevices ? context.gpu
                                                                              : nullptr;
}

std::shared_ptr<Context> contextForBackend(Backend backend, const ContextOptions& options) {
    if (backend == Backend::Cpu) return nullptr;
    if (backend == Backend::Vulkan) return Context::create(options);
    try {
        return Context::create(options);
    } catch (const GpuError& e) {
        logWarn(std::string(e.what()) + "; using the CPU path");
        return nullptr;
    }
}

}  // namespace vpsim::gpu
