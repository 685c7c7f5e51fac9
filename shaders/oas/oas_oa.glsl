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

/// Bush: the level of column `col` (< q) and the leading coefficient c_{t-1}, for the row with
/// base-q digits c_0..c_{t-1}; the polynomial is evaluated from c_0 up with running powers x^i.
uint oas_bush_level(OasPattern pat, OasField f, uint row, uint col)
{
    uint v = 0u;
    uint power = 1u;  // col^i
    uint digit = 0u;
    for (uint i = 0u; i < pat.strength; ++i) {
        uint next = oas_div_s(pat, row);
        digit = row - next * pat.s;
        row = next;
        v = oas_gf_add(f, v, oas_gf_mul(f, digit, power));
        power = oas_gf_mul(f, power, col);
    }
    return col == pat.s ? digit : v;  // column q is the leading coefficient
}

/// Base-s digit `col` of `row` (CMJND).
uint oas_digit(OasPattern pat, uint row, uint col)
{
    for (uint d = 0u; d < col; ++d) row = oas_div_s(pat, row);
    return row - oas_div_s(pat, row) * pat.s;
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
///   (The half-1 constants make quadratic character sums cancel pair by pair; derivation in
///   docs/CONSTRUCTIONS.md.)
/// CMJND: column j is base-s digit j of the row (the full factorial).
uint oas_oa_level(OasPattern pat, uint row, uint col)
{
    OasField f = oas_pattern_field(pat);
    uint q = pat.s;
    uint construction = OAS_CONSTRUCTION(pat);
    if (construction == OAS_BOSE) {
        uint a = oas_div_s(pat, row);
        uint b = row - a * q;
        if (col == 0u) return a;
        if (col == 1u) return b;
        return oas_gf_add(f, a, oas_gf_mul(f, col - 1u, b));
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
        uint k = pat.aux;
        uint kMinus1 = oas_gf_add(f, k, oas_gf_neg(f, 1u));
        uint four = oas_gf_int(f, 4u);
        if (col <= q) {
            uint m = col - 1u;
            uint v = oas_gf_add(f, i, oas_gf_mul(f, m, j));
            if (h == 1u && m != 0u) {
                // b_m = (k - 1) / (4 k m)
                uint denom = oas_gf_mul(f, four, oas_gf_mul(f, k, m));
                v = oas_gf_add(f, v, oas_gf_mul(f, kMinus1, oas_gf_inv(f, denom)));
            }
            return v;
        }
        uint m = col - 1u - q;
        uint quad = oas_gf_add(f, oas_gf_mul(f, i, i), oas_gf_mul(f, m, i));
        if (h == 0u) return oas_gf_add(f, quad, j);
        // k i^2 + k m i + j + m^2 (k - 1) / 4
        uint c = oas_gf_mul(f, oas_gf_mul(f, oas_gf_mul(f, m, m), kMinus1), oas_gf_inv(f, four));
        return oas_gf_add(f, oas_gf_add(f, oas_gf_mul(f, k, quad), j), c);
    }
    return oas_digit(pat, row, col);  // OAS_CMJND
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
        return oas_oa_level(pat, row, partner);
    }
    if (construction == OAS_BUSH) {
        // Given the level, the higher digits fix c_0 (x_j^0 = 1); for the leading-coefficient
        // column the lower t-1 digits are free.
        if (col == q) return row - oas_bush_level(pat, oas_pattern_field(pat), row, col) * pat.aux;
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
    uint high = row;
    uint low = 0u;
    uint place = 1u;
    for (uint d = 0u; d < col; ++d) {
        uint next = oas_div_s(pat, high);
        low += (high - next * q) * place;
        place *= q;
        high = next;
    }
    return oas_div_s(pat, high) * place + low;
}

// Seed tags: fixed odd constants that separate the random streams of one dimension.
const uint OAS_TAG_ROW = 0x5bd1e995u;
const uint OAS_TAG_STRATUM = 0x27d4eb2fu;
const uint OAS_TAG_SUB = 0x165667b1u;
const uint OAS_TAG_JITTER = 0x85ebca6bu;
const uint OAS_TAG_PASS = 0xc2b2ae35u;

/// The per-sample state shared by all dimensions of one OA block: computing it once per block
/// and reusing it across the block's dimensions is the fast path (oas_sample does both).
struct OasRow {
    uint blockSeed;  ///< seed of this (pixel, pass, block)
    uint row;        ///< the sample's row in the block's shuffled OA
    uint index;      ///< the sample index within its pass, in [0, N)
};

/// Pixel seed from integer pixel coordinates and a user seed (frame, render, ...).
uint oas_pixel_seed(uint x, uint y, uint seed) { return oas_hash3(seed, x, y); }

/// Row state of sample `index` for dimension block `block`. Indices >= N begin further passes:
/// pass n uses an independent randomization of the same OA, so any number of samples is valid and
/// every complete pass of N samples is itself stratified.
OasRow oas_row(OasPattern pat, uint pixelSeed, uint index, uint block)
{
    uint seed = pixelSeed;
    uint pass = oas_div_n(pat, index);
    if (pass != 0u) {
        index -= pass * pat.N;
        seed = oas_hash3(pixelSeed, pass, OAS_TAG_PASS);
    }
    OasRow r;
    r.blockSeed = oas_hash2(seed, block);
    r.index = index;
    r.row = oas_permute(index, pat.N, r.blockSeed ^ OAS_TAG_ROW);
    return r;
}

/// Dimension `col` (< blockDims) of the sample described by `r`, in [0, 1).
float oas_row_dim(OasPattern pat, OasRow r, uint col)
{
    uint colSeed = oas_hash2(r.blockSeed, col);
    uint level = oas_oa_level(pat, r.row, col);
    uint stratum = oas_permute(level, pat.s, colSeed ^ OAS_TAG_STRATUM);
    uint offset = OAS_OFFSET(pat);
    uint shiftS = pat.recipShifts & 0xffu;
    if (offset == OAS_OFFSET_CENTERED) return oas_stratum_point_fast(stratum, pat.s, pat.recipS, shiftS, 0x80000000u);
    uint jitter = oas_hash2(colSeed ^ OAS_TAG_JITTER, r.index);
    if (offset == OAS_OFFSET_J) return oas_stratum_point_fast(stratum, pat.s, pat.recipS, shiftS, jitter);
    uint subCount = pat.aux2;  // N / s
    // MJ draws a new substratum permutation for every stratum (Chiu, Shirley and Wang 1994);
    // CMJ shares one per dimension (Kensler 2013), correlating the pattern for better 2D spectra.
    uint subSeed = colSeed ^ OAS_TAG_SUB;
    if (offset == OAS_OFFSET_MJ) subSeed = oas_hash2(subSeed, level);
    uint sub = oas_permute(oas_oa_sublevel(pat, r.row, col), subCount, subSeed);
    return oas_stratum_point_fast(stratum * subCount + sub, pat.N, pat.recipN, (pat.recipShifts >> 16u) & 0xffu, jitter);
}

#endif // OAS_OA_GLSL
