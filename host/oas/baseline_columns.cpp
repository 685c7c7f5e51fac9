// BaselineColumns: the baselines' per-run state made once, then one loop per dimension.
#include "oas/baseline_columns.hpp"
#include <algorithm>
#include <bit>

// The library's fixed-trip loops unrolled, as on the GPU: Sobol-Burley's direction numbers then
// fold to constants, and the Sobol and Halton digit loops lose their loop overhead.
#define OAS_UNROLL _Pragma("GCC unroll 32")
#include "oas/glsl_compat.hpp"

namespace oas {
namespace {

/// The run's loop for one construction: `value(i)` is the value of in-pass index i. Flattened,
/// so that the library's small functions inline into the loop and g++ can vectorize it (the
/// random baseline's loop is one hash per lane).
template <class Value>
[[gnu::flatten]] inline void fill(std::uint32_t firstInPass, std::uint32_t count, float* out, Value value)
{
    for (std::uint32_t k = 0; k < count; ++k) out[k] = value(firstInPass + k);
}

/// A padded pair column with cmj2d's across permutation tabulated over its inputs when the
/// table is no longer than the run (a 1 x N grid of a prime N has an across permutation of length
/// N, applied per sample instead): one permutation apply per sample saved for a few per run.
class PairColumn {
public:
    PairColumn(const glsl::OasPattern& pat, std::uint32_t passSeed, std::uint32_t dim, std::uint32_t count)
        : pat_(pat), column_(glsl::oas_pair_column(pat, passSeed, dim)), cmj_(pat.construction == glsl::OAS_CMJ_2D)
    {
        tabulated_ = cmj_ && column_.across.l <= std::min<std::uint32_t>(count, kMaxTable);
        if (tabulated_)
            for (std::uint32_t v = 0; v < column_.across.l; ++v) table_[v] = glsl::oas_permutation_apply(column_.across, v);
    }
    std::uint32_t cell(std::uint32_t index) const { return glsl::oas_pair_cell(column_, index); }
    /// oas_pair_cell_dim(pat, column, cell, index), bit for bit.
    float value(std::uint32_t cell, std::uint32_t index) const
    {
        std::uint32_t across = 0;
        if (cmj_) {
            const std::uint32_t input = glsl::oas_pair_across_input(pat_, column_, cell);
            across = tabulated_ ? table_[input] : glsl::oas_permutation_apply(column_.across, input);
        }
        return glsl::oas_pair_cell_dim_across(pat_, column_, cell, index, across);
    }

private:
    static constexpr std::uint32_t kMaxTable = 256;
    const glsl::OasPattern& pat_;
    glsl::OasPairColumn column_;
    bool cmj_, tabulated_ = false;
    std::uint32_t table_[kMaxTable];
};

}  // namespace

BaselineColumns::BaselineColumns(const Pattern& pattern)
    : pattern_(pattern), padded2d_(glsl::oas_is_padded_2d(glsl::toGlsl(pattern)))
{
    if (pattern.construction < glsl::OAS_RANDOM)
        throw InvalidArgument("BaselineColumns: " + describe(pattern) + " is an orthogonal array (use OaColumns)");
}

void BaselineColumns::checkRun(std::uint32_t firstIndex, std::uint32_t count) const
{
    if (count > samplesLeftInPass(firstIndex))
        throw InvalidArgument("BaselineColumns: a run of " + std::to_string(count) + " samples from index " +
                              std::to_string(firstIndex) + " leaves its pass (N = " + std::to_string(pattern_.N) +
                              "); at most " + std::to_string(samplesLeftInPass(firstIndex)) + " fit");
}

[[gnu::flatten]] void BaselineColumns::pairValues(std::uint32_t pixelSeed, std::uint32_t firstDim, std::uint32_t firstIndex,
                                                  std::uint32_t count, float* outX, float* outY) const
{
    if (!padded2d_ || firstDim % 2 != 0)
        throw InvalidArgument("BaselineColumns::pairValues: " + describe(pattern_) + ", first dimension " +
                              std::to_string(firstDim) + ": needs a padded 2D pattern and an even first dimension");
    checkRun(firstIndex, count);
    const glsl::OasPattern pat = glsl::toGlsl(pattern_);
    const std::uint32_t pass = glsl::oas_div_n(pat, firstIndex);
    const std::uint32_t passSeed = glsl::oas_pass_seed(pixelSeed, pass);
    const std::uint32_t first = firstIndex - pass * pat.N;
    const PairColumn x(pat, passSeed, firstDim, count), y(pat, passSeed, firstDim + 1, count);
    for (std::uint32_t k = 0; k < count; ++k) {
        const std::uint32_t i = first + k, cell = x.cell(i);  // one shuffle serves both
        outX[k] = x.value(cell, i);
        outY[k] = y.value(cell, i);
    }
}

[[gnu::flatten]] void BaselineColumns::values(std::uint32_t pixelSeed, std::uint32_t dim, std::uint32_t firstIndex,
                                              std::uint32_t count, float* out) const
{
    checkRun(firstIndex, count);
    const glsl::OasPattern pat = glsl::toGlsl(pattern_);
    // oas_baseline_sample, split: the pass and its seed are the run's.
    const std::uint32_t pass = glsl::oas_div_n(pat, firstIndex);
    const std::uint32_t passSeed = glsl::oas_pass_seed(pixelSeed, pass);
    const std::uint32_t first = firstIndex - pass * pat.N;
    switch (pat.construction) {
    case glsl::OAS_RANDOM:  // oas_baseline_dim's independent values
        return fill(first, count, out,
                    [&](std::uint32_t i) { return float(glsl::oas_hash3(passSeed, dim, i) >> 8u) * glsl::OAS_INV_2POW24; });
    case glsl::OAS_SOBOL_BURLEY:
        return fill(first, count, out, [&](std::uint32_t i) { return glsl::oas_sobol_burley_dim(passSeed, i, dim); });
    case glsl::OAS_JITTERED_2D:
    case glsl::OAS_CMJ_2D:
    case glsl::OAS_ZERO_TWO: {  // the pair's permutation keys and grid constants once per run
        const PairColumn column(pat, passSeed, dim, count);
        return fill(first, count, out, [&](std::uint32_t i) { return column.value(column.cell(i), i); });
    }
    case glsl::OAS_HALTON: {  // the base's constants and digit permutations once per run
        const glsl::OasHaltonColumn column = glsl::oas_halton_column(pat, passSeed, dim);
        return fill(first, count, out, [&](std::uint32_t i) { return glsl::oas_halton_column_dim(pat, column, i); });
    }
    case glsl::OAS_SOBOL:
    case glsl::OAS_SOBOL_OWEN: {  // the direction numbers and seeds once per run (OasSobolColumn)
        const glsl::OasSobolColumn column = glsl::oas_sobol_column(passSeed, dim);
        if (column.block != 0)  // later blocks shuffle the indices: the column's per-value code
            return fill(first, count, out, [&](std::uint32_t i) { return glsl::oas_sobol_column_dim(pat, column, i); });
        // Block 0 takes the indices as they are, so consecutive samples' Sobol points differ by
        // the direction numbers of the bits that change: from i - 1 to i, bits 0 .. ctz(i), whose
        // XOR is prefix[ctz(i)]. The seed and scramble per value; the 24-step matrix product once
        // per run (Sobol is linear over XOR, so the bits agree; tests/oa_columns_test.cpp compares
        // every value with oas_sample).
        std::uint32_t prefix[glsl::OAS_INDEX_BITS];
        prefix[0] = column.direction[0];
        for (std::uint32_t b = 1; b < glsl::OAS_INDEX_BITS; ++b) prefix[b] = prefix[b - 1] ^ column.direction[b];
        std::uint32_t x = glsl::oas_sobol(first, dim);
        for (std::uint32_t k = 0; k < count; ++k) {
            if (k != 0) x ^= prefix[std::countr_zero(first + k)];
            out[k] = glsl::oas_sobol_value(pat, x, column.dimSeed);
        }
        return;
    }
    default:  // every construction has its case above; the library's per-value code otherwise
        return fill(first, count, out, [&](std::uint32_t i) { return glsl::oas_baseline_dim(pat, passSeed, i, dim); });
    }
}

}  // namespace oas
