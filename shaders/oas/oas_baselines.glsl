// oas_baselines.glsl - the samplers OA sampling is compared against, behind the same interface.
// Part of the oas GLSL library; include "oas.glsl" rather than this file.
#ifndef OAS_BASELINES_GLSL
#define OAS_BASELINES_GLSL

/// Bits of a sample index within one pass (index < N <= 2^24): the fixed trip count of the
/// per-bit loops below, whatever N is.
const uint OAS_INDEX_BITS = 24u;

/// Whether digit k (base 2 or more) of a sample index can be nonzero: index < N <= 2^B has no
/// digit at k >= B in any base, since base^k >= 2^k. A shader that knows B (OAS_STATIC_INDEX_BITS,
/// oas_pattern.glsl; a pattern with larger N then gets NaN) folds the digit steps past it, which
/// lavapipe would otherwise run masked: Halton at N = 128 makes 7 digits, not 24.
#ifdef OAS_STATIC_INDEX_BITS
#define OAS_INDEX_DIGIT_MAY_EXIST(k) ((k) < OAS_STATIC_INDEX_BITS)
#else
#define OAS_INDEX_DIGIT_MAY_EXIST(k) true
#endif

/// Bit-reversed index: the van der Corput sequence in base 2 (Sobol dimension 0). GLSL's
/// bitfieldReverse: one instruction on GPUs and a few byte shuffles on lavapipe (LLVM's
/// bitreverse), where the shift-and-mask form was 20 operations; the C++ twin's is that form
/// (host/oas/glsl_compat.hpp), the same function.
uint oas_reverse_bits(uint v) { return bitfieldReverse(v); }

/// Sobol dimension 1 (primitive polynomial x + 1, direction numbers m_k = 1): with dimension 0 it
/// forms the (0,2)-sequence in base 2. Direction numbers follow v_{k+1} = v_k ^ (v_k >> 1).
uint oas_sobol_dim1(uint index)
{
    uint v = 0x80000000u;
    uint x = 0u;
    OAS_UNROLL for (uint bit = 0u; bit < OAS_INDEX_BITS; ++bit) {
        if (((index >> bit) & 1u) != 0u) x ^= v;
        v ^= v >> 1u;
    }
    return x;
}

/// Nested uniform (Owen 1995) scrambling of the top 24 bits of a 32-bit fraction: bit b flips
/// when a hash of the bits above it says so, which permutes every elementary interval's halves
/// independently. Bits below the top 24 are left as they are: the caller keeps only the top 24.
/// The reference scramble (OAS_SOBOL_OWEN): 24 hashes a value. OAS_SOBOL, OAS_SOBOL_BURLEY and
/// zerotwo use oas_owen_scramble_hash, the same structure for a chain of multiplies (zerotwo
/// used this one until version 0.3).
uint oas_owen_scramble24(uint x, uint seed)
{
    uint result = x;
    OAS_UNROLL for (uint b = 0u; b < 24u; ++b) {
        uint prefix = b == 0u ? 0u : x >> (32u - b);
        uint flip = oas_hash2(seed, prefix | (1u << b)) & 1u;
        result ^= flip << (31u - b);
    }
    return result;
}

/// A seeded bijection of 32-bit words in which bit b of the result is bit b of x flipped by a
/// function of the seed and of the bits below b only: the Laine-Karras construction (Laine and
/// Karras, "Stratified sampling for stochastic transparency", EGSR 2011) that Burley uses for
/// Owen scrambling ("Practical Hash-based Owen Scrambling", JCGT 9(4), 2020). Every step keeps
/// that shape: adding a key carries upwards, x * c with c even moves bit i to bits above i, and
/// a multiply by an odd key is a bijection of the same kind. Ours draws every multiplier and
/// addend from the seed (a 32-bit LCG read through its high bits, as oas_permutation does),
/// where Laine and Karras's permutation adds the seed once and then multiplies by four fixed
/// constants. Measured against the per-bit scramble (oas_owen_scramble24) on Sobol points, 4D,
/// 4096 seeds, the estimator's variance on the 2-additive Gaussian and radial integrands was
/// 0.72-1.16x of it with the fixed constants and 0.97-1.06x with seeded ones (docs/BENCHMARKS.md).
uint oas_owen_hash_reversed(uint x, uint seed)
{
    uint k = seed * 0x2c1b3c6du + 0x297a2d39u;
    x += seed;
    x ^= x * ((k ^ (k >> 16u)) & 0xfffffffeu);
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    x *= (k ^ (k >> 16u)) | 1u;
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    x ^= x * ((k ^ (k >> 16u)) & 0xfffffffeu);
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    x += k ^ (k >> 16u);
    k = k * 0x2c1b3c6du + 0x297a2d39u;
    x ^= x * ((k ^ (k >> 16u)) & 0xfffffffeu);
    return x;
}

