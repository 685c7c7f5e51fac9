// ComputePipeline: a compute shader's pipeline, its layouts and its descriptor bindings
// (host/vk/context.hpp).
#include "vk/context.hpp"

#include <fmt/format.h>

#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

namespace oas::vk {

VkDescriptorType descriptorType(BindingKind kind)
{
    switch (kind) {
    case BindingKind::Uint4TexelBuffer:
        return VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    case BindingKind::UintStorageTexelBuffer:
        return VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
    case BindingKind::StorageBuffer:
        break;
    }
    return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
}

ComputePipeline::ComputePipeline(Context& ctx, const uint32_t* code, size_t byteSize, uint32_t bindingCount,
                                 uint32_t pushConstantBytes, const SpecConstants& specConstants,
                                 std::vector<BindingKind> bindingKinds)
    : ctx_(&ctx), bindingCount_(bindingCount), pushBytes_(pushConstantBytes), bindingKinds_(std::move(bindingKinds))
{
    if (bindingKinds_.empty()) bindingKinds_.assign(bindingCount, BindingKind::StorageBuffer);
    if (bindingKinds_.size() != bindingCount)
        throw std::invalid_argument(
            fmt::format("ComputePipeline: {} binding kinds for {} bindings", bindingKinds_.size(), bindingCount));
    if (!code || byteSize == 0 || byteSize % 4 != 0)
        throw std::invalid_argument("ComputePipeline: SPIR-V must be a non-empty multiple of 4 bytes");
    if (pushConstantBytes % 4 != 0 || pushConstantBytes > ctx.limits().maxPushConstantsSize)
        throw std::invalid_argument(fmt::format("ComputePipeline: {} push-constant bytes (must be a multiple of 4, "
                                                "at most {})",
                                                pushConstantBytes, ctx.limits().maxPushConstantsSize));
    const VkDevice dev = ctx.device();

    VkShaderModuleCreateInfo smci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    smci.codeSize = byteSize;
    smci.pCode = code;
    VkShaderModule sm = VK_NULL_HANDLE;
    OAS_VK_CHECK(vkCreateShaderModule(dev, &smci, nullptr, &sm));
    // Only needed until the pipeline exists.
    detail::Owned<VkShaderModule> module(sm, [dev](VkShaderModule m) { vkDestroyShaderModule(dev, m, nullptr); });

    std::vector<VkDescriptorSetLayoutBinding> bindings(bindingCount);
    std::map<VkDescriptorType, uint32_t> descriptorsOfType;  // the pool's sizes
    for (uint32_t i = 0; i < bindingCount; ++i) {
        const VkDescriptorType type = descriptorType(bindingKinds_[i]);
        ++descriptorsOfType[type];
        bindings[i] = {i, type, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    }
    VkDescriptorSetLayoutCreateInfo dlci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    dlci.bindingCount = bindingCount;
    dlci.pBindings = bindings.data();
    VkDescriptorSetLayout dsl = VK_NULL_HANDLE;
    OAS_VK_CHECK(vkCreateDescriptorSetLayout(dev, &dlci, nullptr, &dsl));
    setLayout_ = detail::Owned<VkDescriptorSetLayout>(
        dsl, [dev](VkDescriptorSetLayout l) { vkDestroyDescriptorSetLayout(dev, l, nullptr); });

    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, pushConstantBytes};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.setLayoutCount = bindingCount > 0 ? 1 : 0;
    plci.pSetLayouts = &dsl;
    plci.pushConstantRangeCount = pushConstantBytes > 0 ? 1 : 0;
    plci.pPushConstantRanges = &range;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    OAS_VK_CHECK(vkCreatePipelineLayout(dev, &plci, nullptr, &pl));
    layout_ = detail::Owned<VkPipelineLayout>(pl, [dev](VkPipelineLayout l) { vkDestroyPipelineLayout(dev, l, nullptr); });

    std::vector<VkSpecializationMapEntry> entries;
    std::vector<uint32_t> values;
    for (const auto& [id, value] : specConstants) {
        entries.push_back({id, static_cast<uint32_t>(values.size() * sizeof(uint32_t)), sizeof(uint32_t)});
        values.push_back(value);
    }
    VkSpecializationInfo spec{static_cast<uint32_t>(entries.size()), entries.data(), values.size() * sizeof(uint32_t),
                              values.data()};
    VkComputePipelineCreateInfo cpci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpci.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    cpci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpci.stage.module = sm;
    cpci.stage.pName = "main";
    cpci.stage.pSpecializationInfo = entries.empty() ? nullptr : &spec;
    cpci.layout = pl;
    VkPipeline p = VK_NULL_HANDLE;
    OAS_VK_CHECK(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &cpci, nullptr, &p));
    pipeline_ = detail::Owned<VkPipeline>(p, [dev](VkPipeline h) { vkDestroyPipeline(dev, h, nullptr); });

    if (bindingCount > 0) {
        std::vector<VkDescriptorPoolSize> sizes;
        for (const auto& [type, count] : descriptorsOfType) sizes.push_back({type, count});
        VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        dpci.maxSets = 1;
        dpci.poolSizeCount = static_cast<uint32_t>(sizes.size());
        dpci.pPoolSizes = sizes.data();
        VkDescriptorPool pool = VK_NULL_HANDLE;
        OAS_VK_CHECK(vkCreateDescriptorPool(dev, &dpci, nullptr, &pool));
        pool_ = detail::Owned<VkDescriptorPool>(pool, [dev](VkDescriptorPool h) { vkDestroyDescriptorPool(dev, h, nullptr); });
    }
}

ComputePipeline::~ComputePipeline()
{
    if (ctx_->broken()) pool_.leak(), pipeline_.leak(), layout_.leak(), setLayout_.leak();
}

}  // namespace oas::vk
