/* oas_pattern.h - build the 64-byte OasPattern descriptor from C (C99), or from any language with
 * a C FFI. The GLSL library (shaders/oas/oas.glsl) evaluates samples from this descriptor; this
 * header and oas_pattern.c are the one implementation of every value choice that goes into it
 * (the C++ API, oas::makePattern, wraps them). docs/PATTERN.md specifies the layout word by word,
 * and tests/golden/patterns.json holds request -> words -> first samples vectors for other ports.
 *
 *   OasPattern p;
 *   char why[256];
 *   if (oas_make_pattern(OAS_BOSE, 49, 0, OAS_OFFSET_CMJ, &p, why, sizeof why) != 0)
 *       fprintf(stderr, "%s\n", why);          // names the value and what would be valid
 *   // upload p as is: 16 uint32_t, the GLSL struct OasPattern, std430 / push-constant ready
 *
 * Thread-safe, no allocation, no global state. Link oas_pattern.c (CMake target oas::pattern_c).
 */
#ifndef OAS_PATTERN_H
#define OAS_PATTERN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Byte for byte the GLSL struct OasPattern (shaders/oas/oas_pattern.glsl): the same sixteen
 *  uint32_t in the same order under the same names (tests/pattern_test.cpp reads both sources and
 *  compares the field lists). The C++ oas::Pattern derives from this struct rather than restating it. */
typedef struct OasPattern {
    uint32_t construction;                        /**< OAS_BOSE ... OAS_FAURE */
    uint32_t offset;                              /**< OAS_OFFSET_* (0 for the baselines) */
    uint32_t N;                                   /**< points per pixel in one OA (one pass) */
    uint32_t s;                                   /**< levels per dimension */
    uint32_t strength;                            /**< t */
    uint32_t blockDims;                           /**< dimensions per independently randomized block */
    uint32_t fieldP, fieldK, fieldQ, fieldPoly;   /**< GF(p^k), q = p^k, x^k = poly(x) */
    uint32_t aux, aux2;                           /**< per construction, see docs/PATTERN.md */
    uint32_t recipS, recipP, recipN, recipShifts; /**< division constants for s, p, N */
} OasPattern;

/* The same names and values as the GLSL constants, so code reads the same on both sides. */
enum {
    OAS_BOSE = 1,
    OAS_BUSH = 2,
    OAS_BOSE_BUSH = 3,
    OAS_ADDELMAN_KEMPTHORNE = 4,
    OAS_CMJND = 5,
    OAS_RANDOM = 16,
    OAS_JITTERED_2D = 17,
    OAS_CMJ_2D = 18,
    OAS_ZERO_TWO = 19,
    OAS_HALTON = 20,
    OAS_SOBOL_OWEN = 21,
    OAS_SOBOL = 22,
    OAS_SOBOL_BURLEY = 23,
    OAS_FAURE = 24
};
enum { OAS_OFFSET_CENTERED = 0, OAS_OFFSET_J = 1, OAS_OFFSET_MJ = 2, OAS_OFFSET_CMJ = 3 };
enum {
    OAS_MAX_SAMPLES = 1 << 24, /**< points per pixel: strata stay exact in 24-bit fractions */
    OAS_MAX_BOSE_Q = 4096,     /**< q^2 <= 2^24 */
    OAS_MAX_FIELD_Q = 65535,   /**< products of two field elements fit 32 bits */
    OAS_MAX_STRENGTH = 24,
    OAS_HALTON_BLOCK_DIMS = 32, /**< the GLSL's OAS_HALTON_BLOCK (oas_baselines.glsl) */
    OAS_SOBOL_BLOCK_DIMS = 1024, /**< the dimensions Joe and Kuo's table gives us (oas_joe_kuo.inc);
                                        the GLSL's OAS_SOBOL_BLOCK */
    OAS_SOBOL_BURLEY_GROUP_DIMS = 4, /**< Burley's padding: 4D Sobol groups (OAS_SOBOL_BURLEY_GROUP) */
    OAS_FAURE_MAX_DIGITS = 12        /**< the GLSL's OAS_FAURE_MAX_DIGITS: K <= 12 index digits */
};
/* GLSL cannot include this header, so shaders/oas restates the codes, offsets and block sizes;
 * tests/pattern_test.cpp compiles the GLSL as C++ and static_asserts each value against these. */

