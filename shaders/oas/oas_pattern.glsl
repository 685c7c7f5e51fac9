// oas_pattern.glsl - the pattern descriptor shared by the host and every shader.
// Part of the oas GLSL library; include "oas.glsl" rather than this file.
#ifndef OAS_PATTERN_GLSL
#define OAS_PATTERN_GLSL

// Constructions (orthogonal arrays, Jarosz et al. 2019 section 4) ...
const uint OAS_BOSE = 1u;                 ///< OA(q^2, q+1, q, 2), Bose 1938
const uint OAS_BUSH = 2u;                 ///< OA(q^t, q+1, q, t), Bush 1952
const uint OAS_BOSE_BUSH = 3u;            ///< OA(2q^2, 2q+1, q, 2), q = 2^k, Bose and Bush 1952
const uint OAS_ADDELMAN_KEMPTHORNE = 4u;  ///< OA(2q^2, 2q+1, q, 2), q odd, Addelman and Kempthorne 1961
const uint OAS_CMJND = 5u;                ///< OA(s^d, d, s, d): full factorial, the paper's CMJND
// ... and the baselines behind the same interface.
const uint OAS_RANDOM = 16u;              ///< independent uniform samples
const uint OAS_JITTERED_2D = 17u;         ///< jittered nx*ny grid per dimension pair, padded
const uint OAS_CMJ_2D = 18u;              ///< Kensler 2013 correlated multi-jitter per pair, padded
const uint OAS_ZERO_TWO = 19u;            ///< Owen-scrambled (0,2)-sequence per pair, padded
const uint OAS_HALTON = 20u;              ///< Halton with random digit permutations
const uint OAS_SOBOL_OWEN = 21u;          ///< Sobol, per-bit nested uniform (Owen) scramble (needs OAS_SOBOL_DIRECTION)
const uint OAS_SOBOL = 22u;               ///< Sobol, hash-based Owen scramble, Burley 2020 (needs OAS_SOBOL_DIRECTION)
const uint OAS_SOBOL_BURLEY = 23u;        ///< Burley 2020: padded 4D Owen-scrambled Sobol, hash-shuffled (no table)
// ... and the progressive sampler (oas_faure.glsl), which takes the baselines' per-value path.
const uint OAS_FAURE = 24u;               ///< Owen-scrambled generalized Faure (0,s)-sequence in base q, any prefix

// Offsets: where a point sits inside its OA stratum.
const uint OAS_OFFSET_CENTERED = 0u;  ///< centre of the stratum
const uint OAS_OFFSET_J = 1u;         ///< uniform jitter inside the stratum
const uint OAS_OFFSET_MJ = 2u;        ///< multi-jittered: N-strata Latin hypercube in 1D
const uint OAS_OFFSET_CMJ = 3u;       ///< correlated multi-jittered: one substratum permutation per dimension

/// Everything a shader needs to evaluate one sampler. Sixteen uints (64 bytes), so it fits a push
/// constant block or a std140/std430 buffer as is. Build it on the host (oas_make_pattern in C,
/// oas::makePattern in C++), which validates the parameters; the shader trusts it. The host's
/// struct is OasPattern in host/oas/oas_pattern.h, these words in this order: a field added here
/// goes there too (tests/pattern_test.cpp reads both and fails when they differ).
struct OasPattern {
    uint construction; ///< OAS_BOSE ... OAS_FAURE
    uint offset;       ///< OAS_OFFSET_* (OA constructions only)
    uint N;            ///< points per pixel (one OA); sample indices >= N start fresh OAs
    uint s;            ///< levels (strata) per dimension of the OA
    uint strength;     ///< t: every t-dimensional projection is stratified
    uint blockDims;    ///< dimensions one OA covers; dimension d uses block d / blockDims
    uint fieldP;       ///< the OA's field GF(p^k): characteristic
    uint fieldK;       ///<   degree
    uint fieldQ;       ///<   size p^k
    uint fieldPoly;    ///<   reduction polynomial (see OasField)
    uint aux;          ///< Bush: q^(t-1); Addelman-Kempthorne: a non-square of GF(q); 2D baselines: nx
    uint aux2;         ///< OAs: N / s (substrata per stratum); 2D baselines: ny
    uint recipS;       ///< oas_fastdiv constants for dividing by s, p and N ...
    uint recipP;
    uint recipN;
    uint recipShifts;  ///< ... and their shifts l: s in bits 0-7, p in 8-15, N in 16-23
};

