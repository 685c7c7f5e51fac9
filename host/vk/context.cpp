#include "vk/context.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <string_view>

namespace oas::vk {
namespace {

constexpr const char* kLavapipeIcd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

// Retries on VK_INCOMPLETE, which the two-call pattern can return if the set grows in between.
template <class T, class F>
std::vector<T> enumerate(const char* what, F&& f)
{
    for (;;) {
        uint32_t n = 0;
        VkResult r = f(&n, nullptr);
        if (r != VK_SUCCESS) throwVkError(r, what, __FILE__, __LINE__);
        std::vector<T> v(n);
        r = f(&n, v.data());
        if (r == VK_INCOMPLETE) continue;
        if (r != VK_SUCCESS) throwVkError(r, what, __FILE__, __LINE__);
        v.resize(n);
        return v;
    }
}

bool envFlag(const char* name)
{
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0;
}

bool hasExtension(const std::vector<VkExtensionProperties>& exts, const char* name)
{
    return std::any_of(exts.begin(), exts.end(),
                       [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

int typeRank(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return 1;
    default:
        return 0;
    }
}

std::string apiString(uint32_t v)
{
    return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), VK_API_VERSION_PATCH(v));
}

}  // namespace

void selectLavapipeIfUnset()
{
    if (std::getenv("VK_DRIVER_FILES") || std::getenv("VK_ICD_FILENAMES")) return;
    std::error_code ec;
    if (!std::filesystem::exists(kLavapipeIcd, ec)) return;
    // Loaders before 1.3.207 only read VK_ICD_FILENAMES, newer ones prefer VK_DRIVER_FILES.
    ::setenv("VK_DRIVER_FILES", kLavapipeIcd, 0);
    ::setenv("VK_ICD_FILENAMES", kLavapipeIcd, 0);
}

// ---------------------------------------------------------------- Context

VKAPI_ATTR VkBool32 VKAPI_CALL Context::onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT types,
                                                       const VkDebugUtilsMessengerCallbackDataEXT* data, void* user)
{
    auto* self = static_cast<Context*>(user);
    const std::string_view id = data->pMessageIdName ? data->pMessageIdName : "-";
    const char* sev = severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT     ? "error"
                      : severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT ? "warning"
                                                                                    : "info";
    std::string msg = fmt::format("[{}] {}: {}", sev, id, data->pMessage ? data->pMessage : "");
    // Info and verbose messages are notes, not findings: the Khronos layer reports misuse at warning
    // or error severity, and what it says at info is about its environment (its status line at
    // instance creation, "cannot open shader validation cache" on a machine whose ~/.cache is new).
    // A fresh machine must not fail a test that a warm one passes.
    if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        if (self->verbose_) fmt::print(stderr, "oas::vk validation note {}\n", msg);
        std::lock_guard lock(self->logMutex_);
        self->notes_.push_back(std::move(msg));
        return VK_FALSE;
    }
    // Also printed, so applications that never inspect the log still show misuse.
    fmt::print(stderr, "oas::vk validation {}\n", msg);
    std::lock_guard lock(self->logMutex_);
    self->log_.push_back(std::move(msg));
    return VK_FALSE;  // never abort the call: we want the driver's behaviour, not the layer's
}

