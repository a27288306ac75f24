#pragma once
/// @file
/// Vulkan compute runtime. This module is the only code that includes vulkan.h: the types here
/// hide every Vulkan handle so the rest of vpsim (transport, exposure) can run shaders without it.

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "vpsim/core/run_context.h"

namespace vpsim::gpu {

/// What a compute device offers, with the limits vpsim must respect.
struct DeviceInfo {
    uint32_t index = 0;                   ///< position in the Vulkan enumeration
    std::string name;                     ///< e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string type;                     ///< "discrete", "integrated", "virtual", "cpu" or "other"
    std::string driver;                   ///< driver name and info
    std::string apiVersion;               ///< "1.3.230"
    uint64_t maxStorageBufferRange = 0;   ///< bytes one storage binding may span
    uint64_t maxUniformBufferRange = 0;   ///< bytes one uniform binding may span
    uint64_t maxTexelBufferElements = 0;  ///< elements one texel-buffer binding may span
    std::array<uint32_t, 3> maxWorkgroupCount{};
    std::array<uint32_t, 3> maxWorkgroupSize{};
    uint32_t maxWorkgroupInvocations = 0;
    uint32_t maxPushConstantBytes = 0;
    uint32_t maxSharedMemoryBytes = 0;
    uint32_t subgroupSize = 0;
    uint64_t deviceLocalBytes = 0;   ///< size of the largest device-local heap
    bool float32AtomicAdd = false;   ///< VK_EXT_shader_atomic_float buffer add
    bool int64 = false;              ///< shaderInt64
    bool int64Atomics = false;       ///< shaderBufferInt64Atomics
    double timestampPeriodNs = 0.0;  ///< 0 when the compute queue has no timestamps
    /// On a CPU driver, the threads that run its workgroups (lavapipe's rule: LP_NUM_THREADS,
    /// else the CPU count, at most 32); 0 on other devices.
    uint32_t hostThreads = 0;
    bool isHardware() const { return type == "discrete" || type == "integrated"; }
    nlohmann::json toJson() const;
};

/// Lists the Vulkan devices. @throw GpuError when no Vulkan loader/instance is available.
std::vector<DeviceInfo> listDevices();

/// Which implementation runs the physics.
enum class Backend { Auto, Vulkan, Cpu };
/// @throw InputError for anything but "auto", "vulkan", "cpu"
Backend parseBackend(const std::string& text);
std::string toString(Backend backend);

struct ContextOptions {
    /// Device choice: "" picks a hardware GPU first and lavapipe otherwise; a number picks by
    /// index; other text picks the first device whose name contains it. (the CLI reads VPSIM_DEVICE
    /// into it).
    std::string device;
    /// Enable VK_LAYER_KHRONOS_validation and count its messages (the CLI sets it from --validate
    /// or VPSIM_VALIDATION=1).
    bool validation = false;
    /// Move buffer data through staging copies, as on a discrete GPU, even where device memory
    /// is host-visible (lavapipe, integrated GPUs): the tests run a discrete GPU's path with it.
    bool stagedTransfers = false;
    /// Enable shaderInt64 (and its buffer atomics) where the device has them; false makes the
    /// context a device without them (DeviceInfo::int64 false): the tests run the shaders'
    /// CPU fallbacks with it.
    bool int64 = true;
};

class Buffer;
class Kernel;
class Recorder;

/// A Vulkan instance, device and compute queue. Create one and share it.
class Context {
public:
    /// @throw GpuError when no Vulkan device is usable or the chosen one does not exist
    static std::shared_ptr<Context> create(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    const DeviceInfo& info() const;
    /// Validation-layer messages (warnings and errors) seen so far; 0 when validation is off.
    uint64_t validationMessageCount() const;
    /// The text of the most recent validation message ("" if none).
    std::string lastValidationMessage() const;
    bool validationEnabled() const;

    /// Records work with `record`, submits it, waits, and returns the GPU time in milliseconds
    /// measured with timestamps (wall time on the host when the queue has no timestamps).
    template <class F>
    double submit(F&& record);

    struct Impl;
    Impl& impl() const { return *mImpl; }

private:
    Context();
    double submitRecorded(Recorder& recorder);
    Recorder beginRecording();
    std::unique_ptr<Impl> mImpl;
};

/// The backend to use: Cpu gives nullptr; Vulkan gives a context or throws GpuError; Auto gives a
/// context, or logs one line saying why there is none and returns nullptr (the CPU path).
std::shared_ptr<Context> contextForBackend(Backend backend, const ContextOptions& options = {});

/// The context the photon Monte Carlo shader should run on under the run's policy: context.gpu
/// when it is a hardware GPU, or a CPU driver with RunContext::monteCarloOnCpuDevices set; else
/// nullptr (the CPU path). The exposure shaders take context.gpu as it is.
std::shared_ptr<Context> monteCarloContext(const RunContext& context);

/// A storage buffer in device memory, with uploads and downloads through a staging buffer when
/// the memory is not host-visible.
class Buffer {
public:
    /// @throw ResourceError when bytes exceed maxStorageBufferRange or the device heap
    Buffer(std::shared_ptr<Context> context, uint64_t bytes);
    ~Buffer();
    Buffer(Buffer&&) noexcept;
    Buffer& operator=(Buffer&&) noexcept;
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    uint64_t size() const;
    void upload(const void* data, uint64_t bytes, uint64_t offset = 0);
    /// Uploads `rows` rows of `rowBytes` each, read `sourceStride` bytes apart, to `offset`,
    /// `targetStride` bytes apart: one copy into a zero-padded layout, without a padded host copy
    /// (a memcpy per row when the memory is mapped, else one staged copy).
    void uploadRows(const void* data, uint64_t rowBytes, uint64_t rows, uint64_t sourceStride,
                    uint64_t offset, uint64_t targetStride);
    void download(void* data, uint64_t bytes, uint64_t offset = 0) const;
    /// The reverse of uploadRows: `rows` rows of `rowBytes` from `offset`, `sourceStride` bytes
    /// apart in the buffer, to `data`, `targetStride` bytes apart.
    void downloadRows(void* data, uint64_t rowBytes, uint64_t rows, uint64_t offset,
                      uint64_t sourceStride, uint64_t targetStride) const;
    /// The buffer's memory where the host addresses it (host-visible coherent device memory:
    /// lavapipe, integrated GPUs), else nullptr (then upload and download stage their copies).
    /// Read or write it only while no submission that uses the buffer runs (Context::submit
    /// waits for its work, and makes the shaders' writes visible to the host).
    void* hostMemory() const;
    /// Host memory mirroring the whole buffer, holding its contents when first asked for:
    /// hostMemory() where the host addresses the buffer, else the buffer's staging copy, kept at
    /// the buffer's size. Write
    /// it and record Recorder::toDevice, or record Recorder::toHost and read it after the
    /// submission: one submission moves the data and runs the work, and the host reads and writes
    /// the data where it lies (no staged copy of its own per transfer). upload(Rows) and
    /// download(Rows) of the same buffer pass through that staging copy and overwrite it.
    void* hostMirror();
    /// Fills the whole buffer with a repeated 32-bit word.
    void fill(uint32_t word);

