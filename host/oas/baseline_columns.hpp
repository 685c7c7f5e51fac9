#pragma once
// Many samples of one baseline dimension in one call, on the CPU: the baselines' counterpart of
// OaColumns (oa_columns.hpp), compiled from the same GLSL source (glsl_compat.hpp).
//
// Why: the CPU tracer fetched a baseline's values one sample and one dimension at a time
// (oas_draw), remaking for every value what depends only on the pixel, pass and dimension: the
// pass seed, the padded 2D pairs' permutation keys and grid reciprocals (oas_pair_column), the
// Sobol block and scramble seeds. The OAs had a bulk path and the baselines did not, so on the
// CPU twin a padded 2D render traced 0.18-0.35x the paths per second of an OA render (issue
// "Every baseline at its best speed"; docs/BENCHMARKS.md). Here that state is made once per run,
// and each value costs its own work only, in loops compiled per construction and for AVX2
// (baseline_columns_loops.inc) that g++ vectorizes: eight values at a time.
#include <cstdint>

#include "oas/oa_columns.hpp"  // CpuIsa
#include "oas/pattern.hpp"

namespace oas {

/// Bulk evaluation of one baseline pattern (construction >= OAS_RANDOM) on the CPU, for runs of
/// consecutive samples of one pass: the sample indices [firstIndex, firstIndex + count) of one
/// pixel with firstIndex / N == (firstIndex + count - 1) / N. values()[k] == oas::sample(pattern,
/// pixelSeed, firstIndex + k, dim) bit for bit (tests/oa_columns_test.cpp).
class BaselineColumns {
public:
    /// Throws InvalidArgument for an orthogonal array (OaColumns serves those). `isa`: the
    /// instruction set of the loops, CpuIsa::Avx2 meaning the best this CPU runs (the values are
    /// the same bits either way; tests/oa_columns_test.cpp runs both).
    explicit BaselineColumns(const Pattern& pattern, CpuIsa isa = CpuIsa::Avx2);

    /// Dimension `dim` for the run: out[k] for sample firstIndex + k. Throws InvalidArgument when
    /// the run leaves its pass (count > samplesLeftInPass(firstIndex)).
    void values(std::uint32_t pixelSeed, std::uint32_t dim, std::uint32_t firstIndex, std::uint32_t count, float* out) const;

    /// Whether the pattern pads 2D pairs (jittered2d, cmj2d, zerotwo): then pairValues() makes a
    /// pair's two dimensions for the price of one shuffle of the sample order.
    bool padded2d() const { return padded2d_; }
    /// Dimensions `firstDim` (even) and firstDim + 1 of a padded 2D pattern for the run, the
    /// pair's shared cell made once per sample: outX[k], outY[k] == values() of each. Throws
    /// InvalidArgument for other patterns, an odd firstDim or a run that leaves its pass.
    void pairValues(std::uint32_t pixelSeed, std::uint32_t firstDim, std::uint32_t firstIndex, std::uint32_t count, float* outX,
                    float* outY) const;

    /// The longest run that starts at `firstIndex` and stays in its pass.
    std::uint32_t samplesLeftInPass(std::uint32_t firstIndex) const { return pattern_.N - firstIndex % pattern_.N; }
    const Pattern& pattern() const { return pattern_; }
    /// The instruction set the loops run (CpuIsa::Baseline where AVX2 was not asked for or the
    /// CPU lacks it).
    CpuIsa isa() const { return isa_; }

private:
    void checkRun(std::uint32_t firstIndex, std::uint32_t count) const;
    Pattern pattern_;
    bool padded2d_;
    CpuIsa isa_;
};

}  // namespace oas
