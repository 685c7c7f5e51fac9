// The wavefront path tracer's host side: see render/wavefront_gpu.hpp and shaders/pt_wavefront.comp.
#include "render/wavefront_gpu.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "pt_wavefront_spv.h"

namespace oas::render {
namespace {

struct WavefrontParams {  // the push-constant block of pt_wavefront.comp
    Pattern pattern;
    std::uint32_t tileX, tileY, tileWidth, tileHeight, firstSample, sampleCount, seed;
    std::uint32_t pathCount, vertex;
};
static_assert(sizeof(WavefrontParams) == 100);

constexpr std::uint32_t kLocalSize = 64;     // local_size_x of pt_wavefront.comp
constexpr std::uint64_t kPathWords = 20;     // PT_PATH_WORDS: PtPath's fields and the slot
constexpr std::uint64_t kResultWords = 4;    // PT_RESULT_WORDS
constexpr std::uint32_t kWavefrontBindings = pt::PT_BINDING_COUNTERS + 1;
static_assert(kWavefrontBindings == kBindingCount + 4, "pt_wavefront.comp's bindings follow PT_BINDINGS'");

std::unique_ptr<vk::ComputePipeline> makeStage(vk::Context& context, pt::PtSpecialization s, std::uint32_t stage)
{
    s.PT_WAVEFRONT_STAGE = stage;
    std::vector<vk::BindingKind> kinds = sceneBindingKinds(kWavefrontBindings);
    kinds[pt::PT_BINDING_PATHS_IN] = vk::BindingKind::Uint4TexelBuffer;
    kinds[pt::PT_BINDING_PATHS_OUT] = vk::BindingKind::UintStorageTexelBuffer;
    kinds[pt::PT_BINDING_RESULTS] = vk::BindingKind::UintStorageTexelBuffer;
    kinds[pt::PT_BINDING_COUNTERS] = vk::BindingKind::StorageBuffer;
    return std::make_unique<vk::ComputePipeline>(context, pt_wavefront_spv, sizeof(pt_wavefront_spv), kWavefrontBindings,
                                                 std::uint32_t(sizeof(WavefrontParams)), specConstants(s), kinds);
}

}  // namespace

GpuWavefront::GpuWavefront(vk::Context& context, const pt::PtSpecialization& s, std::uint64_t maxPaths)
    : context_(context), maxDepth_(s.PT_MAX_DEPTH)
{
    // A queue's records are a storage texel buffer of uint: kPathWords texels a path.
    const std::uint64_t byTexels = context.limits().maxTexelBufferElements / kPathWords;
    capacity_ = std::min<std::uint64_t>(maxPaths ? maxPaths : kWavefrontMaxPaths, byTexels);
    camera_ = makeStage(context, s, 0);
    step_ = makeStage(context, s, 1);
    resolve_ = makeStage(context, s, 2);
    counters_ = std::make_unique<vk::Buffer>(context, 4 * sizeof(std::uint32_t));
}

GpuWavefront::~GpuWavefront() = default;

void GpuWavefront::reserve(std::uint64_t paths)
{
    if (results_ && results_->size() >= paths * kResultWords * sizeof(std::uint32_t)) return;
    // Grown to the largest batch seen (a small image never holds a whole tile's queues).
    results_.reset();
    queues_[0].reset();
    queues_[1].reset();
    for (auto& queue : queues_) queue = std::make_unique<vk::Buffer>(context_, paths * kPathWords * sizeof(std::uint32_t));
    results_ = std::make_unique<vk::Buffer>(context_, paths * kResultWords * sizeof(std::uint32_t));
}

void GpuWavefront::trace(const Pattern& pattern, const SampleBatch& b, const std::vector<vk::Buffer*>& sceneBindings)
{
    const std::uint64_t paths = std::uint64_t(b.width) * b.height * b.count;
    if (paths == 0) return;
    if (paths > capacity_)
        throw std::invalid_argument(fmt::format("wavefront: a batch of {}x{} pixels x {} samples is {} paths, more than the "
                                                "queues hold ({} paths): split it",
                                                b.width, b.height, b.count, paths, capacity_));
    reserve(paths);
    std::vector<vk::Buffer*> bindings = sceneBindings;
    bindings.resize(kWavefrontBindings);
    bindings[pt::PT_BINDING_RESULTS] = results_.get();
    bindings[pt::PT_BINDING_COUNTERS] = counters_.get();
    auto* counters = static_cast<std::uint32_t*>(counters_->data());
    counters[0] = counters[1] = 0;  // host writes before a submit are visible to it
    WavefrontParams params{pattern, b.x0, b.y0, b.width, b.height, b.firstSample, b.count, b.seed, 0, 0};
    const auto dispatch = [&](vk::ComputePipeline& pipeline, std::uint64_t items, vk::Buffer* in, vk::Buffer* out) {
        bindings[pt::PT_BINDING_PATHS_IN] = in;
        bindings[pt::PT_BINDING_PATHS_OUT] = out;
        const std::uint64_t groups = (items + kLocalSize - 1) / kLocalSize;
        const std::uint32_t gx = std::uint32_t(std::min<std::uint64_t>(groups, context_.limits().maxComputeWorkGroupCount[0]));
        context_.dispatch(pipeline, bindings, &params, sizeof(params), gx, std::uint32_t((groups + gx - 1) / gx));
    };
    // The camera rays: every (pixel, sample) a live path, at its own index of queue 0.
    params.pathCount = std::uint32_t(paths);
    dispatch(*camera_, paths, queues_[1].get(), queues_[0].get());
    stats_.started += paths;
    // One step per vertex while paths live; the survivors of a step are the next one's queue.
    std::uint64_t live = paths;
    int in = 0;
    for (std::uint32_t vertex = 1; live != 0; ++vertex, in = 1 - in) {
        if (vertex > maxDepth_ + 1)
            throw std::logic_error(fmt::format("wavefront: {} paths still live after vertex {} (the plan's depth {} + 1)", live,
                                               vertex - 1, maxDepth_));
        if (stats_.stepped.size() <= vertex) stats_.stepped.resize(vertex + 1, 0);
        stats_.stepped[vertex] += live;
        counters[0] = 0;
        params.pathCount = std::uint32_t(live);
        params.vertex = vertex;
        dispatch(*step_, live, queues_[in].get(), queues_[1 - in].get());
        if (counters[0] > live)
            throw std::logic_error(fmt::format("wavefront: step {} queued {} paths of {}", vertex, counters[0], live));
        live = counters[0];
    }
    stats_.finished += counters[1];
    if (counters[1] != paths)
        throw std::logic_error(fmt::format("wavefront: {} paths started, {} ended", paths, counters[1]));
    // Each pixel's radiances, in sample order, into its exact sums.
    dispatch(*resolve_, std::uint64_t(b.width) * b.height, queues_[0].get(), queues_[1].get());
}

}  // namespace oas::render
