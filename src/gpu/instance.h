#pragma once
// Private to the gpu module: Vulkan instance with the optional validation layer.

#include <vector>

#include "gpu/vulkan_internal.h"

namespace vpsim::gpu {

/// Owns a VkInstance (and the validation messenger when enabled) until release().
class Instance {
public:
    /// @param validation enable VK_LAYER_KHRONOS_validation; messages are counted in `sink`
    /// @throw GpuError when Vulkan is missing or the validation layer is not installed
    Instance(bool validation, Context::Impl* sink);
    ~Instance();
    Instance(const Instance&) = delete;
    Instance& operator=(const Instance&) = delete;

    VkInstance handle() const { return mInstance; }
    std::vector<VkPhysicalDevice> physicalDevices() const;
    /// Hands the instance and messenger to the caller, who destroys them.
    void release(VkInstance& instance, VkDebugUtilsMessengerEXT& messenger);

private:
    VkInstance mInstance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT mMessenger = VK_NULL_HANDLE;
};

DeviceInfo describeDevice(VkPhysicalDevice physical, uint32_t index);
bool supportsAtomicFloat(VkPhysicalDevice physical);
void destroyMessenger(VkInstance instance, VkDebugUtilsMessengerEXT messenger);

}  // namespace vpsim::gpu
