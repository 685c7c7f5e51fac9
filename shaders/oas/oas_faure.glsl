// oas_faure.glsl - a progressive sampler: the generalized Faure (0,s)-sequence in base q,
// nested-scrambled, made for one (sample index, dimension) at a time with no tables and no state.
// Part of the oas GLSL library; include "oas.glsl" rather than this file.
//
// Why: an orthogonal array is a finite set of N points, so a render that stops early, or refines
// progressively, gets a prefix that is not stratified (Jarosz et al. 2019, section 8, their first
// limitation). The generalized Faure sequence is a (0,s)-sequence in base q for s <= q (Faure,
// "Discrepance de suites associees a un systeme de numeration (en dimension s)", Acta Arith. 41,
// 1982, for prime q; Niederreiter, "Point sets and sequences with small discrepancy", Monatsh.
// Math. 104, 1987, over any field GF(q)): every aligned block of q^m consecutive samples is a
// (0,m,s)-net, so every prefix of lambda q^t samples is an orthogonal array of strength t and
// index lambda in the leading digits.
//
// The digits. Sample index i = sum_k d_k q^k (k < K) is read as the polynomial
// D(x) = sum_k d_k x^k over GF(q); the dimension with field element a gets the output digits y_r,
// y_0 the most significant, that are the coefficients of D shifted to a:
//     D(x + a) = sum_r y_r x^r,  i.e.  y_r = sum_{k >= r} C(k, r) a^(k - r) d_k,
// which is row r of the generalized Faure generator matrix (the Pascal matrix's a-th power) times
// the digit vector. y_0 = D(a) is Bush's orthogonal array ("Orthogonal arrays of index unity",
// Ann. Math. Stat. 23, 1952; oas_bush_level with the same digits as its row): the leading digit of
// this sequence is the OA the library already builds, and the further digits refine it.
// The shift is Horner's synthetic division repeated (K (K - 1) / 2 field multiply-adds by a, no
// binomials); digits at or above K are zero, so every step there leaves the digits unchanged.
//
// Randomization: a nested scramble of the output digits (Owen, "Randomly permuted (t,m,s)-nets
// and (t,s)-sequences", 1995): digit r goes through a bijection of GF(q) chosen by a key that
// hashes the caller's key with the original digits above it, y_0 .. y_{r-1}. The bijection is
// affine, y -> g y + h with g != 0 and h uniform (Matousek, "On the L2-discrepancy for anchored
// boxes", J. Complexity 14, 1998): the affine maps of GF(q) carry any two distinct digits to a
// uniformly random pair of distinct digits, the one property of the permutations Owen's variance
// formula uses, so the scramble has the variance of a nested uniform one. Below the last digit a
// hashed jitter places the point inside its stratum of q^K (oas_stratum_point's exact contract:
// the point lies in [m / q^K, (m + 1) / q^K), never 1.0). Bijections keyed by the digits above
// keep every net and every prefix property; the sample index itself is never permuted, which
// would break the prefixes.
#ifndef OAS_FAURE_GLSL
#define OAS_FAURE_GLSL

/// The most digits of an index (and exactly made output digits) a Faure pattern has: K with
/// q^K <= 2^24 for every q >= 4, so bases 2 and 3 reach 2^12 = 4096 and 3^12 = 531441 samples.
/// Fixed loops of this length unroll into straight-line code (OAS_UNROLL, the library's rule).
const uint OAS_FAURE_MAX_DIGITS = 12u;

// A shader whose Faure sequences all have K digits can fix K at compile time (for instance with a
// specialization constant) by defining OAS_STATIC_FAURE_DIGITS to K before including oas.glsl, as
// OAS_STATIC_FIELD_KIND / _DEGREE fix the field. Every digit step is then known to run or not,
// and the steps past K (66 of the 78 field operations at K = 2) compile away; unspecialized, each
// is guarded by K at run time, which lavapipe pays for whatever K is, since it runs both sides of
// a branch. A sequence with another K gets NaN for every value (oas_faure_value), never the
// values of a K it is not. A shader specialized on a faure pattern (OasPattern, oas_specialization)
// gets K that way without defining it: a faure pattern's OAS_STATIC_INDEX_BITS is its K, the
// base-q digits of an index (below 24; 24 and more take any K).
#if defined(OAS_STATIC_FAURE_DIGITS)
#define OAS_FAURE_K(fa) OAS_STATIC_FAURE_DIGITS
#elif defined(OAS_STATIC_INDEX_BITS)
#define OAS_FAURE_K(fa) (OAS_STATIC_INDEX_BITS < 24u ? OAS_STATIC_INDEX_BITS : (fa).digits)
#else
#define OAS_FAURE_K(fa) ((fa).digits)
#endif

