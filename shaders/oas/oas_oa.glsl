// oas_oa.glsl - orthogonal-array constructions and their randomization.
// Part of the oas GLSL library; include "oas.glsl" rather than this file.
#ifndef OAS_OA_GLSL
#define OAS_OA_GLSL

OasField oas_pattern_field(OasPattern pat)
{
    OasField f;
    f.p = pat.fieldP;
    f.k = pat.fieldK;
    f.q = pat.fieldQ;
    f.poly = pat.fieldPoly;
    f.recipP = pat.recipP;
    f.shiftP = (pat.recipShifts >> 8u) & 0xffu;
    return f;
}

/// Bush's largest strength: q^t <= 2^24 with q >= t leaves t <= 8 (8^8 = 2^24).
const uint OAS_MAX_BUSH_T = 8u;

/// base^e for e < 32 (square-and-multiply over e's five bits; no overflow check: callers keep
/// the result below 2^32).
uint oas_uint_pow(uint base, uint e)
{
    uint result = 1u;
    OAS_UNROLL for (uint i = 0u; i < 5u; ++i) {
        result *= result;
        if (((e >> (4u - i)) & 1u) != 0u) result *= base;
    }
    return result;
}

/// Bush: the level of column `col` (< q) for the row with base-q digits c_0..c_{t-1}: the
/// polynomial sum c_i col^i, by Horner's rule from c_{t-1} down. Column q is the leading
/// coefficient c_{t-1}. Two fixed loops of OAS_MAX_BUSH_T steps: the first reverses the t digits
/// (rev < q^t = N), the second pops them most significant first.
uint oas_bush_level(OasPattern pat, OasField f, uint row, uint col)
{
    if (col == pat.s) return row / pat.aux;  // aux = q^(t-1)
    uint reversed = 0u;
    OAS_UNROLL for (uint i = 0u; i < OAS_MAX_BUSH_T; ++i) {
        uint next = oas_div_s(pat, row);
        if (i < pat.strength) reversed = reversed * pat.s + (row - next * pat.s);
        row = next;
    }
    uint v = 0u;
    OAS_UNROLL for (uint i = 0u; i < OAS_MAX_BUSH_T; ++i) {
        uint next = oas_div_s(pat, reversed);
        if (i < pat.strength) v = oas_gf_mul_add(f, v, col, reversed - next * pat.s);
        reversed = next;
    }
    return v;
}

/// Base-s digit `col` of `row` (CMJND): (row / s^col) mod s, in fixed work for any col.
uint oas_digit(OasPattern pat, uint row, uint col)
{
    uint quotient = row / oas_uint_pow(pat.s, col);
    return quotient - oas_div_s(pat, quotient) * pat.s;
}

/// The part of a column's levels that depends on the column alone: Addelman-Kempthorne's half-1
/// constants, (k - 1) / (4 k m) for column 1+m (m != 0) and m^2 (k - 1) / 4 for column 1+q+m.
/// Both need field inverses (a power loop), so they are made once per column (OasColumn), not
/// per sample. 0 for every other construction and column.
uint oas_oa_column_constant(OasPattern pat, uint col)
{
    if (OAS_CONSTRUCTION(pat) != OAS_ADDELMAN_KEMPTHORNE || col == 0u || col == 1u) return 0u;
    OasField f = oas_pattern_field(pat);
    uint q = pat.s;
    uint k = pat.aux;
    uint kMinus1 = oas_gf_add(f, k, f.p - 1u);  // p - 1 is the element -1
    uint four = oas_gf_int(f, 4u);
    // One inverse either way (it is the costly part: a fixed square-and-multiply).
    uint m = col <= q ? col - 1u : col - 1u - q;
    uint numerator = col <= q ? kMinus1 : oas_gf_mul(f, oas_gf_mul(f, m, m), kMinus1);
    uint denominator = col <= q ? oas_gf_mul(f, four, oas_gf_mul(f, k, m)) : four;
    return oas_gf_mul(f, numerator, oas_gf_inv(f, denominator));
}

