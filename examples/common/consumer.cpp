// A project that uses oas: it builds patterns on the host (C++ and C APIs), dispatches its own
// shader (consumer.comp, which includes the GLSL library) and checks every value against the C++
// twin bit for bit, and against the CPU's bulk evaluation (OaColumns). Exit 0: all identical; 1:
// a mismatch, a Vulkan error or a validation message; 77: no Vulkan device (unless
// OAS_REQUIRE_GPU=1, which makes that a failure).
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "oas/oa_columns.hpp"
#include "oas/oas_pattern.h"
#include "oas/pattern.hpp"

#include "consumer_spv.h"

namespace {

struct NoDevice : std::runtime_error {
    using std::runtime_error::runtime_error;
};

const char* resultName(VkResult r)
{
    switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    default: return "VkResult";
    }
}

void check(VkResult r, const char* call, int line)
{
    if (r != VK_SUCCESS)
        throw std::runtime_error(std::string(call) + " failed: " + resultName(r) + " (" + std::to_string(r) +
                                 ") at consumer.cpp:" + std::to_string(line));
}
#define VK_CHECK(call) check((call), #call, __LINE__)

// Owns one handle. Members of a struct are destroyed in reverse order, so declaring children after
// their parents destroys them first.
template <class T>
class Owned {
public:
    Owned() = default;
    Owned(T handle, std::function<void(T)> destroy) : handle_(handle), destroy_(std::move(destroy)) {}
    Owned(Owned&& o) noexcept : handle_(std::exchange(o.handle_, T{})), destroy_(std::move(o.destroy_)) {}
    Owned& operator=(Owned&& o) noexcept
    {
        if (this != &o) {
            reset();
            handle_ = std::exchange(o.handle_, T{});
            destroy_ = std::move(o.destroy_);
        }
        return *this;
    }
    ~Owned() { reset(); }
    T get() const { return handle_; }

private:
    void reset()
    {
        if (handle_ != T{} && destroy_) destroy_(handle_);
        handle_ = T{};
    }
    T handle_{};
    std::function<void(T)> destroy_;
};

// Outlives every Vulkan object, so what the layer says while they are destroyed is kept too.
std::vector<std::string> g_validationMessages;

VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                   VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void*)
{
    // Info-level messages are about the layer's environment (a new machine has no validation
    // cache), not about our use of the API; misuse is reported as a warning or an error.
    if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
    std::string msg = std::string(severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error " : "warning ") +
                      (data->pMessageIdName ? data->pMessageIdName : "-") + ": " + (data->pMessage ? data->pMessage : "");
    std::fprintf(stderr, "vulkan %s\n", msg.c_str());
    g_validationMessages.push_back(std::move(msg));
    return VK_FALSE;
}

void selectLavapipeIfUnset()
{
    if (std::getenv("VK_DRIVER_FILES") || std::getenv("VK_ICD_FILENAMES")) return;
    const char* icd = "/usr/share/vulkan/icd.d/lvp_icd.x86_64.json";
    std::error_code ec;
    if (!std::filesystem::exists(icd, ec)) return;
    // Older loaders read only VK_ICD_FILENAMES; newer ones prefer VK_DRIVER_FILES.
    setenv("VK_DRIVER_FILES", icd, 0);
    setenv("VK_ICD_FILENAMES", icd, 0);
}

bool hasLayer(const char* name)
{
    uint32_t n = 0;
    VK_CHECK(vkEnumerateInstanceLayerProperties(&n, nullptr));
    std::vector<VkLayerProperties> layers(n);
    VK_CHECK(vkEnumerateInstanceLayerProperties(&n, layers.data()));
    for (uint32_t i = 0; i < n; ++i)
        if (std::strcmp(layers[i].layerName, name) == 0) return true;
    return false;
}

bool hasExtension(const char* layer, const char* name)
{
    uint32_t n = 0;
    VK_CHECK(vkEnumerateInstanceExtensionProperties(layer, &n, nullptr));
    std::vector<VkExtensionProperties> exts(n);
    VK_CHECK(vkEnumerateInstanceExtensionProperties(layer, &n, exts.data()));
    for (uint32_t i = 0; i < n; ++i)
        if (std::strcmp(exts[i].extensionName, name) == 0) return true;
    return false;
}

/// What the shader's push-constant block holds, in the same order.
struct Params {
    oas::Pattern pattern;
    uint32_t frameSeed, spp, dims, width;
};
static_assert(sizeof(Params) == 80);

constexpr uint32_t kWidth = 8, kHeight = 4;  // a multiple of the shader's 8 x 4 workgroup
constexpr uint32_t kFrameSeed = 0x0a5u;

class Gpu {
public:
    Gpu()
    {
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const bool validation = hasLayer(layer) && (hasExtension(nullptr, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) ||
                                                    hasExtension(layer, VK_EXT_DEBUG_UTILS_EXTENSION_NAME));
        const bool features = validation && hasExtension(layer, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
        if (!validation) std::printf("note: running without %s (Debian: vulkan-validationlayers)\n", layer);
        std::vector<const char*> layers, extensions;
        if (validation) {
            layers.push_back(layer);
            extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
            if (features) extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
        }

        VkDebugUtilsMessengerCreateInfoEXT messenger{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        messenger.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        messenger.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        messenger.pfnUserCallback = onValidationMessage;
        // The layer's shader validation cache lives in ~/.cache; without it validation is the same,
        // and a run neither depends on nor writes the user's home.
        const VkValidationFeatureDisableEXT disabled = VK_VALIDATION_FEATURE_DISABLE_SHADER_VALIDATION_CACHE_EXT;
        VkValidationFeaturesEXT validationFeatures{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
        validationFeatures.disabledValidationFeatureCount = 1;
        validationFeatures.pDisabledValidationFeatures = &disabled;
        validationFeatures.pNext = &messenger;

        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "oas-consumer";
        app.apiVersion = VK_API_VERSION_1_1;  // the shader is SPIR-V 1.3 (--target-env vulkan1.1)
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        // Chained here, the messenger also sees vkCreateInstance and vkDestroyInstance.
        ici.pNext = !validation ? nullptr : features ? static_cast<const void*>(&validationFeatures) : &messenger;
        ici.pApplicationInfo = &app;
        ici.enabledLayerCount = uint32_t(layers.size());
        ici.ppEnabledLayerNames = layers.data();
        ici.enabledExtensionCount = uint32_t(extensions.size());
        ici.ppEnabledExtensionNames = extensions.data();
        VkInstance instance = VK_NULL_HANDLE;
        const VkResult r = vkCreateInstance(&ici, nullptr, &instance);
        if (r == VK_ERROR_INCOMPATIBLE_DRIVER || r == VK_ERROR_INITIALIZATION_FAILED)
            throw NoDevice(std::string("vkCreateInstance: ") + resultName(r));
        VK_CHECK(r);
        instance_ = Owned<VkInstance>(instance, [](VkInstance i) { vkDestroyInstance(i, nullptr); });

        if (validation) {
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            if (!create || !destroy) throw std::runtime_error("VK_EXT_debug_utils entry points missing");
            VkDebugUtilsMessengerEXT m = VK_NULL_HANDLE;
            VK_CHECK(create(instance, &messenger, nullptr, &m));
            messenger_ = Owned<VkDebugUtilsMessengerEXT>(
                m, [instance, destroy](VkDebugUtilsMessengerEXT h) { destroy(instance, h, nullptr); });
        }

        pickDevice();
        const float priority = 1.0f;
        VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        qci.queueFamilyIndex = family_;
        qci.queueCount = 1;
        qci.pQueuePriorities = &priority;
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        dci.queueCreateInfoCount = 1;
        dci.pQueueCreateInfos = &qci;
        VkDevice device = VK_NULL_HANDLE;
        VK_CHECK(vkCreateDevice(physical_, &dci, nullptr, &device));
        device_ = Owned<VkDevice>(device, [](VkDevice d) {
            vkDeviceWaitIdle(d);  // nothing may be in flight when the device goes
            vkDestroyDevice(d, nullptr);
        });
        vkGetDeviceQueue(device, family_, 0, &queue_);
        createPipeline();
    }

    const std::string& deviceName() const { return deviceName_; }

    /// Runs consumer.comp for the pattern and returns [pixel][sample][dim] values.
    std::vector<float> run(const oas::Pattern& pattern, uint32_t spp, uint32_t dims)
    {
        const VkDevice dev = device_.get();
        const VkDeviceSize bytes = VkDeviceSize(kWidth) * kHeight * spp * dims * sizeof(float);
        VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        bci.size = bytes;
        bci.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        VkBuffer b = VK_NULL_HANDLE;
        VK_CHECK(vkCreateBuffer(dev, &bci, nullptr, &b));
        Owned<VkBuffer> buffer(b, [dev](VkBuffer h) { vkDestroyBuffer(dev, h, nullptr); });
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(dev, b, &req);
        VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        mai.allocationSize = req.size;
        mai.memoryTypeIndex = hostVisibleMemoryType(req.memoryTypeBits);
        VkDeviceMemory m = VK_NULL_HANDLE;
        VK_CHECK(vkAllocateMemory(dev, &mai, nullptr, &m));
        // Freed before the buffer is destroyed, which Vulkan allows for a buffer no longer in use.
        Owned<VkDeviceMemory> memory(m, [dev](VkDeviceMemory h) { vkFreeMemory(dev, h, nullptr); });
        VK_CHECK(vkBindBufferMemory(dev, b, m, 0));

        VkDescriptorBufferInfo info{b, 0, VK_WHOLE_SIZE};
        VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        write.dstSet = set_;
        write.dstBinding = 0;
        write.descriptorCount = 1;
        write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        write.pBufferInfo = &info;
        // Safe to rewrite: the previous dispatch that used the set has finished (we wait below).
        vkUpdateDescriptorSets(dev, 1, &write, 0, nullptr);

        const Params params{pattern, kFrameSeed, spp, dims, kWidth};
        VK_CHECK(vkResetCommandBuffer(cmd_, 0));
        VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        VK_CHECK(vkBeginCommandBuffer(cmd_, &begin));
        vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
        vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &set_, 0, nullptr);
        vkCmdPushConstants(cmd_, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof params, &params);
        vkCmdDispatch(cmd_, kWidth / 8, kHeight / 4, 1);  // one invocation per pixel
        // The fence alone does not make shader writes visible to the host.
        VkMemoryBarrier toHost{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        toHost.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
        toHost.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
        vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &toHost, 0,
                             nullptr, 0, nullptr);
        VK_CHECK(vkEndCommandBuffer(cmd_));
        VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        submit.commandBufferCount = 1;
        submit.pCommandBuffers = &cmd_;
        VkFence fence = fence_.get();
        VK_CHECK(vkQueueSubmit(queue_, 1, &submit, fence));
        VK_CHECK(vkWaitForFences(dev, 1, &fence, VK_TRUE, 60'000'000'000ull));
        VK_CHECK(vkResetFences(dev, 1, &fence));

        std::vector<float> out(bytes / sizeof(float));
        void* mapped = nullptr;
        VK_CHECK(vkMapMemory(dev, m, 0, bytes, 0, &mapped));
        std::memcpy(out.data(), mapped, bytes);
        vkUnmapMemory(dev, m);
        return out;
    }

private:
    void pickDevice()
    {
        uint32_t n = 0;
        VK_CHECK(vkEnumeratePhysicalDevices(instance_.get(), &n, nullptr));
        std::vector<VkPhysicalDevice> devices(n);
        VK_CHECK(vkEnumeratePhysicalDevices(instance_.get(), &n, devices.data()));
        for (VkPhysicalDevice pd : devices) {
            VkPhysicalDeviceProperties props;
            vkGetPhysicalDeviceProperties(pd, &props);
            if (props.apiVersion < VK_API_VERSION_1_1) continue;
            uint32_t nq = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, nullptr);
            std::vector<VkQueueFamilyProperties> families(nq);
            vkGetPhysicalDeviceQueueFamilyProperties(pd, &nq, families.data());
            for (uint32_t f = 0; f < nq; ++f) {
                if (!(families[f].queueFlags & VK_QUEUE_COMPUTE_BIT)) continue;
                physical_ = pd;
                family_ = f;
                deviceName_ = props.deviceName;
                vkGetPhysicalDeviceMemoryProperties(pd, &memory_);
                return;
            }
        }
        throw NoDevice(n == 0 ? "no Vulkan physical device" : "no Vulkan 1.1 device with a compute queue");
    }

    uint32_t hostVisibleMemoryType(uint32_t allowed) const
    {
        const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
            if ((allowed & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & want) == want) return i;
        throw std::runtime_error("no host-visible, coherent memory type for the output buffer");
    }

    void createPipeline()
    {
        const VkDevice dev = device_.get();
        VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        smi.codeSize = sizeof consumer_spv;
        smi.pCode = consumer_spv;
        VkShaderModule sm = VK_NULL_HANDLE;
        VK_CHECK(vkCreateShaderModule(dev, &smi, nullptr, &sm));
        Owned<VkShaderModule> module(sm, [dev](VkShaderModule h) { vkDestroyShaderModule(dev, h, nullptr); });

        VkDescriptorSetLayoutBinding binding{};
        binding.binding = 0;
        binding.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        binding.descriptorCount = 1;
        binding.stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
        VkDescriptorSetLayoutCreateInfo dsli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        dsli.bindingCount = 1;
        dsli.pBindings = &binding;
        VkDescriptorSetLayout dsl = VK_NULL_HANDLE;
        VK_CHECK(vkCreateDescriptorSetLayout(dev, &dsli, nullptr, &dsl));
        setLayout_ = Owned<VkDescriptorSetLayout>(dsl, [dev](VkDescriptorSetLayout h) {
            vkDestroyDescriptorSetLayout(dev, h, nullptr);
        });

        VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Params)};
        VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pli.setLayoutCount = 1;
        pli.pSetLayouts = &dsl;
        pli.pushConstantRangeCount = 1;
        pli.pPushConstantRanges = &range;
        VkPipelineLayout pl = VK_NULL_HANDLE;
        VK_CHECK(vkCreatePipelineLayout(dev, &pli, nullptr, &pl));
        layout_ = Owned<VkPipelineLayout>(pl, [dev](VkPipelineLayout h) { vkDestroyPipelineLayout(dev, h, nullptr); });

        VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        cpi.stage.module = sm;
        cpi.stage.pName = "main";
        cpi.layout = pl;
        VkPipeline p = VK_NULL_HANDLE;
        VK_CHECK(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &cpi, nullptr, &p));
        pipeline_ = Owned<VkPipeline>(p, [dev](VkPipeline h) { vkDestroyPipeline(dev, h, nullptr); });

        VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1};
        VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        dpi.maxSets = 1;
        dpi.poolSizeCount = 1;
        dpi.pPoolSizes = &size;
        VkDescriptorPool pool = VK_NULL_HANDLE;
        VK_CHECK(vkCreateDescriptorPool(dev, &dpi, nullptr, &pool));
        descriptorPool_ = Owned<VkDescriptorPool>(pool, [dev](VkDescriptorPool h) {
            vkDestroyDescriptorPool(dev, h, nullptr);  // frees set_ too
        });
        VkDescriptorSetAllocateInfo dai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        dai.descriptorPool = pool;
        dai.descriptorSetCount = 1;
        dai.pSetLayouts = &dsl;
        VK_CHECK(vkAllocateDescriptorSets(dev, &dai, &set_));

        VkCommandPoolCreateInfo cpci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        cpci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        cpci.queueFamilyIndex = family_;
        VkCommandPool cp = VK_NULL_HANDLE;
        VK_CHECK(vkCreateCommandPool(dev, &cpci, nullptr, &cp));
        commandPool_ = Owned<VkCommandPool>(cp, [dev](VkCommandPool h) { vkDestroyCommandPool(dev, h, nullptr); });
        VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        cai.commandPool = cp;
        cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        cai.commandBufferCount = 1;
        VK_CHECK(vkAllocateCommandBuffers(dev, &cai, &cmd_));

        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence f = VK_NULL_HANDLE;
        VK_CHECK(vkCreateFence(dev, &fci, nullptr, &f));
        fence_ = Owned<VkFence>(f, [dev](VkFence h) { vkDestroyFence(dev, h, nullptr); });
    }

    Owned<VkInstance> instance_;
    Owned<VkDebugUtilsMessengerEXT> messenger_;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties memory_{};
    uint32_t family_ = 0;
    std::string deviceName_;
    Owned<VkDevice> device_;
    VkQueue queue_ = VK_NULL_HANDLE;
    Owned<VkDescriptorSetLayout> setLayout_;
    Owned<VkPipelineLayout> layout_;
    Owned<VkPipeline> pipeline_;
    Owned<VkDescriptorPool> descriptorPool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    Owned<VkCommandPool> commandPool_;  // frees cmd_ too
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    Owned<VkFence> fence_;
};

