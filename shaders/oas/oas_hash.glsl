// oas_hash.glsl - stateless hashing, hashed permutations and exact fixed-point strata.
// Part of the oas GLSL library; include "oas.glsl" rather than this file.
// Shared verbatim with C++ through host/oas/glsl_compat.hpp: keep to the GLSL/C++ common subset
// (scalar uint/float, structs built member by member, no in/out/inout qualifiers).
#ifndef OAS_HASH_GLSL
#define OAS_HASH_GLSL

/// 2^-24 as a float: the one scale that turns 24-bit fixed point into [0,1) exactly.
const float OAS_INV_2POW24 = 5.9604644775390625e-8;
/// One past the largest fixed-point value: outputs are F * 2^-24 with F < 2^24, so never 1.0.
const uint OAS_ONE_FIXED = 16777216u;

/// 32-bit integer hash: the PCG-based hash recommended by Jarzynski and Olano,
/// "Hash Functions for GPU Rendering" (JCGT 2020). A bijection on 32 bits.
uint oas_pcg(uint v)
{
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/// Hash of two words; order matters (oas_hash2(a, b) != oas_hash2(b, a) in general).
uint oas_hash2(uint a, uint b) { return oas_pcg(a ^ oas_pcg(b + 0x9e3779b9u)); }

/// Hash of three words.
uint oas_hash3(uint a, uint b, uint c) { return oas_hash2(oas_hash2(a, b), c); }

/// High 32 bits of the 64-bit product a*b (exact; no 64-bit types needed).
uint oas_mulhi(uint a, uint b)
{
    uint hi;
    uint lo;
    umulExtended(a, b, hi, lo);
    return hi;
}

/// floor(x / d) for any 32-bit x, by a multiply-high and shifts instead of a hardware divide
/// (Granlund and Montgomery, "Division by invariant integers using multiplication", PLDI 1994,
/// section 4): `recip` = floor(2^32 (2^l - d) / d) + 1 and `l` = ceil(log2 d), made once per
/// divisor on the host (oas::makeDivisor). GPUs and lavapipe have no vector integer divide, so
/// every divide by a per-pattern constant goes through here.
uint oas_fastdiv(uint x, uint recip, uint l)
{
    uint t = oas_mulhi(x, recip);
    uint shift1 = l == 0u ? 0u : 1u;
    uint shift2 = l == 0u ? 0u : l - 1u;
    return (t + ((x - t) >> shift1)) >> shift2;
}

/// A seeded pseudo-random permutation of [0, l), evaluated at i (i < l). Bijective for every
/// seed and every l in [1, 2^32). Three steps, each a bijection:
///  1. three keyed rounds on w-bit words, w = ceil(log2 l): xor a key, multiply by an odd key, add a
///     key, xor-shift right, all modulo 2^w;
///  2. cycle-walking (Black and Rogaway 2002, as in Kensler's "Correlated Multi-Jittered
///     Sampling", Pixar Technical Memo 13-01) restricts that bijection of [0, 2^w) to [0, l); as
///     2^w < 2l the walk takes under two passes on average;
///  3. a rotation by r in [0, l) (r = l * hash / 2^32, no division), which makes every input's
///     image uniformly distributed over seeds even for tiny l, where step 1 alone is biased.
/// Kensler's final `(i + p) % l` wraps past 2^32 for p > 2^32 - l and then is no permutation;
/// step 3 compares before adding, so nothing here wraps.
uint oas_permute(uint i, uint l, uint seed)
{
    if (l <= 1u) return 0u;
    uint bits = uint(findMSB(l - 1u)) + 1u;  // w = ceil(log2 l) bits
    uint w = 0xffffffffu >> (32u - bits);
    // About half the word width (at least 1): the xor-shift distance that mixes high bits into low.
    uint shift = (bits + 1u) >> 1u;
    // Round keys from a 32-bit LCG read through its high bits (its low bits have short periods).
    uint k = seed * 0x2c1b3c6du + 0x297a2d39u;
    uint k0 = k ^ (k >> 16u);
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    uint k1 = k ^ (k >> 16u);
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    uint k2 = k ^ (k >> 16u);
    do {
        i = ((i ^ k0) * ((k0 >> 15u) | 1u) + (k0 >> 24u)) & w;
        i ^= i >> shift;
        i = ((i ^ k1) * ((k1 >> 15u) | 1u) + (k1 >> 24u)) & w;
        i ^= i >> shift;
        i = ((i ^ k2) * ((k2 >> 15u) | 1u) + (k2 >> 24u)) & w;
        i ^= i >> shift;
    } while (i >= l);
    uint rotation = oas_mulhi(k * 0x2c1b3c6du + 0x297a2d39u, l);
    return i >= l - rotation ? i - (l - rotation) : i + rotation;
}

/// ceil(m * 2^24 / K) for m <= K and 1 <= K <= 2^24, in 32-bit integers: the smallest 24-bit
/// fixed-point value F with F / 2^24 >= m / K. Long division eight bits at a time keeps every
/// partial remainder below K <= 2^24, so remainder * 256 never overflows.
uint oas_ceil_fixed24(uint m, uint K)
{
    if (m >= K) return OAS_ONE_FIXED;
    if ((K & (K - 1u)) == 0u) {
        // Power of two: an exact shift (K <= 2^24, so the shift distance is >= 0).
        uint shift = 24u;
        uint k = K;
        while (k > 1u) { k >>= 1u; shift -= 1u; }
        return m << shift;
    }
    uint q = 0u;
    uint r = m;
    for (uint step = 0u; step < 3u; ++step) {
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

/// oas_stratum_point with the division by K done by oas_fastdiv (recip, l describe K); the same
/// values, bit for bit. One long division gives both ends of the stratum: the upper end adds
/// floor(2^24 / K) and 2^24 mod K to the lower end's quotient and remainder.
float oas_stratum_point_fast(uint m, uint K, uint recip, uint l, uint u)
{
    uint r = m << 8u;  // m < K <= 2^24, so every r below stays under 2^32
    uint d = oas_fastdiv(r, recip, l);
    uint q = d;
    r = (r - d * K) << 8u;
    d = oas_fastdiv(r, recip, l);
    q = (q << 8u) | d;
    r = (r - d * K) << 8u;
    d = oas_fastdiv(r, recip, l);
    q = (q << 8u) | d;
    r -= d * K;
    uint lo = r != 0u ? q + 1u : q;
    uint stepQ = oas_fastdiv(OAS_ONE_FIXED, recip, l);
    uint r2 = r + (OAS_ONE_FIXED - stepQ * K);
    uint q2 = q + stepQ;
    if (r2 >= K) { r2 -= K; q2 += 1u; }
    uint hi = r2 != 0u ? q2 + 1u : q2;
    return float(lo + oas_mulhi(hi - lo, u)) * OAS_INV_2POW24;
}

/// The 24-bit fixed-point integer behind a float the library returned (x * 2^24, exact).
uint oas_fixed24_of(float x) { return uint(x * 16777216.0); }

#endif // OAS_HASH_GLSL