/// Level (in [0, s)) of row `row` (< N), column `col` (< blockDims) of the un-randomized array.
///
/// Bose: row = a*q + b -> columns (a, b, a + 1*b, a + 2*b, ..., a + (q-1)*b) over GF(q).
/// Bush: row = digits c_0..c_{t-1} base q -> column j < q is the polynomial sum c_i x_j^i at the
///   field element x_j = j; column q is the leading coefficient c_{t-1}.
/// Bose-Bush: with F = GF(2q), row = i*q + g (i in F, g in [0,q)), column j < 2q is
///   phi(i*j) XOR g and column 2q is i >> 1, where phi drops F's top bit: an additive map of F
///   onto GF(2)^k with kernel of size two, which makes the multiplication table of F a difference
///   scheme D(2q, 2q, q) (Hedayat, Sloane and Stufken 1999, ch. 6).
/// Addelman-Kempthorne: row = h*q^2 + i*q + j (h in {0,1}); with a non-square k of GF(q):
///   column 0 = j; column 1+m = i + m j (+ (k-1)/(4km) in half h=1, m != 0);
///   column 1+q+m = i^2 + m i + j (h=0) or k i^2 + k m i + j + m^2 (k-1)/4 (h=1).
///   (The half-1 constants make quadratic character sums cancel pair by pair: Addelman and
///   Kempthorne, "Some main-effect plans and orthogonal arrays of strength two", Ann. Math.
///   Statist. 32, 1961.)
/// CMJND: column j is base-s digit j of the row (the full factorial).
/// `columnConstant` is oas_oa_column_constant(pat, col), which depends on the column only.
uint oas_oa_level_with(OasPattern pat, uint row, uint col, uint columnConstant)
{
    OasField f = oas_pattern_field(pat);
    uint q = pat.s;
    uint construction = OAS_CONSTRUCTION(pat);
    if (construction == OAS_BOSE) {
        uint a = oas_div_s(pat, row);
        uint b = row - a * q;
        if (col == 0u) return a;
        if (col == 1u) return b;
        return oas_gf_mul_add(f, col - 1u, b, a);
    }
    if (construction == OAS_BUSH) return oas_bush_level(pat, f, row, col);
    if (construction == OAS_BOSE_BUSH) {
        uint i = oas_div_s(pat, row);
        uint g = row - i * q;
        if (col == 2u * q) return i >> 1u;
        return (oas_gf_mul(f, i, col) & (q - 1u)) ^ g;
    }
    if (construction == OAS_ADDELMAN_KEMPTHORNE) {
        uint hi = oas_div_s(pat, row);  // h*q + i
        uint j = row - hi * q;
        uint h = oas_div_s(pat, hi);
        uint i = hi - h * q;
        if (col == 0u) return j;
        uint constant = h == 1u ? columnConstant : 0u;
        if (col <= q) return oas_gf_mul_add2(f, col - 1u, j, i, constant);
        uint quad = oas_gf_mul(f, i, oas_gf_add(f, i, col - 1u - q));  // i^2 + m i
        return oas_gf_mul_add2(f, h == 1u ? pat.aux : 1u, quad, j, constant);
    }
    return oas_digit(pat, row, col);  // OAS_CMJND
}

/// Level of row `row`, column `col` (oas_oa_level_with with the column's constant made here).
uint oas_oa_level(OasPattern pat, uint row, uint col)
{
    return oas_oa_level_with(pat, row, col, oas_oa_column_constant(pat, col));
}

