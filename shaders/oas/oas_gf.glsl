// oas_gf.glsl - arithmetic in the finite field GF(p^k), computed on the fly (no tables).
// Part of the oas GLSL library; include "oas.glsl" rather than this file.
#ifndef OAS_GF_GLSL
#define OAS_GF_GLSL

/// A finite field GF(q), q = p^k < 2^16. Elements are the integers [0, q): the base-p digits of
/// an element are the coefficients of a polynomial over GF(p) (digit i <-> x^i). Products are
/// reduced modulo a monic irreducible polynomial f(x) = x^k - g(x); `poly` packs g's k
/// coefficients as base-p digits, so x^k == g(x). The host finds g once per (p, k) (a primitive
/// polynomial: the smallest g for which x has multiplicative order q - 1). For k = 1, poly = 0.
struct OasField {
    uint p;       ///< characteristic, a prime
    uint k;       ///< degree of the extension
    uint q;       ///< p^k
    uint poly;    ///< g(x) packed base p: x^k == g(x)
    uint recipP;  ///< oas_fastdiv constants for dividing by p
    uint shiftP;
};

// Field kinds, for shaders specialised on one (OAS_STATIC_FIELD_KIND, see oas_pattern.glsl).
const uint OAS_FIELD_PRIME = 0u;         ///< k = 1
const uint OAS_FIELD_BINARY = 1u;        ///< p = 2, k > 1
const uint OAS_FIELD_ODD_EXTENSION = 2u; ///< p odd, k > 1
#ifdef OAS_STATIC_FIELD_KIND
#define OAS_FIELD_IS_PRIME(f) (OAS_STATIC_FIELD_KIND == OAS_FIELD_PRIME)
#define OAS_FIELD_IS_BINARY(f) (OAS_STATIC_FIELD_KIND == OAS_FIELD_BINARY)
#else
#define OAS_FIELD_IS_PRIME(f) ((f).k == 1u)
#define OAS_FIELD_IS_BINARY(f) ((f).p == 2u)
#endif

/// a mod p and a / p via the field's reciprocal.
uint oas_gf_divp(OasField f, uint a) { return oas_fastdiv(a, f.recipP, f.shiftP); }

/// y + c * a with digit-wise arithmetic mod p (a polynomial axpy over GF(p)); c < p.
uint oas_gf_axpy(OasField f, uint y, uint a, uint c)
{
    uint r = 0u;
    uint place = 1u;
    for (uint i = 0u; i < f.k; ++i) {
        uint yNext = oas_gf_divp(f, y);
        uint aNext = oas_gf_divp(f, a);
        uint d = (y - yNext * f.p) + c * (a - aNext * f.p);  // < p + p^2 < 2^32
        d -= oas_gf_divp(f, d) * f.p;
        r += d * place;
        place *= f.p;
        y = yNext;
        a = aNext;
    }
    return r;
}

/// a + b in GF(q).
uint oas_gf_add(OasField f, uint a, uint b)
{
    if (OAS_FIELD_IS_PRIME(f)) {
        uint s = a + b;
        return s >= f.p ? s - f.p : s;
    }
    if (OAS_FIELD_IS_BINARY(f)) return a ^ b;
    return oas_gf_axpy(f, a, b, 1u);
}

/// -a in GF(q).
uint oas_gf_neg(OasField f, uint a)
{
    if (OAS_FIELD_IS_PRIME(f)) return a == 0u ? 0u : f.p - a;
    if (OAS_FIELD_IS_BINARY(f)) return a;
    return oas_gf_axpy(f, 0u, a, f.p - 1u);
}

/// a * x mod f(x): shift the digits up one place and fold the overflowing digit back via g.
uint oas_gf_mulx(OasField f, uint a)
{
    if (OAS_FIELD_IS_BINARY(f)) {
        uint shifted = (a << 1u) & (f.q - 1u);
        return a >= (f.q >> 1u) ? shifted ^ f.poly : shifted;
    }
    uint top = a;  // the digit of x^(k-1): k-1 divisions by p
    for (uint i = 1u; i < f.k; ++i) top = oas_gf_divp(f, top);
    uint placeTop = oas_gf_divp(f, f.q);  // p^(k-1)
    return oas_gf_axpy(f, (a - top * placeTop) * f.p, f.poly, top);
}

/// a * b in GF(q), by Horner's rule over the digits of b (most significant first).
/// Prime fields take one multiply and one remainder (a, b < p < 2^16, so a*b < 2^32).
uint oas_gf_mul(OasField f, uint a, uint b)
{
    if (OAS_FIELD_IS_PRIME(f)) {
        uint product = a * b;
        return product - oas_gf_divp(f, product) * f.p;
    }
    uint r = 0u;
    if (OAS_FIELD_IS_BINARY(f)) {
        for (uint i = f.k; i > 0u; --i) {
            r = oas_gf_mulx(f, r);
            if (((b >> (i - 1u)) & 1u) != 0u) r ^= a;
        }
        return r;
    }
    // Odd extension: b's digits least significant first, then Horner from the top one.
    uint digits = 0u;  // b's digits reversed (base p), so Horner can pop them most significant first
    uint rest = b;
    for (uint i = 0u; i < f.k; ++i) {
        uint next = oas_gf_divp(f, rest);
        digits = digits * f.p + (rest - next * f.p);
        rest = next;
    }
    for (uint i = 0u; i < f.k; ++i) {
        uint next = oas_gf_divp(f, digits);
        uint digit = digits - next * f.p;
        digits = next;
        r = oas_gf_axpy(f, oas_gf_mulx(f, r), a, digit);
    }
    return r;
}

/// a^e in GF(q) by square-and-multiply.
uint oas_gf_pow(OasField f, uint a, uint e)
{
    uint result = 1u;
    uint base = a;
    while (e != 0u) {
        if ((e & 1u) != 0u) result = oas_gf_mul(f, result, base);
        base = oas_gf_mul(f, base, base);
        e >>= 1u;
    }
    return result;
}

/// 1/a in GF(q) for a != 0 (a^(q-2), since a^(q-1) = 1). Undefined for a = 0.
uint oas_gf_inv(OasField f, uint a) { return oas_gf_pow(f, a, f.q - 2u); }

/// The field element n * 1 (n mod p, the constant polynomial), for small integers n.
uint oas_gf_int(OasField f, uint n) { return n - oas_gf_divp(f, n) * f.p; }

#endif // OAS_GF_GLSL
