#pragma once
// Rendering a flattened scene with the path tracer of shaders/pt/pt_trace.glsl, on the GPU
// (pt_render.comp) or on the CPU (the same GLSL compiled as C++: the reference tracer).
// Both accumulate radiance sums per pixel: rgb = sum of sample radiances, a = samples taken.
#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "oas/pattern.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "vk/context.hpp"

namespace oas::render {

/// Samples [firstSample, firstSample + count) of every pixel in the rectangle, added to
/// accumulation (width * height vec4, row-major over the whole image).
struct SampleBatch {
    std::uint32_t x0 = 0, y0 = 0, width = 0, height = 0;
    std::uint32_t firstSample = 0, count = 1;
    std::uint32_t seed = 0;
};

/// The CPU reference: `threads` workers (0: all).
void traceCpu(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern, const SampleBatch& batch,
              std::vector<float>& accumulation, unsigned threads = 0);

/// One sample's radiance on the CPU (tests: compare single samples).
glm::vec3 radianceCpu(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern, std::uint32_t px,
                      std::uint32_t py, std::uint32_t seed, std::uint32_t sampleIndex);

class GpuTracer {
public:
    GpuTracer(vk::Context& context, const SceneData& data, const DimensionPlan& plan, const Pattern& pattern);
    ~GpuTracer();
    /// Dispatches the batch (the whole rectangle in one dispatch) and waits.
    void trace(const SampleBatch& batch);
    /// The accumulation buffer (width * height vec4 of the image).
    std::vector<float> accumulation() const;
    void clear();

private:
    vk::Context& context_;
    Pattern pattern_;
    std::uint32_t width_, height_;
    std::unique_ptr<vk::ComputePipeline> pipeline_;
    std::vector<std::unique_ptr<vk::Buffer>> buffers_;
};

}  // namespace oas::render
