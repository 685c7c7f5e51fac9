// OaColumns: picks the compiled variant (oa_columns_variant.inc) for a pattern and checks runs.
#include "oas/oa_columns.hpp"

#include <string>

#include "oas/glsl_compat.hpp"
#include "oas/oa_columns_variants.hpp"

namespace oas {
namespace detail {
#define OAS_DECLARE_KERNELS(name)                                                                                                \
    namespace name {                                                                                                             \
    extern const OaColumnKernels kernels;                                                                                        \
    }
#define OAS_DECLARE_VARIANT(name, variantConstruction, variantFieldKind)                                                         \
    OAS_DECLARE_KERNELS(name##_centered)                                                                                         \
    OAS_DECLARE_KERNELS(name##_j)                                                                                                \
    OAS_DECLARE_KERNELS(name##_mj)                                                                                               \
    OAS_DECLARE_KERNELS(name##_cmj)
OAS_OA_COLUMN_VARIANTS(OAS_DECLARE_VARIANT)
#define OAS_DECLARE_DEGREE_VARIANT(name, variantConstruction, degree) OAS_DECLARE_KERNELS(name##_cmj_k##degree)
OAS_OA_COLUMN_DEGREE_VARIANTS(OAS_DECLARE_DEGREE_VARIANT)
#undef OAS_DECLARE_DEGREE_VARIANT
OAS_DECLARE_KERNELS(generic)
#undef OAS_DECLARE_VARIANT
#undef OAS_DECLARE_KERNELS
}  // namespace detail

namespace {
const detail::OaColumnKernels* kernelsFor(const Pattern& p)
{
    using namespace glsl;
    // The specialised variants (one per construction, field kind and offset, and the binary ones
    // per degree for CMJ offsets, which go first) assume N <= 2^16 (OAS_STATIC_SMALL_N); larger
    // patterns (the hard cases, never a renderer's pixel) take the generic variant.
    if (smallN(p) == 1u) {
#define OAS_MATCH_DEGREE_VARIANT(name, variantConstruction, degree)                                                              \
    if (p.construction == (variantConstruction) && fieldKind(p) == OAS_FIELD_BINARY && fieldDegree(p) == (degree) &&             \
        p.offset == OAS_OFFSET_CMJ)                                                                                              \
        return &detail::name##_cmj_k##degree::kernels;
        OAS_OA_COLUMN_DEGREE_VARIANTS(OAS_MATCH_DEGREE_VARIANT)
#undef OAS_MATCH_DEGREE_VARIANT
#define OAS_MATCH_VARIANT(name, variantConstruction, variantFieldKind)                                                           \
    if (p.construction == (variantConstruction) && fieldKind(p) == (variantFieldKind)) {                                         \
        const detail::OaColumnKernels* const byOffset[] = {&detail::name##_centered::kernels, &detail::name##_j::kernels,        \
                                                           &detail::name##_mj::kernels, &detail::name##_cmj::kernels};           \
        if (p.offset < 4) return byOffset[p.offset];                                                                             \
    }
        OAS_OA_COLUMN_VARIANTS(OAS_MATCH_VARIANT)
#undef OAS_MATCH_VARIANT
    }
    return &detail::generic::kernels;
}

void checkRun(const Pattern& p, std::uint32_t firstIndex, std::uint32_t count)
{
    if (count > p.N - firstIndex % p.N)
        throw InvalidArgument("OaColumns: the run of " + std::to_string(count) + " samples from index " +
                              std::to_string(firstIndex) + " leaves its pass (N = " + std::to_string(p.N) + "); at most " +
                              std::to_string(p.N - firstIndex % p.N) + " fit");
}
}  // namespace

CpuIsa bestCpuIsa()
{
#if OAS_CPU_HAS_AVX2_VARIANT
    if (__builtin_cpu_supports("avx2")) return CpuIsa::Avx2;
#endif
    return CpuIsa::Baseline;
}

OaColumns::OaColumns(const Pattern& pattern, CpuIsa isa)
    : pattern_(pattern), kernels_(kernelsFor(pattern)), isa_(isa == CpuIsa::Avx2 ? bestCpuIsa() : CpuIsa::Baseline)
{
    if (pattern.construction >= glsl::OAS_RANDOM)
        throw InvalidArgument("OaColumns: pattern construction " + std::to_string(pattern.construction) +
                              " is a baseline, not an orthogonal array (valid: 1-5)");
}

void OaColumns::rows(std::uint32_t pixelSeed, std::uint32_t block, std::uint32_t firstIndex, std::uint32_t count,
                     std::uint32_t* rows) const
{
    checkRun(pattern_, firstIndex, count);
    kernels_->rows[int(isa_)](pattern_, pixelSeed, block, firstIndex, count, rows);
}

void OaColumns::values(std::uint32_t pixelSeed, std::uint32_t dim, std::uint32_t firstIndex, std::uint32_t count,
                       const std::uint32_t* rows, float* out) const
{
    checkRun(pattern_, firstIndex, count);
    kernels_->values[int(isa_)](pattern_, pixelSeed, dim, firstIndex, count, rows, out);
}

}  // namespace oas