struct Case {
    oas::PatternRequest request;
    uint32_t cOffset;  // the same offset as the C API's constant
};

/// Round-trip digits and the bits, since values that differ only in their last bit look alike.
std::string floatText(float f)
{
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    char text[48];
    std::snprintf(text, sizeof text, "%.9g (0x%08x)", f, bits);
    return text;
}

/// The C API must give the same 16 words as the C++ one; returns an error text, empty if equal.
std::string checkCApi(const Case& c, const oas::Pattern& expected)
{
    uint32_t construction = 0;
    if (oas_construction_from_name(c.request.sampler.c_str(), &construction) != 0)
        return "oas_construction_from_name(\"" + c.request.sampler + "\") failed";
    OasPattern p;
    char why[256] = "";
    if (oas_make_pattern(construction, c.request.spp, c.request.strength, c.cOffset, &p, why, sizeof why) != 0)
        return std::string("oas_make_pattern failed: ") + why;
    static_assert(sizeof(OasPattern) == sizeof(oas::Pattern));
    uint32_t got[16], want[16];
    std::memcpy(got, &p, sizeof got);
    std::memcpy(want, &expected, sizeof want);
    for (int i = 0; i < 16; ++i)
        if (got[i] != want[i])
            return std::string("oas_make_pattern gives ") + oas_pattern_field_name(std::size_t(i)) + " = " + std::to_string(got[i]) +
                   ", oas::makePattern " + std::to_string(want[i]);
    return {};
}