Context::Context(const ContextOptions& opts)
{
    // The XDG base-directory spec says an empty or relative XDG_CACHE_HOME is to be ignored (use
    // ~/.cache); Mesa 22.3 takes it literally, prints "Failed to create  for shader cache" and runs
    // without its cache. Follow the spec for the driver, before it reads the variable.
    if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache && cache[0] != '/') ::unsetenv("XDG_CACHE_HOME");
    timeoutNs_ = static_cast<uint64_t>(std::max(opts.dispatchTimeoutSeconds, 0.0) * 1e9);

    uint32_t loaderApi = VK_API_VERSION_1_0;
    OAS_VK_CHECK(vkEnumerateInstanceVersion(&loaderApi));
    if (loaderApi < VK_API_VERSION_1_1) throw NoDeviceError("Vulkan loader is " + apiString(loaderApi) + ", need 1.1");
    // Asking for the newest the loader knows lets 1.2+ devices expose their driver properties.
    const uint32_t api = std::min(loaderApi, VK_API_VERSION_1_3);

    const bool wantValidation = opts.validation || opts.requireValidation || envFlag("OAS_VK_VALIDATION");
    verbose_ = envFlag("OAS_VK_VERBOSE");
    std::vector<const char*> layers, extensions;
    bool haveValidationFeatures = false;
    if (wantValidation) {
        const auto props =
            enumerate<VkLayerProperties>("vkEnumerateInstanceLayerProperties", [](uint32_t* n, VkLayerProperties* p) {
                return vkEnumerateInstanceLayerProperties(n, p);
            });
        const bool haveLayer = std::any_of(props.begin(), props.end(), [](const VkLayerProperties& l) {
            return std::strcmp(l.layerName, kValidationLayer) == 0;
        });
        bool haveDebugUtils = false;
        if (haveLayer) {
            auto exts = enumerate<VkExtensionProperties>(
                "vkEnumerateInstanceExtensionProperties",
                [](uint32_t* n, VkExtensionProperties* p) { return vkEnumerateInstanceExtensionProperties(nullptr, n, p); });
            const auto layerExts = enumerate<VkExtensionProperties>(
                "vkEnumerateInstanceExtensionProperties(layer)", [](uint32_t* n, VkExtensionProperties* p) {
                    return vkEnumerateInstanceExtensionProperties(kValidationLayer, n, p);
                });
            exts.insert(exts.end(), layerExts.begin(), layerExts.end());
            haveDebugUtils = hasExtension(exts, VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
            haveValidationFeatures = hasExtension(layerExts, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
        }
        // Without the messenger nothing would be collected and "no messages" would prove nothing.
        if (opts.requireValidation && !(haveLayer && haveDebugUtils))
            throw VulkanError(haveLayer ? "validation required but VK_EXT_debug_utils is unavailable"
                                        : "validation required but VK_LAYER_KHRONOS_validation is not installed "
                                          "(Debian: apt install vulkan-validationlayers)");
        if (haveLayer && haveDebugUtils) {
            validation_ = true;
            layers.push_back(kValidationLayer);
            extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
            if (haveValidationFeatures) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
        }
    }

    VkDebugUtilsMessengerCreateInfoEXT messengerInfo{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    messengerInfo.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_INFO_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    messengerInfo.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    messengerInfo.pfnUserCallback = &Context::onDebugMessage;
    messengerInfo.pUserData = this;
    // The layer's shader validation cache is a file in ~/.cache that parallel processes race to read
    // and write, and that does not exist on a new machine. Validation is the same without it (it only
    // skips re-validating SPIR-V seen before), so our runs neither depend on nor write the user's HOME.
    const VkValidationFeatureDisableEXT disabled[] = {VK_VALIDATION_FEATURE_DISABLE_SHADER_VALIDATION_CACHE_EXT};
    VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    features.disabledValidationFeatureCount = 1;
    features.pDisabledValidationFeatures = disabled;
    features.pNext = &messengerInfo;  // instance creation only: the messenger's own create info takes no chain

    for (const auto& e : opts.instanceExtensions)
        if (std::none_of(extensions.begin(), extensions.end(), [&](const char* x) { return e == x; }))
            extensions.push_back(e.c_str());

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "oas";
    app.pEngineName = "oas";
    app.apiVersion = api;
    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    // The messenger also covers vkCreate/DestroyInstance.
    ici.pNext = !validation_ ? nullptr : haveValidationFeatures ? static_cast<const void*>(&features) : &messengerInfo;
    ici.pApplicationInfo = &app;
    ici.enabledLayerCount = static_cast<uint32_t>(layers.size());
    ici.ppEnabledLayerNames = layers.data();
    ici.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    ici.ppEnabledExtensionNames = extensions.data();
    VkInstance inst = VK_NULL_HANDLE;
    if (VkResult r = vkCreateInstance(&ici, nullptr, &inst); r != VK_SUCCESS) {
        if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
            throw NoDeviceError(fmt::format("vkCreateInstance failed: {} (no usable Vulkan driver)", resultName(r)), r);
        throwVkError(r, "vkCreateInstance", __FILE__, __LINE__);
    }
    instance_ = detail::Owned<VkInstance>(inst, [](VkInstance i) { vkDestroyInstance(i, nullptr); });

    if (validation_) {
        auto create =
            reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(inst, "vkCreateDebugUtilsMessengerEXT"));
        auto destroy =
            reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(inst, "vkDestroyDebugUtilsMessengerEXT"));
        if (!create || !destroy) throw VulkanError("VK_EXT_debug_utils enabled but its entry points are missing");
        VkDebugUtilsMessengerEXT m = VK_NULL_HANDLE;
        OAS_VK_CHECK(create(inst, &messengerInfo, nullptr, &m));
        messenger_ = detail::Owned<VkDebugUtilsMessengerEXT>(
            m, [inst, destroy](VkDebugUtilsMessengerEXT h) { destroy(inst, h, nullptr); });
    }

    pickPhysicalDevice(opts, api);

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = queueFamily_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    std::vector<const char*> deviceExtensions;
    for (const auto& e : opts.deviceExtensions) deviceExtensions.push_back(e.c_str());
    dci.enabledExtensionCount = static_cast<uint32_t>(deviceExtensions.size());
    dci.ppEnabledExtensionNames = deviceExtensions.data();
    VkDevice dev = VK_NULL_HANDLE;
    if (VkResult r = vkCreateDevice(physical_, &dci, nullptr, &dev); r != VK_SUCCESS) {
        if (r == VK_ERROR_INITIALIZATION_FAILED)
            throw NoDeviceError(fmt::format("vkCreateDevice failed on {}: {}", deviceName_, resultName(r)), r);
        throwVkError(r, "vkCreateDevice", __FILE__, __LINE__);
    }
    device_ = detail::Owned<VkDevice>(dev, [](VkDevice d) { vkDestroyDevice(d, nullptr); });
    vkGetDeviceQueue(dev, queueFamily_, 0, &queue_);

    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queueFamily_;
    VkCommandPool pool = VK_NULL_HANDLE;
    OAS_VK_CHECK(vkCreateCommandPool(dev, &pci, nullptr, &pool));
    cmdPool_ = detail::Owned<VkCommandPool>(pool, [dev](VkCommandPool p) { vkDestroyCommandPool(dev, p, nullptr); });
    VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.commandPool = pool;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    OAS_VK_CHECK(vkAllocateCommandBuffers(dev, &cai, &cmd_));

    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence = VK_NULL_HANDLE;
    OAS_VK_CHECK(vkCreateFence(dev, &fci, nullptr, &fence));
    fence_ = detail::Owned<VkFence>(fence, [dev](VkFence f) { vkDestroyFence(dev, f, nullptr); });
}

