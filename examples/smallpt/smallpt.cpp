// examples/smallpt: the host side of the example tracer (smallpt.hpp).
#include "smallpt.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

#include "smallpt_prefetch_spv.h"
#include "smallpt_spv.h"
#include "smallpt_two_blocks_spv.h"

namespace smallpt {

/// smallpt.comp's and prefetch.comp's push constants.
struct Renderer::Params {
    OasPattern pattern;
    std::uint32_t width, height, frameSeed, firstSample, samples, dims;
};

namespace {
constexpr std::uint32_t kDrawMax = 8;   // the GLSL's OAS_DRAW_MAX: dimensions one oas_draw returns
constexpr std::uint32_t kGroupSide = 8, kPrefetchGroup = 64;

/// The specialization constants 0-4 of both shaders (the include's five OAS_STATIC_* values),
/// filled by the C API's oas_specialization, and constant 5: the tracer's sampler mode, the
/// prefetch kernel's group width.
oas::vk::ComputePipeline::SpecConstants specialization(const OasPattern& pattern, std::uint32_t constant5)
{
    OasSpecialization s;
    oas_specialization(&pattern, &s);
    return {{0, s.construction}, {1, s.offset}, {2, s.fieldKind}, {3, s.fieldDegree}, {4, s.smallN}, {5, constant5}};
}
}  // namespace

const char* samplerName(Sampler s)
{
    switch (s) {
    case Sampler::OwnHash: return "own hash";
    case Sampler::OasInline: return "oas inline";
    case Sampler::OasPrefetch: return "oas prefetch";
    }
    return "?";
}

namespace {
/// One draw of smallpt.comp: dimensions [first, end).
struct Draw {
    std::uint32_t first, end;
};

/// smallpt.comp's layout replayed through the C API, one draw per path vertex: the camera's pixel
/// sample, then per scattering vertex a 2D light sample, a 2D bounce, a lobe choice and a
/// roulette number, every 2D sample on oas_pair_dimension.
std::vector<Draw> pathDraws(const OasPattern& pattern)
{
    const std::uint32_t pixel = oas_pair_dimension(&pattern, 0);
    std::vector<Draw> draws = {{pixel, pixel + 2}};
    for (std::uint32_t vertex = 1; vertex < kPathVertices; ++vertex) {
        const std::uint32_t first = draws.back().end;
        std::uint32_t cursor = oas_pair_dimension(&pattern, first) + 2;  // light
        cursor = oas_pair_dimension(&pattern, cursor) + 2;              // bounce
        draws.push_back({first, cursor + 2});                           // lobe, roulette
    }
    return draws;
}
}  // namespace

std::uint32_t pathDimensions(const OasPattern& pattern, std::uint32_t vertices)
{
    if (vertices > kPathVertices)
        throw std::invalid_argument("smallpt: a path has " + std::to_string(kPathVertices) + " vertices (the camera and " +
                                    std::to_string(kPathVertices - 1) + " bounces, smallpt.comp's MAX_DEPTH), not " +
                                    std::to_string(vertices));
    if (vertices == 0) return 0;
    const std::vector<Draw> draws = pathDraws(pattern);
    for (std::uint32_t v = 0; v < vertices; ++v)
        if (draws[v].end - draws[v].first > kDrawMax)
            throw std::invalid_argument(std::string("smallpt: a path vertex of ") + oas_construction_name(pattern.construction) +
                                        " with " + std::to_string(pattern.N) + " samples spans " +
                                        std::to_string(draws[v].end - draws[v].first) + " dimensions, more than one oas_draw's " +
                                        std::to_string(kDrawMax));
    return draws[vertices - 1].end;
}

Renderer::Renderer(oas::vk::Context& ctx, const OasPattern& pattern, Sampler sampler, std::uint32_t width, std::uint32_t height,
                   std::uint32_t samplesPerDispatch, std::uint32_t oasVertices)
    : ctx_(ctx), pattern_(pattern), sampler_(sampler), width_(width), height_(height), samplesPerDispatch_(samplesPerDispatch),
      dims_(pathDimensions(pattern, oasVertices)), sums_(ctx, VkDeviceSize(width) * height * 16),
      values_(ctx, sampler == Sampler::OasPrefetch ? VkDeviceSize(width) * height * samplesPerDispatch * dims_ * 4 + 16 : 16)
{
    if (width == 0 || height == 0 || samplesPerDispatch == 0)
        throw std::invalid_argument("smallpt: width, height and samples per dispatch must be at least 1");
    const std::uint64_t texels = values_.size() / 4, limit = ctx.limits().maxTexelBufferElements;
    if (texels > limit)
        throw std::invalid_argument("smallpt: " + std::to_string(width) + " x " + std::to_string(height) + " pixels x " +
                                    std::to_string(samplesPerDispatch) + " samples x " + std::to_string(dims_) +
                                    " dims of prefetched values exceed the device's maxTexelBufferElements (" +
                                    std::to_string(limit) + "): fewer samples per dispatch or a smaller image");
}

std::uint32_t drawBlocks(const OasPattern& pattern)
{
    if (pattern.construction >= OAS_RANDOM) return 1;  // baselines have no blocks
    std::uint32_t most = 1;
    for (const Draw& d : pathDraws(pattern)) most = std::max(most, (d.end - 1) / pattern.blockDims - d.first / pattern.blockDims + 1);
    return most;
}

std::uint32_t prefetchWidth(const OasPattern& pattern, std::uint32_t dims)
{
    constexpr std::uint32_t kMost = 8;
    const std::uint32_t span = pattern.construction >= OAS_RANDOM ? kMost : pattern.blockDims;
    const std::uint32_t widest = std::max(1u, std::min(span, dims));
    const std::uint32_t parts = (widest + kMost - 1) / kMost;
    return (widest + parts - 1) / parts;
}

std::uint32_t prefetchGroups(const OasPattern& pattern, std::uint32_t dims)
{
    const std::uint32_t width = prefetchWidth(pattern, dims);
    const std::uint32_t span = pattern.construction >= OAS_RANDOM ? width : pattern.blockDims;
    const std::uint32_t perBlock = (span + width - 1) / width, fullBlocks = dims / span, rest = dims - fullBlocks * span;
    return fullBlocks * perBlock + (rest + width - 1) / width;
}

void Renderer::prefetchDispatch(const Params& params)
{
    if (!prefetcher_)
        prefetcher_.emplace(ctx_, smallpt_prefetch_spv, sizeof smallpt_prefetch_spv, 1, sizeof(Params),
                            specialization(pattern_, prefetchWidth(pattern_, dims_)),
                            std::vector{oas::vk::BindingKind::UintStorageTexelBuffer});
    oas::vk::Buffer* bindings[] = {&values_};
    const std::uint64_t items = std::uint64_t(width_) * height_ * prefetchGroups(pattern_, dims_);
    ctx_.dispatch(*prefetcher_, bindings, &params, sizeof params, std::uint32_t((items + kPrefetchGroup - 1) / kPrefetchGroup));
}

std::vector<float> Renderer::render(std::uint32_t frameSeed, std::uint32_t spp)
{
    if (!tracer_) {
        // The two-block build where every draw of the layout fits it: fewer rows a draw.
        const bool twoBlocks = drawBlocks(pattern_) <= 2;
        const std::uint32_t* code = twoBlocks ? smallpt_two_blocks_spv : smallpt_spv;
        const std::size_t bytes = twoBlocks ? sizeof smallpt_two_blocks_spv : sizeof smallpt_spv;
        tracer_.emplace(ctx_, code, bytes, 2, sizeof(Params), specialization(pattern_, std::uint32_t(sampler_)),
                        std::vector{oas::vk::BindingKind::StorageBuffer, oas::vk::BindingKind::Uint4TexelBuffer});
    }
    std::memset(sums_.data(), 0, sums_.size());
    oas::vk::Buffer* bindings[] = {&sums_, &values_};
    for (std::uint32_t first = 0; first < spp; first += samplesPerDispatch_) {
        const Params params{pattern_, width_, height_, frameSeed, first, std::min(samplesPerDispatch_, spp - first), dims_};
        if (sampler_ == Sampler::OasPrefetch && dims_ > 0) prefetchDispatch(params);
        ctx_.dispatch(*tracer_, bindings, &params, sizeof params, (width_ + kGroupSide - 1) / kGroupSide,
                      (height_ + kGroupSide - 1) / kGroupSide);
    }
    std::vector<float> rgb(std::size_t(width_) * height_ * 3);
    const float* sums = static_cast<const float*>(sums_.data());
    for (std::size_t p = 0; p < std::size_t(width_) * height_; ++p)
        for (int c = 0; c < 3; ++c) rgb[p * 3 + c] = sums[p * 4 + c] / float(spp);
    return rgb;
}

std::vector<float> Renderer::prefetch(std::uint32_t frameSeed, std::uint32_t firstSample)
{
    if (sampler_ != Sampler::OasPrefetch) throw std::logic_error("smallpt: prefetch() needs a renderer made with Sampler::OasPrefetch");
    const Params params{pattern_, width_, height_, frameSeed, firstSample, samplesPerDispatch_, dims_};
    prefetchDispatch(params);
    std::vector<float> out(std::size_t(width_) * height_ * samplesPerDispatch_ * dims_);
    std::memcpy(out.data(), values_.data(), out.size() * sizeof(float));
    return out;
}

}  // namespace smallpt
