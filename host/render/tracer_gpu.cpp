#include <chrono>
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "render/tracer.hpp"
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

GpuTracer::GpuTracer(vk::Context& context, const SceneData& data, const DimensionPlan& plan, const Pattern& pattern,
                     const GpuTracerOptions& options)
    : context_(context), pattern_(pattern), width_(std::uint32_t(data.globals.image.x)),
      height_(std::uint32_t(data.globals.image.y))
{
    SceneFeatures features{true, true, true, true, true};
    if (options.specialiseSceneFeatures) features = sceneFeatures(data);
    const vk::ComputePipeline::SpecConstants spec = {
        {0, pattern.construction}, {1, pattern.offset}, {2, oas::fieldKind(pattern)},
        {10, plan.hasLens}, {11, plan.hasMotion}, {12, plan.nee}, {13, plan.mis}, {14, plan.lobe != kAbsent},
        {15, plan.maxDepth}, {16, plan.roulette != kAbsent ? plan.rouletteStart : 0u},
        {20, plan.pixel}, {21, plan.lens}, {22, plan.time}, {23, plan.vertexBase}, {24, plan.vertexStride},
        {25, plan.lightSelect}, {26, plan.lightUV}, {27, plan.bsdfUV}, {28, plan.lobe}, {29, plan.roulette},
        {30, std::uint32_t(options.stage)}, {31, features.spheres}, {32, features.quads}, {33, features.triangles},
        {34, features.conductors}, {35, features.pointLights}};
    const auto buildStart = std::chrono::steady_clock::now();
    pipeline_ = std::make_unique<vk::ComputePipeline>(context_, pt_render_spv, sizeof(pt_render_spv), 7,
                                                      std::uint32_t(sizeof(RenderParams)), spec);
    pipelineBuildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - buildStart).count();
    buffers_.push_back(upload(context_, data.shapes));
    buffers_.push_back(upload(context_, data.materials));
    buffers_.push_back(upload(context_, data.lights));
    buffers_.push_back(upload(context_, data.nodes));
    buffers_.push_back(upload(context_, std::vector<pt::PtGlobals>{data.globals}));
    buffers_.push_back(
        std::make_unique<vk::Buffer>(context_, std::size_t(width_) * height_ * kSumWords * sizeof(std::uint32_t)));
    buffers_.push_back(upload(context_, sobolDirections()));
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
        throw std::invalid_argument("GpuTracer::setPattern: " + oas::describe(pattern) +
                                    " needs another pipeline than " + oas::describe(pattern_));
    pattern_ = pattern;
}

std::uint32_t samplesPerBatch(const DimensionPlan& plan)
{
    return std::max<std::uint32_t>(1, 8 / std::max<std::uint32_t>(1, plan.maxDepth));
}

BatchCursor::BatchCursor(std::uint32_t width, std::uint32_t height, std::uint32_t spp, std::uint32_t perBatch,
                         std::uint32_t seed, std::uint32_t tile, std::uint32_t firstSample)
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

void GpuTracer::clear() { std::memset(buffers_[5]->data(), 0, buffers_[5]->size()); }

std::uint64_t GpuTracer::rejectedSamples() const { return accumulation().rejectedSamples(); }

void GpuTracer::trace(const SampleBatch& b)
{
    RenderParams params{pattern_, b.x0, b.y0, b.width, b.height, b.firstSample, b.count, b.seed};
    std::vector<vk::Buffer*> bindings;
    for (auto& buffer : buffers_) bindings.push_back(buffer.get());
    context_.dispatch(*pipeline_, bindings, &params, sizeof(params), (b.width + 7) / 8, (b.height + 7) / 8);
}

Accumulation GpuTracer::accumulation() const
{
    Accumulation out(width_, height_);
    std::memcpy(out.words.data(), buffers_[5]->data(), out.words.size() * sizeof(std::uint32_t));
    return out;
}

}  // namespace oas::render
