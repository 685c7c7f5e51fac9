// oas_strata.glsl - the library's output format, 24-bit fixed point in [0,1), and exact points
// inside stratum m of K equal strata of [0,1).
// Part of the oas GLSL library; include "oas.glsl" rather than this file. Depends on
// oas_intdiv.glsl (oas_mulhi, oas_fastdiv) and OAS_UNROLL (oas.glsl).
// Shared verbatim with C++ through host/oas/glsl_compat.hpp: keep to the GLSL/C++ common subset
// (scalar uint/float, structs built member by member, no in/out/inout qualifiers).
#ifndef OAS_STRATA_GLSL
#define OAS_STRATA_GLSL

/// 2^-24 as a float: the one scale that turns 24-bit fixed point into [0,1) exactly.
const float OAS_INV_2POW24 = 5.9604644775390625e-8;
/// One past the largest fixed-point value: outputs are F * 2^-24 with F < 2^24, so never 1.0.
const uint OAS_ONE_FIXED = 16777216u;
// Whether oas_stratum_point_fast may take its one-division path, which needs K <= 2^16. With
// OAS_STATIC_SMALL_N (oas_pattern.glsl: 1 when the pattern's N <= 2^16, which bounds every K the
// library passes, since s, N and a 2D grid's sides are all at most N) the choice is made at
// compile time. The C++ twin (OAS_RUNTIME_BRANCHES) tests K: a CPU branch is cheap. Otherwise the
// long division runs for every K, as before: testing K at run time cost lavapipe 5-14%, since it
// runs both paths (measured on oas-bench's OA rows).
#if defined(OAS_STATIC_SMALL_N)
#define OAS_SMALL_STRATA(K) (OAS_STATIC_SMALL_N != 0u)
#elif defined(OAS_RUNTIME_BRANCHES)
#define OAS_SMALL_STRATA(K) ((K) <= 65536u)
#else
#define OAS_SMALL_STRATA(K) false
#endif
// The same test for a K that the pattern's N does not bound (Halton's base^digits can pass 2^16
// with N <= 2^16): the C++ twin's branch, or the long division.
#if defined(OAS_RUNTIME_BRANCHES)
#define OAS_SMALL_STRATA_ANY_N(K) ((K) <= 65536u)
#else
#define OAS_SMALL_STRATA_ANY_N(K) false
#endif

/// ceil(m * 2^24 / K) for m <= K and 1 <= K <= 2^24, in 32-bit integers: the smallest 24-bit
/// fixed-point value F with F / 2^24 >= m / K. Long division eight bits at a time keeps every
/// partial remainder below K <= 2^24, so remainder * 256 never overflows.
uint oas_ceil_fixed24(uint m, uint K)
{
    if (m >= K) return OAS_ONE_FIXED;
    if ((K & (K - 1u)) == 0u) return m << (24u - uint(findMSB(K)));  // power of two: exact shift
    uint q = 0u;
    uint r = m;
    OAS_UNROLL for (uint step = 0u; step < 3u; ++step) {
        r <<= 8u;
        uint d = r / K;
        q = (q << 8u) | d;
        r -= d * K;
    }
    return r != 0u ? q + 1u : q;
}

/// A point of stratum m of K equal strata of [0,1), placed by the 32-bit fraction u (u = 2^31
/// is the stratum's centre). Guarantees m/K <= x < (m+1)/K exactly as real numbers and x < 1,
/// for every K <= 2^24: the result is F * 2^-24 with F in [ceil(m 2^24/K), ceil((m+1) 2^24/K)),
/// a non-empty range because a shift-open interval of width >= 2^-24 holds a multiple of 2^-24.
float oas_stratum_point(uint m, uint K, uint u)
{
    uint lo = oas_ceil_fixed24(m, K);
    uint hi = oas_ceil_fixed24(m + 1u, K);
    return float(lo + oas_mulhi(hi - lo, u)) * OAS_INV_2POW24;
}

/// oas_stratum_point_fast's work with its path chosen by the caller: shortDivision needs K <=
/// 2^16 (the one-division path); false takes the long division, exact for every K <= 2^24.
float oas_stratum_point_divided(uint m, uint K, uint recip, uint l, uint u, bool shortDivision)
{
    uint stepQ = oas_fastdiv(OAS_ONE_FIXED, recip, l);  // A
    uint stepR = OAS_ONE_FIXED - stepQ * K;             // B
    uint q;
    uint r;
    if (shortDivision) {
        uint product = m * stepR;  // < K^2 <= 2^32
        uint d = oas_fastdiv(product, recip, l);
        q = m * stepQ + d;
        r = product - d * K;
    } else {
        r = m << 8u;  // m < K <= 2^24, so every r below stays under 2^32
        uint d = oas_fastdiv(r, recip, l);
        q = d;
        r = (r - d * K) << 8u;
        d = oas_fastdiv(r, recip, l);
        q = (q << 8u) | d;
        r = (r - d * K) << 8u;
        d = oas_fastdiv(r, recip, l);
        q = (q << 8u) | d;
        r -= d * K;
    }
    uint lo = r != 0u ? q + 1u : q;
    uint r2 = r + stepR;
    uint q2 = q + stepQ;
    if (r2 >= K) { r2 -= K; q2 += 1u; }
    uint hi = r2 != 0u ? q2 + 1u : q2;
    return float(lo + oas_mulhi(hi - lo, u)) * OAS_INV_2POW24;
}

/// oas_stratum_point with the division by K done by oas_fastdiv (recip, l describe K); the same
/// values, bit for bit. With A = floor(2^24 / K) and B = 2^24 mod K, m 2^24 = m A K + m B, so
/// ceil(m 2^24 / K) = m A + ceil(m B / K), and m B < K^2 fits 32 bits for K <= 2^16: one division
/// of m B (A does not depend on m, so it is off the value's critical path). Otherwise a long
/// division eight bits at a time: three dependent divisions. Either way the upper end m + 1 adds
/// A and B to the lower end's quotient and remainder. Which path runs is OAS_SMALL_STRATA(K)
/// (oas_pattern.glsl): a shader specialised on the pattern (OAS_STATIC_SMALL_N) compiles one path;
/// an unspecialised shader takes the long division, as lavapipe would run both sides of a branch.
float oas_stratum_point_fast(uint m, uint K, uint recip, uint l, uint u)
{
    return oas_stratum_point_divided(m, K, recip, l, u, OAS_SMALL_STRATA(K));
}

#endif // OAS_STRATA_GLSL
