#include <algorithm>
#include <map>
#include <mutex>
#include <tuple>

#include "gpu/vulkan_internal.h"

namespace vpsim::gpu {
namespace {

constexpr uint32_t SETS_PER_POOL = 64;
constexpr uint32_t DESCRIPTORS_PER_SET = 16;

VkDescriptorType descriptorType(Binding binding) {
    switch (binding) {
        case Binding::Uniform: return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        case Binding::UniformTexels:
        case Binding::UniformTexels4: return VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
        default: return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    }
}

}  // namespace

std::shared_ptr<const Kernel> Kernel::shared(std::shared_ptr<Context> context,
                                             const uint32_t* spirv, size_t spirvBytes,
                                             const std::vector<Binding>& bindings,
                                             uint32_t pushConstantBytes,
                                             const std::vector<SpecConstant>& specConstants,
                                             uint32_t localSizeX) {
    using Key = std::tuple<const Context*, const uint32_t*, size_t, std::vector<int>, uint32_t,
                           std::vector<uint32_t>, uint32_t>;
    static std::mutex mutex;
    static std::map<Key, std::weak_ptr<const Kernel>> kernels;
    std::vector<int> kinds;
    for (Binding b : bindings) kinds.push_back(int(b));
    std::vector<uint32_t> constants;
    for (const SpecConstant& c : specConstants) constants.insert(constants.end(), {c.id, c.value});
    const Key key{context.get(),        spirv,     spirvBytes, std::move(kinds), pushConstantBytes,
                  std::move(constants), localSizeX};
    // Held while a pipeline is made, so that engines made at once wait for one creation.
    const std::lock_guard<std::mutex> lock(mutex);
    for (auto it = kernels.begin(); it != kernels.end();)
        it = it->second.expired() ? kernels.erase(it) : std::next(it);
    if (auto it = kernels.find(key); it != kernels.end())
        if (auto kernel = it->second.lock()) return kernel;  // its last holder may just have gone
    auto kernel = std::make_shared<const Kernel>(std::move(context), spirv, spirvBytes, bindings,
                                                 pushConstantBytes, specConstants, localSizeX);
    kernels[key] = kernel;
    return kernel;
}

Kernel::Kernel(std::shared_ptr<Context> context, const uint32_t* spirv, size_t spirvBytes,
               uint32_t bindingCount, uint32_t pushConstantBytes,
               const std::vector<SpecConstant>& specConstants, uint32_t localSizeX)
    : Kernel(
          std::move(context), spirv, spirvBytes,
          std::vector<Binding>(std::min(bindingCount, DESCRIPTORS_PER_SET + 1), Binding::Storage),
          pushConstantBytes, specConstants, localSizeX) {}

Kernel::Kernel(std::shared_ptr<Context> context, const uint32_t* spirv, size_t spirvBytes,
               const std::vector<Binding>& bindingKinds, uint32_t pushConstantBytes,
               const std::vector<SpecConstant>& specConstants, uint32_t localSizeX)
    : mImpl(std::make_unique<Impl>()) {
    const uint32_t bindingCount = uint32_t(bindingKinds.size());
    if (!context) throw GpuError("kernel created without a Vulkan context");
    const DeviceInfo& info = context->info();
    if (pushConstantBytes > info.maxPushConstantBytes)
        throw ResourceError("push constants of " + std::to_string(pushConstantBytes) +
                            " bytes exceed the " + std::to_string(info.maxPushConstantBytes) +
                            "-byte limit of " + info.name);
    if (bindingCount > DESCRIPTORS_PER_SET)
        throw ResourceError("a kernel may use at most " + std::to_string(DESCRIPTORS_PER_SET) +
                            " buffers");
    if (localSizeX == 0 || localSizeX > info.maxWorkgroupSize[0])
        throw ResourceError("local_size_x " + std::to_string(localSizeX) +
                            " is outside the device limit");
    Impl& k = *mImpl;
    k.context = std::move(context);
    k.bindingCount = bindingCount;
    k.bindings = bindingKinds;
    k.pushConstantBytes = pushConstantBytes;
    k.localSizeX = localSizeX;
    VkDevice device = k.context->impl().device;

    VkShaderModuleCreateInfo moduleInfo{};
    moduleInfo.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    moduleInfo.codeSize = spirvBytes;
    moduleInfo.pCode = spirv;
    VK_CHECK(vkCreateShaderModule(device, &moduleInfo, nullptr, &k.module));

    std::vector<VkDescriptorSetLayoutBinding> bindings(bindingCount);
    for (uint32_t i = 0; i < bindingCount; ++i) {
        bindings[i].binding = i;
        bindings[i].descriptorType = descriptorType(bindingKinds[i]);
        bindings[i].descriptorCount = 1;
        bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    VkDescriptorSetLayoutCreateInfo layoutInfo{};
    layoutInfo.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    layoutInfo.bindingCount = bindingCount;
    layoutInfo.pBindings = bindings.data();
    VK_CHECK(vkCreateDescriptorSetLayout(device, &layoutInfo, nullptr, &k.setLayout));

    VkPushConstantRange pushRange{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes};
    VkPipelineLayoutCreateInfo pipelineLayoutInfo{};
    pipelineLayoutInfo.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    pipelineLayoutInfo.setLayoutCount = 1;
    pipelineLayoutInfo.pSetLayouts = &k.setLayout;
    pipelineLayoutInfo.pushConstantRangeCount = pushConstantBytes > 0 ? 1 : 0;
    pipelineLayoutInfo.pPushConstantRanges = &pushRange;
    VK_CHECK(vkCreatePipelineLayout(device, &pipelineLayoutInfo, nullptr, &k.pipelineLayout));

    std::vector<VkSpecializationMapEntry> entries;
    std::vector<uint32_t> values;
    for (const auto& constant : specConstants) {
        entries.push_back(
            {constant.id, uint32_t(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
        values.push_back(constant.value);
    }
    VkSpecializationInfo specialization{uint32_t(entries.size()), entries.data(),
                                        values.size() * sizeof(uint32_t), values.data()};
    VkComputePipelineCreateInfo pipelineInfo{};
    pipelineInfo.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
    pipelineInfo.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    pipelineInfo.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pipelineInfo.stage.module = k.module;
    pipelineInfo.stage.pName = "main";
    pipelineInfo.stage.pSpecializationInfo = entries.empty() ? nullptr : &specialization;
    pipelineInfo.layout = k.pipelineLayout;
    VK_CHECK(
        vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &pipelineInfo, nullptr, &k.pipeline));
}

Kernel::~Kernel() {
    if (!mImpl || !mImpl->context) return;
    VkDevice device = mImpl->context->impl().device;
    if (mImpl->pipeline) vkDestroyPipeline(device, mImpl->pipeline, nullptr);
    if (mImpl->pipelineLayout) vkDestroyPipelineLayout(device, mImpl->pipelineLayout, nullptr);
    if (mImpl->setLayout) vkDestroyDescriptorSetLayout(device, mImpl->setLayout, nullptr);
    if (mImpl->module) vkDestroyShaderModule(device, mImpl->module, nullptr);
}

uint32_t Kernel::bindingCount() const {
    return mImpl->bindingCount;
}
uint32_t Kernel::pushConstantBytes() const {
    return mImpl->pushConstantBytes;
}
uint32_t Kernel::localSizeX() const {
    return mImpl->localSizeX;
}

VkDescriptorSet Recorder::Impl::allocateSet(VkDescriptorSetLayout layout) {
    if (setsLeftInPool == 0) {
        VkDescriptorPoolSize sizes[3] = {
            {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, SETS_PER_POOL * DESCRIPTORS_PER_SET},
            {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, SETS_PER_POOL * DESCRIPTORS_PER_SET},
            {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, SETS_PER_POOL * DESCRIPTORS_PER_SET}};
        VkDescriptorPoolCreateInfo poolInfo{};
        poolInfo.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
        poolInfo.maxSets = SETS_PER_POOL;
        poolInfo.poolSizeCount = 3;
        poolInfo.pPoolSizes = sizes;
        VkDescriptorPool pool = VK_NULL_HANDLE;
        VK_CHECK(vkCreateDescriptorPool(context->device, &poolInfo, nullptr, &pool));
        pools.push_back(pool);
        setsLeftInPool = SETS_PER_POOL;
    }
    VkDescriptorSetAllocateInfo allocate{};
    allocate.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    allocate.descriptorPool = pools.back();
    allocate.descriptorSetCount = 1;
    allocate.pSetLayouts = &layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    VK_CHECK(vkAllocateDescriptorSets(context->device, &allocate, &set));
    --setsLeftInPool;
    return set;
}

Recorder::Impl::~Impl() {
    // Pools outlive the submission: the Recorder is destroyed after Context::submit waits.
    if (commandBuffer != VK_NULL_HANDLE)
        vkFreeCommandBuffers(context->device, context->commandPool, 1, &commandBuffer);
    for (VkDescriptorPool pool : pools) vkDestroyDescriptorPool(context->device, pool, nullptr);
}

void Recorder::dispatch(const Kernel& kernel, const std::vector<const Buffer*>& buffers,
                        const void* push, uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) {
    Kernel::Impl& k = kernel.impl();
    const DeviceInfo& info = k.context->info();
    if (buffers.size() != k.bindingCount)
        throw GpuError("kernel expects " + std::to_string(k.bindingCount) + " buffers, got " +
                       std::to_string(buffers.size()));
    if ((k.pushConstantBytes > 0) != (push != nullptr))
        throw GpuError("push constants given to a kernel that does not take them, or missing");
    uint32_t groups[3] = {groupsX, groupsY, groupsZ};
    for (int i = 0; i < 3; ++i)
        if (groups[i] > info.maxWorkgroupCount[i])
            throw ResourceError(
                "dispatch of " + std::to_string(groups[i]) + " workgroups exceeds the limit of " +
                std::to_string(info.maxWorkgroupCount[i]) + " (use dispatch1D or fold the grid)");
    if (groupsX == 0 || groupsY == 0 || groupsZ == 0) return;

    VkDescriptorSet set = mImpl->allocateSet(k.setLayout);
    std::vector<VkDescriptorBufferInfo> bufferInfos(buffers.size());
    std::vector<VkBufferView> views(buffers.size());
    std::vector<VkWriteDescriptorSet> writes(buffers.size());
    for (size_t i = 0; i < buffers.size(); ++i) {
        if (!buffers[i]) throw GpuError("null buffer bound to binding " + std::to_string(i));
        Buffer::Impl& b = buffers[i]->impl();
        const Binding kind = k.bindings[i];
        if (kind == Binding::Uniform && b.storage.bytes > info.maxUniformBufferRange)
            throw ResourceError("uniform buffer of " + formatBytes(double(b.storage.bytes)) +
                                " exceeds maxUniformBufferRange of " + info.name);
        const uint64_t texelBytes = kind == Binding::UniformTexels4 ? 16 : 4;
        if ((kind == Binding::UniformTexels || kind == Binding::UniformTexels4) &&
            b.storage.bytes / texelBytes > info.maxTexelBufferElements)
            throw ResourceError("texel buffer of " + std::to_string(b.storage.bytes / texelBytes) +
                                " texels exceeds maxTexelBufferElements of " + info.name);
        bufferInfos[i] = {b.storage.buffer, 0, VK_WHOLE_SIZE};
        writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        writes[i].dstSet = set;
        writes[i].dstBinding = uint32_t(i);
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = descriptorType(kind);
        if (kind == Binding::UniformTexels || kind == Binding::UniformTexels4) {
            views[i] = kind == Binding::UniformTexels4 ? b.vec4TexelView() : b.floatTexelView();
            writes[i].pTexelBufferView = &views[i];
        } else {
            writes[i].pBufferInfo = &bufferInfos[i];
        }
    }
    vkUpdateDescriptorSets(mImpl->context->device, uint32_t(writes.size()), writes.data(), 0,
                           nullptr);
    VkCommandBuffer commandBuffer = mImpl->commandBuffer;
    vkCmdBindPipeline(commandBuffer, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline);
    vkCmdBindDescriptorSets(commandBuffer, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipelineLayout, 0, 1,
                            &set, 0, nullptr);
    if (push)
        vkCmdPushConstants(commandBuffer, k.pipelineLayout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                           k.pushConstantBytes, push);
    vkCmdDispatch(commandBuffer, groupsX, groupsY, groupsZ);
}

void Recorder::dispatch1D(const Kernel& kernel, const std::vector<const Buffer*>& buffers,
                          const void* push, uint64_t invocations) {
    const DeviceInfo& info = kernel.impl().context->info();
    uint64_t groups = (invocations + kernel.localSizeX() - 1) / kernel.localSizeX();
    uint64_t groupsX = std::min<uint64_t>(groups, info.maxWorkgroupCount[0]);
    uint64_t groupsY = groupsX == 0 ? 0 : (groups + groupsX - 1) / groupsX;
    if (groupsY > info.maxWorkgroupCount[1])
        throw ResourceError("dispatch of " + std::to_string(invocations) +
                            " invocations is too large");
    dispatch(kernel, buffers, push, uint32_t(groupsX), uint32_t(groupsY), 1);
}

void Recorder::barrier() {
    VkMemoryBarrier barrier{};
    barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                            VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    const VkPipelineStageFlags stages =
        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
    vkCmdPipelineBarrier(mImpl->commandBuffer, stages, stages, 0, 1, &barrier, 0, nullptr, 0,
                         nullptr);
}

void Recorder::fill(Buffer& buffer, uint32_t word) {
    vkCmdFillBuffer(mImpl->commandBuffer, buffer.impl().storage.buffer, 0, VK_WHOLE_SIZE, word);
}

void Recorder::toDevice(Buffer& buffer) {
    Buffer::Impl& b = buffer.impl();
    if (b.storage.mapped) return;
    if (!b.mirrored) throw GpuError("a buffer's host mirror was recorded before it was made");
    const VkBufferCopy region{0, 0, b.storage.bytes};
    vkCmdCopyBuffer(mImpl->commandBuffer, b.staging.buffer, b.storage.buffer, 1, &region);
    barrier();
}

void Recorder::toHost(Buffer& buffer) {
    Buffer::Impl& b = buffer.impl();
    if (b.storage.mapped) return;
    if (!b.mirrored) throw GpuError("a buffer's host mirror was recorded before it was made");
    barrier();
    const VkBufferCopy region{0, 0, b.storage.bytes};
    vkCmdCopyBuffer(mImpl->commandBuffer, b.storage.buffer, b.staging.buffer, 1, &region);
}

void Recorder::copy(const Buffer& source, Buffer& destination, uint64_t bytes,
                    uint64_t sourceOffset, uint64_t destinationOffset) {
    if (sourceOffset + bytes > source.size() || destinationOffset + bytes > destination.size())
        throw ResourceError("GPU buffer copy beyond a buffer's end");
    VkBufferCopy region{sourceOffset, destinationOffset, bytes};
    vkCmdCopyBuffer(mImpl->commandBuffer, source.impl().storage.buffer,
                    destination.impl().storage.buffer, 1, &region);
}

}  // namespace vpsim::gpu
