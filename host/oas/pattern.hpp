#pragma once
// Host side of the sampler library: building validated OasPattern descriptors, listing valid
// sample counts, choosing the best orthogonal array for a request, and the CPU reference
// generator (which runs the shared GLSL code, see glsl_compat.hpp).
#include <cstdint>
#include <tuple>
#include <stdexcept>
#include <string>
#include <vector>

#include "oas/oas_pattern.h"

namespace oas {

/// Bad parameters: the message names the parameter, the value and the valid range or nearest
/// valid values. Tools print it and exit with status 2.
struct InvalidArgument : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// The C builder's OasPattern (oas/oas_pattern.h, byte for byte the GLSL struct of
/// shaders/oas/oas_pattern.glsl); upload as is. Derived rather than restated, so the layout has
/// one definition; the constructors only add what C lacks: zeroed words by default, and taking
/// an OasPattern the C builder filled.
struct Pattern : OasPattern {
    Pattern() : OasPattern{} {}
    Pattern(const OasPattern& built) : OasPattern(built) {}
};

/// Constants for oas_fastdiv (Granlund-Montgomery): floor(x / d) == oas_fastdiv(x, recip, shift).
struct Divisor {
    std::uint32_t recip = 0, shift = 0;
};
Divisor makeDivisor(std::uint32_t d);
static_assert(sizeof(Pattern) == sizeof(OasPattern), "oas::Pattern adds no words to OasPattern");

/// Largest points per pixel: the exact-strata limit (K <= 2^24 strata per dimension).
constexpr std::uint32_t kMaxSamples = OAS_MAX_SAMPLES;
/// Largest Bose q: q^2 <= 2^24.
constexpr std::uint32_t kMaxBoseQ = OAS_MAX_BOSE_Q;
/// Field sizes stay below 2^16 so that products of two elements fit 32 bits.
constexpr std::uint32_t kMaxFieldQ = OAS_MAX_FIELD_Q;
/// Most dimensions the tools generate per point (the library itself takes any 32-bit dim).
constexpr std::uint32_t kMaxDims = 4096;

/// What a user asks for. sampler: one of samplerNames(), or "oa" for the best OA (chooser).
/// strength 0 means the sampler's default (2; CMJND: the number of dims).
struct PatternRequest {
    std::string sampler = "oa";
    std::uint32_t spp = 0;
    std::uint32_t dims = 2;
    std::uint32_t strength = 0;
    std::string offset = "cmj";  ///< centered | j | mj | cmj (OA constructions only)
    bool roundUp = false;        ///< allow the next valid spp when spp cannot be made exactly
};

/// Names accepted in PatternRequest::sampler (besides "oa").
const std::vector<std::string>& samplerNames();
/// One line per sampler saying what it is.
std::string samplerDescription(const std::string& name);
/// True for the orthogonal-array constructions.
bool isOrthogonalArray(const std::string& name);

/// The OAS_STATIC_* values a shader specialized for the pattern is compiled with (the C API's
/// oas_specialization, the one definition).
inline OasSpecialization specialization(const Pattern& p)
{
    OasSpecialization s;
    oas_specialization(&p, &s);
    return s;
}
/// The pattern's field kind for OAS_STATIC_FIELD_KIND specialization: 0 prime (or no field),
/// 1 GF(2^k) with k > 1, 2 odd extension field (OAS_FIELD_* in shaders/oas/oas_gf.glsl).
inline std::uint32_t fieldKind(const Pattern& p) { return specialization(p).fieldKind; }
/// The pattern's field degree for OAS_STATIC_FIELD_DEGREE specialization: k of GF(p^k), 1 when
/// the pattern has no field (its field loops are never reached).
inline std::uint32_t fieldDegree(const Pattern& p) { return specialization(p).fieldDegree; }
/// OAS_STATIC_SMALL_N for the pattern: 1 when N <= 2^16, so that every stratum count the library
/// divides by fits the stratum point's one-division path (shaders/oas/oas_strata.glsl).
inline std::uint32_t smallN(const Pattern& p) { return specialization(p).smallN; }
/// OAS_STATIC_INDEX_BITS for the pattern: for Halton the bits of N - 1, which bound its digit
/// loops (shaders/oas/oas_baselines.glsl); for faure K, its index's base-q digits (oas_faure.glsl);
/// 24, any N, for the others.
inline std::uint32_t indexBits(const Pattern& p) { return specialization(p).indexBits; }
/// What a GPU pipeline is specialized on (construction, offset, field kind, field degree, small
/// N, index bits): two patterns with the same key run on the same pipeline, the rest of the
/// pattern being push constants.
using SpecializationKey = std::tuple<std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>;
inline SpecializationKey specializationKey(const Pattern& p)
{
    const OasSpecialization s = specialization(p);
    return {s.construction, s.offset, s.fieldKind, s.fieldDegree, s.smallN, s.indexBits};
}

/// Sobol direction numbers, OAS_SOBOL_BLOCK_DIMS (1024) dimensions x 32 bits, [dim * 32 + bit], bit 0
/// the most significant. Dimension 0 is van der Corput; dimension j >= 1 is Joe and Kuo's
/// dimension j + 1 (new-joe-kuo-6.21201, chosen for good 2D projections; the set scipy and pbrt
/// use), so dimension 1 (x + 1, m = 1) makes the (0,2)-sequence with dimension 0. Unscrambled,
/// the points equal scipy.stats.qmc.Sobol(scramble=False)'s bit for bit (tests/sobol_scipy_test.py).
const std::vector<std::uint32_t>& sobolDirections();

/// Validated pattern for the request; throws InvalidArgument naming the nearest valid spp.
Pattern makePattern(const PatternRequest& request);
/// The chooser behind sampler "oa": the pattern and a human explanation of the choice.
struct Choice {
    Pattern pattern;
    std::string sampler;
    std::string explanation;
};
Choice chooseOrthogonalArray(const PatternRequest& request);

/// Sample counts in [lo, hi] the sampler makes exactly with this strength and dims: the C
/// builder's rules (oas_valid_counts); for a baseline, which takes every count, the first 64.
std::vector<std::uint32_t> validCounts(const std::string& sampler, std::uint32_t strength, std::uint32_t dims, std::uint32_t lo,
                                       std::uint32_t hi);

/// "bose q=11 N=121 t=2 cmj, 12 dims/block", for logs and headers.
std::string describe(const Pattern& pattern);
/// What the first `spp` samples of a progressive pattern (faure) guarantee, in a sentence: the
/// largest lambda q^m <= spp and the nets it holds; "" for the other samplers, whose N is spp.
std::string prefixGuarantee(const Pattern& pattern, std::uint32_t spp);
/// Sampler name of a pattern's construction code.
std::string constructionName(std::uint32_t construction);

/// Prime-power decomposition: q = p^k with p prime, or {0, 0}.
struct PrimePower {
    std::uint32_t p = 0, k = 0;
};
PrimePower primePower(std::uint32_t q);
/// The reduction polynomial g (x^k = g(x)) the library uses for GF(p^k): the first in counting
/// order for which x is primitive. Throws for p^k > kMaxFieldQ.
std::uint32_t primitivePolynomial(std::uint32_t p, std::uint32_t k);

/// One point set laid out [pixel][sample][dim], pixel = y * width + x over the given rectangle.
struct SampleRequest {
    std::uint32_t x0 = 0, y0 = 0, width = 1, height = 1;
    std::uint32_t spp = 1;  ///< samples per pixel (indices >= N use further passes)
    std::uint32_t dims = 2;
    std::uint32_t seed = 0;         ///< user seed mixed into every pixel seed
    std::uint32_t firstSample = 0;  ///< sample indices [firstSample, firstSample + spp)
    /// Bit d set: dimension d (< 32) is read by nobody, so the GPU generator's baselines need not
    /// make it (its elements are then left as they were). A path tracer's plan leaves such gaps
    /// (alignment, padding to whole texels). The padded 2D baselines make a pair whole where
    /// either of its dimensions is read; the OAs make every dimension (the block's row serves its
    /// columns); generateCpu makes every dimension.
    std::uint32_t unreadDims = 0;
};

/// Pixel seed (oas_pixel_seed) for pixel (x, y) and user seed.
std::uint32_t pixelSeed(std::uint32_t x, std::uint32_t y, std::uint32_t seed);
/// One sample value, on the CPU (the shared GLSL code).
float sample(const Pattern& pattern, std::uint32_t pixelSeed, std::uint32_t index, std::uint32_t dim);
/// Whole point sets on the CPU, `threads` worker threads (0: all hardware threads).
void generateCpu(const Pattern& pattern, const SampleRequest& request, float* out, unsigned threads = 0);

}  // namespace oas
