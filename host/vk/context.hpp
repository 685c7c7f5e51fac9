#pragma once
// Minimal Vulkan compute host: one device, one queue, synchronous dispatches.
// Lifetime rule: Buffers and ComputePipelines must be destroyed before the Context they came from.
// After a dispatch times out the GPU may still be using every object, and destroying them would be
// undefined (lavapipe corrupts the heap); so a broken() context and its objects leak instead.
// Thread safety: a Context records into a single command buffer, so dispatch() must not be called
// from several threads at once; only the validation-message log is safe to touch concurrently.
#include "vk/check.hpp"

#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace oas::vk {

// Points the loader at lavapipe when the caller has not chosen a driver, so CI machines without a
// GPU still get a device. Must run before the first Vulkan call; uses setenv, so not thread-safe.
void selectLavapipeIfUnset();

struct ContextOptions {
    bool validation = false;                // also switched on by env OAS_VK_VALIDATION=1
    bool requireValidation = false;         // throw if the validation layer is not installed
    std::string preferDevice;               // case-sensitive substring of the device name; wins over type
    double dispatchTimeoutSeconds = 120.0;  // a hung kernel throws instead of blocking forever
    // Presentation (oas-view): the instance extensions a window system needs (GLFW's
    // glfwGetRequiredInstanceExtensions), device extensions (VK_KHR_swapchain), and a test of whether
    // a queue family of a device can present. With canPresent set, only a family that computes and
    // presents is chosen, so one queue does both and no ownership transfers are needed.
    std::vector<std::string> instanceExtensions, deviceExtensions;
    std::function<bool(VkInstance, VkPhysicalDevice, uint32_t family)> canPresent;
};

namespace detail {
// Owns one Vulkan handle; the deleter captures whatever parent handle destruction needs.
template <class T>
class Owned {
public:
    Owned() = default;
    Owned(T h, std::function<void(T)> del) : h_(h), del_(std::move(del)) {}
    Owned(Owned&& o) noexcept : h_(std::exchange(o.h_, T{})), del_(std::move(o.del_)) {}
    Owned& operator=(Owned&& o) noexcept
    {
        if (this != &o) {
            reset();
            h_ = std::exchange(o.h_, T{});
            del_ = std::move(o.del_);
        }
        return *this;
    }
    Owned(const Owned&) = delete;
    Owned& operator=(const Owned&) = delete;
    ~Owned() { reset(); }
    void reset()
    {
        if (h_ != T{} && del_) del_(h_);
        h_ = T{};
    }
    T get() const { return h_; }
    void leak() { h_ = T{}; }  // for when destroying could race with a GPU that never finished

private:
    T h_{};
    std::function<void(T)> del_;
};
}  // namespace detail

class Context;

/// What a pipeline binding is. Storage buffers are read and written per lane; a texel buffer of
/// uvec4 (R32G32B32A32_UINT, `usamplerBuffer` in GLSL) is read-only. Lavapipe (Mesa 22.3) loads
/// a storage-buffer element whose index differs across lanes one lane at a time, with a branch and
/// a bounds check per lane, and a texel fetch as one gather for all lanes (measured with perf on
/// its JIT code: the lane loops were over half of the path tracer's frame).
/// A storage texel buffer of uint (R32_UINT, `uimageBuffer` with `r32ui`) is written per lane with
/// imageStore: the generation kernel's output (oas_generate.comp).
enum class BindingKind { StorageBuffer, Uint4TexelBuffer, UintStorageTexelBuffer };
/// The descriptor type of a binding of that kind.
VkDescriptorType descriptorType(BindingKind kind);

