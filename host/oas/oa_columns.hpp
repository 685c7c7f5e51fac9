#pragma once
// Many samples of one orthogonal-array dimension in one call, on the CPU: the bulk form of the
// GLSL library's fast path (oas_block, oas_block_row, oas_column, oas_column_dim), compiled from
// the same source (glsl_compat.hpp) and vectorized across samples.
//
// Why: a CPU renderer that evaluates a sample's dimensions one at a time pays ~15-30 ns per OA
// value in scalar code (measured on the CPU tracer). A loop over the samples of one pass for one
// dimension does the same integer work lane by lane, so g++ vectorizes it, but only when the
// pattern kind is fixed at compile time: each (construction, field kind, offset) is compiled as
// its own variant with the library's OAS_STATIC_* switches (binary fields with CMJ offsets also
// per degree, k = 2..5: oa_columns_variants.hpp), and the variant is chosen once per pattern
// (OaColumns' constructor), so no value pays for the pattern switch. Each variant that
// vectorizes is built for AVX2 and for the baseline ISA, picked at run time (function target
// attributes: -march is not allowed in a portable build). The values are those of oas_sample,
// bit for bit (tests/oa_columns_test.cpp).
#include <cstdint>

#include "oas/pattern.hpp"

namespace oas {

/// The instruction sets the loops are compiled for. On x86-64 each variant that vectorizes gets
/// an AVX2 build (eight 32-bit lanes) besides the baseline one (SSE2), used where the CPU has
/// AVX2; the others have the baseline build alone, whatever is asked.
enum class CpuIsa { Baseline = 0, Avx2 = 1 };
#if defined(__x86_64__) && defined(__GNUC__)
#define OAS_CPU_HAS_AVX2_VARIANT 1
#else
#define OAS_CPU_HAS_AVX2_VARIANT 0
#endif
/// The best of CpuIsa this CPU runs.
CpuIsa bestCpuIsa();

namespace detail {
/// One compiled variant: its name and its two loops (OaColumns documents them), per CpuIsa.
struct OaColumnKernels {
    const char* name;
    bool specialised;  ///< compiled for one construction, field kind and offset (false: the generic variant)
    void (*rows[2])(const Pattern&, std::uint32_t pixelSeed, std::uint32_t block, std::uint32_t firstIndex, std::uint32_t count,
                    std::uint32_t* rows);
    void (*values[2])(const Pattern&, std::uint32_t pixelSeed, std::uint32_t dim, std::uint32_t firstIndex, std::uint32_t count,
                      const std::uint32_t* rows, float* out);
};
}  // namespace detail

/// Bulk evaluation of one OA pattern on the CPU, for runs of consecutive samples of one pass.
///
/// A run is the sample indices [firstIndex, firstIndex + count) of one pixel, all in one pass
/// (one OA: firstIndex / N == (firstIndex + count - 1) / N). For each OA block the run touches,
/// rows() gives every sample's row of the block's shuffled array; values() then gives any of that
/// block's dimensions for the whole run. values()[k] == oas::sample(pattern, pixelSeed,
/// firstIndex + k, dim) bit for bit.
class OaColumns {
public:
    /// Throws InvalidArgument when the pattern is not an orthogonal array (the baselines have no
    /// rows or columns). `isa` picks the loops' build (tests run both); where the CPU lacks it,
    /// the baseline build runs.
    explicit OaColumns(const Pattern& pattern, CpuIsa isa = bestCpuIsa());

    /// Rows of block `block` for the run: rows[k] for sample firstIndex + k.
    void rows(std::uint32_t pixelSeed, std::uint32_t block, std::uint32_t firstIndex, std::uint32_t count,
              std::uint32_t* rows) const;
    /// Dimension `dim` for the run, given rows() of the block that holds it (dim / blockDims).
    void values(std::uint32_t pixelSeed, std::uint32_t dim, std::uint32_t firstIndex, std::uint32_t count,
                const std::uint32_t* rows, float* out) const;

    /// The longest run that starts at `firstIndex` and stays in its pass.
    std::uint32_t samplesLeftInPass(std::uint32_t firstIndex) const { return pattern_.N - firstIndex % pattern_.N; }
    const Pattern& pattern() const { return pattern_; }
    /// Whether a variant compiled for this pattern's construction, field kind and offset serves it
    /// (else the generic one, with every pattern switch at run time: patterns with N > 2^16).
    bool specialised() const { return kernels_->specialised; }
    /// The variant's name, e.g. "bose_prime_cmj" (test messages print it).
    const char* variantName() const { return kernels_->name; }
    /// The instruction set asked for and available (a variant that does not vectorize runs its
    /// baseline build for either).
    CpuIsa isa() const { return isa_; }

private:
    Pattern pattern_;
    const detail::OaColumnKernels* kernels_;
    CpuIsa isa_;
};

}  // namespace oas