/// Index in [0, N/s) of row `row` among the rows that share its level in column `col`: a
/// bijection from each level set onto [0, N/s). MJ and CMJ offsets place substrata by it, which
/// gives every column the N-strata Latin-hypercube property.
/// Bose pairs columns (0,1), (2,3), ...: a column's sub-index is its partner's level, which makes
/// each pair a correlated multi-jittered 2D pattern (the paper's Bose-CMJ). Any two Bose columns
/// form a full q x q factorial, so the partner's level is a bijection on each level set.
uint oas_oa_sublevel(OasPattern pat, uint row, uint col)
{
    uint q = pat.s;
    uint construction = OAS_CONSTRUCTION(pat);
    if (construction == OAS_BOSE) {
        uint partner = col ^ 1u;
        if (partner >= q + 1u) partner = 0u;  // q even: the last column pairs with column 0
        return oas_oa_level_with(pat, row, partner, 0u);  // Bose has no column constants
    }
    if (construction == OAS_BUSH) {
        // Given the level, the higher digits fix c_0 (x_j^0 = 1); for the leading-coefficient
        // column the lower t-1 digits are free.
        if (col == q) return row - (row / pat.aux) * pat.aux;
        return oas_div_s(pat, row);
    }
    if (construction == OAS_BOSE_BUSH) {
        uint i = oas_div_s(pat, row);
        if (col == 2u * q) return (i & 1u) * q + (row - i * q);
        return i;  // for each i exactly one g gives the level
    }
    if (construction == OAS_ADDELMAN_KEMPTHORNE) {
        uint hi = oas_div_s(pat, row);  // h*q + i
        uint j = row - hi * q;
        uint h = oas_div_s(pat, hi);
        if (col >= 1u && col <= q) return h * q + j;  // i + m j (+ b): j and h fix i
        return hi;                                     // j, and the quadratic columns: i fixes j
    }
    // OAS_CMJND: the row with digit `col` removed.
    uint place = oas_uint_pow(q, col);
    uint quotient = row / place;
    return oas_div_s(pat, quotient) * place + (row - quotient * place);
}

// Seed tags: fixed odd constants that separate the random streams of one dimension.
const uint OAS_TAG_ROW = 0x5bd1e995u;
const uint OAS_TAG_STRATUM = 0x27d4eb2fu;
const uint OAS_TAG_SUB = 0x165667b1u;
const uint OAS_TAG_JITTER = 0x85ebca6bu;
const uint OAS_TAG_PASS = 0xc2b2ae35u;

/// Whether the pattern's s levels are the elements of a prime field GF(p), s = p (Bose, Bush and
/// Addelman-Kempthorne over prime q). Their permutations are then the affine maps
/// x -> a x + b mod p, a != 0: a sharply 2-transitive group, so every ordered pair of distinct
/// levels lands on every ordered pair of distinct strata equally often over seeds. That is exactly
/// what uniformly random permutations give pairs, and the variance of a randomized-OA estimate is
/// a sum over pairs of points (Owen, "Orthogonal arrays for computer experiments, integration and
/// visualization", Statistica Sinica 1992), so it is the same as with uniform permutations, at
/// nine integer operations per value instead of oas_permutation_apply's ~90.
bool oas_levels_form_prime_field(OasPattern pat)
{
    uint construction = OAS_CONSTRUCTION(pat);
    return OAS_FIELD_IS_PRIME(oas_pattern_field(pat)) &&
           (construction == OAS_BOSE || construction == OAS_BUSH || construction == OAS_ADDELMAN_KEMPTHORNE);
}

/// The affine permutation x -> a x + b mod p of GF(p) for `seed`, kept in an OasPermutation
/// (key0 = a in [1, p), pivot0 = b in [0, p)); apply it with oas_affine_apply.
OasPermutation oas_affine_permutation(uint p, uint seed)
{
    uint k = oas_pcg(seed);
    OasPermutation perm;
    perm.l = p;
    perm.mask = 0u;
    perm.shift = 0u;
    perm.key0 = 1u + oas_mulhi(k, p - 1u);
    perm.key1 = 0u;
    perm.key2 = 0u;
    perm.key3 = 0u;
    perm.pivot0 = oas_mulhi(oas_pcg(k), p);
    perm.pivot1 = 0u;
    perm.pivot2 = 0u;
    perm.pivot3 = 0u;
    perm.rotation = 0u;
    return perm;
}

/// a x + b mod p for x < p = s (a x + b < p^2 + p < 2^32 for the fields the host accepts).
uint oas_affine_apply(OasPattern pat, OasPermutation perm, uint x)
{
    uint v = perm.key0 * x + perm.pivot0;
    return v - oas_div_s(pat, v) * pat.s;
}

