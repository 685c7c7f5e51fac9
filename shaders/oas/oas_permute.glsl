// oas_permute.glsl - seeded pseudo-random permutations of [0, l) in fixed work: how the library
// shuffles OA rows, levels and sub-strata.
// Part of the oas GLSL library; include "oas.glsl" rather than this file. Depends on
// oas_intdiv.glsl (oas_mulhi).
// Shared verbatim with C++ through host/oas/glsl_compat.hpp: keep to the GLSL/C++ common subset
// (scalar uint/float, structs built member by member, no in/out/inout qualifiers).
#ifndef OAS_PERMUTE_GLSL
#define OAS_PERMUTE_GLSL

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
/// Not Kensler's cycle-walking (restricting a bijection of [0, 2^w) to [0, l) by re-applying it
/// while the value is >= l): its trip count differs between lanes, and it mixes worse. Measured
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

#endif // OAS_PERMUTE_GLSL