int runAll()
{
    Gpu gpu;
    std::printf("device: %s\n", gpu.deviceName().c_str());
    // Every OA construction, over prime, binary and odd extension fields, and two baselines; with
    // dims past one block where that is cheap. Strengths are given where the C API (which takes no
    // dims) needs them to mean the same pattern. One invocation evaluates all of its pixel's
    // values: up to 1024 x 8 = 8192 here.
    const Case cases[] = {
        {{.sampler = "bose", .spp = 49, .dims = 12, .offset = "cmj"}, OAS_OFFSET_CMJ},
        {{.sampler = "bose", .spp = 1024, .dims = 8, .offset = "cmj"}, OAS_OFFSET_CMJ},  // GF(2^5)
        {{.sampler = "bose", .spp = 625, .dims = 8, .offset = "mj"}, OAS_OFFSET_MJ},     // GF(5^2)
        {{.sampler = "bose", .spp = 81, .dims = 6, .offset = "mj"}, OAS_OFFSET_MJ},  // GF(3^2)
        {{.sampler = "bose-bush", .spp = 32, .dims = 10, .offset = "cmj"}, OAS_OFFSET_CMJ},  // GF(2^3)
        {{.sampler = "addelman-kempthorne", .spp = 18, .dims = 9, .offset = "cmj"}, OAS_OFFSET_CMJ},
        {{.sampler = "bush", .spp = 27, .dims = 6, .strength = 3, .offset = "j"}, OAS_OFFSET_J},
        {{.sampler = "cmjnd", .spp = 27, .dims = 3, .strength = 3, .offset = "centered"}, OAS_OFFSET_CENTERED},
        {{.sampler = "random", .spp = 16, .dims = 4}, OAS_OFFSET_CMJ},
        {{.sampler = "cmj2d", .spp = 16, .dims = 4}, OAS_OFFSET_CMJ},
    };
    int failures = 0;
    for (const Case& c : cases) {
        const oas::Pattern pattern = oas::makePattern(c.request);
        const std::string name = oas::describe(pattern);
        if (const std::string err = checkCApi(c, pattern); !err.empty()) {
            std::printf("%s: FAILED: %s\n", name.c_str(), err.c_str());
            ++failures;
        }
        const uint32_t spp = c.request.spp, dims = c.request.dims;
        const std::vector<float> gpuValues = gpu.run(pattern, spp, dims);
        size_t differ = 0, i = 0;
        std::string first;
        for (uint32_t y = 0; y < kHeight; ++y)
            for (uint32_t x = 0; x < kWidth; ++x) {
                const uint32_t seed = oas::pixelSeed(x, y, kFrameSeed);
                for (uint32_t s = 0; s < spp; ++s)
                    for (uint32_t d = 0; d < dims; ++d, ++i) {
                        const float cpu = oas::sample(pattern, seed, s, d);
                        // Bits, not values: the contract is bit-identical output.
                        if (std::memcmp(&cpu, &gpuValues[i], sizeof cpu) == 0) continue;
                        if (differ++ == 0)
                            first = "pixel (" + std::to_string(x) + "," + std::to_string(y) + ") sample " +
                                    std::to_string(s) + " dim " + std::to_string(d) + ": gpu " + floatText(gpuValues[i]) +
                                    " cpu " + floatText(cpu);
                    }
            }
        // The CPU's bulk form (oas/oa_columns.hpp): pixel (0,0), all samples, each dimension at once.
        if (pattern.construction < OAS_RANDOM) {
            const oas::OaColumns columns(pattern);
            const uint32_t seed = oas::pixelSeed(0, 0, kFrameSeed), count = std::min(spp, pattern.N);
            std::vector<uint32_t> rows(count);
            std::vector<float> values(count);
            for (uint32_t d = 0; d < dims; ++d) {
                columns.rows(seed, d / pattern.blockDims, 0, count, rows.data());
                columns.values(seed, d, 0, count, rows.data(), values.data());
                for (uint32_t s = 0; s < count; ++s)
                    if (std::memcmp(&values[s], &gpuValues[size_t(s) * dims + d], sizeof(float)) != 0 && differ++ == 0)
                        first = "OaColumns, pixel (0,0) sample " + std::to_string(s) + " dim " + std::to_string(d);
            }
        }
        if (differ) {
            std::printf("%s: FAILED: %zu of %zu values differ, first at %s\n", name.c_str(), differ, i, first.c_str());
            ++failures;
        } else {
            std::printf("%s: %zu values identical\n", name.c_str(), i);
        }
    }
    return failures;
}

}  // namespace

