#include "oas/generate_gpu.hpp"

#include <algorithm>
#include <cstring>

#include "oas_generate_spv.h"
#include "oas_generate_hash_only_spv.h"

namespace oas {
namespace {
constexpr std::uint32_t kLocalSize = 64;          // local_size_x of oas_generate.comp
constexpr std::uint32_t kDimsPerInvocation = 8;   // OAS_DIMS_PER_INVOCATION of oas_generate.comp

struct GenerateParams {  // the push-constant block of oas_generate.comp
    Pattern pattern;
    std::uint32_t x0, y0, width, spp, dims, seed, firstItem, itemCount, firstSample;
};
static_assert(sizeof(GenerateParams) == 100);
}  // namespace

GpuGenerator::GpuGenerator(vk::Context& context, bool hashOnly) : context_(context), hashOnly_(hashOnly) {}

vk::ComputePipeline& GpuGenerator::pipelineFor(const Pattern& pattern)
{
    const auto key = hashOnly_ ? std::make_tuple(0u, 0u, 0u) : oas::specializationKey(pattern);
    auto& slot = pipelines_[key];
    if (!slot) {
        const std::uint32_t* code = hashOnly_ ? oas_generate_hash_only_spv : oas_generate_spv;
        const std::size_t bytes = hashOnly_ ? sizeof(oas_generate_hash_only_spv) : sizeof(oas_generate_spv);
        const vk::ComputePipeline::SpecConstants spec = {
            {0, std::get<0>(key)}, {1, std::get<1>(key)}, {2, std::get<2>(key)}};
        slot = std::make_unique<vk::ComputePipeline>(context_, code, bytes, 2, std::uint32_t(sizeof(GenerateParams)),
                                                     hashOnly_ ? vk::ComputePipeline::SpecConstants{} : spec);
    }
    return *slot;
}

GpuGenerator::~GpuGenerator() = default;

std::uint64_t GpuGenerator::pointsPerDispatch(std::uint32_t dims) const
{
    const auto& limits = context_.limits();
    // Cap a chunk at 64 MiB even where the device allows more: big enough to amortise a submit,
    // small enough that no single dispatch runs long (watchdogs on real GPUs).
    const std::uint64_t maxBytes = std::min<std::uint64_t>(limits.maxStorageBufferRange, 64ull << 20);
    const std::uint64_t byBuffer = maxBytes / (std::uint64_t(dims) * sizeof(float));
    const std::uint64_t groups = (dims + kDimsPerInvocation - 1) / kDimsPerInvocation;
    const std::uint64_t byGroups = std::uint64_t(limits.maxComputeWorkGroupCount[0]) * kLocalSize *
                                   std::min<std::uint32_t>(limits.maxComputeWorkGroupCount[1], 64) / groups;
    std::uint64_t points = std::max<std::uint64_t>(1, std::min(byBuffer, byGroups));
    if (maxPointsPerDispatch_) points = std::min(points, maxPointsPerDispatch_);
    return points;
}

void GpuGenerator::dispatchAll(const Pattern& pattern, const SampleRequest& r, float* out)
{
    const std::uint64_t groups = (r.dims + kDimsPerInvocation - 1) / kDimsPerInvocation;
    const std::uint64_t totalPoints = std::uint64_t(r.width) * r.height * r.spp;
    if (totalPoints * groups > 0xffffffffull)
        throw InvalidArgument("width * height * spp * ceil(dims / 8) = " + std::to_string(totalPoints * groups) +
                              " exceeds 2^32 - 1 work items; split the request");
    const std::uint64_t chunk = std::min(totalPoints, pointsPerDispatch(r.dims));
    const std::uint64_t chunkBytes = std::max<std::uint64_t>(chunk * r.dims * sizeof(float), 4);
    if (!buffer_ || buffer_->size() < chunkBytes) {
        buffer_.reset();
        buffer_ = std::make_unique<vk::Buffer>(context_, chunkBytes);
    }
    if (!sobol_) {
        const auto& directions = sobolDirections();
        sobol_ = std::make_unique<vk::Buffer>(context_, directions.size() * sizeof(std::uint32_t));
        std::memcpy(sobol_->data(), directions.data(), directions.size() * sizeof(std::uint32_t));
    }
    vk::Buffer* buffers[] = {buffer_.get(), sobol_.get()};
    vk::ComputePipeline& pipeline = pipelineFor(pattern);
    const std::uint32_t maxGroupsX = context_.limits().maxComputeWorkGroupCount[0];
    for (std::uint64_t first = 0; first < totalPoints; first += chunk) {
        const std::uint64_t points = std::min(chunk, totalPoints - first);
        const auto items = std::uint32_t(points * groups);
        GenerateParams params{pattern, r.x0, r.y0, r.width, r.spp, r.dims, r.seed,
                              std::uint32_t(first * groups), items, r.firstSample};
        const std::uint32_t workGroups = (items + kLocalSize - 1) / kLocalSize;
        const std::uint32_t gx = std::min(workGroups, maxGroupsX);
        const std::uint32_t gy = (workGroups + gx - 1) / gx;
        context_.dispatch(pipeline, buffers, &params, sizeof(params), gx, gy);
        if (out) std::memcpy(out + first * r.dims, buffer_->data(), std::size_t(points) * r.dims * sizeof(float));
    }
}

void GpuGenerator::generate(const Pattern& pattern, const SampleRequest& request, float* out)
{
    dispatchAll(pattern, request, out);
}

}  // namespace oas