/// A Faure sequence's per-pattern state: the field, K, q^K and the oas_fastdiv constants of q
/// and of q^K.
struct OasFaure {
    OasField field;
    uint digits;       ///< K: indices below q^K; q^K <= 2^24
    uint strata;       ///< q^K
    uint recipQ;       ///< oas_fastdiv constants of q (digit extraction)
    uint shiftQ;
    uint recipStrata;  ///< oas_fastdiv constants of q^K (the stratum point's divisions)
    uint shiftStrata;
};

/// The state for base field `f` (q = f.q) and K = `digits` (1 <= K <= OAS_FAURE_MAX_DIGITS,
/// q^K <= 2^24; the host checks both).
OasFaure oas_faure_make(OasField f, uint digits)
{
    OasFaure fa;
    fa.field = f;
    fa.digits = digits;
    fa.strata = oas_uint_pow(f.q, digits);
    fa.shiftQ = oas_fastdiv_shift(f.q);
    fa.recipQ = oas_fastdiv_recip(f.q, fa.shiftQ);
    fa.shiftStrata = oas_fastdiv_shift(fa.strata);
    fa.recipStrata = oas_fastdiv_recip24(fa.strata, fa.shiftStrata);  // q^K may pass 2^16
    return fa;
}

/// The output digits y_0 .. y_{K-1} (y_0 the most significant) of one sample in one dimension,
/// unscrambled; y[r] = 0 for r >= K.
struct OasFaureDigits {
    uint y[OAS_FAURE_MAX_DIGITS];
};

/// The digits of sample `index` (< q^K; higher digits are ignored) in the dimension whose
/// generator is the field element `element` (< q): D(x + element) by repeated synthetic division.
OasFaureDigits oas_faure_digits(OasFaure fa, uint element, uint index)
{
    OasFaureDigits c;
    OAS_UNROLL for (uint k = 0u; k < OAS_FAURE_MAX_DIGITS; ++k) {
        uint next = oas_fastdiv(index, fa.recipQ, fa.shiftQ);
        c.y[k] = k < OAS_FAURE_K(fa) ? index - next * fa.field.q : 0u;
        index = next;
    }
    // Pass r leaves c.y[r] final: c_j += a c_{j+1} from the top down to j = r. Steps with
    // j + 1 >= K add a zero digit times a, so only those with r < j < K run, in this order.
#if defined(OAS_RUNTIME_BRANCHES)
    // The C++ twin, which branches for real: loops bounded by the pattern's K. OAS_UNROLL lets a
    // twin loop that fixes K (host/oas/baseline_columns_loops.inc) unroll both into straight-line
    // code, which g++ then vectorizes across samples; elsewhere the twin defines it as nothing.
    OAS_UNROLL for (uint r = 0u; r + 1u < fa.digits; ++r) {
        OAS_UNROLL for (uint j = fa.digits - 1u; j > r; --j) c.y[j - 1u] = oas_gf_mul_add(fa.field, c.y[j], element, c.y[j - 1u]);
    }
#else
    // On the GPU one flat loop of fixed length over every (r, j) step, each guarded: a pattern's
    // uniform K skips the same steps on every lane, and OAS_STATIC_FAURE_DIGITS folds the guards.
    // Not two nested loops: Mesa's NIR, which lavapipe compiles with, unrolls only innermost
    // loops whose trip count it knows, so with the inner one bounded by r both stayed loops, and
    // the digits stayed in memory indexed at run time, and a shader making thousands of values
    // in one invocation ran into lavapipe's loop cap (docs/BENCHMARKS.md, DESIGN-NOTES.md).
    OAS_UNROLL for (uint step = 0u; step < (OAS_FAURE_MAX_DIGITS - 1u) * (OAS_FAURE_MAX_DIGITS - 1u); ++step) {
        uint r = step / (OAS_FAURE_MAX_DIGITS - 1u);
        uint j = OAS_FAURE_MAX_DIGITS - 1u - (step - r * (OAS_FAURE_MAX_DIGITS - 1u));  // 11 down to 1
        if (j > r && j < OAS_FAURE_K(fa)) c.y[j - 1u] = oas_gf_mul_add(fa.field, c.y[j], element, c.y[j - 1u]);
    }
#endif
    return c;
}