int main()
{
    // An empty or relative XDG_CACHE_HOME is to be ignored (XDG spec), but Mesa takes it literally
    // and complains; follow the spec before the driver reads it.
    if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache && cache[0] != '/') unsetenv("XDG_CACHE_HOME");
    selectLavapipeIfUnset();
    std::setvbuf(stdout, nullptr, _IOLBF, 0);  // keeps stdout and stderr in order in one pipe (ctest)
    int failures = 0;
    try {
        failures = runAll();  // every Vulkan object is gone when it returns, so all messages are in
    } catch (const NoDevice& e) {
        const char* require = std::getenv("OAS_REQUIRE_GPU");
        if (require && std::strcmp(require, "1") == 0) {
            std::fprintf(stderr, "FAILED: no Vulkan device and OAS_REQUIRE_GPU=1: %s\n", e.what());
            return 1;
        }
        std::printf("SKIPPED: no Vulkan device (%s)\n", e.what());
        return 77;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "FAILED: %s\n", e.what());
        return 1;
    }
    for (const std::string& m : g_validationMessages) std::fprintf(stderr, "FAILED: Vulkan said %s\n", m.c_str());
    if (!g_validationMessages.empty() || failures) return 1;
    std::printf("all patterns identical on GPU and CPU\n");
    return 0;
}