/// Hash-based nested uniform scramble (Burley 2020): oas_owen_hash_reversed of the bit reversal,
/// reversed back, so that bit b flips by a function of the seed and the bits above it: the
/// structure of Owen's scramble (each elementary interval's halves swapped or not), for a few
/// multiplies instead of a hash per bit. Net properties survive it as they survive Owen's
/// (tests/sampler_property_test.cpp); its flips come from one hash of the seed, not from
/// independent coin flips per interval.
uint oas_owen_scramble_hash(uint x, uint seed) { return oas_reverse_bits(oas_owen_hash_reversed(oas_reverse_bits(x), seed)); }

/// The bit-reversed Sobol point of Burley's four padded dimensions, k < 4, from the bit-reversed
/// index y: bit b of y from the top selects the bit-reversed direction number r_b. Dimension 0
/// is van der Corput; 1, 2 and 3 are Joe and Kuo's dimensions 2, 3 and 4 (primitive polynomials
/// x + 1, x^2 + x + 1, x^3 + x + 1 with initial m = 1 | 1, 3 | 1, 3, 1), so that they equal the
/// first four dimensions of oas::sobolDirections() (tests/sampler_property_test.cpp). The
/// direction numbers follow their recurrences (Bratley and Fox 1988: v_b = a_1 v_(b-1) ^ ... ^
/// v_(b-s) ^ v_(b-s) >> s, here bit-reversed, so >> becomes <<) inside the unrolled loop, where
/// each is a compile-time constant: no table is read. Working bit-reversed saves two reversals a
/// value (Burley 2020, sec. 4). The top OAS_INDEX_BITS bits of y (an index < 2^24) take part.
uint oas_sobol4_reversed(uint y, uint k)
{
    uint x = 0u;
    uint r1 = 1u;               // x + 1, m = 1: r_b = r_(b-1) ^ r_(b-1) << 1
    uint r2a = 1u, r2b = 3u;    // x^2 + x + 1, m = 1, 3: r_b = r_(b-1) ^ r_(b-2) ^ r_(b-2) << 2
    uint r3a = 1u, r3b = 3u, r3c = 4u;  // x^3 + x + 1, m = 1, 3, 1: r_b = r_(b-2) ^ r_(b-3) ^ r_(b-3) << 3
    OAS_UNROLL for (uint bit = 0u; bit < OAS_INDEX_BITS; ++bit) {
        uint r = k == 0u ? (1u << bit) : (k == 1u ? r1 : (k == 2u ? r2a : r3a));
        x ^= ((y >> (31u - bit)) & 1u) != 0u ? r : 0u;
        r1 ^= r1 << 1u;
        uint next2 = r2b ^ r2a ^ (r2a << 2u);
        r2a = r2b;
        r2b = next2;
        uint next3 = r3b ^ r3a ^ (r3a << 3u);
        r3a = r3b;
        r3b = r3c;
        r3c = next3;
    }
    return x;
}

/// Dimensions of one Sobol-Burley group: Burley pads 4D Sobol points, each group of four
/// dimensions with its own index shuffle and scrambles.
const uint OAS_SOBOL_BURLEY_GROUP = 4u;

/// Burley's padded Sobol sampler ("Practical Hash-based Owen Scrambling", JCGT 2020, sec. 5; what
/// Cycles ships as Sobol-Burley): dimension `dim` of point `index` (< 2^24) for pass seed `seed`.
/// Dimensions go in groups of four; each group shuffles the index by a nested uniform scramble of
/// its bits (Owen-scrambling the index reorders the points of every aligned power-of-two block
/// among themselves, so any 2^m consecutive indices still make a (0,m,2)-net in dimensions 0 and
/// 1 of the group) and scrambles each of its dimensions' values, all keyed by (seed, group,
/// dimension). No direction-number table: the four dimensions' numbers fold to constants.
float oas_sobol_burley_dim(uint seed, uint index, uint dim)
{
    uint group = dim >> 2u;
    uint groupSeed = oas_hash2(seed, group);
    // The shuffled index, bit-reversed (what oas_sobol4_reversed reads): the hash of the reversed
    // index, so no reversal back and forth.
    uint shuffledReversed = oas_owen_hash_reversed(oas_reverse_bits(index), groupSeed);
    uint k = dim & 3u;
    uint x = oas_sobol4_reversed(shuffledReversed, k);
    uint scrambled = oas_reverse_bits(oas_owen_hash_reversed(x, oas_hash2(groupSeed ^ OAS_TAG_STRATUM, k)));
    return float(scrambled >> 8u) * OAS_INV_2POW24;
}