/** Status codes (0 is success). */
enum {
    OAS_PATTERN_OK = 0,
    OAS_PATTERN_BAD_ARGUMENT = 1, /**< construction, offset, spp or strength out of range */
    OAS_PATTERN_NOT_EXACT = 2     /**< this construction cannot make exactly `spp` points */
};

/**
 * Builds the pattern for `construction` (OAS_BOSE ... OAS_FAURE) with exactly `spp` points per
 * pixel. `strength` 0 means the default: 2, or for OAS_CMJND the number of dimensions of one full
 * factorial, which must then be given (CMJND has no default).
 * OAS_FAURE, the progressive sampler, is the exception on both counts: its `strength` is d, the
 * dimensions of one block (1 .. OAS_MAX_STRENGTH; 0 means 2), its base q the smallest prime
 * power >= max(d, 2), and N = q^K the smallest power of q >= spp (K <= OAS_FAURE_MAX_DIGITS, N <=
 * OAS_MAX_SAMPLES): the sequence a render takes its first spp samples of. Every prefix of
 * lambda q^m samples is a (0,m,d)-net in each block (docs/DESIGN-NOTES.md). `offset` is OAS_OFFSET_* and is
 * ignored (stored as 0) by the baselines. On failure *out is zeroed and, when why != NULL, a
 * NUL-terminated message (at most whyLen bytes) names the value and the rule it breaks.
 */
int oas_make_pattern(uint32_t construction, uint32_t spp, uint32_t strength, uint32_t offset, OasPattern* out, char* why,
                     size_t whyLen);

/** The constructions in their listing order, the orthogonal arrays first: index 0, 1, ... gives
 *  each code once, then 0 past the last. Tools list samplers in this order. */
uint32_t oas_construction_at(size_t index);
/** Construction code for a sampler name ("bose", "bush", "bose-bush", "addelman-kempthorne",
 *  "cmjnd", "random", "jittered2d", "cmj2d", "zerotwo", "halton", "sobol", "sobol-owen", "sobol-burley",
 *  "faure"); 0 on success. */
int oas_construction_from_name(const char* name, uint32_t* construction);
/** The sampler name of a construction code, or NULL. */
const char* oas_construction_name(uint32_t construction);
/** The name of OasPattern's 32-bit word `word` (0 .. 15, "construction" ... "recipShifts"), as
 *  the struct declares it, for tools that print a pattern; NULL past the last word. */
const char* oas_pattern_field_name(size_t word);

/**
 * The sample counts n in [lo, hi] for which oas_make_pattern(construction, n, strength, ...)
 * succeeds, ascending: the first `capacity` of them are written to out (which may be NULL when
 * capacity is 0) and the return value is how many there are in all, so a caller can size a
 * buffer with a first call. Stated from the construction rules rather than found by trial builds:
 *   bose                OA(q^2, q+1, q, 2), t = 2: n = q^2, q a prime power <= OAS_MAX_BOSE_Q;
 *   bush                OA(q^t, q+1, q, t), t >= 2: n = q^t <= OAS_MAX_SAMPLES, q a prime power >= t;
 *   bose-bush           OA(2q^2, 2q+1, q, 2), t = 2: n = 2q^2 <= OAS_MAX_SAMPLES, q = 2^k >= 2;
 *   addelman-kempthorne OA(2q^2, 2q+1, q, 2), t = 2: n = 2q^2 <= OAS_MAX_SAMPLES, q an odd prime power;
 *   cmjnd               OA(s^t, t, s, t), t >= 1: n = s^t <= OAS_MAX_SAMPLES, any s >= 2;
 *   the baselines       any n in 1 .. OAS_MAX_SAMPLES;
 *   faure               any n up to q^K, the largest power of its base q within OAS_MAX_SAMPLES and
 *                       OAS_FAURE_MAX_DIGITS digits (4096 for q = 2, 531441 for q = 3);
 * and for the OA constructions over GF(q) only the fields whose products the shaders can form in
 * one 32-bit word. `strength` 0 means the default, as for oas_make_pattern (2; none for cmjnd,
 * which then has no counts); an unknown construction or strength > OAS_MAX_STRENGTH has none.
 */
size_t oas_valid_counts(uint32_t construction, uint32_t strength, uint32_t lo, uint32_t hi, uint32_t* out, size_t capacity);

