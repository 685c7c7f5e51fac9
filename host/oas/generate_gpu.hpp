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
    /// Points ((pixel, sample) pairs) per dispatch for `dims`, from the device limits.
    std::uint64_t pointsPerDispatch(std::uint32_t dims) const;
    /// Caps points per dispatch below the device limits (tests use it to cover chunk seams); 0: no cap.
    void setMaxPointsPerDispatch(std::uint64_t points) { maxPointsPerDispatch_ = points; }
    /// Seconds spent building pipelines so far (one per specialisation, on first use).
    double pipelineBuildSeconds() const { return pipelineBuildSeconds_; }

private:
    void dispatchAll(const Pattern& pattern, const SampleRequest& request, float* out);
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
