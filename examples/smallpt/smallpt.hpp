#pragma once
// examples/smallpt: a small Vulkan compute path tracer (smallpt.comp) that embeds oas the way
// docs/EMBEDDING.md says, with its own hash kept as the baseline. Used by oas-smallpt (render,
// benchmark) and tests/smallpt_test.cpp.
#include <cstdint>
#include <optional>
#include <vector>

#include "oas/oas_pattern.h"
#include "vk/context.hpp"

namespace smallpt {

/// Where the tracer's random numbers come from (smallpt.comp's samplerMode).
enum class Sampler : std::uint32_t {
    OwnHash = 0,      ///< the renderer's own integer hash
    OasInline = 1,    ///< oas_sample where each number is used
    OasPrefetch = 2,  ///< oas_prefetch in a kernel dispatched before each tracer dispatch
};
const char* samplerName(Sampler s);

/// Path vertices, the camera's included: the camera and up to 8 scattering vertices.
constexpr std::uint32_t kPathVertices = 9;

/// The number of dimensions the first `vertices` vertices of a path use with `pattern` (all of a
/// path's by default): smallpt.comp's layout (the camera's 2D pixel sample, then per scattering
/// vertex a 2D light sample, a 2D bounce, a lobe choice and a roulette number, every 2D sample on
/// oas_pair_dimension), replayed through the C API. Throws std::invalid_argument for vertices
/// past kPathVertices.
std::uint32_t pathDimensions(const OasPattern& pattern, std::uint32_t vertices = kPathVertices);

/// The most OA blocks one of a path's draws spans (the camera's pixel sample, a vertex's numbers)
/// in smallpt.comp's layout with `pattern` (1 for a baseline). At most 2, the renderer uses the
/// tracer built with OAS_STATIC_DRAW_BLOCKS 2.
std::uint32_t drawBlocks(const OasPattern& pattern);

/// The prefetch kernel's (prefetch.comp) group width for `dims` dimensions of `pattern`: at most 8,
/// an OA block's columns (or, where dims is less, the dims) cut into equal groups as near as can be.
std::uint32_t prefetchWidth(const OasPattern& pattern, std::uint32_t dims);
/// Invocations per pixel of the prefetch kernel: one per group of prefetchWidth consecutive
/// dimensions (fewer in a block's last group) of one OA block, or of the run for a baseline.
std::uint32_t prefetchGroups(const OasPattern& pattern, std::uint32_t dims);

/// One renderer: the pipelines for one pattern kind (specialized with oas_specialization) and
/// one sampler, and the buffers for one image size. With an oas sampler, the numbers of a path's
/// first `oasVertices` vertices (the camera is vertex 0) come from oas and the rest from the own
/// hash: 0 is the own hash throughout, kPathVertices oas throughout. Throws std::invalid_argument
/// for a size or a dispatch too large for the device's texel buffers, naming the limit, and for
/// oasVertices past kPathVertices.
class Renderer {
public:
    Renderer(oas::vk::Context& ctx, const OasPattern& pattern, Sampler sampler, std::uint32_t width, std::uint32_t height,
             std::uint32_t samplesPerDispatch = 8, std::uint32_t oasVertices = kPathVertices);
    /// Samples [0, spp) of every pixel with `frameSeed`; the mean radiance, RGB per pixel, rows top down.
    std::vector<float> render(std::uint32_t frameSeed, std::uint32_t spp);
    /// The prefetch kernel's values for samples [firstSample, firstSample + samplesPerDispatch):
    /// value (pixel, k, dim) at (pixel * samplesPerDispatch + k) * dimensions() + dim.
    std::vector<float> prefetch(std::uint32_t frameSeed, std::uint32_t firstSample);
    /// The dimensions drawn from oas (the first oasVertices vertices'), and the prefetch's stride.
    std::uint32_t dimensions() const { return dims_; }

private:
    struct Params;
    void prefetchDispatch(const Params& params);
    oas::vk::Context& ctx_;
    OasPattern pattern_;
    Sampler sampler_;
    std::uint32_t width_, height_, samplesPerDispatch_, dims_;
    oas::vk::Buffer sums_, values_;
    std::optional<oas::vk::ComputePipeline> tracer_, prefetcher_;  // made on first use
};

}  // namespace smallpt
