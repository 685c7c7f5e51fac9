/* oas_pattern.c - the pattern builder behind oas_pattern.h (C99). Every value choice that changes
 * the samples is made here, once, and docs/PATTERN.md specifies each of them. */
#include "oas_pattern.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

/* ---- small integer helpers ------------------------------------------------------------------- */

static int oasp_is_prime(uint32_t n)
{
    uint32_t d;
    if (n < 2) return 0;
    for (d = 2; d * d <= n; ++d)
        if (n % d == 0) return 0;
    return 1;
}

/* base^exponent, or 0 when it exceeds limit. */
static uint32_t oasp_pow_capped(uint32_t base, uint32_t exponent, uint32_t limit)
{
    uint64_t v = 1;
    uint32_t i;
    for (i = 0; i < exponent; ++i) {
        v *= base;
        if (v > limit) return 0;
    }
    return (uint32_t)v;
}

/* The largest r with r^t <= n (t >= 1, n >= 1): exact integer roots, no floating point. */
static uint32_t oasp_integer_root(uint32_t n, uint32_t t)
{
    uint32_t lo = 1, hi = n;
    if (t == 1) return n;
    if (hi > 65536) hi = 65536; /* t >= 2 and n < 2^32 */
    while (lo < hi) {
        const uint32_t mid = lo + (hi - lo + 1) / 2;
        if (oasp_pow_capped(mid, t, n) != 0)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

static void oasp_say(char* why, size_t whyLen, const char* format, ...)
{
    va_list args;
    if (why == NULL || whyLen == 0) return;
    va_start(args, format);
    vsnprintf(why, whyLen, format, args);
    va_end(args);
}

/* Appends "; nearest valid spp: a, b" to why: the largest count below spp and the smallest above
 * that the construction makes at this strength (oas_valid_counts), either missing where there is
 * none; nothing when there is neither. */
static void oasp_say_nearest(uint32_t code, uint32_t strength, uint32_t spp, char* why, size_t whyLen)
{
    uint32_t above = 0, lo = 1, hi, mid;
    size_t used;
    int haveAbove = 0, haveBelow = 0;
    if (why == NULL || whyLen == 0) return;
    if (spp < OAS_MAX_SAMPLES) haveAbove = oas_valid_counts(code, strength, spp + 1, OAS_MAX_SAMPLES, &above, 1) > 0;
    if (spp > 1 && oas_valid_counts(code, strength, 1, spp - 1, NULL, 0) > 0) {
        /* The largest lo whose window [lo, spp - 1] still holds a count: that count. */
        hi = spp - 1;
        while (lo < hi) {
            mid = lo + (hi - lo + 1) / 2;
            if (oas_valid_counts(code, strength, mid, spp - 1, NULL, 0) > 0)
                lo = mid;
            else
                hi = mid - 1;
        }
        haveBelow = 1;
    }
    if (!haveAbove && !haveBelow) return;
    used = strlen(why);
    if (haveAbove && haveBelow)
        snprintf(why + used, whyLen - used, "; nearest valid spp: %u, %u", lo, above);
    else
        snprintf(why + used, whyLen - used, "; nearest valid spp: %u", haveBelow ? lo : above);
}

int oas_prime_power(uint32_t q, uint32_t* p, uint32_t* k)
{
    uint32_t smallest = 2, v, count = 0;
    if (q < 2) return 0;
    while (q % smallest != 0) ++smallest;
    for (v = q; v % smallest == 0; v /= smallest) ++count;
    if (v != 1) return 0;
    if (p) *p = smallest;
    if (k) *k = count;
    return 1;
}

void oas_divisor(uint32_t d, uint32_t* recip, uint32_t* shift)
{
    uint32_t l = 0;
    if (d == 0) d = 1;                  /* documented precondition; keep the result defined */
    while (((uint64_t)1 << l) < d) ++l; /* ceil(log2 d) */
    *recip = (uint32_t)((((uint64_t)1 << 32) * (((uint64_t)1 << l) - d)) / d + 1);
    *shift = l;
}

/* ---- GF(p^k): elements are integers whose base-p digits are polynomial coefficients ---------- */

typedef struct {
    uint32_t p, k, q, g; /* x^k == g(x) */
} OaspField;

/* y + c * a, digit by digit mod p. */
static uint32_t oasp_axpy(const OaspField* f, uint32_t y, uint32_t a, uint32_t c)
{
    uint32_t r = 0, place = 1, i;
    for (i = 0; i < f->k; ++i) {
        r += ((y % f->p + c * (a % f->p)) % f->p) * place;
        place *= f->p;
        y /= f->p;
        a /= f->p;
    }
    return r;
}

/* a * x reduced by x^k = g(x). */
static uint32_t oasp_mulx(const OaspField* f, uint32_t a)
{
    const uint32_t topPlace = f->q / f->p;
    const uint32_t top = a / topPlace;
    return oasp_axpy(f, (a % topPlace) * f->p, f->g, top);
}

/* a * b by Horner's rule over b's digits, most significant first. */
static uint32_t oasp_mul(const OaspField* f, uint32_t a, uint32_t b)
{
    uint32_t r = 0, place = f->q / f->p, i;
    for (i = 0; i < f->k; ++i, place /= f->p) r = oasp_axpy(f, oasp_mulx(f, r), a, (b / place) % f->p);
    return r;
}

static uint32_t oasp_pow(const OaspField* f, uint32_t a, uint32_t e)
{
    uint32_t result = 1;
    for (; e != 0; e >>= 1) {
        if (e & 1u) result = oasp_mul(f, result, a);
        a = oasp_mul(f, a, a);
    }
    return result;
}

/* Whether x has multiplicative order q - 1 modulo x^k - g(x); only an irreducible f leaves q - 1
 * units, so this also proves f irreducible. */
static int oasp_x_is_primitive(const OaspField* f)
{
    uint32_t power = 1, order = 0;
    do {
        power = oasp_mulx(f, power);
        ++order;
    } while (power != 1 && order < f->q - 1);
    return power == 1 && order == f->q - 1;
}

uint32_t oas_primitive_polynomial(uint32_t p, uint32_t k)
{
    OaspField f;
    uint32_t g;
    const uint32_t q = oasp_pow_capped(p, k, OAS_MAX_FIELD_Q + 1);
    if (!oasp_is_prime(p) || k <= 1 || q == 0) return 0;
    f.p = p;
    f.k = k;
    f.q = q;
    for (g = 1; g < q; ++g) {
        if (g % p == 0) continue; /* f(0) = -g(0) must be nonzero */
        f.g = g;
        if (oasp_x_is_primitive(&f)) return g;
    }
    return 0; /* cannot happen: GF(p^k) has primitive polynomials for every p, k */
}

/* ---- names -------------------------------------------------------------------------------- */

static const struct {
    const char* name;
    uint32_t code;
} oasp_names[] = {
    {"bose", OAS_BOSE},
    {"bush", OAS_BUSH},
    {"bose-bush", OAS_BOSE_BUSH},
    {"addelman-kempthorne", OAS_ADDELMAN_KEMPTHORNE},
    {"cmjnd", OAS_CMJND},
    {"random", OAS_RANDOM},
    {"jittered2d", OAS_JITTERED_2D},
    {"cmj2d", OAS_CMJ_2D},
    {"zerotwo", OAS_ZERO_TWO},
    {"halton", OAS_HALTON},
    {"sobol", OAS_SOBOL},
    {"sobol-owen", OAS_SOBOL_OWEN},
    {"sobol-burley", OAS_SOBOL_BURLEY},
    {"faure", OAS_FAURE},
};
#define OASP_NAME_COUNT (sizeof oasp_names / sizeof oasp_names[0])

uint32_t oas_construction_at(size_t index)
{
    return index < OASP_NAME_COUNT ? oasp_names[index].code : 0;
}

int oas_construction_from_name(const char* name, uint32_t* construction)
{
    size_t i;
    for (i = 0; name != NULL && i < OASP_NAME_COUNT; ++i)
        if (strcmp(name, oasp_names[i].name) == 0) {
            if (construction) *construction = oasp_names[i].code;
            return 0;
        }
    return OAS_PATTERN_BAD_ARGUMENT;
}

const char* oas_construction_name(uint32_t construction)
{
    size_t i;
    for (i = 0; i < OASP_NAME_COUNT; ++i)
        if (oasp_names[i].code == construction) return oasp_names[i].name;
    return NULL;
}

const char* oas_pattern_field_name(size_t word)
{
    /* In the struct's order; tests/pattern_test.cpp compares this list with the parsed struct. */
    static const char* const names[] = {"construction", "offset", "N",    "s",      "strength", "blockDims",
                                        "fieldP",       "fieldK", "fieldQ", "fieldPoly", "aux", "aux2",
                                        "recipS",       "recipP", "recipN", "recipShifts"};
    return word < sizeof names / sizeof names[0] ? names[word] : NULL;
}

/* ---- patterns ----------------------------------------------------------------------------- */

/* Whether the shaders can multiply in GF(p^k): an odd extension field's products run in one
 * 32-bit word of k digit slots, each wide enough for 2k(p-1)^2 + 2(p-1) (oas_gf_slot_bits in
 * shaders/oas/oas_gf.glsl). Of the fields with q <= 4096 this leaves out GF(3^6), GF(3^7), GF(5^5)
 * and GF(7^4), which only sample counts of 531441 and more would use. The formula is the GLSL's,
 * restated in C99; GfHost.OddExtensionFieldsOutsideOneWordAreRefused checks the two agree for
 * every q <= 4096. */
static int oasp_field_supported(uint32_t q, char* why, size_t whyLen)
{
    uint32_t p = 0, k = 0, bound, bits = 0;
    oas_prime_power(q, &p, &k);
    if (p == 2 || k == 1) return 1;
    bound = 2 * k * (p - 1) * (p - 1) + 2 * (p - 1);
    while (bound >> bits) ++bits;
    if (k * bits <= 32) return 1;
    oasp_say(why, whyLen,
             "q = %u = %u^%u: the shaders' fixed-work GF(%u^%u) arithmetic needs %u digit slots of %u bits, "
             "more than 32",
             q, p, k, p, k, k, bits);
    return 0;
}

static void oasp_set_field(OasPattern* pat, uint32_t q)
{
    uint32_t p = 0, k = 0;
    oas_prime_power(q, &p, &k);
    pat->fieldP = p;
    pat->fieldK = k;
    pat->fieldQ = q;
    pat->fieldPoly = k > 1 ? oas_primitive_polynomial(p, k) : 0;
}

/* Faure's base for d dimensions a block: the smallest prime power q >= max(d, 2) (a (0,s)-sequence
 * in base q has s <= q dimensions, one field element each; Niederreiter 1987). Every q up to
 * OAS_MAX_STRENGTH + 1 = 25 has a field the shaders multiply in. */
static uint32_t oasp_faure_base(uint32_t d)
{
    uint32_t q = d < 2 ? 2 : d;
    while (!oas_prime_power(q, NULL, NULL)) ++q;
    return q;
}

/* The longest Faure sequence in base q: q^K with K <= OAS_FAURE_MAX_DIGITS and q^K <= OAS_MAX_SAMPLES. */
static uint32_t oasp_faure_longest(uint32_t q)
{
    uint32_t n = q, k = 1;
    while (k < OAS_FAURE_MAX_DIGITS && (uint64_t)n * q <= OAS_MAX_SAMPLES) {
        n *= q;
        ++k;
    }
    return n;
}

/* The construction's own fields; returns OAS_PATTERN_NOT_EXACT with a reason when spp cannot be
 * made exactly. t is the resolved strength. */
static int oasp_fields(OasPattern* pat, uint32_t code, uint32_t spp, uint32_t t, char* why, size_t whyLen)
{
    uint32_t q, p = 0, k = 0;
    switch (code) {
    case OAS_BOSE:
        if (t != 2) {
            oasp_say(why, whyLen, "bose has strength 2 only");
            return OAS_PATTERN_NOT_EXACT;
        }
        q = oasp_integer_root(spp, 2);
        if (q * q != spp) {
            oasp_say(why, whyLen, "%u is not a square q^2", spp);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (!oas_prime_power(q, NULL, NULL)) {
            oasp_say(why, whyLen, "q = %u is not a prime power", q);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (q > OAS_MAX_BOSE_Q) {
            oasp_say(why, whyLen, "q = %u exceeds 4096", q);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (!oasp_field_supported(q, why, whyLen)) return OAS_PATTERN_NOT_EXACT;
        pat->s = q;
        pat->blockDims = q + 1;
        oasp_set_field(pat, q);
        return OAS_PATTERN_OK;
    case OAS_BUSH:
        if (t < 2) {
            oasp_say(why, whyLen, "bush needs strength t >= 2");
            return OAS_PATTERN_NOT_EXACT;
        }
        q = oasp_integer_root(spp, t);
        if (q < 2 || oasp_pow_capped(q, t, OAS_MAX_SAMPLES) != spp) {
            oasp_say(why, whyLen, "%u is not q^%u", spp, t);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (!oas_prime_power(q, NULL, NULL)) {
            oasp_say(why, whyLen, "q = %u is not a prime power", q);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (q < t) {
            oasp_say(why, whyLen, "bush needs q >= t (q = %u, t = %u)", q, t);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (!oasp_field_supported(q, why, whyLen)) return OAS_PATTERN_NOT_EXACT;
        pat->s = q;
        pat->blockDims = q + 1;
        pat->aux = spp / q; /* q^(t-1) */
        oasp_set_field(pat, q);
        return OAS_PATTERN_OK;
    case OAS_BOSE_BUSH:
    case OAS_ADDELMAN_KEMPTHORNE: {
        const int bb = code == OAS_BOSE_BUSH;
        const char* name = bb ? "bose-bush" : "addelman-kempthorne";
        if (t != 2) {
            oasp_say(why, whyLen, "%s has strength 2 only", name);
            return OAS_PATTERN_NOT_EXACT;
        }
        q = oasp_integer_root(spp / 2, 2);
        if (spp % 2 != 0 || 2 * q * q != spp) {
            oasp_say(why, whyLen, "%u is not 2q^2", spp);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (!oas_prime_power(q, &p, &k)) p = 0;
        if (bb && p != 2) {
            oasp_say(why, whyLen, "q = %u is not a power of two", q);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (!bb && (p == 0 || p == 2)) {
            oasp_say(why, whyLen, "q = %u is not an odd prime power", q);
            return OAS_PATTERN_NOT_EXACT;
        }
        if (!oasp_field_supported(q, why, whyLen)) return OAS_PATTERN_NOT_EXACT;
        pat->s = q;
        pat->blockDims = 2 * q + 1;
        if (bb) {
            oasp_set_field(pat, 2 * q); /* GF(2q), mapped onto q levels by dropping the top bit */
        } else {
            OaspField f;
            uint32_t a;
            oasp_set_field(pat, q);
            f.p = pat->fieldP;
            f.k = pat->fieldK;
            f.q = q;
            f.g = pat->fieldPoly;
            /* The smallest non-square: a^((q-1)/2) != 1 (Euler's criterion in GF(q)). */
            for (a = 1; a < q; ++a)
                if (oasp_pow(&f, a, (q - 1) / 2) != 1) {
                    pat->aux = a;
                    break;
                }
        }
        return OAS_PATTERN_OK;
    }
    case OAS_CMJND:
        if (t < 1) {
            oasp_say(why, whyLen, "cmjnd needs d >= 1 dimensions");
            return OAS_PATTERN_NOT_EXACT;
        }
        q = oasp_integer_root(spp, t);
        if (q < 2 || oasp_pow_capped(q, t, OAS_MAX_SAMPLES) != spp) {
            oasp_say(why, whyLen, "%u is not s^%u with s >= 2", spp, t);
            return OAS_PATTERN_NOT_EXACT;
        }
        pat->s = q;
        pat->blockDims = t;
        return OAS_PATTERN_OK;
    case OAS_FAURE: {
        /* t is d, the dimensions of a block; N = q^K >= spp, the sequence the render takes a prefix of. */
        uint32_t n = 1, digits = 0;
        q = oasp_faure_base(t);
        if (spp > oasp_faure_longest(q)) {
            oasp_say(why, whyLen, "spp %u is more than the %u samples of the longest Faure sequence in base %u (%u digits)",
                     spp, oasp_faure_longest(q), q, (uint32_t)OAS_FAURE_MAX_DIGITS);
            return OAS_PATTERN_NOT_EXACT;
        }
        while (n < spp || digits == 0) {
            n *= q;
            ++digits;
        }
        pat->N = n;
        pat->s = q;
        pat->blockDims = t;
        pat->aux = digits;
        oasp_set_field(pat, q);
        return OAS_PATTERN_OK;
    }
    default: { /* the baselines take any N */
        uint32_t nx = oasp_integer_root(spp, 2);
        pat->s = spp;
        const int sobol = code == OAS_SOBOL || code == OAS_SOBOL_OWEN;
        pat->blockDims = code == OAS_HALTON         ? OAS_HALTON_BLOCK_DIMS
                         : sobol                    ? OAS_SOBOL_BLOCK_DIMS
                         : code == OAS_SOBOL_BURLEY ? OAS_SOBOL_BURLEY_GROUP_DIMS
                         : code == OAS_RANDOM       ? 1
                                                    : 2;
        pat->strength = code == OAS_RANDOM ? 0 : (code == OAS_HALTON || sobol || code == OAS_SOBOL_BURLEY ? 1 : 2);
        /* The 2D grid nx * ny = N with nx the largest divisor <= sqrt(N): squares give n x n,
         * primes a 1 x N grid (then jittered2d is a 1D stratification of the second axis). */
        while (nx > 1 && spp % nx != 0) --nx;
        pat->aux = nx;
        pat->aux2 = spp / nx;
        return OAS_PATTERN_OK;
    }
    }
}

int oas_make_pattern(uint32_t construction, uint32_t spp, uint32_t strength, uint32_t offset, OasPattern* out, char* why,
                     size_t whyLen)
{
    OasPattern pat;
    uint32_t shiftS, shiftP, shiftN;
    int status;
    const uint32_t code = construction;
    const int isOa = code >= OAS_BOSE && code <= OAS_CMJND;
    memset(&pat, 0, sizeof pat);
    if (out) memset(out, 0, sizeof *out);
    if (why && whyLen) why[0] = '\0';
    if (out == NULL) {
        oasp_say(why, whyLen, "out is NULL");
        return OAS_PATTERN_BAD_ARGUMENT;
    }
    if (oas_construction_name(code) == NULL) {
        oasp_say(why, whyLen,
                 "construction %u is unknown: valid %u .. %u (orthogonal arrays), %u .. %u (baselines), %u (faure)", code,
                 (uint32_t)OAS_BOSE, (uint32_t)OAS_CMJND, (uint32_t)OAS_RANDOM, (uint32_t)OAS_SOBOL_BURLEY,
                 (uint32_t)OAS_FAURE);
        return OAS_PATTERN_BAD_ARGUMENT;
    }
    if (spp < 1 || spp > OAS_MAX_SAMPLES) {
        oasp_say(why, whyLen, "spp %u is out of range: valid 1 .. %u", spp, (uint32_t)OAS_MAX_SAMPLES);
        return OAS_PATTERN_BAD_ARGUMENT;
    }
    if (strength > OAS_MAX_STRENGTH) {
        oasp_say(why, whyLen, "strength %u is out of range: valid 2 .. 24", strength);
        return OAS_PATTERN_BAD_ARGUMENT;
    }
    if (isOa && offset > OAS_OFFSET_CMJ) {
        oasp_say(why, whyLen, "offset %u is out of range: valid 0 (centered), 1 (j), 2 (mj), 3 (cmj)", offset);
        return OAS_PATTERN_BAD_ARGUMENT;
    }
    if (strength == 0) {
        if (code == OAS_CMJND) {
            oasp_say(why, whyLen, "cmjnd needs its strength (the dimensions of one full factorial) given: valid 1 .. 24");
            return OAS_PATTERN_BAD_ARGUMENT;
        }
        strength = 2;
    }
    pat.construction = code;
    pat.N = spp;
    pat.strength = strength;
    pat.offset = isOa ? offset : 0;
    status = oasp_fields(&pat, code, spp, strength, why, whyLen);
    if (status == OAS_PATTERN_NOT_EXACT) oasp_say_nearest(code, strength, spp, why, whyLen);
    if (status != OAS_PATTERN_OK) return status;
    /* The constants every shader divides by. */
    if (isOa) pat.aux2 = pat.N / pat.s;
    oas_divisor(pat.s, &pat.recipS, &shiftS);
    oas_divisor(pat.fieldP > 1 ? pat.fieldP : 1, &pat.recipP, &shiftP);
    oas_divisor(pat.N, &pat.recipN, &shiftN);
    pat.recipShifts = shiftS | (shiftP << 8) | (shiftN << 16);
    *out = pat;
    return OAS_PATTERN_OK;
}

/* ---- valid sample counts ------------------------------------------------------------------ */

/* The counts in [lo, hi] seen so far; n arrive in ascending order. */
typedef struct {
    uint32_t lo, hi;
    uint32_t* out;
    size_t capacity, count;
} OaspCounts;

/* Records n (when it lies in [lo, hi]); returns 0 once n is past hi, so that loops over growing
 * q can stop. */
static int oasp_count(OaspCounts* c, uint32_t n)
{
    if (n > c->hi) return 0;
    if (n < c->lo) return 1;
    if (c->count < c->capacity) c->out[c->count] = n;
    ++c->count;
    return 1;
}

/* The rules of oasp_fields, run forwards: each construction's N as a function of its q (or s),
 * for the q the construction is defined for, within the limits oas_make_pattern enforces. */
size_t oas_valid_counts(uint32_t construction, uint32_t strength, uint32_t lo, uint32_t hi, uint32_t* out, size_t capacity)
{
    OaspCounts c;
    uint32_t q, n;
    c.lo = lo < 1 ? 1 : lo;
    c.hi = hi < OAS_MAX_SAMPLES ? hi : OAS_MAX_SAMPLES;
    c.out = out;
    c.capacity = out == NULL ? 0 : capacity;
    c.count = 0;
    if (oas_construction_name(construction) == NULL || strength > OAS_MAX_STRENGTH || c.lo > c.hi) return 0;
    if (strength == 0) {
        if (construction == OAS_CMJND) return 0; /* no default: the full factorial's d must be given */
        strength = 2;
    }
    switch (construction) {
    case OAS_BOSE:
        /* Bose (1938): the lines of the affine plane over GF(q) give OA(q^2, q+1, q, 2) for every
         * prime power q; q <= OAS_MAX_BOSE_Q keeps q^2 within OAS_MAX_SAMPLES. */
        if (strength != 2) return 0;
        for (q = 2; q <= OAS_MAX_BOSE_Q; ++q)
            if (oas_prime_power(q, NULL, NULL) && oasp_field_supported(q, NULL, 0) && !oasp_count(&c, q * q)) break;
        return c.count;
    case OAS_BUSH:
        /* Bush (1952): polynomials of degree < t over GF(q) give OA(q^t, q+1, q, t) for a prime
         * power q >= t (strength 2 gives Bose's counts). */
        if (strength < 2) return 0;
        for (q = strength; (n = oasp_pow_capped(q, strength, OAS_MAX_SAMPLES)) != 0; ++q)
            if (oas_prime_power(q, NULL, NULL) && oasp_field_supported(q, NULL, 0) && !oasp_count(&c, n)) break;
        return c.count;
    case OAS_BOSE_BUSH:
        /* Bose and Bush (1952): OA(2q^2, 2q+1, q, 2) from GF(2q) for q a power of two. */
        if (strength != 2) return 0;
        for (q = 2; 2 * q * q <= OAS_MAX_SAMPLES; q *= 2)
            if (!oasp_count(&c, 2 * q * q)) break;
        return c.count;
    case OAS_ADDELMAN_KEMPTHORNE:
        /* Addelman and Kempthorne (1961): OA(2q^2, 2q+1, q, 2) for q an odd prime power (their
         * second half uses a non-square of GF(q), which only odd q have). */
        if (strength != 2) return 0;
        for (q = 3; 2 * q * q <= OAS_MAX_SAMPLES; q += 2)
            if (oas_prime_power(q, NULL, NULL) && oasp_field_supported(q, NULL, 0) && !oasp_count(&c, 2 * q * q)) break;
        return c.count;
    case OAS_CMJND:
        /* The full factorial OA(s^d, d, s, d) of Jarosz et al. (EGSR 2019, CMJND): any s >= 2. */
        for (q = 2; (n = oasp_pow_capped(q, strength, OAS_MAX_SAMPLES)) != 0; ++q)
            if (!oasp_count(&c, n)) break;
        return c.count;
    case OAS_FAURE: /* any spp up to the longest sequence in the block's base, as the baselines below */
        n = oasp_faure_longest(oasp_faure_base(strength));
        if (c.hi > n) c.hi = n;
        if (c.lo > c.hi) return 0;
        /* fall through */
    default: /* the baselines take any N */
        for (n = c.lo; n - c.lo < c.capacity && n <= c.hi; ++n) c.out[n - c.lo] = n;
        return (size_t)(c.hi - c.lo) + 1;
    }
}

/* ---- Sobol direction numbers --------------------------------------------------------------- */

/* Joe and Kuo's table (s, a, m_1 .. m_s per dimension), generated from data/sobol/ by
 * scripts/joe_kuo.py; a table rather than code because these numbers come from a search, not a
 * formula. */
#include "oas_joe_kuo.inc"

/* The table must cover exactly one Sobol block (a negative array size fails the build; the casts
 * because the two constants belong to different enums). */
typedef char oasp_joe_kuo_covers_one_block[(int)OASP_JOE_KUO_DIMS == (int)OAS_SOBOL_BLOCK_DIMS ? 1 : -1];

void oas_sobol_directions(uint32_t out[OAS_SOBOL_BLOCK_DIMS * 32])
{
    const uint16_t* entry = oasp_joe_kuo;
    uint32_t b, dim;
    for (b = 0; b < 32; ++b) out[b] = 1u << (31 - b); /* dimension 0: van der Corput (all m_k = 1) */
    for (dim = 1; dim < OAS_SOBOL_BLOCK_DIMS; ++dim) {
        /* v[k] is the k-th direction number (k = 1 .. 32) as a 32-bit fraction, v_k = m_k / 2^k.
         * Bratley and Fox (1988), as Joe and Kuo (2003, 2008) state it: v_k = m_k << (32 - k) for
         * k <= s, then v_k = v_{k-s} ^ (v_{k-s} >> s) ^ a_1 v_{k-1} ^ ... ^ a_{s-1} v_{k-s+1},
         * where a's bits, most significant first, are a_1 .. a_{s-1}. */
        const uint32_t s = entry[0], a = entry[1];
        uint32_t v[33], k, i;
        for (k = 1; k <= s; ++k) v[k] = (uint32_t)entry[1 + k] << (32 - k);
        for (k = s + 1; k <= 32; ++k) {
            uint32_t vk = v[k - s] ^ (v[k - s] >> s);
            for (i = 1; i < s; ++i)
                if ((a >> (s - 1 - i)) & 1u) vk ^= v[k - i];
            v[k] = vk;
        }
        for (b = 0; b < 32; ++b) out[dim * 32 + b] = v[b + 1];
        entry += 2 + s;
    }
}

/* ---- Specialization ------------------------------------------------------------------------ */

/* Bits of a sample index within a pass (index < N <= 2^24): OAS_INDEX_BITS of oas_baselines.glsl. */
#define OASP_INDEX_BITS 24u

void oas_specialization(const OasPattern* pattern, OasSpecialization* out)
{
    out->construction = pattern->construction;
    out->offset = pattern->offset;
    out->fieldKind = pattern->fieldK <= 1 ? 0u : (pattern->fieldP == 2 ? 1u : 2u);
    out->fieldDegree = pattern->fieldK <= 1 ? 1u : pattern->fieldK;
    out->smallN = pattern->N <= 65536u ? 1u : 0u;
    /* Only Halton's and Faure's work grows with the index's digits (Halton: the bits of N - 1;
       Faure: K, its base-q digits); the others keep 24 so that patterns of one kind and any N
       share a pipeline. */
    out->indexBits = OASP_INDEX_BITS;
    if (pattern->construction == OAS_FAURE) out->indexBits = pattern->aux; /* K, its base-q index digits */
    if (pattern->construction == OAS_HALTON) {
        uint32_t bits = 0;
        while (bits < OASP_INDEX_BITS && ((pattern->N - 1u) >> bits) != 0u) ++bits;
        out->indexBits = bits;
    }
}

int oas_specialization_matches(const OasPattern* pattern, const OasSpecialization* spec)
{
    OasSpecialization own;
    oas_specialization(pattern, &own);
    return own.construction == spec->construction && own.offset == spec->offset && own.fieldKind == spec->fieldKind &&
           own.fieldDegree == spec->fieldDegree && (spec->smallN == 0 || own.smallN == 1) &&
           (spec->indexBits >= OASP_INDEX_BITS || (pattern->construction == OAS_FAURE ? own.indexBits == spec->indexBits
                                                                                       : ((pattern->N - 1u) >> spec->indexBits) == 0u));
}

/* ---- Dimension layout ---------------------------------------------------------------------- */

uint32_t oas_pair_dimension(const OasPattern* pattern, uint32_t from)
{
    const uint32_t blockDims = pattern->blockDims;
    uint32_t block, col;
    if (blockDims < 2) return from; /* random: no pairs */
    block = from / blockDims;
    col = from - block * blockDims;
    col += col & 1u;               /* an even column */
    if (col + 1 >= blockDims) {    /* no partner left in this block: the next block's first pair */
        block += 1;
        col = 0;
    }
    return block * blockDims + col;
}
