// The wavefront path tracer's host side: see render/wavefront_gpu.hpp and shaders/pt_wavefront.comp.
#include "render/wavefront_gpu.hpp"

#include <algorithm>
#include <cstring>
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
// The counters' words (pt_wavefront.comp's PT_COUNTER_*): records a step appended, paths ended,
// the next step's three group counts, its live paths, and from kSteppedWord the live paths of each
// step by vertex.
constexpr std::uint32_t kAppendedWord = 0, kFinishedWord = 1, kGroupsWord = 2, kSteppedWord = 8;
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
    size_ = makeStage(context, s, 3);
    // Steps run for vertices 1 .. maxDepth + 1.
    counters_ = std::make_unique<vk::Buffer>(context, (kSteppedWord + maxDepth_ + 2) * sizeof(std::uint32_t));
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
    std::memset(counters, 0, counters_->size());  // host writes before a submit are visible to it
    WavefrontParams params{pattern, b.x0, b.y0, b.width, b.height, b.firstSample, b.count, b.seed, std::uint32_t(paths), 0};
    // The batch as one command buffer: the camera rays (every (pixel, sample) a live path, at its
    // own index of queue 0); per vertex 1 .. maxDepth + 1, the size kernel, which turns the
    // survivors of the step before into this step's group counts, and the step, dispatched
    // indirectly from them (a step with no live path dispatches no group); then each pixel's
    // radiances, in sample order, into its exact sums.
    std::vector<vk::SequencedDispatch> sequence;
    const auto add = [&](vk::ComputePipeline& pipeline, vk::Buffer* in, vk::Buffer* out, std::uint64_t items, bool indirect) {
        vk::SequencedDispatch d;
        d.pipeline = &pipeline;
        d.buffers = bindings;
        d.buffers[pt::PT_BINDING_PATHS_IN] = in;
        d.buffers[pt::PT_BINDING_PATHS_OUT] = out;
        d.push.resize(sizeof(params) / sizeof(std::uint32_t));
        std::memcpy(d.push.data(), &params, sizeof(params));
        if (indirect) {
            d.indirect = counters_.get();
            d.indirectOffset = kGroupsWord * sizeof(std::uint32_t);
        } else {
            const std::uint64_t groups = (items + kLocalSize - 1) / kLocalSize;
            const std::uint32_t gx = std::uint32_t(std::min<std::uint64_t>(groups, context_.limits().maxComputeWorkGroupCount[0]));
            d.groups[0] = gx;
            d.groups[1] = std::uint32_t((groups + gx - 1) / gx);
        }
        sequence.push_back(std::move(d));
    };
    add(*camera_, queues_[1].get(), queues_[0].get(), paths, false);
    for (std::uint32_t vertex = 1; vertex <= maxDepth_ + 1; ++vertex) {
        const int in = int(vertex - 1) % 2;
        params.vertex = vertex;
        add(*size_, queues_[in].get(), queues_[1 - in].get(), 1, false);
        add(*step_, queues_[in].get(), queues_[1 - in].get(), 0, true);
    }
    add(*resolve_, queues_[0].get(), queues_[1].get(), std::uint64_t(b.width) * b.height, false);
    context_.dispatchSequence(sequence);
    // What the device counted: every path started must end once, no step may queue more paths
    // than it had, and none may be live after the last vertex.
    stats_.started += paths;
    std::uint64_t live = paths;
    for (std::uint32_t vertex = 1; vertex <= maxDepth_ + 1; ++vertex) {
        const std::uint64_t stepped = counters[kSteppedWord + vertex];
        if (stepped == 0) break;
        if (stepped > live)
            throw std::logic_error(fmt::format("wavefront: step {} queued {} paths of {}", vertex - 1, stepped, live));
        if (stats_.stepped.size() <= vertex) stats_.stepped.resize(vertex + 1, 0);
        stats_.stepped[vertex] += stepped;
        live = stepped;
    }
    if (counters[kAppendedWord] != 0)
        throw std::logic_error(fmt::format("wavefront: {} paths still live after vertex {} (the plan's depth {} + 1)",
                                           counters[kAppendedWord], maxDepth_ + 1, maxDepth_));
    stats_.finished += counters[kFinishedWord];
    if (counters[kFinishedWord] != paths)
        throw std::logic_error(fmt::format("wavefront: {} paths started, {} ended", paths, counters[kFinishedWord]));
}

}  // namespace oas::render
