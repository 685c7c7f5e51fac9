#pragma once
// The cost part of the study: sample-dimensions per second of every study sampler, on the CPU
// (the shared GLSL compiled as C++, 1 thread and all threads) and on the Vulkan device, against
// a hash-only kernel of the same shape measured in the same run (the ceiling; bench/peer measures the
// Mitsuba 3 figures on the same machine kind).
#include <cstdint>
#include <string>
#include <vector>

#include "experiment.hpp"
#include "vk/context.hpp"

namespace oas::study {

struct CostOptions {
    std::uint32_t pixels = 16384;  ///< a 128 x 128 tile
    std::uint32_t dims = 8;
    std::uint32_t repeats = 3;  ///< median of
    std::string outDir = "docs/study";
    std::string command;
    bool quick = false;
};

/// Measures every sampler at its count nearest 128 spp; writes outDir/cost.csv and returns the
/// markdown section.
std::string runCostStudy(const CostOptions& options, const std::vector<SamplerSpec>& samplers, oas::vk::Context& context);

}  // namespace oas::study