// A shader that evaluates one kind of pattern can fix these at compile time (for instance with
// specialization constants) by defining OAS_STATIC_CONSTRUCTION, OAS_STATIC_OFFSET,
// OAS_STATIC_FIELD_KIND, OAS_STATIC_FIELD_DEGREE (fieldK, or 1 where the pattern has no field),
// OAS_STATIC_SMALL_N (1 when N <= 65536, else 0) and OAS_STATIC_INDEX_BITS (Halton: the bits of
// N - 1, which bound its digit loops; 24 for the others, whose work does not depend on it) before
// including oas.glsl (oas_specialization in oas_pattern.h fills them). A pattern whose own values differ gets NaN for every value
// (oas_specialized_value below), not another kind's code run on its words.
// Software rasterisers such as lavapipe run both sides of every branch, so folding the branches
// of the constructions a shader does not use is what makes it fast there.
#ifdef OAS_STATIC_CONSTRUCTION
#define OAS_CONSTRUCTION(pat) OAS_STATIC_CONSTRUCTION
#else
#define OAS_CONSTRUCTION(pat) ((pat).construction)
#endif
#ifdef OAS_STATIC_OFFSET
#define OAS_OFFSET(pat) OAS_STATIC_OFFSET
#else
#define OAS_OFFSET(pat) ((pat).offset)
#endif

/// Whether `pat` is a pattern this shader's specialization was made for: every OAS_STATIC_* the
/// shader defines equals the pattern's own value (oas_specialization in oas_pattern.h fills them;
/// a shader with OAS_STATIC_SMALL_N = 0 takes any N, its stratum points divide the long way; one
/// with OAS_STATIC_INDEX_BITS = B takes every N <= 2^B, or for faure the sequences of K = B digits).
/// Always true in a shader without OAS_STATIC_*. Lanes that share a pattern agree, so a shader
/// may branch on it (to paint an error colour, say).
bool oas_specialization_matches(OasPattern pat)
{
    bool b = true;  // short names only: an includer's macro named like a local breaks the include (oas.glsl)
#ifdef OAS_STATIC_CONSTRUCTION
    b = b && pat.construction == OAS_STATIC_CONSTRUCTION;
#endif
#ifdef OAS_STATIC_OFFSET
    b = b && pat.offset == OAS_STATIC_OFFSET;
#endif
#ifdef OAS_STATIC_FIELD_KIND  // OAS_FIELD_PRIME (k <= 1: also no field), _BINARY, _ODD_EXTENSION
    b = b && (pat.fieldK <= 1u ? 0u : (pat.fieldP == 2u ? 1u : 2u)) == OAS_STATIC_FIELD_KIND;
#endif
#ifdef OAS_STATIC_FIELD_DEGREE
    b = b && (pat.fieldK <= 1u ? 1u : pat.fieldK) == OAS_STATIC_FIELD_DEGREE;
#endif
#ifdef OAS_STATIC_SMALL_N
    b = b && (OAS_STATIC_SMALL_N == 0u || pat.N <= 65536u);
#endif
#ifdef OAS_STATIC_INDEX_BITS  // every index < N fits the bits (24 or more: any N); faure: its K digits
    b = b && (OAS_STATIC_INDEX_BITS >= 24u ||
              (OAS_CONSTRUCTION(pat) == OAS_FAURE ? pat.aux == OAS_STATIC_INDEX_BITS : ((pat.N - 1u) >> OAS_STATIC_INDEX_BITS) == 0u));
#endif
    return b;
}

/// A sample value as the library returns it: v where the pattern matches the shader's
/// specialization, NaN where it does not. A specialized shader compiles only its pattern kind's
/// code, so it cannot make another kind's values; NaN, where the contract otherwise promises
/// [0, 1), is what an image or a host check cannot mistake for samples (a plausible image with
/// wrong values was what a mismatch gave before version 0.3). Without OAS_STATIC_* this is
/// v, and the comparison folds away; with them it is a few comparisons of uniform words.
float oas_specialized_value(OasPattern pat, float v)
{
    return oas_specialization_matches(pat) ? v : uintBitsToFloat(0x7fc00000u);
}

/// The first dimension d >= `dim` where a 2D sample (d, d + 1) is a stratified pair of the
/// pattern: both in one block, at an even column (Bose CMJ's partners (0,1), (2,3), ... of each
/// block; the padded baselines' own pairs); `dim` for random. The C API's oas_pair_dimension
/// (oas_pattern.h says more), the same function: tests/pattern_test.cpp compares them.
uint oas_pair_dimension(OasPattern pat, uint dim)
{
    if (pat.blockDims < 2u) return dim;
    uint block = dim / pat.blockDims;
    uint col = dim - block * pat.blockDims;
    col += col & 1u;
    if (col + 1u >= pat.blockDims) {
        block += 1u;
        col = 0u;
    }
    return block * pat.blockDims + col;
}

/// floor(x / s), floor(x / N) for the pattern's s and N.
uint oas_div_s(OasPattern pat, uint x) { return oas_fastdiv(x, pat.recipS, pat.recipShifts & 0xffu); }
uint oas_div_n(OasPattern pat, uint x) { return oas_fastdiv(x, pat.recipN, (pat.recipShifts >> 16u) & 0xffu); }

#endif // OAS_PATTERN_GLSL