/**
 * What a shader specialized for a pattern is compiled with: the six OAS_STATIC_* values
 * (shaders/oas/oas_pattern.glsl), as consecutive uint32_t, so a VkSpecializationMapEntry's offset
 * is offsetof(OasSpecialization, member). Specializing is what makes the GLSL include fast: an
 * unspecialized shader carries every construction's and field's code, and lavapipe runs both
 * sides of every branch (docs/EMBEDDING.md has the measured factors). A specialized shader given a
 * pattern whose specialization differs returns NaN for every value, never wrong numbers
 * (oas_specialized_value); oas_specialization_matches says beforehand whether it would.
 */
typedef struct OasSpecialization {
    uint32_t construction; /**< OAS_STATIC_CONSTRUCTION: the pattern's construction */
    uint32_t offset;       /**< OAS_STATIC_OFFSET: its offset (0 for the baselines) */
    uint32_t fieldKind;    /**< OAS_STATIC_FIELD_KIND: 0 prime field or none, 1 GF(2^k), k > 1, 2 GF(p^k), p odd, k > 1 */
    uint32_t fieldDegree;  /**< OAS_STATIC_FIELD_DEGREE: k of GF(p^k), 1 with no field */
    uint32_t smallN;       /**< OAS_STATIC_SMALL_N: 1 when N <= 65536, else 0 */
    uint32_t indexBits;    /**< OAS_STATIC_INDEX_BITS: Halton, the bits of N - 1 (its digit loops stop there); faure, K
                                (its index's base-q digits, N = q^K); 24 for the other constructions, whose work does
                                not depend on it (24 takes any N) */
} OasSpecialization;

/** Fills *out with the specialization of `pattern` (made by oas_make_pattern). */
void oas_specialization(const OasPattern* pattern, OasSpecialization* out);
/** 1 when a shader specialized with `spec` gives `pattern`'s values, 0 when it would give NaN: every
 *  value equal, except that smallN = 0 takes any N (its stratum points divide the long way) and
 *  indexBits = B takes every N <= 2^B (for faure, exactly the sequences of K = B digits). */
int oas_specialization_matches(const OasPattern* pattern, const OasSpecialization* spec);

/**
 * Where to put a renderer's 2D sample (a pixel position, a lens or light or BSDF sample): the
 * first dimension d >= from such that dimensions (d, d + 1) lie in one block of `pattern` at an
 * even column. Such a pair is stratified jointly (any two columns of one strength-2 OA block
 * are; columns of different blocks are independent) and, with CMJ offsets, is a correlated
 * multi-jitter partner pair (columns (0,1), (2,3), ... of each block; with an odd blockDims the
 * last column of a block has no partner and the next pair starts the next block). For the
 * padded baselines the pairs are their own (jittered2d, cmj2d, zerotwo: (2p, 2p+1); sobol-burley:
 * within its 4D groups; Halton and Sobol: within their blocks); random has none and gets `from`.
 * 1D samples go anywhere, for instance in the gaps this leaves. The GLSL library's
 * oas_pair_dimension is the same function (tests/pattern_test.cpp compares them).
 */
uint32_t oas_pair_dimension(const OasPattern* pattern, uint32_t from);

/** q = p^k with p prime: returns 1 and sets *p, *k; else 0. */
int oas_prime_power(uint32_t q, uint32_t* p, uint32_t* k);
/** The reduction polynomial g (x^k = g(x), coefficients packed as base-p digits) used for GF(p^k):
 *  the smallest g, counting up, for which x has multiplicative order p^k - 1. 0 for k = 1, and
 *  0 when p is not prime or p^k > 65536. */
uint32_t oas_primitive_polynomial(uint32_t p, uint32_t k);

/** Granlund-Montgomery constants: floor(x / d) == (mulhi(x, recip) + ((x - mulhi) >> 1)) >> (shift - 1)
 *  for every 32-bit x, as oas_fastdiv computes it (shaders/oas/oas_intdiv.glsl); d >= 1. */
void oas_divisor(uint32_t d, uint32_t* recip, uint32_t* shift);

/** The Sobol baseline's direction numbers: OAS_SOBOL_BLOCK_DIMS (1024) x 32 words, [dim * 32 + bit],
 *  bit 0 the most significant (what a shader's OAS_SOBOL_DIRECTION(dim, bit) must return).
 *  Dimension 0 is van der Corput; dimensions 1 .. 1023 are Joe and Kuo's dimensions 2 .. 1024
 *  (new-joe-kuo-6.21201, the set scipy.stats.qmc.Sobol and pbrt use; data/sobol/README.md). */
void oas_sobol_directions(uint32_t out[OAS_SOBOL_BLOCK_DIMS * 32]);

#ifdef __cplusplus
}
#endif

#endif /* OAS_PATTERN_H */