class Buffer {
public:
    Buffer(Context& ctx, VkDeviceSize bytes);
    Buffer(Buffer&& o) noexcept;
    Buffer& operator=(Buffer&&) = delete;
    ~Buffer();
    void* data() const { return mapped_; }
    VkDeviceSize size() const { return size_; }
    VkBuffer handle() const { return buffer_.get(); }
    bool deviceLocal() const { return deviceLocal_; }
    /// The whole buffer as texels of uvec4 (R32G32B32A32_UINT), made on first use. Throws
    /// std::invalid_argument when the size is not a whole number of texels or exceeds the
    /// device's maxTexelBufferElements.
    VkBufferView uint4View();
    /// The whole buffer as storage texels of uint (R32_UINT), made on first use; throws like
    /// uint4View where it is not a whole number of 4-byte texels or too many of them.
    VkBufferView uintView();

private:
    const Context* ctx_;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
    bool deviceLocal_ = false;
    detail::Owned<VkDeviceMemory> memory_;  // declared first: freed after the buffer using it
    detail::Owned<VkBuffer> buffer_;
    detail::Owned<VkBufferView> uint4View_;  // declared after the buffer: destroyed before it
    detail::Owned<VkBufferView> uintView_;
    VkBufferView makeView(detail::Owned<VkBufferView>& slot, VkFormat format, VkDeviceSize texelBytes, const char* what);
};

class ComputePipeline {
public:
    using SpecConstants = std::vector<std::pair<uint32_t, uint32_t>>;  // (constant_id, value)
    /// bindingKinds: one per binding, or empty for bindingCount storage buffers.
    ComputePipeline(Context& ctx, const uint32_t* code, size_t byteSize, uint32_t bindingCount, uint32_t pushConstantBytes,
                    const SpecConstants& specConstants = {}, std::vector<BindingKind> bindingKinds = {});
    ComputePipeline(ComputePipeline&&) noexcept = default;
    ComputePipeline& operator=(ComputePipeline&&) = delete;
    ~ComputePipeline();
    uint32_t bindingCount() const { return bindingCount_; }
    uint32_t pushConstantBytes() const { return pushBytes_; }
    VkPipeline handle() const { return pipeline_.get(); }

private:
    friend class Context;
    const Context* ctx_;
    uint32_t bindingCount_ = 0;
    uint32_t pushBytes_ = 0;
    std::vector<BindingKind> bindingKinds_;
    detail::Owned<VkDescriptorSetLayout> setLayout_;
    detail::Owned<VkPipelineLayout> layout_;
    detail::Owned<VkPipeline> pipeline_;
    detail::Owned<VkDescriptorPool> pool_;  // one set, reset per dispatch
};

/// One dispatch of Context::dispatchSequence: its pipeline, buffers (binding i: buffers[i]) and
/// push-constant block (whole words), and its group counts: given, or read on the device from
/// three uints at byte `indirectOffset` of `indirect`, which an earlier dispatch of the sequence
/// wrote (vkCmdDispatchIndirect; counts of 0 dispatch nothing).
struct SequencedDispatch {
    ComputePipeline* pipeline = nullptr;
    std::vector<Buffer*> buffers;
    std::vector<uint32_t> push;
    uint32_t groups[3] = {1, 1, 1};
    Buffer* indirect = nullptr;
    VkDeviceSize indirectOffset = 0;
};

class Context {
public:
    explicit Context(const ContextOptions& opts = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return instance_.get(); }
    VkDevice device() const { return device_.get(); }
    VkPhysicalDevice physicalDevice() const { return physical_; }
    VkQueue queue() const { return queue_; }
    uint32_t queueFamily() const { return queueFamily_; }
    const std::string& deviceName() const { return deviceName_; }
    const std::string& driverName() const { return driverName_; }  // empty if not reported
    const VkPhysicalDeviceLimits& limits() const { return limits_; }
    const VkPhysicalDeviceMemoryProperties& memoryProperties() const { return memProps_; }
    // Worth checking in tests: lavapipe (verified on Mesa 22.3) silently ends shader loops after
    // 65535 back-edges per invocation, summed over all loops, and caps storage bindings at 128 MiB.
    bool isLavapipe() const { return isLavapipe_; }
    // The lanes that run in lock step (8 on lavapipe, 32 on NVIDIA), and whether compute shaders
    // may ballot across them (GL_KHR_shader_subgroup_ballot): Vulkan 1.1 properties, which every
    // device we pick has.
    uint32_t subgroupSize() const { return subgroupSize_; }
    bool computeSubgroupBallot() const { return computeSubgroupBallot_; }
    bool broken() const { return broken_; }  // a dispatch timed out or the device was lost