/// The i-th prime, for i < 32 (Halton bases; larger dimensions start a new scrambled block).
uint oas_halton_base(uint i)
{
    switch (i) {
    case 0u: return 2u;    case 1u: return 3u;    case 2u: return 5u;    case 3u: return 7u;
    case 4u: return 11u;   case 5u: return 13u;   case 6u: return 17u;   case 7u: return 19u;
    case 8u: return 23u;   case 9u: return 29u;   case 10u: return 31u;  case 11u: return 37u;
    case 12u: return 41u;  case 13u: return 43u;  case 14u: return 47u;  case 15u: return 53u;
    case 16u: return 59u;  case 17u: return 61u;  case 18u: return 67u;  case 19u: return 71u;
    case 20u: return 73u;  case 21u: return 79u;  case 22u: return 83u;  case 23u: return 89u;
    case 24u: return 97u;  case 25u: return 101u; case 26u: return 103u; case 27u: return 107u;
    case 28u: return 109u; case 29u: return 113u; case 30u: return 127u; default: return 131u;
    }
}

/// Digits a Halton base above 2 can need: base 3 stops at 3^15 > 2^24 / 3 (the exact limit).
const uint OAS_HALTON_ODD_BASE_DIGITS = 15u;

/// Dimensions of one Halton block: beyond it, a new block with freshly shuffled indices and digit
/// permutations (padding), never a silent wrap onto the same bases with the same scrambling.
const uint OAS_HALTON_BLOCK = 32u;

/// Dimensions of one Sobol block: the host's direction-number table (oas::sobolDirections, Joe and
/// Kuo's first 1024 dimensions) has this many; further dimensions start new blocks with shuffled
/// indices and fresh scrambling.
const uint OAS_SOBOL_BLOCK = 1024u;

#if !defined(OAS_SOBOL_DIRECTION) && !defined(OAS_NO_SOBOL)
#error "oas.glsl: define OAS_SOBOL_DIRECTION(dim, bit) (the Sobol baseline's direction numbers, oas::sobolDirections() on the host) or OAS_NO_SOBOL (this shader never gets a Sobol pattern) before including oas.glsl"
#endif
/// Sobol point x of a table-driven Sobol sampler, scrambled with dimension seed dimSeed as the
/// pattern says (OAS_SOBOL_OWEN: per bit; OAS_SOBOL: hash-based), as the sample value. Shared
/// by oas_baseline_dim and the CPU's bulk path (host/oas/baseline_columns.cpp).
float oas_sobol_value(OasPattern pat, uint x, uint dimSeed)
{
    uint scrambled = OAS_CONSTRUCTION(pat) == OAS_SOBOL_OWEN ? oas_owen_scramble24(x, dimSeed) : oas_owen_scramble_hash(x, dimSeed);
    return oas_specialized_value(pat, float(scrambled >> 8u) * OAS_INV_2POW24);
}

#ifdef OAS_SOBOL_DIRECTION
/// Sobol point `index` (< 2^24), dimension `dim` < OAS_SOBOL_BLOCK, as a 32-bit fraction.
/// Direction numbers are data, not computable on the fly: a shader that wants the Sobol
/// baselines (OAS_SOBOL, OAS_SOBOL_OWEN) defines OAS_SOBOL_DIRECTION(dim, bit) (bit 0 = the most
/// significant direction number) before including oas.glsl, typically reading a buffer filled
/// from oas::sobolDirections() (a texel buffer on lavapipe: it loads a storage buffer one lane at
/// a time). Without it those patterns are unavailable in that shader and oas_sample returns
/// independent random values for them. The samplers' indices are below N <= 2^24, so 24
/// direction numbers are all an index can select (OAS_INDEX_BITS); 32 were read before.
/// Every direction number is read and masked by its bit rather than read under a branch on the
/// bit: unconditional reads of the same texel are one fetch to the shader compiler, so a buffer
/// of four numbers a texel costs 6 fetches a value, where 24 reads under per-lane branches
/// stayed 24 (lavapipe makes a fetch under a branch for all lanes anyway). That took the Sobol
/// row of oas-bench on lavapipe from 58 to 125 M values/s (docs/BENCHMARKS.md).
uint oas_sobol(uint index, uint dim)
{
    uint x = 0u;
    OAS_UNROLL for (uint bit = 0u; bit < OAS_INDEX_BITS; ++bit)
        x ^= OAS_SOBOL_DIRECTION(dim, bit) & (0u - ((index >> bit) & 1u));
    return x;
}

