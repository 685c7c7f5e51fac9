#pragma once
// The wavefront path tracer's host side (shaders/pt_wavefront.comp): its four pipelines, the
// path queues and how a batch runs through them. GpuTracer (render/tracer.hpp) owns one where
// GpuTracerOptions::kernel is Wavefront; nothing else uses this header.
#include <cstdint>
#include <memory>
#include <vector>

#include "oas/pattern.hpp"
#include "render/pt_constants.hpp"
#include "render/tracer.hpp"
#include "vk/context.hpp"

namespace oas::render {

/// The pipeline's specialization constants, one {constant_id, value} per entry of `s`: what
/// pt_render.comp and pt_wavefront.comp are built with (render/tracer_gpu.cpp).
vk::ComputePipeline::SpecConstants specConstants(const pt::PtSpecialization& s);
/// Binding kinds for `bindingCount` bindings, PT_BINDINGS's set as that table says (the scene's
/// texel buffers, the sums' storage buffer); the rest are the caller's to set.
std::vector<vk::BindingKind> sceneBindingKinds(std::uint32_t bindingCount);

class GpuWavefront {
public:
    /// `s`: the megakernel's specialization (plan, sampler, scene features, PT_PREFETCH_DIMS);
    /// `maxPaths`: the queues' capacity in paths (0: kWavefrontMaxPaths), cut to what the device's
    /// texel buffers hold.
    GpuWavefront(vk::Context& context, const pt::PtSpecialization& s, std::uint64_t maxPaths);
    ~GpuWavefront();
    /// Paths one trace() can hold: a batch's pixels x samples must not exceed it.
    std::uint64_t capacity() const { return capacity_; }
    /// Traces every (pixel, sample) of `batch` (at most capacity() of them) in one submission: the
    /// camera kernel, one step per vertex (sized on the device by the step before), then the
    /// pixels' sums. `bindings`: PT_BINDINGS's
    /// buffers, as the megakernel has them. Throws std::logic_error where a path is lost or
    /// outlives its last vertex (conservation: every path started ends once).
    void trace(const Pattern& pattern, const SampleBatch& batch, const std::vector<vk::Buffer*>& bindings);
    const WavefrontStats& stats() const { return stats_; }
    void clearStats() { stats_ = WavefrontStats{}; }

private:
    void reserve(std::uint64_t paths);
    vk::Context& context_;
    std::uint32_t maxDepth_;
    std::uint64_t capacity_;
    std::unique_ptr<vk::ComputePipeline> camera_, step_, resolve_, size_;
    std::unique_ptr<vk::Buffer> queues_[2], results_, counters_;
    WavefrontStats stats_;
};

}  // namespace oas::render