void Context::pickPhysicalDevice(const ContextOptions& opts, uint32_t instanceApi)
{
    const std::string& prefer = opts.preferDevice;
    const VkInstance inst = instance_.get();
    const auto devices = enumerate<VkPhysicalDevice>("vkEnumeratePhysicalDevices", [inst](uint32_t* n, VkPhysicalDevice* p) {
        return vkEnumeratePhysicalDevices(inst, n, p);
    });
    int bestScore = -1;
    std::string seen;
    for (VkPhysicalDevice pd : devices) {
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(pd, &props);
        seen += fmt::format(" '{}' (Vulkan {})", props.deviceName, apiString(props.apiVersion));
        // Our SPIR-V targets vulkan1.1 (SPIR-V 1.3), which a 1.0 device cannot run.
        if (props.apiVersion < VK_API_VERSION_1_1) continue;
        uint32_t nq = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, nullptr);
        std::vector<VkQueueFamilyProperties> families(nq);
        vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, families.data());
        auto fam = families.begin();
        for (; fam != families.end(); ++fam) {
            const uint32_t index = static_cast<uint32_t>(fam - families.begin());
            if ((fam->queueFlags & VK_QUEUE_COMPUTE_BIT) && fam->queueCount > 0 &&
                (!opts.canPresent || opts.canPresent(inst, pd, index)))
                break;
        }
        if (fam == families.end()) continue;
        if (!opts.deviceExtensions.empty()) {
            const auto exts = enumerate<VkExtensionProperties>(
                "vkEnumerateDeviceExtensionProperties",
                [pd](uint32_t* n, VkExtensionProperties* p) { return vkEnumerateDeviceExtensionProperties(pd, nullptr, n, p); });
            if (!std::all_of(opts.deviceExtensions.begin(), opts.deviceExtensions.end(),
                             [&](const std::string& e) { return hasExtension(exts, e.c_str()); }))
                continue;
        }
        const bool named = !prefer.empty() && std::string_view(props.deviceName).find(prefer) != std::string_view::npos;
        const int score = typeRank(props.deviceType) + (named ? 100 : 0);
        if (score <= bestScore) continue;  // ties keep enumeration order, which is stable per machine
        bestScore = score;
        physical_ = pd;
        queueFamily_ = static_cast<uint32_t>(fam - families.begin());
    }
    if (physical_ == VK_NULL_HANDLE)
        throw NoDeviceError(
            devices.empty() ? std::string("no Vulkan physical devices")
                            : std::string(opts.canPresent ? "no Vulkan 1.1 device with a queue that computes and presents among:"
                                                          : "no Vulkan 1.1 device with a compute queue among:") +
                                  seen);

    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(physical_, &props);
    deviceName_ = props.deviceName;
    limits_ = props.limits;
    vkGetPhysicalDeviceMemoryProperties(physical_, &memProps_);

    // Driver properties are core only from 1.2, and the instance version caps what we may query.
    VkDriverId driverId{};
    if (std::min(props.apiVersion, instanceApi) >= VK_API_VERSION_1_2) {
        VkPhysicalDeviceDriverProperties drv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
        VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
        p2.pNext = &drv;
        vkGetPhysicalDeviceProperties2(physical_, &p2);
        driverName_ = drv.driverName;
        driverId = drv.driverID;
    }
    // Subgroup properties are core in 1.1, the least this device has (checked above).
    VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 withSubgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    withSubgroup.pNext = &subgroup;
    vkGetPhysicalDeviceProperties2(physical_, &withSubgroup);
    subgroupSize_ = subgroup.subgroupSize;
    computeSubgroupBallot_ = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0 &&
                             (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_BALLOT_BIT) != 0;
    isLavapipe_ = driverId == VK_DRIVER_ID_MESA_LLVMPIPE || deviceName_.find("llvmpipe") != std::string::npos;
}