/// The state of one dimension of a table-driven Sobol sampler (OAS_SOBOL, OAS_SOBOL_OWEN) that
/// does not depend on the sample: its 24 direction numbers, seeds and index shuffle, made once per
/// (pixel, pass, dimension) and reused for the pass's samples, as OasColumn is for the OAs. On
/// lavapipe the direction numbers' fetches were most of a value: dropping them took the generation
/// kernel's Sobol from 0.33 to 0.86 of the hash-only kernel's values/s (docs/BENCHMARKS.md).
struct OasSobolColumn {
    uint direction[OAS_INDEX_BITS];  ///< the dimension's direction numbers, bit 0 the most significant
    uint block;                      ///< dim / OAS_SOBOL_BLOCK: blocks past the first shuffle the index
    uint shuffleSeed;                ///< the block's index shuffle (OAS_TAG_ROW of the block seed)
    uint dimSeed;                    ///< the value's scramble
};

/// OasSobolColumn of dimension `dim` for pass seed `seed`.
OasSobolColumn oas_sobol_column(uint seed, uint dim)
{
    OasSobolColumn c;
    c.block = dim / OAS_SOBOL_BLOCK;
    uint blockSeed = oas_hash2(seed, c.block);
    c.shuffleSeed = blockSeed ^ OAS_TAG_ROW;
    c.dimSeed = oas_hash2(blockSeed, dim);
    uint tableDim = dim - c.block * OAS_SOBOL_BLOCK;
    OAS_UNROLL for (uint bit = 0u; bit < OAS_INDEX_BITS; ++bit) c.direction[bit] = OAS_SOBOL_DIRECTION(tableDim, bit);
    return c;
}

/// Sample `index` (< N) of the Sobol dimension that `c` was made for.
float oas_sobol_column_dim(OasPattern pat, OasSobolColumn c, uint index)
{
    // Blocks past the first shuffle the indices, so that dimension 1024 + k is not dimension
    // k again. OAS_SOBOL_OWEN permutes [0, N) (oas_permute, its values since version 0.2);
    // OAS_SOBOL scrambles the index's bits as Burley pads (a bijection of every aligned
    // power-of-two block, so a block of 2^m indices stays a net): a few multiplies where
    // oas_permute makes four rounds' keys, and lavapipe pays for the shuffle in block 0 too
    // (it runs both sides of the select).
    uint shuffled = OAS_CONSTRUCTION(pat) == OAS_SOBOL_OWEN ? oas_permute(index, pat.N, c.shuffleSeed)
                                                            : oas_owen_scramble_hash(index, c.shuffleSeed);
    uint i = c.block == 0u ? index : shuffled;
    uint x = 0u;
    OAS_UNROLL for (uint bit = 0u; bit < OAS_INDEX_BITS; ++bit) x ^= c.direction[bit] & (0u - ((i >> bit) & 1u));
    return oas_sobol_value(pat, x, c.dimSeed);
}
#endif

/// The state of one dimension of a padded 2D baseline (jittered2d, cmj2d, zerotwo) that does not
/// depend on the sample: made once per (pixel, pass, dimension) and reused for all N samples of
/// the pass (oas_pair_column_dim), as OasColumn is for the OAs. Dimensions (2p, 2p+1) form pair p;
/// every pair shuffles the sample order independently (Kollig and Keller 2002), which decorrelates
/// pairs, and that shuffle's keys, not its application, are what the state saves.
struct OasPairColumn {
    uint pairSeed;
    uint axis;               ///< 0: x of the pair, 1: y
    OasPermutation order;    ///< the pair's shuffle of the sample order
    OasPermutation across;   ///< cmj2d: the sub-stratum permutation this axis reads (l = 1 otherwise)
    uint scrambleSeed;       ///< zerotwo: the Owen scrambling seed of this axis (oas_owen_scramble_hash)
    uint recipX;             ///< oas_fastdiv constants of nx (a cell's row is its index / nx)
    uint shiftX;
    uint strata;             ///< K, the strata of this axis: nx or ny (jittered2d), N (cmj2d)
    uint recipStrata;        ///< oas_fastdiv constants of K
    uint shiftStrata;
};

