#include <chrono>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "oas/glsl_compat.hpp"
#include "render/tracer.hpp"
#include "render/wavefront_gpu.hpp"
#include "pt_render_lanes_spv.h"
#include "pt_render_spv.h"

namespace oas::render {
namespace {

struct RenderParams {  // the push-constant block of pt_render.comp
    Pattern pattern;
    std::uint32_t tileX, tileY, tileWidth, tileHeight, firstSample, sampleCount, seed;
};
static_assert(sizeof(RenderParams) == 92);

template <class T>
std::unique_ptr<vk::Buffer> upload(vk::Context& context, const std::vector<T>& items)
{
    auto buffer = std::make_unique<vk::Buffer>(context, items.size() * sizeof(T));
    std::memcpy(buffer->data(), items.data(), items.size() * sizeof(T));
    return buffer;
}

}  // namespace

namespace {
/// The dimensions a sample reads, rounded up to whole uvec4 texels: what a prefetch writes.
std::uint32_t fetchedTexelDims(const DimensionPlan& plan, const Pattern& pattern)
{
    return (fetchedDimsEnd(plan, pattern) + 3) / 4 * 4;
}
}  // namespace

std::uint32_t unusedDims(const DimensionPlan& plan)
{
    std::uint32_t used = 0;
    for (const auto& entry : plan.entries)
        for (std::uint32_t d = entry.first; d < entry.first + entry.count && d < 32; ++d) used |= 1u << d;
    return ~used;
}

std::uint32_t prefetchDims(const DimensionPlan& plan, const Pattern& pattern)
{
    const bool padded2d = glsl::oas_is_padded_2d(glsl::toGlsl(pattern));
    const bool columnState = pattern.construction == glsl::OAS_SOBOL || pattern.construction == glsl::OAS_SOBOL_OWEN ||
                             pattern.construction == glsl::OAS_HALTON;
    if (pattern.construction >= glsl::OAS_RANDOM && !padded2d && !columnState) return 0;  // no per-pass state to share
    return fetchedTexelDims(plan, pattern);
}

pt::PtSpecialization specialization(const DimensionPlan& plan, const Pattern& pattern, KernelStage stage,
                                    const SceneFeatures* featuresOrNull)
{
    // The names the table's HOST expressions use (pattern, plan, stage, features, PT_ABSENT).
    using pt::PT_ABSENT;
    using pt::uint;
    pt::PtSpecialization s;
#define PT_SET_FROM_HOST(NAME, ID, TYPE, DEFAULT, HOST) s.NAME = TYPE(HOST);
    PT_SAMPLER_CONSTANTS(PT_SET_FROM_HOST)
    PT_PLAN_CONSTANTS(PT_SET_FROM_HOST)
    PT_KERNEL_CONSTANTS(PT_SET_FROM_HOST)
    if (featuresOrNull) {
        const SceneFeatures& features = *featuresOrNull;
        PT_SCENE_FEATURE_CONSTANTS(PT_SET_FROM_HOST)
    }
#undef PT_SET_FROM_HOST
    return s;
}

vk::ComputePipeline::SpecConstants specConstants(const pt::PtSpecialization& s)
{
#define PT_SPEC_ENTRY(NAME, ID, TYPE, DEFAULT, HOST) {ID, std::uint32_t(s.NAME)},
    return {PT_SPEC_CONSTANTS(PT_SPEC_ENTRY)};
#undef PT_SPEC_ENTRY
}

std::vector<vk::BindingKind> sceneBindingKinds(std::uint32_t bindingCount)
{
    std::vector<vk::BindingKind> kinds(bindingCount);
#define PT_BINDING_KIND(NAME, BINDING, TEXELS)                                                                                   \
    kinds[BINDING] = (TEXELS) ? vk::BindingKind::Uint4TexelBuffer : vk::BindingKind::StorageBuffer;
    PT_BINDINGS(PT_BINDING_KIND)
#undef PT_BINDING_KIND
    return kinds;
}

GpuTracer::GpuTracer(vk::Context& context, const SceneData& data, const DimensionPlan& plan, const Pattern& pattern,
                     const GpuTracerOptions& options)
    : context_(context), pattern_(pattern), width_(std::uint32_t(data.globals.image.x)),
      height_(std::uint32_t(data.globals.image.y)), samplesPerBatch_(render::samplesPerBatch(plan, data))
{
    const SceneFeatures features = sceneFeatures(data);
    pt::PtSpecialization s = specialization(plan, pattern, options.stage, options.specialiseSceneFeatures ? &features : nullptr);
    // Always prefetches any pattern (the tests and the benchmark's profile); WherePays what pays.
    const bool always = options.prefetch == GpuTracerOptions::Prefetch::Always;
    const std::uint32_t dims = always ? fetchedTexelDims(plan, pattern) : prefetchDims(plan, pattern);
    const bool prefetch = always || (options.prefetch == GpuTracerOptions::Prefetch::WherePays && dims <= kPrefetchPaysUpToDims);
    s.PT_PREFETCH_DIMS = prefetch ? dims : 0;
    prefetchDims_ = s.PT_PREFETCH_DIMS;
    unreadDims_ = unusedDims(plan);
    const auto buildStart = std::chrono::steady_clock::now();  // times the pipeline build alone
    if (options.kernel == GpuTracerOptions::Kernel::Wavefront) {
        if (options.countLanes)
            throw std::invalid_argument("GpuTracer: lanes are counted in the megakernel only (the wavefront counts its paths)");
        if (options.stage != KernelStage::PathTrace)
            throw std::invalid_argument("GpuTracer: the wavefront kernel traces paths only (KernelStage::PathTrace)");
        wavefront_ = std::make_unique<GpuWavefront>(context_, s, options.maxWavefrontPaths);
    } else if (options.countLanes) {
        if (!context_.computeSubgroupBallot())
            throw std::invalid_argument(fmt::format("GpuTracer: counting lanes needs subgroup ballots in compute shaders, "
                                                    "which {} does not offer",
                                                    context_.deviceName()));
        std::vector<vk::BindingKind> kinds = sceneBindingKinds(kBindingCount + 1);
        kinds[pt::PT_BINDING_OCCUPANCY] = vk::BindingKind::StorageBuffer;
        pipeline_ = std::make_unique<vk::ComputePipeline>(context_, pt_render_lanes_spv, sizeof(pt_render_lanes_spv),
                                                          kBindingCount + 1, std::uint32_t(sizeof(RenderParams)),
                                                          specConstants(s), kinds);
        // Two words per vertex loop iteration, v = 0 .. PT_MAX_DEPTH + 1.
        laneWords_ = std::make_unique<vk::Buffer>(context_, 2 * (std::size_t(s.PT_MAX_DEPTH) + 2) * sizeof(std::uint32_t));
        std::memset(laneWords_->data(), 0, laneWords_->size());
        laneCounts_.subgroupSize = context_.subgroupSize();
    } else {
        pipeline_ = std::make_unique<vk::ComputePipeline>(context_, pt_render_spv, sizeof(pt_render_spv), kBindingCount,
                                                          std::uint32_t(sizeof(RenderParams)), specConstants(s),
                                                          sceneBindingKinds(kBindingCount));
    }
    if (prefetchDims_ != 0) {
        generator_ = std::make_unique<GpuGenerator>(context_);
        if (options.maxPrefetchPoints) generator_->setMaxPointsPerDispatch(options.maxPrefetchPoints);
        generator_->prepare(pattern);
    }
    pipelineBuildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - buildStart).count();
    buffers_.resize(kBindingCount);
    buffers_[pt::PT_BINDING_SHAPES] = upload(context_, data.shapes);
    buffers_[pt::PT_BINDING_MATERIALS] = upload(context_, data.materials);
    buffers_[pt::PT_BINDING_LIGHTS] = upload(context_, data.lights);
    buffers_[pt::PT_BINDING_NODES] = upload(context_, data.nodes);
    buffers_[pt::PT_BINDING_GLOBALS] = upload(context_, std::vector<pt::PtGlobals>{data.globals});
    buffers_[pt::PT_BINDING_ACCUMULATION] =
        std::make_unique<vk::Buffer>(context_, std::size_t(width_) * height_ * kSumWords * sizeof(std::uint32_t));
    buffers_[pt::PT_BINDING_SOBOL_DIRECTIONS] = upload(context_, sobolDirections());
    // Replaced per batch by the generator's buffer where the kernel reads prefetched samples.
    buffers_[pt::PT_BINDING_SAMPLES] = std::make_unique<vk::Buffer>(context_, 16);
    for (const auto& buffer : buffers_)
        if (!buffer) throw std::logic_error("GpuTracer: a binding of pt_constants.glsl's PT_BINDINGS has no buffer");
    // The scene records are texel buffers: a scene too large for this device's texel buffers is
    // named here, before any dispatch, with what to do about it.
    const auto makeTexelView = [&](std::uint32_t binding, std::string_view name) {
        try {
            buffers_[binding]->uint4View();
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(fmt::format("the scene's {} records do not fit this device's texel buffers ({}); "
                                                    "render it with --device cpu",
                                                    name.substr(std::string_view("PT_BINDING_").size()), e.what()));
        }
    };
#define PT_MAKE_TEXEL_VIEW(NAME, BINDING, TEXELS)                                                                                \
    if (TEXELS) makeTexelView(BINDING, #NAME);
    PT_BINDINGS(PT_MAKE_TEXEL_VIEW)
#undef PT_MAKE_TEXEL_VIEW
    clear();
}

GpuTracer::~GpuTracer() = default;

bool GpuTracer::accepts(const Pattern& pattern) const
{
    return oas::specializationKey(pattern) == oas::specializationKey(pattern_);
}

void GpuTracer::setPattern(const Pattern& pattern)
{
    if (!accepts(pattern))
        throw std::invalid_argument("GpuTracer::setPattern: " + oas::describe(pattern) + " needs another pipeline than " +
                                    oas::describe(pattern_));
    pattern_ = pattern;
}

std::uint32_t samplesPerBatch(const DimensionPlan& plan, const SceneData& data)
{
    // pt_render.comp's loops, per sample: the sample loop (1), the vertex loop (maxDepth + 2), and
    // pt_trace's walk for each of maxDepth + 1 rays, as many shadow rays again with next-event
    // estimation (pt_visible). The other loops are unrolled.
    constexpr std::uint64_t kLoopCap = 65535;
    const std::uint64_t depth = plan.maxDepth;
    const std::uint64_t rays = (depth + 1) * (plan.nee ? 2 : 1);
    const std::uint64_t perSample = 1 + (depth + 2) + rays * (data.nodes.size() + data.shapes.size());
    return std::uint32_t(std::clamp<std::uint64_t>(kLoopCap / perSample, 1, kMaxSamplesPerBatch));
}

BatchCursor::BatchCursor(std::uint32_t width, std::uint32_t height, std::uint32_t spp, std::uint32_t perBatch, std::uint32_t seed,
                         std::uint32_t tile, std::uint32_t firstSample)
    : width_(width), height_(height), spp_(width && height && spp > firstSample ? spp - firstSample : 0),
      perBatch_(std::max(1u, perBatch)), first_(firstSample)
{
    setTile(tile);
    batch_.seed = seed;
    startPass();
}

void BatchCursor::startPass()
{
    tile_ = nextTile_;
    batch_.firstSample = first_ + done_;
    batch_.count = std::min(perBatch_, spp_ - std::min(spp_, done_));
    batch_.x0 = batch_.y0 = 0;
    batch_.width = std::min(tile_, width_);
    batch_.height = std::min(tile_, height_);
}

bool BatchCursor::advance()
{
    if (done()) return false;
    // Tiles row by row, then the next pass.
    batch_.x0 += tile_;
    if (batch_.x0 >= width_) {
        batch_.x0 = 0;
        batch_.y0 += tile_;
    }
    if (batch_.y0 < height_) {
        batch_.width = std::min(tile_, width_ - batch_.x0);
        batch_.height = std::min(tile_, height_ - batch_.y0);
        return false;
    }
    done_ += batch_.count;
    if (!done()) startPass();
    return true;
}

std::uint32_t forEachBatch(std::uint32_t width, std::uint32_t height, std::uint32_t spp, std::uint32_t perBatch,
                           std::uint32_t seed, const std::function<void(const SampleBatch&)>& trace,
                           const std::function<bool(std::uint32_t)>& afterPass, std::uint32_t firstSample)
{
    BatchCursor cursor(width, height, spp, perBatch, seed, kRenderTile, firstSample);
    while (!cursor.done()) {
        trace(cursor.batch());
        if (cursor.advance() && afterPass && !afterPass(cursor.samplesDone())) break;
    }
    return cursor.samplesDone();
}

void GpuTracer::clear()
{
    if (wavefront_) wavefront_->clearStats();
    if (laneWords_) laneCounts_ = LaneCounts{laneCounts_.subgroupSize, {}, {}};
    const vk::Buffer& sums = *buffers_[pt::PT_BINDING_ACCUMULATION];
    std::memset(sums.data(), 0, sums.size());
}

std::uint64_t GpuTracer::rejectedSamples() const
{
    return accumulation().rejectedSamples();
}

void GpuTracer::trace(const SampleBatch& b)
{
    std::vector<vk::Buffer*> bindings;
    for (auto& buffer : buffers_) bindings.push_back(buffer.get());
    if (laneWords_) bindings.push_back(laneWords_.get());
    const auto dispatch = [&](const SampleBatch& part) {
        if (wavefront_) return wavefront_->trace(pattern_, part, bindings);
        RenderParams params{pattern_, part.x0, part.y0, part.width, part.height, part.firstSample, part.count, part.seed};
        context_.dispatch(*pipeline_, bindings, &params, sizeof(params), (part.width + 7) / 8, (part.height + 7) / 8);
        if (laneWords_) addLaneWords();
    };
    if ((prefetchDims_ == 0 && !wavefront_) || b.width == 0 || b.height == 0 || b.count == 0) return dispatch(b);
    // The generation kernel writes the batch's values, [pixel of the rectangle][sample][dim], and
    // the path tracer reads them; a rectangle too large for one generation dispatch, or for the
    // wavefront's queues, goes in strips of rows (the pixels are independent, so the sums are the
    // same).
    SampleRequest request;
    request.x0 = b.x0;
    request.width = b.width;
    request.spp = b.count;
    request.dims = prefetchDims_;
    request.unreadDims = unreadDims_;
    request.seed = b.seed;
    request.firstSample = b.firstSample;
    std::uint32_t rows = b.height;
    request.height = rows;
    const auto fits = [&] {
        return (prefetchDims_ == 0 || generator_->fitsOneDispatch(pattern_, request)) &&
               (!wavefront_ || std::uint64_t(b.width) * rows * b.count <= wavefront_->capacity());
    };
    while (rows > 1 && !fits()) request.height = rows = (rows + 1) / 2;
    for (std::uint32_t y = 0; y < b.height; y += rows) {
        SampleBatch strip = b;
        strip.y0 = b.y0 + y;
        strip.height = std::min(rows, b.height - y);
        request.y0 = strip.y0;
        request.height = strip.height;
        if (prefetchDims_ != 0) bindings[pt::PT_BINDING_SAMPLES] = &generator_->generateOnDevice(pattern_, request);
        dispatch(strip);
    }
}

static_assert(pt::PT_BINDING_OCCUPANCY == kBindingCount, "the counting variant's binding follows PT_BINDINGS'");

void GpuTracer::addLaneWords()
{
    // One dispatch's 32-bit counts into 64-bit totals, then zeroed for the next: a dispatch counts
    // at most its pixels x samples lanes a vertex, far below 2^32 (kMaxSamplesPerBatch).
    auto* words = static_cast<std::uint32_t*>(laneWords_->data());
    const std::size_t vertices = laneWords_->size() / sizeof(std::uint32_t) / 2;
    laneCounts_.liveLanes.resize(vertices, 0);
    laneCounts_.subgroupSteps.resize(vertices, 0);
    for (std::size_t v = 0; v < vertices; ++v) {
        laneCounts_.liveLanes[v] += words[2 * v];
        laneCounts_.subgroupSteps[v] += words[2 * v + 1];
    }
    std::memset(words, 0, laneWords_->size());
}

WavefrontStats GpuTracer::wavefrontStats() const
{
    return wavefront_ ? wavefront_->stats() : WavefrontStats{};
}

const char* kernelName(GpuTracerOptions::Kernel kernel)
{
    return kernel == GpuTracerOptions::Kernel::Wavefront ? "wavefront" : "mega";
}

GpuTracerOptions::Kernel parseKernel(const std::string& value, const char* option)
{
    for (const auto kernel : {GpuTracerOptions::Kernel::Mega, GpuTracerOptions::Kernel::Wavefront})
        if (value == kernelName(kernel)) return kernel;
    throw InvalidArgument(fmt::format("{} \"{}\": valid mega (one invocation traces whole paths) or wavefront (paths as "
                                      "records, one dispatch per vertex)",
                                      option, value));
}

std::string describeKernels(const DimensionPlan& plan, const Pattern& pattern, GpuTracerOptions::Kernel kernel)
{
    const std::uint32_t dims = prefetchDims(plan, pattern);
    std::string out;
    if (dims != 0 && dims <= kPrefetchPaysUpToDims)
        out = fmt::format("oas_generate ({} sample dimensions per path, made before each batch), then ", dims);
    if (kernel == GpuTracerOptions::Kernel::Mega)
        return out + "pt_render (the megakernel: one invocation traces a pixel's samples, whole paths)";
    return out + fmt::format("pt_wavefront: the camera kernel, up to {} step kernels (one per vertex, over the paths still "
                             "live, each sized on the device by the one before), the pixels' sums",
                             plan.maxDepth + 1);
}

Accumulation GpuTracer::accumulation() const
{
    Accumulation out(width_, height_);
    const vk::Buffer& sums = *buffers_[pt::PT_BINDING_ACCUMULATION];
    std::memcpy(out.words.data(), sums.data(), out.words.size() * sizeof(std::uint32_t));
    return out;
}

}  // namespace oas::render