Context::~Context()
{
    if (broken_) {
        // Waiting could block forever on a hung kernel; leaking is the only safe way out.
        sequencePool_.leak(), fence_.leak(), cmdPool_.leak(), device_.leak(), messenger_.leak(), instance_.leak();
        return;
    }
    // Destroying objects the GPU may still use is undefined; the owned handles then go in reverse
    // declaration order (descriptor pool, fence, command pool, device, messenger, instance).
    if (device_.get() != VK_NULL_HANDLE) vkDeviceWaitIdle(device_.get());
}

std::vector<std::string> Context::validationMessages() const
{
    std::lock_guard lock(logMutex_);
    return log_;
}

std::vector<std::string> Context::validationNotes() const
{
    std::lock_guard lock(logMutex_);
    return notes_;
}

void Context::clearValidationMessages()
{
    std::lock_guard lock(logMutex_);
    log_.clear();
    notes_.clear();
}

void throwIfValidationMessages(const Context& ctx)
{
    const auto msgs = ctx.validationMessages();
    if (msgs.empty()) return;
    std::string text = fmt::format("{} Vulkan validation message(s):", msgs.size());
    for (const auto& m : msgs) text += "\n  " + m;
    throw VulkanError(text);
}

void Context::checkDispatch(const ComputePipeline& pipe, std::span<Buffer* const> buffers, const void* pushData,
                            uint32_t pushBytes) const
{
    if (broken_) throw VulkanError("Context unusable: an earlier dispatch timed out or lost the device");
    if (buffers.size() != pipe.bindingCount_)
        throw std::invalid_argument(
            fmt::format("dispatch: pipeline has {} bindings, got {} buffers", pipe.bindingCount_, buffers.size()));
    // A partial push leaves the rest of the block undefined, a silent source of wrong results.
    if (pushBytes != pipe.pushBytes_ || (pushBytes && !pushData))
        throw std::invalid_argument(
            fmt::format("dispatch: pipeline expects {} push-constant bytes, got {}", pipe.pushBytes_, pushBytes));
    for (size_t i = 0; i < buffers.size(); ++i)
        if (!buffers[i]) throw std::invalid_argument(fmt::format("dispatch: buffer {} is null", i));
}

void Context::checkGroups(const uint32_t (&groups)[3]) const
{
    for (int i = 0; i < 3; ++i)
        if (groups[i] > limits_.maxComputeWorkGroupCount[i])
            throw std::invalid_argument(fmt::format("dispatch: group count {} exceeds device limit {} on axis {}", groups[i],
                                                    limits_.maxComputeWorkGroupCount[i], i));
}