/// Whether the pattern is a padded 2D baseline (jittered2d, cmj2d, zerotwo): the ones with an
/// OasPairColumn fast path.
bool oas_is_padded_2d(OasPattern pat)
{
    uint construction = OAS_CONSTRUCTION(pat);
    return construction == OAS_JITTERED_2D || construction == OAS_CMJ_2D || construction == OAS_ZERO_TWO;
}

/// OasPairColumn for dimension `dim` of a padded 2D baseline, pass seed `seed`.
OasPairColumn oas_pair_column(OasPattern pat, uint seed, uint dim)
{
    OasPairColumn c;
    c.pairSeed = oas_hash2(seed, dim >> 1u);
    c.axis = dim & 1u;
    c.order = oas_permutation(pat.N, c.pairSeed ^ OAS_TAG_ROW);
    // cmj2d's x reads a permutation of the row's ny sub-strata, its y one of the column's nx.
    bool cmj = OAS_CONSTRUCTION(pat) == OAS_CMJ_2D;
    uint acrossLength = !cmj ? 1u : c.axis == 0u ? pat.aux2 : pat.aux;
    c.across = oas_permutation(acrossLength, c.pairSeed ^ (c.axis == 0u ? OAS_TAG_SUB : OAS_TAG_STRATUM));
    c.scrambleSeed = oas_hash2(c.pairSeed, c.axis);
    // Divisions by the grid's sides through reciprocals: made here once, so that a value costs
    // multiplies only (oas_stratum_point would divide six times per value).
    uint nx = pat.aux == 0u ? 1u : pat.aux;  // zerotwo has no grid; any divisor keeps its unused path defined
    c.shiftX = oas_fastdiv_shift(nx);
    c.recipX = oas_fastdiv_recip24(nx, c.shiftX);
    c.strata = cmj ? pat.N : c.axis == 0u ? nx : pat.aux2 == 0u ? 1u : pat.aux2;
    c.shiftStrata = cmj ? (pat.recipShifts >> 16u) & 0xffu : c.axis == 0u ? c.shiftX : oas_fastdiv_shift(c.strata);
    c.recipStrata = cmj ? pat.recipN : c.axis == 0u ? c.recipX : oas_fastdiv_recip24(c.strata, c.shiftStrata);
    return c;
}

/// The cell of sample `index` (< N) in its pair's shuffled order: the same for both dimensions
/// of the pair (their columns share the order), so a caller filling both computes it once.
uint oas_pair_cell(OasPairColumn c, uint index) { return oas_permutation_apply(c.order, index); }

/// cmj2d's input to its across permutation for cell i: the cell's row cy for x, its column cx
/// for y (a CPU caller tabulates c.across over these per run: oas_pair_cell_dim_across).
uint oas_pair_across_input(OasPattern pat, OasPairColumn c, uint i)
{
    uint cy = oas_fastdiv(i, c.recipX, c.shiftX);
    return c.axis == 0u ? cy : i - cy * pat.aux;
}

/// oas_pair_cell_dim with cmj2d's permuted sub-stratum given: acrossImage =
/// oas_permutation_apply(c.across, oas_pair_across_input(pat, c, i)) for cmj2d (ignored by the
/// other padded baselines).
float oas_pair_cell_dim_across(OasPattern pat, OasPairColumn c, uint i, uint index, uint acrossImage)
{
    uint jitter = oas_hash3(c.pairSeed ^ OAS_TAG_JITTER, c.axis, index);
    if (OAS_CONSTRUCTION(pat) == OAS_ZERO_TWO) {
        uint x = c.axis == 0u ? oas_reverse_bits(i) : oas_sobol_dim1(i);
        return oas_specialized_value(pat, float(oas_owen_scramble_hash(x, c.scrambleSeed) >> 8u) * OAS_INV_2POW24);
    }
    uint nx = pat.aux;
    uint ny = pat.aux2;
    uint cy = oas_fastdiv(i, c.recipX, c.shiftX);
    uint cx = i - cy * nx;
    // jittered2d: cell (cx, cy) of the nx x ny grid. cmj2d (Kensler 2013): the cell's
    // x-substratum is a permutation of its row, shared by all rows (and vice versa), which makes
    // both 1D projections N-strata Latin hypercubes.
    uint stratum = c.axis == 0u ? cx : cy;
    if (OAS_CONSTRUCTION(pat) == OAS_CMJ_2D) stratum = c.axis == 0u ? cx * ny + acrossImage : cy * nx + acrossImage;
    return oas_specialized_value(pat, oas_stratum_point_fast(stratum, c.strata, c.recipStrata, c.shiftStrata, jitter));
}

