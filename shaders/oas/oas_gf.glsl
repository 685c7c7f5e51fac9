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
    uint p;     ///< characteristic, a prime
    uint k;     ///< degree of the extension
    uint q;     ///< p^k
    uint poly;  ///< g(x) packed base p: x^k == g(x)
};

/// y + c * a with digit-wise arithmetic mod p (a polynomial axpy over GF(p)); c < p.
uint oas_gf_axpy(OasField f, uint y, uint a, uint c)
{
    uint r = 0u;
    uint place = 1u;
    for (uint i = 0u; i < f.k; ++i) {
        uint d = (y % f.p + c * (a % f.p)) % f.p;
        r += d * place;
        place *= f.p;
        y /= f.p;
        a /= f.p;
    }
    return r;
}

/// a + b in GF(q).
uint oas_gf_add(OasField f, uint a, uint b)
{
    if (f.k == 1u) {
        uint s = a + b;
        return s >= f.p ? s - f.p : s;
    }
    if (f.p == 2u) return a ^ b;
    return oas_gf_axpy(f, a, b, 1u);
}

/// -a in GF(q).
uint oas_gf_neg(OasField f, uint a)
{
    if (f.k == 1u) return a == 0u ? 0u : f.p - a;
    if (f.p == 2u) return a;
    return oas_gf_axpy(f, 0u, a, f.p - 1u);
}

/// a * x mod f(x): shift the digits up one place and fold the overflowing digit back via g.
uint oas_gf_mulx(OasField f, uint a)
{
    uint placeTop = f.q / f.p;  // p^(k-1)
    uint top = a / placeTop;
    uint shifted = (a - top * placeTop) * f.p;
    if (f.p == 2u) return top != 0u ? shifted ^ f.poly : shifted;
    return oas_gf_axpy(f, shifted, f.poly, top);
}

/// a * b in GF(q), by Horner's rule over the digits of b (most significant first).
/// Prime fields take one multiply and one remainder (a, b < p < 2^16, so a*b < 2^32).
uint oas_gf_mul(OasField f, uint a, uint b)
{
    if (f.k == 1u) return (a * b) % f.p;
    uint r = 0u;
    uint place = f.q / f.p;
    for (uint i = 0u; i < f.k; ++i) {
        uint digit = (b / place) % f.p;
        r = oas_gf_mulx(f, r);
        if (digit != 0u) r = f.p == 2u ? r ^ a : oas_gf_axpy(f, r, a, digit);
        place /= f.p;
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

/// 1/a in GF(q) for a != 0 (a^(q-2), since a^(q-1) = 1). Returns 0 for a = 0.
uint oas_gf_inv(OasField f, uint a) { return oas_gf_pow(f, a, f.q - 2u); }

/// The field element n * 1 (n mod p, the constant polynomial), for small integers n.
uint oas_gf_int(OasField f, uint n) { return n % f.p; }

#endif // OAS_GF_GLSL