void Context::writeDescriptorSet(VkDescriptorSet set, const ComputePipeline& pipe, std::span<Buffer* const> buffers) const
{
    std::vector<VkDescriptorBufferInfo> infos(buffers.size());
    std::vector<VkBufferView> views(buffers.size());
    std::vector<VkWriteDescriptorSet> writes(buffers.size());
    for (size_t i = 0; i < buffers.size(); ++i) {
        writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        writes[i].dstSet = set;
        writes[i].dstBinding = static_cast<uint32_t>(i);
        writes[i].descriptorCount = 1;
        if (pipe.bindingKinds_[i] != BindingKind::StorageBuffer) {
            const bool uniform = pipe.bindingKinds_[i] == BindingKind::Uint4TexelBuffer;
            views[i] = uniform ? buffers[i]->uint4View() : buffers[i]->uintView();
            writes[i].descriptorType = descriptorType(pipe.bindingKinds_[i]);
            writes[i].pTexelBufferView = &views[i];
            continue;
        }
        if (buffers[i]->size() > limits_.maxStorageBufferRange)
            throw std::invalid_argument(fmt::format("dispatch: buffer {} is {} bytes, above maxStorageBufferRange {}", i,
                                                    buffers[i]->size(), limits_.maxStorageBufferRange));
        infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[i].pBufferInfo = &infos[i];
    }
    vkUpdateDescriptorSets(device_.get(), static_cast<uint32_t>(writes.size()), writes.data(), 0, nullptr);
}

void Context::beginCommands()
{
    OAS_VK_CHECK(vkResetCommandBuffer(cmd_, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    OAS_VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
}

void Context::recordDispatch(const ComputePipeline& pipe, VkDescriptorSet set, const void* pushData, uint32_t pushBytes)
{
    vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.pipeline_.get());
    if (set != VK_NULL_HANDLE)
        vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipe.layout_.get(), 0, 1, &set, 0, nullptr);
    if (pushBytes > 0) vkCmdPushConstants(cmd_, pipe.layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, pushBytes, pushData);
}

void Context::recordBarrier()
{
    // Host writes before submit are made visible by the submission itself; the way back needs an
    // explicit barrier, or the mapped pointer may show stale data even after the fence. The same
    // barrier orders this dispatch's writes before the reads of later dispatches, in this command
    // buffer or a later submission (a barrier's second scope reaches them): the path tracer reads
    // the samples the generation kernel wrote in the dispatch before, and a wavefront step its
    // group counts (indirect) and the records the step before wrote.
    VkMemoryBarrier written{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    written.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    written.dstAccessMask =
        VK_ACCESS_HOST_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT;
    vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                         0, 1, &written, 0, nullptr, 0, nullptr);
}

void Context::submitAndWait(const std::string& what)
{
    OAS_VK_CHECK(vkEndCommandBuffer(cmd_));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd_;
    VkFence fence = fence_.get();
    VkResult r = vkQueueSubmit(queue_, 1, &submit, fence);
    if (r == VK_SUCCESS) r = vkWaitForFences(device_.get(), 1, &fence, VK_TRUE, timeoutNs_);
    if (r != VK_SUCCESS) {
        broken_ = true;  // the command buffer may still be pending, so nothing may be reused or freed
        if (r == VK_TIMEOUT)
            throw VulkanError(fmt::format("{} did not finish within {:g} s on {}", what, timeoutNs_ / 1e9, deviceName_), r);
        throwVkError(r, "vkQueueSubmit/vkWaitForFences", __FILE__, __LINE__);
    }
    OAS_VK_CHECK(vkResetFences(device_.get(), 1, &fence));
}