/// Sample `index` (< N), in cell i = oas_pair_cell(c, index), of the padded 2D baseline
/// dimension that `c` was made for.
float oas_pair_cell_dim(OasPattern pat, OasPairColumn c, uint i, uint index)
{
    uint acrossImage = OAS_CONSTRUCTION(pat) == OAS_CMJ_2D ? oas_permutation_apply(c.across, oas_pair_across_input(pat, c, i)) : 0u;
    return oas_pair_cell_dim_across(pat, c, i, index, acrossImage);
}

/// Sample `index` (< N) of the padded 2D baseline dimension that `c` was made for.
float oas_pair_column_dim(OasPattern pat, OasPairColumn c, uint index)
{
    return oas_pair_cell_dim(pat, c, oas_pair_cell(c, index), index);
}

/// The state of one dimension of randomized Halton that does not depend on the sample: its base
/// and the base's division constants, how many digits it makes, every digit's permutation and the
/// index shuffle's seed, made once per (pixel, pass, dimension) and reused for the pass's
/// samples, as OasColumn is for the OAs.
///
/// Digits of the index, least significant first, each go through their own random permutation
/// (random-digit-permutation Halton); enough digits to tell all N indices apart, capped where
/// base^digits would pass 2^24 (the exact fixed-point limit). The bases are prime, so the
/// permutations are the affine maps d -> a d + b mod base (a != 0), the sharply 2-transitive
/// family (see oas_levels_form_prime_field): the pair statistics, and so the variance, of
/// uniformly random digit permutations, for one multiply and one remainder. At most
/// OAS_INDEX_BITS digits (base 2 at N = 2^24): the first OAS_HALTON_ODD_BASE_DIGITS for every
/// base (base 3 needs no more), the rest for base 2 only, whose digit permutations d -> a d + b
/// mod 2 are d XOR b (a = 1): their nine b are nine bits of one hash (`flips`). The keys (a, b)
/// are a 32-bit LCG stream seeded by the dimension, read through its high bits (mulhi), one step
/// per key, advanced only for the digits made (until version 0.3 each was a hash of (dimension
/// seed, digit), and those hashes were most of a value; until this column they were remade for
/// every value).
struct OasHaltonColumn {
    uint base;
    uint recipBase;    ///< oas_fastdiv constants of base (bases are below 2^8)
    uint shiftBase;
    uint digits;       ///< digits a value is made of: base^digits >= N, within 2^24
    uint strata;       ///< base^digits
    uint recipStrata;  ///< oas_fastdiv constants of strata: the stratum point divides by it
    uint shiftStrata;
    uint scale[OAS_HALTON_ODD_BASE_DIGITS];   ///< digit k's permutation: d -> scale d + offset mod base
    uint offset[OAS_HALTON_ODD_BASE_DIGITS];
    uint flips;        ///< base 2's digits 15 .. 23: bit (k - 15) flips digit k
    uint block;        ///< dim / OAS_HALTON_BLOCK: blocks past the first shuffle the index
    uint shuffleSeed;
    uint jitterSeed;
};

