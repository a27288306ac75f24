#pragma once
// Private to the gpu module: the Vulkan handles behind the public types in vpsim/gpu/context.h.

#include <vulkan/vulkan.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "vpsim/core/error.h"
#include "vpsim/gpu/context.h"

namespace vpsim::gpu {

/// Name of a VkResult such as "VK_ERROR_OUT_OF_DEVICE_MEMORY".
const char* resultName(VkResult result);

/// Throws GpuError naming the call, the VkResult and the source location.
#define VK_CHECK(call)                                                              \
    do {                                                                            \
        VkResult vkCheckResult_ = (call);                                           \
        if (vkCheckResult_ != VK_SUCCESS)                                           \
            ::vpsim::gpu::throwGpuError(#call, vkCheckResult_, __FILE__, __LINE__); \
    } while (0)

/// Out-of-memory results become ResourceError (a size refusal), others GpuError.
[[noreturn]] void throwGpuError(const char* what, VkResult result, const char* file, int line);
GpuError makeGpuError(const char* what, VkResult result, const char* file, int line);

struct Context::Impl {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkCommandPool commandPool = VK_NULL_HANDLE;
    VkQueryPool timestampPool = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties memory{};
    DeviceInfo info;
    bool validation = false;
    bool stagedTransfers = false;  ///< ContextOptions::stagedTransfers
    std::atomic<uint64_t> validationMessages{0};
    std::mutex mutex;  ///< guards lastMessage and queue submission
    std::string lastMessage;

    /// Records a one-off command buffer with `record`, submits it and waits.
    template <class F>
    void runOnce(F&& record);
    VkCommandBuffer beginOneOff();
    void endOneOffAndWait(VkCommandBuffer commandBuffer);
    /// Index of a memory type allowed by `typeBits` having all `required` flags, or -1.
    int findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;
};

template <class F>
void Context::Impl::runOnce(F&& record) {
    VkCommandBuffer commandBuffer = beginOneOff();
    record(commandBuffer);
    endOneOffAndWait(commandBuffer);
}

/// A VkBuffer with its memory; mapped when host-visible.
struct RawBuffer {
    VkDevice device = VK_NULL_HANDLE;
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void* mapped = nullptr;
    uint64_t bytes = 0;
    void create(Context::Impl& context, uint64_t size, VkBufferUsageFlags usage, bool hostVisible);
    void destroy();
};

struct Buffer::Impl {
    std::shared_ptr<Context> context;
    RawBuffer storage;
    /// Host-side copy area of a buffer the host cannot map (a discrete GPU's), kept between
    /// transfers and grown as needed: allocating host-visible memory for each transfer cost more
    /// than the transfer. Host-cached where the device offers it (reading back from uncached,
    /// write-combined memory is slow).
    RawBuffer staging;
    std::mutex stagingMutex;  ///< one transfer through `staging` at a time
    RawBuffer& stagingFor(uint64_t bytes);
    bool mirrored = false;  ///< hostMirror() has sized `staging` and copied the buffer in
    VkBufferView texelView = VK_NULL_HANDLE;   ///< R32_SFLOAT view, made on first texel binding
    VkBufferView texelView4 = VK_NULL_HANDLE;  ///< R32G32B32A32_SFLOAT view, the same way
    VkBufferView floatTexelView();
    VkBufferView vec4TexelView();
    ~Impl();
};

struct Kernel::Impl {
    std::shared_ptr<Context> context;
    VkShaderModule module = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout pipelineLayout = VK_NULL_HANDLE;
    VkPipeline pipeline = VK_NULL_HANDLE;
    uint32_t bindingCount = 0;
    std::vector<Binding> bindings;
    uint32_t pushConstantBytes = 0;
    uint32_t localSizeX = 64;
};

struct Recorder::Impl {
    Context::Impl* context = nullptr;
    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
    std::vector<VkDescriptorPool> pools;
    uint32_t setsLeftInPool = 0;
    bool hasTimestamps = false;
    VkDescriptorSet allocateSet(VkDescriptorSetLayout layout);
    ~Impl();
};

}  // namespace vpsim::gpu