/// A sample's scrambled stratum of q^K (its leading K digits after the nested scramble, as an
/// integer, most significant digit first) and the key the scramble ended with (the jitter's).
struct OasFaureStratum {
    uint stratum;
    uint key;
};

/// The nested scramble of sample `index`'s digits in the dimension of `element`, keyed by `key`
/// (oas_faure_key: the pixel, the block and the dimension).
OasFaureStratum oas_faure_stratum(OasFaure fa, uint element, uint index, uint key)
{
    OasFaureDigits c = oas_faure_digits(fa, element, index);
    OasFaureStratum result;
    result.stratum = 0u;
    OAS_UNROLL for (uint r = 0u; r < OAS_FAURE_MAX_DIGITS; ++r) {
        if (r < OAS_FAURE_K(fa)) {
            // y -> g y + h on GF(q), g in [1, q), h in [0, q): from the key of the digits above.
            uint h = oas_mulhi(key, fa.field.q);
            uint g = 1u + oas_mulhi(oas_pcg(key ^ 0x5bd1e995u), fa.field.q - 1u);
            result.stratum = result.stratum * fa.field.q + oas_gf_mul_add(fa.field, g, c.y[r], h);
            key = oas_hash2(key, c.y[r]);
        }
    }
    result.key = key;
    return result;
}

/// The scramble key of a dimension: the pixel seed, the dimension's block and its element.
uint oas_faure_key(uint pixelSeed, uint block, uint element) { return oas_hash3(pixelSeed, block, element); }

/// Sample `index` of the sequence in the dimension of `element`, scrambled by `key`: a float in
/// its scrambled stratum of q^K, placed there by a hash of the scramble's last key (the exact
/// contract of oas_stratum_point, with q^K's division by its oas_fastdiv constants: one division
/// where q^K <= 2^16 is known, OAS_STATIC_SMALL_N = 1 as for a pattern's N, three otherwise). NaN
/// in a shader specialized on another K (OAS_STATIC_FAURE_DIGITS) or, with OAS_STATIC_SMALL_N = 1,
/// for q^K > 2^16.
float oas_faure_value(OasFaure fa, uint element, uint index, uint key)
{
    OasFaureStratum st = oas_faure_stratum(fa, element, index, key);
    float v = oas_stratum_point_divided(st.stratum, fa.strata, fa.recipStrata, fa.shiftStrata, oas_pcg(st.key ^ 0x68e31da4u),
                                        OAS_SMALL_STRATA(fa.strata));
    bool fits = fa.digits == OAS_FAURE_K(fa);
#ifdef OAS_STATIC_SMALL_N
    fits = fits && (OAS_STATIC_SMALL_N == 0u || fa.strata <= 65536u);  // the short division needs q^K <= 2^16
#endif
    return fits ? v : uintBitsToFloat(0x7fc00000u);
}

/// The sequence of a pattern (OAS_FAURE): the pattern holds every constant oas_faure_make would
/// compute (s = q and N = q^K with their division constants, K in aux), so none is made per value.
OasFaure oas_faure_of(OasPattern pat)
{
    OasFaure fa;
    fa.field = oas_pattern_field(pat);
    fa.digits = pat.aux;
    fa.strata = pat.N;
    fa.recipQ = pat.recipS;
    fa.shiftQ = pat.recipShifts & 0xffu;
    fa.recipStrata = pat.recipN;
    fa.shiftStrata = (pat.recipShifts >> 16u) & 0xffu;
    return fa;
}

/// Value `index` (< N, within one pass) of dimension `dim` for a pattern's pass seed: blocks of
/// blockDims (<= q) dimensions, each dimension one field element of its block (0, 1, ...), each
/// block scrambled by its own keys (oas_faure_key), as the OAs pad with independent blocks.
float oas_faure_dim(OasPattern pat, uint passSeed, uint index, uint dim)
{
    uint block = dim / pat.blockDims;
    uint element = dim - block * pat.blockDims;
    return oas_faure_value(oas_faure_of(pat), element, index, oas_faure_key(passSeed, block, element));
}

#endif // OAS_FAURE_GLSL