/// OasHaltonColumn of dimension `dim` for pass seed `seed`.
OasHaltonColumn oas_halton_column(OasPattern pat, uint seed, uint dim)
{
    OasHaltonColumn c;
    c.block = dim / OAS_HALTON_BLOCK;
    c.base = oas_halton_base(dim - c.block * OAS_HALTON_BLOCK);
    uint blockSeed = oas_hash2(seed, c.block);
    c.shuffleSeed = blockSeed ^ OAS_TAG_ROW;
    uint dimSeed = oas_hash2(blockSeed, dim);
    c.jitterSeed = dimSeed ^ OAS_TAG_JITTER;
    c.shiftBase = uint(findMSB(c.base - 1u)) + 1u;
    c.recipBase = oas_fastdiv_recip(c.base, c.shiftBase);
    uint strataLimit = oas_fastdiv(OAS_ONE_FIXED, c.recipBase, c.shiftBase);
    c.strata = 1u;
    c.digits = 0u;
    uint key = dimSeed;
    OAS_UNROLL for (uint k = 0u; k < OAS_HALTON_ODD_BASE_DIGITS; ++k) {
        c.scale[k] = 0u;
        c.offset[k] = 0u;
        if (OAS_INDEX_DIGIT_MAY_EXIST(k) && c.strata < pat.N && c.strata <= strataLimit) {
            key = key * 0x2c1b3c6du + 0x297a2d39u;
            c.scale[k] = 1u + oas_mulhi(key, c.base - 1u);
            key = key * 0x2c1b3c6du + 0x297a2d39u;
            c.offset[k] = oas_mulhi(key, c.base);
            c.strata *= c.base;
            c.digits += 1u;
        }
    }
    // Read only when all fifteen steps ran (then key is the same as if it had always advanced).
    c.flips = oas_pcg(key);
    OAS_UNROLL for (uint k = OAS_HALTON_ODD_BASE_DIGITS; k < OAS_INDEX_BITS; ++k) {
        if (OAS_INDEX_DIGIT_MAY_EXIST(k) && c.base == 2u && c.strata < pat.N) {  // strata <= 2^23: within the limit
            c.strata *= 2u;
            c.digits += 1u;
        }
    }
    // The stratum point's divisions by strata through a reciprocal made here, once: per value,
    // oas_stratum_point's long divisions were most of a Halton value's cost on the CPU (integer
    // division has no vector form) and a share on lavapipe.
    c.shiftStrata = oas_fastdiv_shift(c.strata);
    c.recipStrata = oas_fastdiv_recip24(c.strata, c.shiftStrata);
    return c;
}

/// Where sample `i` stands in one Halton dimension: its index's digits in the column's base and
/// their permuted values, so that the next sample's follow by a carry (oas_halton_cursor_next)
/// where a cold start divides by the base twice per digit. Digits 0 .. 14 (every base), then
/// base 2's digits 15 .. 23 as the bits of `high`.
struct OasHaltonCursor {
    uint digit[OAS_HALTON_ODD_BASE_DIGITS];     ///< the index's digits, least significant first
    uint permuted[OAS_HALTON_ODD_BASE_DIGITS];  ///< digit k through digit k's permutation
    uint high;                                  ///< what is left of the index above digit 14
};

/// The cursor of index `i` (already shuffled, for blocks past the first) in the column `c`.
OasHaltonCursor oas_halton_cursor(OasHaltonColumn c, uint i)
{
    OasHaltonCursor r;
    OAS_UNROLL for (uint k = 0u; k < OAS_HALTON_ODD_BASE_DIGITS; ++k) {
        r.digit[k] = 0u;
        r.permuted[k] = 0u;
        if (OAS_INDEX_DIGIT_MAY_EXIST(k) && k < c.digits) {
            uint next = oas_fastdiv(i, c.recipBase, c.shiftBase);
            r.digit[k] = i - next * c.base;
            i = next;
            uint permuted = c.scale[k] * r.digit[k] + c.offset[k];  // < base^2
            r.permuted[k] = permuted - oas_fastdiv(permuted, c.recipBase, c.shiftBase) * c.base;
        }
    }
    r.high = i;
    return r;
}

/// The cursor of the index after r's. The permutation d -> scale d + offset mod base moves by
/// scale when d steps up, and a digit that wraps from base - 1 to 0 lands on offset, which is
/// the same step mod base: so each digit adds scale where a carry arrives, and subtracts base
/// when it passes it. Only compares and adds, where oas_halton_cursor divides; for runs of
/// consecutive samples of one pass (the generation kernel's, block 0, whose indices are not
/// shuffled). The carry out of the column's last digit goes to `high`, which only base 2 reads.
OasHaltonCursor oas_halton_cursor_next(OasHaltonColumn c, OasHaltonCursor r)
{
    uint carry = 1u;
    OAS_UNROLL for (uint k = 0u; k < OAS_HALTON_ODD_BASE_DIGITS; ++k) {
        if (OAS_INDEX_DIGIT_MAY_EXIST(k) && k < c.digits) {
            uint wraps = carry != 0u && r.digit[k] == c.base - 1u ? 1u : 0u;
            r.digit[k] = wraps != 0u ? 0u : r.digit[k] + carry;
            uint p = r.permuted[k] + (carry != 0u ? c.scale[k] : 0u);  // < 2 base
            r.permuted[k] = p >= c.base ? p - c.base : p;
            carry = wraps;
        }
    }
    r.high += carry;
    return r;
}