void Context::dispatch(ComputePipeline& pipe, std::span<Buffer* const> buffers, const void* pushData, uint32_t pushBytes,
                       uint32_t gx, uint32_t gy, uint32_t gz)
{
    checkDispatch(pipe, buffers, pushData, pushBytes);
    const uint32_t groups[3] = {gx, gy, gz};
    checkGroups(groups);
    const VkDevice dev = device_.get();
    VkDescriptorSet set = VK_NULL_HANDLE;
    if (pipe.bindingCount_ > 0) {
        OAS_VK_CHECK(vkResetDescriptorPool(dev, pipe.pool_.get(), 0));
        VkDescriptorSetLayout layout = pipe.setLayout_.get();
        VkDescriptorSetAllocateInfo dai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        dai.descriptorPool = pipe.pool_.get();
        dai.descriptorSetCount = 1;
        dai.pSetLayouts = &layout;
        OAS_VK_CHECK(vkAllocateDescriptorSets(dev, &dai, &set));
        writeDescriptorSet(set, pipe, buffers);
    }
    beginCommands();
    recordDispatch(pipe, set, pushData, pushBytes);
    vkCmdDispatch(cmd_, gx, gy, gz);
    recordBarrier();
    submitAndWait(fmt::format("dispatch ({}x{}x{} groups)", gx, gy, gz));
}

void Context::dispatchSequence(std::span<const SequencedDispatch> dispatches)
{
    if (dispatches.empty()) return;
    std::map<VkDescriptorType, uint32_t> needed;
    for (const SequencedDispatch& d : dispatches) {
        if (!d.pipeline) throw std::invalid_argument("dispatchSequence: a dispatch without a pipeline");
        checkDispatch(*d.pipeline, d.buffers, d.push.data(), uint32_t(d.push.size() * sizeof(uint32_t)));
        if (d.indirect) {
            if (d.indirectOffset % 4 != 0 || d.indirectOffset + 3 * sizeof(uint32_t) > d.indirect->size())
                throw std::invalid_argument(fmt::format("dispatchSequence: indirect group counts at byte {} of a {}-byte buffer",
                                                        d.indirectOffset, d.indirect->size()));
        } else {
            checkGroups(d.groups);
        }
        for (const BindingKind kind : d.pipeline->bindingKinds_) ++needed[descriptorType(kind)];
    }
    const VkDevice dev = device_.get();
    const auto sets = uint32_t(dispatches.size());
    bool fits = sequencePool_.get() != VK_NULL_HANDLE && sets <= sequencePoolSets_;
    for (const auto& [type, count] : needed) fits = fits && count <= sequencePoolDescriptors_[type];
    if (!fits) {
        sequencePool_.reset();
        sequencePoolSets_ = std::max(sets, sequencePoolSets_);
        std::vector<VkDescriptorPoolSize> sizes;
        for (const auto& [type, count] : needed) sequencePoolDescriptors_[type] = std::max(count, sequencePoolDescriptors_[type]);
        for (const auto& [type, count] : sequencePoolDescriptors_)
            if (count) sizes.push_back({type, count});
        VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        dpci.maxSets = sequencePoolSets_;
        dpci.poolSizeCount = static_cast<uint32_t>(sizes.size());
        dpci.pPoolSizes = sizes.data();
        VkDescriptorPool pool = VK_NULL_HANDLE;
        OAS_VK_CHECK(vkCreateDescriptorPool(dev, &dpci, nullptr, &pool));
        sequencePool_ = detail::Owned<VkDescriptorPool>(pool, [dev](VkDescriptorPool h) { vkDestroyDescriptorPool(dev, h, nullptr); });
    }
    OAS_VK_CHECK(vkResetDescriptorPool(dev, sequencePool_.get(), 0));
    beginCommands();
    for (const SequencedDispatch& d : dispatches) {
        const ComputePipeline& pipe = *d.pipeline;
        VkDescriptorSet set = VK_NULL_HANDLE;
        if (pipe.bindingCount_ > 0) {
            VkDescriptorSetLayout layout = pipe.setLayout_.get();
            VkDescriptorSetAllocateInfo dai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
            dai.descriptorPool = sequencePool_.get();
            dai.descriptorSetCount = 1;
            dai.pSetLayouts = &layout;
            OAS_VK_CHECK(vkAllocateDescriptorSets(dev, &dai, &set));
            writeDescriptorSet(set, pipe, d.buffers);
        }
        recordDispatch(pipe, set, d.push.data(), uint32_t(d.push.size() * sizeof(uint32_t)));
        if (d.indirect)
            vkCmdDispatchIndirect(cmd_, d.indirect->handle(), d.indirectOffset);
        else
            vkCmdDispatch(cmd_, d.groups[0], d.groups[1], d.groups[2]);
        recordBarrier();
    }
    submitAndWait(fmt::format("a sequence of {} dispatches", dispatches.size()));
}

}  // namespace oas::vk