/// Whether a column's substrata [0, N/s) are GF(p) too: Bose over a prime field (N/s = q = p).
bool oas_substrata_form_prime_field(OasPattern pat)
{
    return OAS_CONSTRUCTION(pat) == OAS_BOSE && OAS_FIELD_IS_PRIME(oas_pattern_field(pat));
}

// The permutations of a column's levels (level -> stratum) and substrata: affine where they form
// a prime field, oas_permutation otherwise. The choice depends on the construction and field
// kind only, so a shader specialised on them (OAS_STATIC_*) compiles one kind, not both.
OasPermutation oas_strata_permutation(OasPattern pat, uint seed)
{
    if (oas_levels_form_prime_field(pat)) return oas_affine_permutation(pat.s, seed);
    return oas_permutation(pat.s, seed);
}

uint oas_strata_permute(OasPattern pat, OasPermutation perm, uint level)
{
    if (oas_levels_form_prime_field(pat)) return oas_affine_apply(pat, perm, level);
    return oas_permutation_apply(perm, level);
}

OasPermutation oas_sub_permutation(OasPattern pat, uint seed)
{
    if (oas_substrata_form_prime_field(pat)) return oas_affine_permutation(pat.s, seed);
    return oas_permutation(pat.aux2, seed);
}

uint oas_sub_permute(OasPattern pat, OasPermutation perm, uint sublevel)
{
    if (oas_substrata_form_prime_field(pat)) return oas_affine_apply(pat, perm, sublevel);
    return oas_permutation_apply(perm, sublevel);
}

/// The state of one (pixel, pass, block): what every sample of the pass shares in this block.
/// Make it once (oas_block) and reuse it for all samples of the pass (oas_block_row).
struct OasBlock {
    uint seed;        ///< seed of this (pixel, pass, block)
    uint firstIndex;  ///< the pass's first sample index (a multiple of N)
    OasPermutation rows;  ///< sample index within the pass -> row of the shuffled OA
};

/// The per-sample state shared by all dimensions of one OA block: computing it once per block
/// and reusing it across the block's dimensions is the fast path (oas_sample does both).
struct OasRow {
    uint blockSeed;  ///< seed of this (pixel, pass, block)
    uint row;        ///< the sample's row in the block's shuffled OA
    uint index;      ///< the sample index within its pass, in [0, N)
};

/// The state of one (pixel, pass, block, column): everything oas_row_dim computes that does not
/// depend on the sample. Make it once (oas_column) and reuse it for every sample of the pass.
struct OasColumn {
    uint col;             ///< column within the block, < blockDims
    uint seed;            ///< seed of this column
    uint jitterSeed;      ///< seed of the in-stratum jitter
    uint constant;        ///< oas_oa_column_constant
    OasPermutation strata;  ///< level -> stratum
    OasPermutation sub;     ///< sublevel -> substratum (CMJ; MJ draws one per level, per sample)
};

/// Pixel seed from integer pixel coordinates and a user seed (frame, render, ...).
uint oas_pixel_seed(uint x, uint y, uint seed) { return oas_hash3(seed, x, y); }

/// The seed of pass `pass` (samples [pass N, pass N + N)) of the pixel with seed `pixelSeed`: the
/// pixel seed itself in pass 0, a hash of it and the pass after that. Every sampler's randomization
/// of a pass starts here, so that passes are independent and pass 0 needs no hash.
uint oas_pass_seed(uint pixelSeed, uint pass) { return pass == 0u ? pixelSeed : oas_hash3(pixelSeed, pass, OAS_TAG_PASS); }

/// Block state for the pass that holds sample `index` (any index: indices >= N begin further
/// passes, each an independent randomization of the same OA, so any number of samples is valid
/// and every complete pass of N samples is itself stratified). Valid for the N indices
/// [firstIndex, firstIndex + N).
OasBlock oas_block(OasPattern pat, uint pixelSeed, uint index, uint block)
{
    uint pass = oas_div_n(pat, index);
    OasBlock b;
    b.seed = oas_hash2(oas_pass_seed(pixelSeed, pass), block);
    b.firstIndex = pass * pat.N;
    b.rows = oas_permutation(pat.N, b.seed ^ OAS_TAG_ROW);
    return b;
}