/// The stratum of cursor r: its permuted digits read as an integer below c.strata, digit 0 the
/// most significant (digit k at base^-(k+1) of the radical inverse). A sum of one term per digit,
/// so the stratum of i = g base^L + j is that of g base^L plus that of j less that of 0, which
/// the CPU's bulk loop uses (host/oas/baseline_columns_loops.inc).
uint oas_halton_cursor_stratum(OasHaltonColumn c, OasHaltonCursor r)
{
    uint m = 0u;
    OAS_UNROLL for (uint k = 0u; k < OAS_HALTON_ODD_BASE_DIGITS; ++k)
        if (OAS_INDEX_DIGIT_MAY_EXIST(k) && k < c.digits) m = m * c.base + r.permuted[k];  // digit k at base^-(k+1)
    OAS_UNROLL for (uint k = OAS_HALTON_ODD_BASE_DIGITS; k < OAS_INDEX_BITS; ++k) {
        uint bit = k - OAS_HALTON_ODD_BASE_DIGITS;
        if (OAS_INDEX_DIGIT_MAY_EXIST(k) && k < c.digits) m = m * 2u + (((r.high ^ c.flips) >> bit) & 1u);  // base 2 only
    }
    return m;
}

/// The value of sample `index` (before any shuffle: the jitter's key) in stratum m of column c.
float oas_halton_stratum_value(OasPattern pat, OasHaltonColumn c, uint m, uint index)
{
    uint jitter = oas_hash2(c.jitterSeed, index);
    return oas_specialized_value(
        pat, oas_stratum_point_divided(m, c.strata, c.recipStrata, c.shiftStrata, jitter, OAS_SMALL_STRATA_ANY_N(c.strata)));
}

/// The value of the sample at cursor r (sample `index`, before any shuffle: the jitter's key).
float oas_halton_cursor_value(OasPattern pat, OasHaltonColumn c, OasHaltonCursor r, uint index)
{
    return oas_halton_stratum_value(pat, c, oas_halton_cursor_stratum(c, r), index);
}

/// Sample `index` (< N) of the Halton dimension that `c` was made for.
float oas_halton_column_dim(OasPattern pat, OasHaltonColumn c, uint index)
{
    uint i = c.block == 0u ? index : oas_permute(index, pat.N, c.shuffleSeed);
    return oas_halton_cursor_value(pat, c, oas_halton_cursor(c, i), index);
}

/// Baseline samplers. `index` < N; passes (index >= N) are handled by oas_sample.
float oas_baseline_dim(OasPattern pat, uint seed, uint index, uint dim)
{
    if (OAS_CONSTRUCTION(pat) == OAS_SOBOL_BURLEY) return oas_specialized_value(pat, oas_sobol_burley_dim(seed, index, dim));
    if (OAS_CONSTRUCTION(pat) == OAS_FAURE) return oas_specialized_value(pat, oas_faure_dim(pat, seed, index, dim));
    bool sobol = OAS_CONSTRUCTION(pat) == OAS_SOBOL || OAS_CONSTRUCTION(pat) == OAS_SOBOL_OWEN;
#ifdef OAS_SOBOL_DIRECTION
    if (sobol) return oas_sobol_column_dim(pat, oas_sobol_column(seed, dim), index);
#endif
    if (OAS_CONSTRUCTION(pat) == OAS_RANDOM || sobol) return oas_specialized_value(pat, float(oas_hash3(seed, dim, index) >> 8u) * OAS_INV_2POW24);

    if (OAS_CONSTRUCTION(pat) == OAS_HALTON) return oas_halton_column_dim(pat, oas_halton_column(pat, seed, dim), index);

    return oas_pair_column_dim(pat, oas_pair_column(pat, seed, dim), index);
}

#endif // OAS_BASELINES_GLSL
