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

/// High 32 bits of the 64-bit product a*b from 16-bit limbs: for targets without umulExtended
/// (WGSL, some shading-language translators). Define OAS_MULHI as oas_mulhi_portable there.
uint oas_mulhi_portable(uint a, uint b)
{
    uint aLo = a & 0xffffu;
    uint aHi = a >> 16u;
    uint bLo = b & 0xffffu;
    uint bHi = b >> 16u;
    uint lowLow = aLo * bLo;
    uint cross1 = aHi * bLo;
    uint cross2 = aLo * bHi;
    // The middle column: the carry out of the low 32 bits, summed without overflow.
    uint middle = (lowLow >> 16u) + (cross1 & 0xffffu) + (cross2 & 0xffffu);
    return aHi * bHi + (cross1 >> 16u) + (cross2 >> 16u) + (middle >> 16u);
}

/// High 32 bits of the 64-bit product a*b (exact; no 64-bit types needed). An includer may define
/// OAS_MULHI(a, b) to supply its own (for instance oas_mulhi_portable).
uint oas_mulhi(uint a, uint b)
{
#ifdef OAS_MULHI
    return OAS_MULHI(a, b);
#else
    uint hi;
    uint lo;
    umulExtended(a, b, hi, lo);
    return hi;
#endif
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

/// The oas_fastdiv reciprocal of a divisor d in [1, 2^16] whose shift l = ceil(log2 d) is given:
/// floor(2^32 (2^l - d) / d) + 1 by long division in two 16-bit steps (2^l - d < d, so each
/// partial dividend fits 32 bits). For divisors known only in the shader (Halton's bases): two
/// integer divisions once, instead of one per use.
uint oas_fastdiv_recip(uint d, uint l)
{
    uint n = (l == 32u ? 0u : (1u << l)) - d;
    uint high = (n << 16u) / d;
    uint low = (((n << 16u) - high * d) << 16u) / d;
    return (high << 16u) + low + 1u;
}

/// A seeded pseudo-random permutation of [0, l), l in [1, 2^32), with its keys made once
/// (oas_permutation) and applied to any number of inputs (oas_permutation_apply) in fixed work:
/// no loops and no data-dependent trip counts, so SIMD lanes stay in lock step and no iteration
/// cap (lavapipe ends every invocation's loops after 65535 iterations) can be reached. Four steps,
/// each a bijection of [0, l), then a rotation:
///  1. a keyed mix of the window [0, h), h = 2^floor(log2 l) > l/2 (xor a key, multiply by an odd
///     key, add a key, xor-shift right, all mod h; values >= h are left alone), which scrambles bits;
///  2. a swap-or-not round (Hoang, Morris and Rogaway, "An enciphering scheme based on a card
///     shuffle", CRYPTO 2012): every x is paired with pivot - x mod l and the pair swaps when a
///     keyed hash of the pair's larger member says so, which moves values across the whole range;
///  3. after the four steps, a rotation by r in [0, l) (r = l * key / 2^32, no division) makes every
///     input's image exactly uniform over seeds, even for tiny l.
/// This replaced Kensler's cycle-walking (restricting a bijection of [0, 2^w) to [0, l) by
/// re-applying it while the value is >= l), whose trip count differs between lanes. Measured
/// against uniform permutations, pairs (x, y) land on differences pi(x) - pi(y) mod l with
/// chi^2/dof 0.8-1.4 for l <= 49 and 3.4 at l = 121, against 6-30 and 4.7 for the cycle walk
/// (uniform: 1.0); tests/permutation_quality_test.cpp checks integration error against
/// std::shuffle. Nothing here wraps: comparisons come before every modular add.
struct OasPermutation {
    uint l;      ///< length
    uint mask;   ///< h - 1
    uint shift;  ///< xor-shift distance, about half of log2 h
    uint key0;   ///< step keys
    uint key1;
    uint key2;
    uint key3;
    uint pivot0; ///< swap-or-not pivots in [0, l)
    uint pivot1;
    uint pivot2;
    uint pivot3;
    uint rotation;
};

/// The keys of the permutation of [0, l) for `seed` (a 32-bit LCG read through its high bits
/// makes the step keys; its low bits alone would have short periods).
OasPermutation oas_permutation(uint l, uint seed)
{
    OasPermutation p;
    p.l = l;
    uint bits = l == 0u ? 0u : uint(findMSB(l));  // h = 2^bits <= l
    p.mask = (1u << bits) - 1u;
    p.shift = (bits + 1u) >> 1u;
    uint k = seed * 0x2c1b3c6du + 0x297a2d39u;
    p.key0 = k ^ (k >> 16u);
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    p.key1 = k ^ (k >> 16u);
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    p.key2 = k ^ (k >> 16u);
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    p.key3 = k ^ (k >> 16u);
    p.pivot0 = oas_mulhi(p.key0 * 0x2c1b3c6du + 0x297a2d39u, l);
    p.pivot1 = oas_mulhi(p.key1 * 0x2c1b3c6du + 0x297a2d39u, l);
    p.pivot2 = oas_mulhi(p.key2 * 0x2c1b3c6du + 0x297a2d39u, l);
    p.pivot3 = oas_mulhi(p.key3 * 0x2c1b3c6du + 0x297a2d39u, l);
    p.rotation = oas_mulhi(k * 0x2c1b3c6du + 0x297a2d39u, l);
    return p;
}

/// One step of oas_permutation_apply: the window mix, then the swap-or-not round.
uint oas_permutation_step(OasPermutation p, uint i, uint key, uint pivot)
{
    uint mixed = ((i ^ key) * ((key >> 15u) | 1u) + (key >> 24u)) & p.mask;
    mixed ^= mixed >> p.shift;
    i = i <= p.mask ? mixed : i;
    uint partner = i <= pivot ? pivot - i : pivot + (p.l - i);
    uint hashed = ((i > partner ? i : partner) ^ key) * 0x7feb352du;
    hashed = (hashed ^ (hashed >> 15u)) * 0x846ca68bu;
    return (hashed >> 31u) != 0u ? partner : i;
}

/// The image of i (< p.l) under the permutation p.
uint oas_permutation_apply(OasPermutation p, uint i)
{
    if (p.l <= 1u) return 0u;
    i = oas_permutation_step(p, i, p.key0, p.pivot0);
    i = oas_permutation_step(p, i, p.key1, p.pivot1);
    i = oas_permutation_step(p, i, p.key2, p.pivot2);
    i = oas_permutation_step(p, i, p.key3, p.pivot3);
    return i >= p.l - p.rotation ? i - (p.l - p.rotation) : i + p.rotation;
}

/// oas_permutation(l, seed) applied to i (< l): the one-shot form.
uint oas_permute(uint i, uint l, uint seed) { return oas_permutation_apply(oas_permutation(l, seed), i); }

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

#endif // OAS_HASH_GLSL