/// Row state of sample `index` (in [b.firstIndex, b.firstIndex + N)) in block b.
OasRow oas_block_row(OasBlock b, uint index)
{
    OasRow r;
    r.blockSeed = b.seed;
    r.index = index - b.firstIndex;
    r.row = oas_permutation_apply(b.rows, r.index);
    return r;
}

/// Row state of sample `index` for dimension block `block` (oas_block + oas_block_row).
OasRow oas_row(OasPattern pat, uint pixelSeed, uint index, uint block)
{
    return oas_block_row(oas_block(pat, pixelSeed, index, block), index);
}

/// Column state of column `col` (< blockDims) for the block whose seed is `blockSeed`
/// (OasBlock.seed or OasRow.blockSeed).
OasColumn oas_column(OasPattern pat, uint blockSeed, uint col)
{
    OasColumn c;
    c.col = col;
    c.seed = oas_hash2(blockSeed, col);
    c.jitterSeed = c.seed ^ OAS_TAG_JITTER;
    c.constant = oas_oa_column_constant(pat, col);
    c.strata = oas_strata_permutation(pat, c.seed ^ OAS_TAG_STRATUM);
    // CMJ shares one substratum permutation per dimension (Kensler 2013), correlating the
    // pattern for better 2D spectra; MJ draws a new one per stratum (Chiu, Shirley and Wang 1994).
    c.sub = oas_sub_permutation(pat, c.seed ^ OAS_TAG_SUB);
    return c;
}

/// oas_column_dim's last steps, given the sample's level in column c, the level's stratum
/// (c.strata applied) and, for CMJ offsets, its substratum (c.sub applied to the sublevel; any
/// value for the other offsets). A caller that evaluates many samples of one column may apply the
/// column's two permutations through tables of them (host/oas/oa_columns_loops.inc); the values
/// are the same.
float oas_column_dim_at(OasPattern pat, OasColumn c, OasRow r, uint level, uint stratum, uint cmjSubstratum)
{
    uint offset = OAS_OFFSET(pat);
    uint shiftS = pat.recipShifts & 0xffu;
    if (offset == OAS_OFFSET_CENTERED)
        return oas_specialized_value(pat, oas_stratum_point_fast(stratum, pat.s, pat.recipS, shiftS, 0x80000000u));
    uint jitter = oas_hash2(c.jitterSeed, r.index);
    if (offset == OAS_OFFSET_J) return oas_specialized_value(pat, oas_stratum_point_fast(stratum, pat.s, pat.recipS, shiftS, jitter));
    uint subCount = pat.aux2;  // N / s
    uint substratum = cmjSubstratum;
    if (offset == OAS_OFFSET_MJ) {
        OasPermutation sub = oas_sub_permutation(pat, oas_hash2(c.seed ^ OAS_TAG_SUB, level));
        substratum = oas_sub_permute(pat, sub, oas_oa_sublevel(pat, r.row, c.col));
    }
    return oas_specialized_value(
        pat, oas_stratum_point_fast(stratum * subCount + substratum, pat.N, pat.recipN, (pat.recipShifts >> 16u) & 0xffu, jitter));
}

/// The value of column c for the sample r, in [0, 1): dimension block * blockDims + c.col.
float oas_column_dim(OasPattern pat, OasColumn c, OasRow r)
{
    uint level = oas_oa_level_with(pat, r.row, c.col, c.constant);
    uint stratum = oas_strata_permute(pat, c.strata, level);
    // CMJ shares one substratum permutation per column; MJ's depends on the level (made inside).
    uint substratum =
        OAS_OFFSET(pat) == OAS_OFFSET_CMJ ? oas_sub_permute(pat, c.sub, oas_oa_sublevel(pat, r.row, c.col)) : 0u;
    return oas_column_dim_at(pat, c, r, level, stratum, substratum);
}

/// Dimension `col` (< blockDims) of the sample described by `r`, in [0, 1).
float oas_row_dim(OasPattern pat, OasRow r, uint col)
{
    return oas_column_dim(pat, oas_column(pat, r.blockSeed, col), r);
}

#endif // OAS_OA_GLSL