    template <class T>
    void upload(const std::vector<T>& values, uint64_t offset = 0) {
        upload(values.data(), values.size() * sizeof(T), offset);
    }
    template <class T>
    std::vector<T> download(size_t count, uint64_t offset = 0) const {
        std::vector<T> values(count);
        download(values.data(), count * sizeof(T), offset);
        return values;
    }

    struct Impl;
    Impl& impl() const { return *mImpl; }

private:
    std::unique_ptr<Impl> mImpl;
};

/// A specialization constant: 32-bit value (use floatBitsToUint for floats) for constant_id `id`.
struct SpecConstant {
    uint32_t id;
    uint32_t value;
};

/// What a kernel's binding is in the shader. Storage: `buffer` (read-write); Uniform: `uniform`
/// block (read-only, at most maxUniformBufferRange bytes; on lavapipe a load at a computed index
/// is a per-lane gather, and so were the unrolled tabulated shader's vec4 loads at constant
/// indices, where `shared` memory loads at a constant address are one scalar load; storage loads
/// go lane by lane);
/// UniformTexels: `samplerBuffer` of R32_SFLOAT read with texelFetch (read-only, at most
/// maxTexelBufferElements floats; on lavapipe a vector gather instead of a per-lane loop);
/// UniformTexels4: the same as an R32G32B32A32_SFLOAT `samplerBuffer`, one vec4 (four consecutive
/// floats) per texelFetch (on lavapipe each fetch is a call, so four floats per call).
enum class Binding { Storage, Uniform, UniformTexels, UniformTexels4 };

/// A compute pipeline from embedded SPIR-V whose bindings 0..bindingCount-1 are storage buffers
/// (or the kinds given) in set 0, with an optional push-constant block.
class Kernel {
public:
    /// @param spirv,spirvBytes the embedded SPIR-V (e.g. `photon_mc_spv`, `sizeof photon_mc_spv`)
    /// @param localSizeX the shader's local_size_x, used by Recorder::dispatch1D
    /// @throw GpuError when pipeline creation fails; ResourceError when push constants exceed
    ///        the device limit
    Kernel(std::shared_ptr<Context> context, const uint32_t* spirv, size_t spirvBytes,
           uint32_t bindingCount, uint32_t pushConstantBytes = 0,
           const std::vector<SpecConstant>& specConstants = {}, uint32_t localSizeX = 64);
    /// The same with the kind of each binding 0..bindings.size()-1.
    Kernel(std::shared_ptr<Context> context, const uint32_t* spirv, size_t spirvBytes,
           const std::vector<Binding>& bindings, uint32_t pushConstantBytes = 0,
           const std::vector<SpecConstant>& specConstants = {}, uint32_t localSizeX = 64);
    ~Kernel();
    Kernel(const Kernel&) = delete;
    Kernel& operator=(const Kernel&) = delete;