    bool validationEnabled() const { return validation_; }
    // Findings: every warning or error the layers reported (VUIDs, undefined behaviour, performance
    // warnings). Tests fail on any of these.
    std::vector<std::string> validationMessages() const;
    // Notes: info-level messages (the layer's status lines, its cache file). The Khronos layer
    // reports every usage finding at warning or error severity, so these say nothing about our use of
    // the API; they are kept for diagnosis and printed only with OAS_VK_VERBOSE=1.
    std::vector<std::string> validationNotes() const;
    void clearValidationMessages();

    // Synchronous: returns once the GPU is done and shader writes are visible through
    // Buffer::data(). buffers[i] is bound to binding i, as the pipeline's BindingKind for it says.
    void dispatch(ComputePipeline& pipe, std::span<Buffer* const> buffers, const void* pushData, uint32_t pushBytes, uint32_t gx,
                  uint32_t gy = 1, uint32_t gz = 1);
    // Records the dispatches in one command buffer, each after a barrier that makes the writes of
    // the ones before visible to its reads and to its indirect group counts, submits it once and
    // waits, as dispatch() does: kernels that feed each other without a round trip through the
    // host (the wavefront's steps, each sized by the survivors of the one before).
    void dispatchSequence(std::span<const SequencedDispatch> dispatches);

private:
    static VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                                         const VkDebugUtilsMessengerCallbackDataEXT*, void*);
    void pickPhysicalDevice(const ContextOptions& opts, uint32_t instanceApi);
    // dispatch()'s and dispatchSequence()'s common steps.
    void checkDispatch(const ComputePipeline& pipe, std::span<Buffer* const> buffers, const void* pushData,
                       uint32_t pushBytes) const;
    void checkGroups(const uint32_t (&groups)[3]) const;
    void writeDescriptorSet(VkDescriptorSet set, const ComputePipeline& pipe, std::span<Buffer* const> buffers) const;
    void beginCommands();
    void recordDispatch(const ComputePipeline& pipe, VkDescriptorSet set, const void* pushData, uint32_t pushBytes);
    void recordBarrier();
    void submitAndWait(const std::string& what);

    // The log is declared before every handle so it outlives the messenger's last callback.
    mutable std::mutex logMutex_;
    std::vector<std::string> log_, notes_;
    bool verbose_ = false;
    bool validation_ = false;
    bool broken_ = false;
    uint64_t timeoutNs_ = 0;

    detail::Owned<VkInstance> instance_;
    detail::Owned<VkDebugUtilsMessengerEXT> messenger_;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    uint32_t queueFamily_ = 0;
    std::string deviceName_, driverName_;
    VkPhysicalDeviceLimits limits_{};
    VkPhysicalDeviceMemoryProperties memProps_{};
    bool isLavapipe_ = false;
    uint32_t subgroupSize_ = 1;
    bool computeSubgroupBallot_ = false;
    detail::Owned<VkDevice> device_;
    VkQueue queue_ = VK_NULL_HANDLE;
    detail::Owned<VkCommandPool> cmdPool_;  // frees the command buffer with it
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    detail::Owned<VkFence> fence_;
    // dispatchSequence's descriptor sets, one per dispatch, reset per sequence; grown to the
    // largest sequence seen (its sets and descriptors of each type).
    detail::Owned<VkDescriptorPool> sequencePool_;
    std::map<VkDescriptorType, uint32_t> sequencePoolDescriptors_;
    uint32_t sequencePoolSets_ = 0;
};

// Throws VulkanError listing every collected validation message (no-op when there are none).
void throwIfValidationMessages(const Context& ctx);

}  // namespace oas::vk
