#pragma once
// Exact stratification checks of generated point sets, with integer strata: a float x made by
// the library is F * 2^-24, so its stratum among K is floor(F * K / 2^24), exact in 64-bit.
// Used by oas-samples --summary and by the tests.
#include <cstdint>
#include <string>
#include <vector>

#include "oas/pattern.hpp"

namespace oas {

/// Stratum of x among K equal strata of [0,1), exactly; K <= 2^24. Throws for x outside [0,1)
/// or x not a multiple of 2^-24 (the library never makes one).
std::uint32_t stratumOf(float x, std::uint32_t K);

/// True when the projection of the n points (row-major, `dims` values each) onto `cols` puts the
/// same number of points, n / K^cols.size(), into every cell of the K x ... x K grid.
bool isStratified(const float* points, std::uint32_t n, std::uint32_t dims, const std::vector<std::uint32_t>& cols,
                  std::uint32_t K);

/// What a pattern promises and whether one pixel's N points keep it, as printable lines.
struct StratificationSummary {
    std::vector<std::string> lines;
    bool allKept = true;
};
StratificationSummary summarize(const Pattern& pattern, const float* points, std::uint32_t n, std::uint32_t dims);

}  // namespace oas