    /// The kernel of these arguments that someone holds already (the same context, embedded
    /// SPIR-V, bindings, push constants, specialisation and local size), else a new one. The
    /// engines of a tiled run, and the whole grid's, specialise their shader alike, and creating
    /// an unrolled pipeline takes seconds on lavapipe. A kernel is not changed once made, so
    /// threads may share it; the kernels are held weakly (each lives as long as its users).
    static std::shared_ptr<const Kernel> shared(std::shared_ptr<Context> context,
                                                const uint32_t* spirv, size_t spirvBytes,
                                                const std::vector<Binding>& bindings,
                                                uint32_t pushConstantBytes = 0,
                                                const std::vector<SpecConstant>& specConstants = {},
                                                uint32_t localSizeX = 64);

    uint32_t bindingCount() const;
    uint32_t pushConstantBytes() const;
    uint32_t localSizeX() const;

    struct Impl;
    Impl& impl() const { return *mImpl; }

private:
    std::unique_ptr<Impl> mImpl;
};

/// Records dispatches for one submission. Workgroup counts are checked against the device limits
/// (a ResourceError, never an oversized dispatch: lavapipe would not complain).
class Recorder {
public:
    /// @param buffers one buffer per binding, in binding order
    /// @param push push-constant bytes (must equal the kernel's pushConstantBytes)
    /// @throw ResourceError when a count exceeds maxWorkgroupCount, or a buffer exceeds its
    ///        binding's range (maxUniformBufferRange, maxTexelBufferElements)
    void dispatch(const Kernel& kernel, const std::vector<const Buffer*>& buffers, const void* push,
                  uint32_t groupsX, uint32_t groupsY = 1, uint32_t groupsZ = 1);
    /// Dispatches ceil(invocations / localSizeX) groups, folded into Y when X would exceed the
    /// device's workgroup-count limit (65535 on lavapipe). The shader's flat index is
    /// gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x
    /// (see flatInvocationIndex() in shaders/include/glsl_common.glsl) and must be bounds-checked.
    void dispatch1D(const Kernel& kernel, const std::vector<const Buffer*>& buffers,
                    const void* push, uint64_t invocations);
    /// Makes all earlier shader writes visible to later dispatches and transfers.
    void barrier();
    /// Fills `buffer` with a repeated 32-bit word inside the submission (no submission of its own).
    void fill(Buffer& buffer, uint32_t word);
    /// Copies `buffer`'s host mirror (Buffer::hostMirror) to the device and makes it visible to
    /// the work recorded after; nothing where the mirror is the buffer itself.
    void toDevice(Buffer& buffer);
    /// Copies `buffer` to its host mirror once the work recorded before has written it; nothing
    /// where the mirror is the buffer itself (Context::submit's wait makes the writes visible).
    void toHost(Buffer& buffer);
    /// Copies bytes between buffers inside the submission.
    void copy(const Buffer& source, Buffer& destination, uint64_t bytes, uint64_t sourceOffset = 0,
              uint64_t destinationOffset = 0);

    struct Impl;
    explicit Recorder(std::shared_ptr<Impl> impl) : mImpl(std::move(impl)) {}
    Impl& impl() const { return *mImpl; }

private:
    std::shared_ptr<Impl> mImpl;
};

template <class F>
double Context::submit(F&& record) {
    Recorder recorder = beginRecording();
    record(recorder);
    return submitRecorded(recorder);
}

}  // namespace vpsim::gpu
