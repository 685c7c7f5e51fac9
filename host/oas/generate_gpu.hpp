#pragma once
// GPU generation of whole point sets with shaders/oas_generate.comp, in chunks that respect the
// device's storage-buffer and work-group-count limits (lavapipe: 128 MiB, 65535 groups).
#include <cstdint>
#include <map>
#include <memory>
#include <tuple>

#include "oas/pattern.hpp"
#include "vk/context.hpp"

namespace oas {

class GpuGenerator {
public:
    /// Which build of oas_generate.comp runs: specialised per pattern kind (the normal one), the
    /// same kernel unspecialised (every construction, offset and field kind decided at run time:
    /// what specialisation buys, for the benchmark), or the same-shape kernel that only hashes
    /// (the benchmark's ceiling).
    enum class Kernel { Specialised, Unspecialised, HashOnly };
    explicit GpuGenerator(vk::Context& context, Kernel kernel = Kernel::Specialised);
    ~GpuGenerator();

    /// Fills out[] ([pixel][sample][dim], like generateCpu) from the GPU.
    void generate(const Pattern& pattern, const SampleRequest& request, float* out);
    /// Runs the kernel over the request without copying results back; for benchmarks.
    void run(const Pattern& pattern, const SampleRequest& request) { dispatchAll(pattern, request, nullptr); }
    /// Whether `request` takes one dispatch (generateOnDevice's condition).
    bool fitsOneDispatch(const Pattern& pattern, const SampleRequest& request) const;
    /// Generates the request in one dispatch into the generator's device buffer, [pixel][sample][dim]
    /// as generate() writes, and returns that buffer (valid until the next call; its size is a whole
    /// number of 16-byte texels). For kernels that read the samples on the device (the path tracer).
    /// Throws std::invalid_argument where the request needs more than one dispatch.
    vk::Buffer& generateOnDevice(const Pattern& pattern, const SampleRequest& request);
    /// Builds the pattern's pipeline now rather than on first use.
    void prepare(const Pattern& pattern) { pipelineFor(pattern); }
    /// Points ((pixel, sample) pairs) per dispatch for `dims`, from the device limits.
    std::uint64_t pointsPerDispatch(std::uint32_t dims) const;
    /// Caps points per dispatch below the device limits (tests use it to cover chunk seams); 0: no cap.
    void setMaxPointsPerDispatch(std::uint64_t points) { maxPointsPerDispatch_ = points; }
    /// Seconds spent building pipelines so far (one per specialisation, on first use).
    double pipelineBuildSeconds() const { return pipelineBuildSeconds_; }

private:
    /// Runs the kernel over the request; copies the results to `out` unless it is null.
    void dispatchAll(const Pattern& pattern, const SampleRequest& request, float* out);
    /// Work items (runs of samples) per dispatch for `request`.
    std::uint64_t runsPerDispatch(const Pattern& pattern, const SampleRequest& request) const;
    vk::ComputePipeline& pipelineFor(const Pattern& pattern);
    vk::Context& context_;
    Kernel kernel_;
    /// One pipeline per specializationKey (the kernel's specialization constants), made on first use.
    std::map<decltype(specializationKey(Pattern{})), std::unique_ptr<vk::ComputePipeline>> pipelines_;
    std::unique_ptr<vk::Buffer> buffer_;
    std::unique_ptr<vk::Buffer> sobol_;  ///< Sobol direction numbers (binding 1)
    std::uint64_t maxPointsPerDispatch_ = 0;
    double pipelineBuildSeconds_ = 0;
};

}  // namespace oas
