#pragma once
// Where a progressive render can stop and show or write a whole, stratified prefix of its
// samples: oas-render's --checkpoints and oas-view's refinement with the faure sampler.
#include <cstdint>
#include <vector>

#include "oas/pattern.hpp"

namespace oas::apps {

/// The sample counts c with first < c < end after which samples [0, c) are a prefix the pattern
/// stratifies as a whole, in increasing order. For `faure`, every power q^m of its base q: the
/// first q^m points of a (0,s)-sequence in base q are a (0,m,s)-net (Niederreiter, *Point sets and
/// sequences with small discrepancy*, 1987), so every block of the pattern is one. For the other
/// samplers, every whole pass (a multiple of N): each pass is one complete randomized point set.
inline std::vector<std::uint32_t> checkpointCounts(const Pattern& pattern, std::uint32_t first, std::uint32_t end)
{
    std::vector<std::uint32_t> counts;
    const bool faure = pattern.construction == OAS_FAURE;
    const std::uint64_t step = faure ? pattern.s : pattern.N;
    if (step < (faure ? 2u : 1u)) return counts;  // a base below 2 would never grow
    for (std::uint64_t c = step; c < end; c = faure ? c * step : c + step)
        if (c > first) counts.push_back(std::uint32_t(c));
    return counts;
}

}  // namespace oas::apps
