#include "gpu/instance.h"

#include <cstring>
#include <iostream>
#ifdef __SANITIZE_ADDRESS__
#include <dlfcn.h>
#endif

#include "vpsim/core/log.h"

namespace vpsim::gpu {
namespace {

constexpr const char* VALIDATION_LAYER = "VK_LAYER_KHRONOS_validation";

/// Under AddressSanitizer (VPSIM_SANITIZE): keeps Mesa's lavapipe loaded for the whole process
/// (RTLD_NODELETE). It allocates a buffer once and never frees it; the loader unloads the driver
/// with the instance, so at exit the leak's frames would be "<unknown module>" and could not be
/// told from ours. Pinned, they name libvulkan_lvp.so, which tests/sanitizers/lsan.supp matches.
void pinCpuDriverForLeakReports() {
#ifdef __SANITIZE_ADDRESS__
    static void* const pinned = dlopen("libvulkan_lvp.so", RTLD_LAZY | RTLD_NODELETE);
    (void)pinned;
#endif
}

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data,
                                                   void* userData) {
    auto* sink = static_cast<Context::Impl*>(userData);
    std::string message = data && data->pMessage ? data->pMessage : "(no text)";
    if (severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        if (sink) {
            sink->validationMessages++;
            std::lock_guard<std::mutex> lock(sink->mutex);
            sink->lastMessage = message;
        }
        logError("Vulkan validation: " + message);
    }
    return VK_FALSE;
}

bool layerAvailable(const char* name) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> layers(count);
    vkEnumerateInstanceLayerProperties(&count, layers.data());
    for (const auto& layer : layers)
        if (!std::strcmp(layer.layerName, name)) return true;
    return false;
}

}  // namespace

Instance::Instance(bool validation, Context::Impl* sink) {
    VkApplicationInfo app{};
    app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
    app.pApplicationName = "vpsim";
    app.pEngineName = "vpsim";
    app.apiVersion = VK_API_VERSION_1_2;

    std::vector<const char*> layers, extensions;
    if (validation) {
        if (!layerAvailable(VALIDATION_LAYER))
            throw GpuError(
                "validation requested but VK_LAYER_KHRONOS_validation is not installed "
                "(Debian package vulkan-validationlayers)");
        layers.push_back(VALIDATION_LAYER);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    VkDebugUtilsMessengerCreateInfoEXT messengerInfo{};
    messengerInfo.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
    messengerInfo.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messengerInfo.pfnUserCallback = onValidationMessage;
    messengerInfo.pUserData = sink;

    VkInstanceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
    info.pApplicationInfo = &app;
    info.enabledLayerCount = uint32_t(layers.size());
    info.ppEnabledLayerNames = layers.data();
    info.enabledExtensionCount = uint32_t(extensions.size());
    info.ppEnabledExtensionNames = extensions.data();
    if (validation)
        info.pNext = &messengerInfo;  // also reports problems in vkCreateInstance itself
    pinCpuDriverForLeakReports();
    VkResult result = vkCreateInstance(&info, nullptr, &mInstance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER || result == VK_ERROR_INITIALIZATION_FAILED)
        throw GpuError(std::string("no Vulkan driver is installed (") + resultName(result) +
                       "); install mesa-vulkan-drivers for lavapipe or use --backend cpu");
    VK_CHECK(result);

    if (validation) {
        auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(mInstance, "vkCreateDebugUtilsMessengerEXT"));
        if (!create) throw GpuError("vkCreateDebugUtilsMessengerEXT is unavailable");
        VK_CHECK(create(mInstance, &messengerInfo, nullptr, &mMessenger));
    }
}

Instance::~Instance() {
    if (mInstance == VK_NULL_HANDLE) return;
    destroyMessenger(mInstance, mMessenger);
    vkDestroyInstance(mInstance, nullptr);
}

void destroyMessenger(VkInstance instance, VkDebugUtilsMessengerEXT messenger) {
    if (messenger == VK_NULL_HANDLE) return;
    auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
    if (destroy) destroy(instance, messenger, nullptr);
}

std::vector<VkPhysicalDevice> Instance::physicalDevices() const {
    uint32_t count = 0;
    VK_CHECK(vkEnumeratePhysicalDevices(mInstance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    VK_CHECK(vkEnumeratePhysicalDevices(mInstance, &count, devices.data()));
    return devices;
}

void Instance::release(VkInstance& instance, VkDebugUtilsMessengerEXT& messenger) {
    instance = mInstance;
    messenger = mMessenger;
    mInstance = VK_NULL_HANDLE;
    mMessenger = VK_NULL_HANDLE;
}

}  // namespace vpsim::gpu
