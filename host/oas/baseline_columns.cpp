// BaselineColumns: the baselines' per-run state made once, then one loop per dimension.
#include "oas/baseline_columns.hpp"
#include <algorithm>
#include <array>
#include <bit>
#include <type_traits>
#include <utility>

// The library's fixed-trip loops unrolled, as on the GPU: Sobol-Burley's direction numbers then
// fold to constants, and the Sobol and Halton digit loops lose their loop overhead.
#define OAS_UNROLL _Pragma("GCC unroll 32")
#include "oas/glsl_compat.hpp"

namespace oas {
namespace {

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
    /// Whether value<true> may be used: cmj2d's across permutation is in the table (always
    /// true for the other padded baselines, which have none).
    bool tabulated() const { return tabulated_ || !cmj_; }
    /// oas_pair_cell_dim(pat, column, cell, index), bit for bit; FromTable (when tabulated())
    /// reads cmj2d's across image from the table. A template rather than a run-time test, so
    /// that each loop has one straight-line body: g++ vectorized neither with the choice inside.
    template <bool FromTable>
    float value(std::uint32_t cell, std::uint32_t index) const
    {
        std::uint32_t across = 0;
        if (cmj_) {
            const std::uint32_t input = glsl::oas_pair_across_input(pat_, column_, cell);
            across = FromTable ? table_[input] : glsl::oas_permutation_apply(column_.across, input);
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

using glsl::uint;
/// The longest stretch the Sobol loop keeps points for on the stack before scrambling them.
constexpr uint kMaxRun = 256;

// The loops, once per instruction set: the baseline (SSE2 on x86-64) and AVX2 (eight lanes),
// taken where the CPU has it, as OaColumns does (oa_columns.hpp).
#define OAS_LOOP_ATTRIBUTES [[gnu::flatten]]
#define OAS_LOOP_NAME(name) name##Baseline
#include "oas/baseline_columns_loops.inc"
#if OAS_CPU_HAS_AVX2_VARIANT
#define OAS_LOOP_ATTRIBUTES [[gnu::target("avx2"), gnu::flatten]]
#define OAS_LOOP_NAME(name) name##Avx2
#include "oas/baseline_columns_loops.inc"
#else
template <uint Digits, bool Binary>
constexpr auto runFaureAvx2 = runFaureBaseline<Digits, Binary>;
template <uint Construction>
constexpr auto runValuesAvx2 = runValuesBaseline<Construction>;
template <uint Construction>
constexpr auto runPairsAvx2 = runPairsBaseline<Construction>;
#endif

/// The largest K with a loop of its own (runFaure): base 11 reaches 14641 samples, base 2 64.
/// Other Faure patterns (longer sequences, odd extension fields) take oas::sample per value
/// (generate_cpu.cpp), out of this file: here OAS_UNROLL unrolls the twin's digit loops, which
/// with K known only at run time multiplied this file's compile time by seven (240 s).
constexpr uint kFaureUnrolledDigits = 6;
using FaureLoop = void (*)(glsl::OasPattern, uint, uint, uint, uint, float*);
/// runFaure<K, binary> for K = 1 .. kFaureUnrolledDigits; [isa][binary][K - 1].
template <std::size_t... K>
constexpr std::array<std::array<std::array<FaureLoop, sizeof...(K)>, 2>, 2> faureLoops(std::index_sequence<K...>)
{
    return {{{{{runFaureBaseline<K + 1, false>...}, {runFaureBaseline<K + 1, true>...}}},
             {{{runFaureAvx2<K + 1, false>...}, {runFaureAvx2<K + 1, true>...}}}}};
}
constexpr auto kFaureLoops = faureLoops(std::make_index_sequence<kFaureUnrolledDigits>());

}  // namespace

BaselineColumns::BaselineColumns(const Pattern& pattern, CpuIsa isa)
    : pattern_(pattern), padded2d_(glsl::oas_is_padded_2d(glsl::toGlsl(pattern))),
      isa_(isa == CpuIsa::Avx2 ? bestCpuIsa() : CpuIsa::Baseline)
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

void BaselineColumns::pairValues(std::uint32_t pixelSeed, std::uint32_t firstDim, std::uint32_t firstIndex, std::uint32_t count,
                                 float* outX, float* outY) const
{
    if (!padded2d_ || firstDim % 2 != 0)
        throw InvalidArgument("BaselineColumns::pairValues: " + describe(pattern_) + ", first dimension " +
                              std::to_string(firstDim) + ": needs a padded 2D pattern and an even first dimension");
    checkRun(firstIndex, count);
    if (count == 0) return;  // an empty run writes nothing
    const glsl::OasPattern pat = glsl::toGlsl(pattern_);
    const uint pass = glsl::oas_div_n(pat, firstIndex);
    const uint passSeed = glsl::oas_pass_seed(pixelSeed, pass), first = firstIndex - pass * pat.N;
    const bool avx2 = isa_ == CpuIsa::Avx2;
    switch (pat.construction) {
    case glsl::OAS_JITTERED_2D:
        return (avx2 ? runPairsAvx2<glsl::OAS_JITTERED_2D> : runPairsBaseline<glsl::OAS_JITTERED_2D>)(pat, passSeed, firstDim, first, count, outX, outY);
    case glsl::OAS_CMJ_2D:
        return (avx2 ? runPairsAvx2<glsl::OAS_CMJ_2D> : runPairsBaseline<glsl::OAS_CMJ_2D>)(pat, passSeed, firstDim, first, count, outX, outY);
    default:
        return (avx2 ? runPairsAvx2<glsl::OAS_ZERO_TWO> : runPairsBaseline<glsl::OAS_ZERO_TWO>)(pat, passSeed, firstDim, first, count, outX, outY);
    }
}

void BaselineColumns::values(std::uint32_t pixelSeed, std::uint32_t dim, std::uint32_t firstIndex, std::uint32_t count,
                             float* out) const
{
    checkRun(firstIndex, count);
    if (count == 0) return;  // an empty run writes nothing (the Halton loop counts groups to first + count - 1)
    const glsl::OasPattern pat = glsl::toGlsl(pattern_);
    // oas_baseline_sample, split: the pass and its seed are the run's.
    const uint pass = glsl::oas_div_n(pat, firstIndex);
    const uint passSeed = glsl::oas_pass_seed(pixelSeed, pass), first = firstIndex - pass * pat.N;
    const bool avx2 = isa_ == CpuIsa::Avx2;
#define OAS_RUN_VALUES(construction) \
    return (avx2 ? runValuesAvx2<construction> : runValuesBaseline<construction>)(pat, passSeed, dim, first, count, out)
    switch (pat.construction) {
    case glsl::OAS_RANDOM: OAS_RUN_VALUES(glsl::OAS_RANDOM);
    case glsl::OAS_SOBOL_BURLEY: OAS_RUN_VALUES(glsl::OAS_SOBOL_BURLEY);
    case glsl::OAS_JITTERED_2D: OAS_RUN_VALUES(glsl::OAS_JITTERED_2D);
    case glsl::OAS_CMJ_2D: OAS_RUN_VALUES(glsl::OAS_CMJ_2D);
    case glsl::OAS_ZERO_TWO: OAS_RUN_VALUES(glsl::OAS_ZERO_TWO);
    case glsl::OAS_HALTON: OAS_RUN_VALUES(glsl::OAS_HALTON);
    case glsl::OAS_SOBOL: OAS_RUN_VALUES(glsl::OAS_SOBOL);
    case glsl::OAS_SOBOL_OWEN: OAS_RUN_VALUES(glsl::OAS_SOBOL_OWEN);
    case glsl::OAS_FAURE:
        if ((pat.fieldK == 1 || pat.fieldP == 2) && pat.aux >= 1 && pat.aux <= kFaureUnrolledDigits)
            return kFaureLoops[avx2 ? 1 : 0][pat.fieldK == 1 ? 0 : 1][pat.aux - 1](pat, passSeed, dim, first, count, out);
        [[fallthrough]];
    default:  // the library's per-value code (oas_sample, compiled without this file's unrolling)
        for (uint k = 0; k < count; ++k) out[k] = sample(pattern_, pixelSeed, firstIndex + k, dim);
    }
#undef OAS_RUN_VALUES
}

}  // namespace oas
