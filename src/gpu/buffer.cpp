#include <cstring>
#include <vector>

#include "gpu/vulkan_internal.h"

namespace vpsim::gpu {

void RawBuffer::create(Context::Impl& context, uint64_t size, VkBufferUsageFlags usage,
                       bool hostVisible) {
    device = context.device;
    bytes = size;
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    VK_CHECK(vkCreateBuffer(device, &info, nullptr, &buffer));
    VkMemoryRequirements requirements;
    vkGetBufferMemoryRequirements(device, buffer, &requirements);

    // Host-visible coherent memory when asked (staging) or when it is also device-local (lavapipe,
    // integrated GPUs): then uploads are a memcpy. Otherwise plain device-local memory.
    const VkMemoryPropertyFlags hostFlags =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    // Device memory the host maps directly (lavapipe, integrated GPUs); a discrete GPU's is
    // reached through staging copies, even where it is host-visible (reading it across the bus
    // is slow).
    const bool unified = !context.stagedTransfers &&
                         (context.info.type == "cpu" || context.info.type == "integrated");
    int type = -1;
    if (hostVisible) {
        type = context.findMemoryType(requirements.memoryTypeBits,
                                      hostFlags | VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
        if (type < 0) type = context.findMemoryType(requirements.memoryTypeBits, hostFlags);
    } else {
        if (unified)
            type = context.findMemoryType(requirements.memoryTypeBits,
                                          hostFlags | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        if (type < 0)
            type = context.findMemoryType(requirements.memoryTypeBits,
                                          VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        if (type < 0) type = context.findMemoryType(requirements.memoryTypeBits, 0);
    }
    if (type < 0) {
        destroy();
        throw GpuError("no suitable memory type for a buffer");
    }
    VkMemoryAllocateInfo allocate{};
    allocate.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    allocate.allocationSize = requirements.size;
    allocate.memoryTypeIndex = uint32_t(type);
    VkResult result = vkAllocateMemory(device, &allocate, nullptr, &memory);
    if (result != VK_SUCCESS) {
        destroy();
        throwGpuError("vkAllocateMemory", result, __FILE__, __LINE__);
    }
    VK_CHECK(vkBindBufferMemory(device, buffer, memory, 0));
    const bool mappable =
        context.memory.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    if (mappable && (hostVisible || unified))
        VK_CHECK(vkMapMemory(device, memory, 0, VK_WHOLE_SIZE, 0, &mapped));
}

void RawBuffer::destroy() {
    if (mapped) vkUnmapMemory(device, memory);
    if (buffer) vkDestroyBuffer(device, buffer, nullptr);
    if (memory) vkFreeMemory(device, memory, nullptr);
    mapped = nullptr;
    buffer = VK_NULL_HANDLE;
    memory = VK_NULL_HANDLE;
    bytes = 0;
}

Buffer::Buffer(std::shared_ptr<Context> context, uint64_t bytes) : mImpl(std::make_unique<Impl>()) {
    if (!context) throw GpuError("buffer created without a Vulkan context");
    const DeviceInfo& info = context->info();
    if (bytes == 0) throw ResourceError("refusing to create an empty GPU buffer");
    if (bytes > info.maxStorageBufferRange)
        throw ResourceError("GPU buffer of " + formatBytes(double(bytes)) +
                            " exceeds the device's " + "maxStorageBufferRange of " +
                            formatBytes(double(info.maxStorageBufferRange)) + " on " + info.name +
                            "; the data must be split into smaller buffers");
    if (info.deviceLocalBytes > 0 && bytes > info.deviceLocalBytes)
        throw ResourceError("GPU buffer of " + formatBytes(double(bytes)) +
                            " exceeds the device memory of " +
                            formatBytes(double(info.deviceLocalBytes)));
    mImpl->context = std::move(context);
    // Storage buffers are padded to 4 bytes so fill() and word-sized shader access stay in range.
    uint64_t padded = (bytes + 3) & ~uint64_t(3);
    mImpl->storage.create(mImpl->context->impl(), padded,
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                              VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                              VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          false);
    mImpl->storage.bytes = bytes;
}

Buffer::Impl::~Impl() {
    if (texelView) vkDestroyBufferView(storage.device, texelView, nullptr);
    if (texelView4) vkDestroyBufferView(storage.device, texelView4, nullptr);
    staging.destroy();
    storage.destroy();
}

RawBuffer& Buffer::Impl::stagingFor(uint64_t bytes) {
    if (staging.bytes < bytes) {
        staging.destroy();
        staging.create(context->impl(), bytes,
                       VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
    }
    return staging;
}

namespace {

VkBufferView makeTexelView(const RawBuffer& storage, VkFormat format, uint64_t texelBytes) {
    VkBufferViewCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO;
    info.buffer = storage.buffer;
    info.format = format;
    info.offset = 0;
    info.range = (storage.bytes / texelBytes) * texelBytes;
    VkBufferView view = VK_NULL_HANDLE;
    VK_CHECK(vkCreateBufferView(storage.device, &info, nullptr, &view));
    return view;
}

}  // namespace

VkBufferView Buffer::Impl::floatTexelView() {
    if (!texelView) texelView = makeTexelView(storage, VK_FORMAT_R32_SFLOAT, 4);
    return texelView;
}

VkBufferView Buffer::Impl::vec4TexelView() {
    if (!texelView4) texelView4 = makeTexelView(storage, VK_FORMAT_R32G32B32A32_SFLOAT, 16);
    return texelView4;
}

Buffer::~Buffer() = default;
Buffer::Buffer(Buffer&&) noexcept = default;
Buffer& Buffer::operator=(Buffer&&) noexcept = default;

uint64_t Buffer::size() const {
    return mImpl->storage.bytes;
}

void* Buffer::hostMemory() const {
    return mImpl->storage.mapped;
}

namespace {

/// One submission copying `regions` from `from` to `to`.
void copyRegions(Context::Impl& context, VkBuffer from, VkBuffer to,
                 const std::vector<VkBufferCopy>& regions) {
    context.runOnce([&](VkCommandBuffer commandBuffer) {
        vkCmdCopyBuffer(commandBuffer, from, to, uint32_t(regions.size()), regions.data());
    });
}

}  // namespace

void* Buffer::hostMirror() {
    RawBuffer& storage = mImpl->storage;
    if (storage.mapped) return storage.mapped;
    std::lock_guard<std::mutex> lock(mImpl->stagingMutex);
    RawBuffer& staging = mImpl->stagingFor(storage.bytes);
    if (!mImpl->mirrored)
        copyRegions(mImpl->context->impl(), storage.buffer, staging.buffer,
                    {{0, 0, storage.bytes}});
    mImpl->mirrored = true;
    return staging.mapped;
}

void Buffer::upload(const void* data, uint64_t bytes, uint64_t offset) {
    if (offset + bytes > size()) throw ResourceError("GPU buffer upload beyond the buffer's end");
    uploadRows(data, bytes, 1, bytes, offset, bytes);
}

void Buffer::uploadRows(const void* data, uint64_t rowBytes, uint64_t rows, uint64_t sourceStride,
                        uint64_t offset, uint64_t targetStride) {
    if (rows == 0 || rowBytes == 0) return;
    if (rowBytes > targetStride || offset + (rows - 1) * targetStride + rowBytes > size())
        throw ResourceError("GPU buffer row upload beyond the buffer's end");
    const char* source = static_cast<const char*>(data);
    RawBuffer& storage = mImpl->storage;
    if (storage.mapped) {
        char* target = static_cast<char*>(storage.mapped) + offset;
        for (uint64_t r = 0; r < rows; ++r)
            std::memcpy(target + r * targetStride, source + r * sourceStride, rowBytes);
        return;
    }
    std::lock_guard<std::mutex> lock(mImpl->stagingMutex);
    RawBuffer& staging = mImpl->stagingFor(rows * rowBytes);
    std::vector<VkBufferCopy> regions(rows);
    for (uint64_t r = 0; r < rows; ++r) {
        std::memcpy(static_cast<char*>(staging.mapped) + r * rowBytes, source + r * sourceStride,
                    rowBytes);
        regions[r] = {r * rowBytes, offset + r * targetStride, rowBytes};
    }
    copyRegions(mImpl->context->impl(), staging.buffer, storage.buffer, regions);
}

void Buffer::download(void* data, uint64_t bytes, uint64_t offset) const {
    if (offset + bytes > size()) throw ResourceError("GPU buffer download beyond the buffer's end");
    downloadRows(data, bytes, 1, offset, bytes, bytes);
}

void Buffer::downloadRows(void* data, uint64_t rowBytes, uint64_t rows, uint64_t offset,
                          uint64_t sourceStride, uint64_t targetStride) const {
    if (rows == 0 || rowBytes == 0) return;
    if (rowBytes > sourceStride || offset + (rows - 1) * sourceStride + rowBytes > size())
        throw ResourceError("GPU buffer row download beyond the buffer's end");
    char* target = static_cast<char*>(data);
    RawBuffer& storage = mImpl->storage;
    if (storage.mapped) {
        const char* source = static_cast<const char*>(storage.mapped) + offset;
        for (uint64_t r = 0; r < rows; ++r)
            std::memcpy(target + r * targetStride, source + r * sourceStride, rowBytes);
        return;
    }
    std::lock_guard<std::mutex> lock(mImpl->stagingMutex);
    RawBuffer& staging = mImpl->stagingFor(rows * rowBytes);
    std::vector<VkBufferCopy> regions(rows);
    for (uint64_t r = 0; r < rows; ++r)
        regions[r] = {offset + r * sourceStride, r * rowBytes, rowBytes};
    copyRegions(mImpl->context->impl(), storage.buffer, staging.buffer, regions);
    for (uint64_t r = 0; r < rows; ++r)
        std::memcpy(target + r * targetStride,
                    static_cast<const char*>(staging.mapped) + r * rowBytes, rowBytes);
}

void Buffer::fill(uint32_t word) {
    RawBuffer& storage = mImpl->storage;
    mImpl->context->impl().runOnce([&](VkCommandBuffer commandBuffer) {
        vkCmdFillBuffer(commandBuffer, storage.buffer, 0, VK_WHOLE_SIZE, word);
    });
}

}  // namespace vpsim::gpu
