// oas_gf.glsl - arithmetic in the finite field GF(p^k), computed on the fly (no tables).
// Part of the oas GLSL library; include "oas.glsl" rather than this file.
//
// Fixed work: every loop here runs a compile-time number of times (OAS_GF_MAX_BINARY_K or
// OAS_GF_MAX_ODD_K steps, whatever the field's k) and is marked OAS_UNROLL, so it unrolls into
// straight-line code. A digit or bit above the field's k is zero and leaves the result unchanged,
// which is what lets one fixed-length loop serve every k. (Lavapipe ends an invocation's loops
// after 65535 iterations in all; straight-line code costs none of them.)
#ifndef OAS_GF_GLSL
#define OAS_GF_GLSL

/// A finite field GF(q), q = p^k <= 4096. Elements are the integers [0, q): the base-p digits of
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
// Whether the digit or bit step at `place` of a field loop does work: the loops below run
// OAS_GF_MAX_*_K steps, and steps at or past the field's degree k do nothing. With the degree
// fixed at compile time (OAS_STATIC_FIELD_DEGREE, see oas_pattern.glsl) those steps fold away:
// GF(3^2) runs 2 of 5 steps, GF(2^3) 3 of 12. A shader without it runs every step, as before:
// testing a run-time k per step made lavapipe's unspecialised kernel twice as slow (measured),
// since it predicates every guarded step. The C++ twin (glsl_compat.hpp defines
// OAS_RUNTIME_BRANCHES) tests k at run time: a CPU branch skips the work.
// OAS_FIELD_TOP_STEP: whether `place` is the field's top digit, k - 1. An element below q = p^k
// that has been divided by p k - 1 times is its own top digit, so that last division (quotient 0)
// can go; a shader that does not know k keeps it.
#if defined(OAS_STATIC_FIELD_DEGREE)
#define OAS_KNOWN_FIELD_DEGREE(f) OAS_STATIC_FIELD_DEGREE
#elif defined(OAS_RUNTIME_BRANCHES)
#define OAS_KNOWN_FIELD_DEGREE(f) ((f).k)
#endif
#ifdef OAS_KNOWN_FIELD_DEGREE
#define OAS_FIELD_STEP_USED(f, place) ((place) < OAS_KNOWN_FIELD_DEGREE(f))
#define OAS_FIELD_TOP_STEP(f, place) ((place) + 1u == OAS_KNOWN_FIELD_DEGREE(f))
#else
#define OAS_FIELD_STEP_USED(f, place) true
#define OAS_FIELD_TOP_STEP(f, place) false
#endif

/// The largest degrees the constructions use: every OA has N >= q^2 and N <= 2^24, so q <= 4096,
/// which is 2^12 and 3^7. The host refuses odd extension fields whose digit slots (below) do not
/// fit 32 bits, which leaves k <= 5 for p = 3 (OAS_GF_MAX_ODD_K covers every odd field).
const uint OAS_GF_MAX_BINARY_K = 12u;
const uint OAS_GF_MAX_ODD_K = 5u;
/// Exponents of oas_gf_pow are below 2^OAS_GF_POW_BITS (q - 2 < 4096 for inverses).
const uint OAS_GF_POW_BITS = 12u;

/// a mod p and a / p via the field's reciprocal.
uint oas_gf_divp(OasField f, uint a) { return oas_fastdiv(a, f.recipP, f.shiftP); }

/// a / p while peeling the base-p digit `place` off an element below q (what is left of it after
/// `place` divisions): 0 at the top digit, which needs no division (OAS_FIELD_TOP_STEP).
uint oas_gf_digit_rest(OasField f, uint a, uint place)
{
    return OAS_FIELD_TOP_STEP(f, place) ? 0u : oas_gf_divp(f, a);
}

/// Width in bits of one digit slot of the packed form oas_gf_mul_add2 computes in: slot values
/// there stay below 2 k (p-1)^2 + 2 (p-1), so a slot is that many bits wide; the host accepts an
/// odd extension field only when k slots fit one 32-bit word (oas_gf_slots_fit).
uint oas_gf_slot_bits(OasField f)
{
    uint pm1 = f.p - 1u;
    return uint(findMSB(2u * f.k * pm1 * pm1 + 2u * pm1)) + 1u;
}

/// Whether GF(p^k), p odd, has packed digit slots that fit 32 bits (see oas_gf_slot_bits).
bool oas_gf_slots_fit(OasField f) { return f.k * oas_gf_slot_bits(f) <= 32u; }

/// The base-p digits of a (< q) in slots of `bits` bits: digit i at bit i * bits.
uint oas_gf_spread(OasField f, uint a, uint bits)
{
    uint packed = 0u;
    uint shift = 0u;
    OAS_UNROLL for (uint i = 0u; i < OAS_GF_MAX_ODD_K; ++i) {
        if (OAS_FIELD_STEP_USED(f, i)) {  // digits past the field's k are 0
            uint next = oas_gf_digit_rest(f, a, i);
            packed |= (a - next * f.p) << shift;
            a = next;
            shift = min(shift + bits, 31u);  // stays a valid shift; only zeros go there
        }
    }
    return packed;
}

/// a * b + y + extra in GF(p^k) for odd p and k > 1, in fixed work. The digits of a sit in slots of a
/// 32-bit word (a polynomial over GF(p) evaluated at 2^bits), and Horner's rule over b's digits,
/// most significant first, runs on the whole word at once: shift every slot up one place, fold
/// the digit that leaves the top slot back in through x^k = g(x), and add b's digit times a.
/// Slots are reduced mod p only where needed: the digit leaving the top (exactly, by one
/// division), and every slot once at the end. In between they grow by at most 2 (p-1)^2 per step
/// over at most k steps, which is what oas_gf_slot_bits makes room for.
uint oas_gf_mul_add2_odd(OasField f, uint a, uint b, uint y, uint extra)
{
    uint bits = oas_gf_slot_bits(f);
    uint slotMask = (1u << bits) - 1u;
    uint topShift = bits * (f.k - 1u);
    uint belowTop = (1u << topShift) - 1u;
    uint packedA = oas_gf_spread(f, a, bits);
    uint packedG = oas_gf_spread(f, f.poly, bits);
    uint packedB = oas_gf_spread(f, b, bits);
    uint acc = 0u;
    OAS_UNROLL for (uint i = 0u; i < OAS_GF_MAX_ODD_K; ++i) {
        uint place = OAS_GF_MAX_ODD_K - 1u - i;  // b's digit, most significant first
        if (OAS_FIELD_STEP_USED(f, place)) {       // above k: a zero digit into a zero acc
            uint digitShift = bits * place;  // >= 32 past k for wide slots: never used there
            uint digit = place < f.k ? (packedB >> digitShift) & slotMask : 0u;
            uint top = acc >> topShift;  // the slot of x^(k-1), unreduced
            // The first step that does work is the top digit's, and acc is still 0 there.
            if (!OAS_FIELD_TOP_STEP(f, place)) top -= oas_gf_divp(f, top) * f.p;
            acc = ((acc & belowTop) << bits) + top * packedG + digit * packedA;
        }
    }
    // Reduce every slot mod p, add y's and extra's digits, and read the digits back out base p.
    uint result = 0u;
    uint power = 1u;
    OAS_UNROLL for (uint i = 0u; i < OAS_GF_MAX_ODD_K; ++i) {
        if (OAS_FIELD_STEP_USED(f, i)) {  // past k every slot and digit is 0
            uint yNext = oas_gf_digit_rest(f, y, i);  // y, extra < q
            uint extraNext = oas_gf_digit_rest(f, extra, i);
            uint slot = (acc & slotMask) + (y - yNext * f.p) + (extra - extraNext * f.p);
            result += (slot - oas_gf_divp(f, slot) * f.p) * power;
            acc >>= bits;
            power *= f.p;
            y = yNext;
            extra = extraNext;
        }
    }
    return result;
}

/// a * b in GF(2^k) by Horner's rule over b's bits, most significant first; b's bits past k
/// are zero and leave the product 0 until its top bit.
uint oas_gf_mul_binary(OasField f, uint a, uint b)
{
    uint r = 0u;
    uint top = f.q >> 1u;
    OAS_UNROLL for (uint i = 0u; i < OAS_GF_MAX_BINARY_K; ++i) {
        uint place = OAS_GF_MAX_BINARY_K - 1u - i;
        if (OAS_FIELD_STEP_USED(f, place)) {  // b's bits at k and above are 0, and so is r there
            // Masks (0 - bit: all ones or none) rather than selects: the same values, and g++
            // vectorizes a loop over samples around them, where it rejected the selects.
            uint carry = uint(r >= top);
            uint bit = (b >> place) & 1u;
            r = (((r << 1u) & (f.q - 1u)) ^ ((0u - carry) & f.poly)) ^ ((0u - bit) & a);
        }
    }
    return r;
}

/// a + b in GF(q). Odd extensions add digit by digit mod p.
uint oas_gf_add(OasField f, uint a, uint b)
{
    if (OAS_FIELD_IS_PRIME(f)) {
        uint s = a + b;
        return s >= f.p ? s - f.p : s;
    }
    if (OAS_FIELD_IS_BINARY(f)) return a ^ b;
    uint result = 0u;
    uint power = 1u;
    OAS_UNROLL for (uint i = 0u; i < OAS_GF_MAX_ODD_K; ++i) {
        if (OAS_FIELD_STEP_USED(f, i)) {  // digits past k are 0
            uint aNext = oas_gf_digit_rest(f, a, i);
            uint bNext = oas_gf_digit_rest(f, b, i);
            uint d = (a - aNext * f.p) + (b - bNext * f.p);
            result += (d >= f.p ? d - f.p : d) * power;
            power *= f.p;
            a = aNext;
            b = bNext;
        }
    }
    return result;
}

/// a * b + y + extra in GF(q): one product and two sums for the price of the product.
uint oas_gf_mul_add2(OasField f, uint a, uint b, uint y, uint extra)
{
    if (OAS_FIELD_IS_PRIME(f)) {
        uint v = a * b + y + extra;  // < p^2 + 2p <= 2^32 for p < 2^16
        return v - oas_gf_divp(f, v) * f.p;
    }
    if (OAS_FIELD_IS_BINARY(f)) return oas_gf_mul_binary(f, a, b) ^ y ^ extra;
    return oas_gf_mul_add2_odd(f, a, b, y, extra);
}

/// a * b + y in GF(q).
uint oas_gf_mul_add(OasField f, uint a, uint b, uint y) { return oas_gf_mul_add2(f, a, b, y, 0u); }

/// a * b in GF(q). Prime fields take one multiply and one remainder (a, b < p < 2^16).
uint oas_gf_mul(OasField f, uint a, uint b) { return oas_gf_mul_add2(f, a, b, 0u, 0u); }

/// -a in GF(q). Odd extensions multiply by the constant p - 1, the element -1 (the samplers
/// never negate, so it shares the product's code rather than a digit loop of its own).
uint oas_gf_neg(OasField f, uint a)
{
    if (OAS_FIELD_IS_PRIME(f)) return a == 0u ? 0u : f.p - a;
    if (OAS_FIELD_IS_BINARY(f)) return a;
    return oas_gf_mul(f, f.p - 1u, a);
}

/// a * x mod f(x) (x is the element p; for k = 1 it is 0, and so is the product).
uint oas_gf_mulx(OasField f, uint a) { return oas_gf_mul(f, a, OAS_FIELD_IS_PRIME(f) ? 0u : f.p); }

/// a^e in GF(q) for e < 2^OAS_GF_POW_BITS, by square-and-multiply over e's bits from the top.
uint oas_gf_pow(OasField f, uint a, uint e)
{
    uint result = 1u;
    OAS_UNROLL for (uint i = 0u; i < OAS_GF_POW_BITS; ++i) {
        result = oas_gf_mul(f, result, result);
        if (((e >> (OAS_GF_POW_BITS - 1u - i)) & 1u) != 0u) result = oas_gf_mul(f, result, a);
    }
    return result;
}

/// 1/a in GF(q) for a != 0 (a^(q-2), since a^(q-1) = 1). Undefined for a = 0.
uint oas_gf_inv(OasField f, uint a) { return oas_gf_pow(f, a, f.q - 2u); }

/// The field element n * 1 (n mod p, the constant polynomial), for small integers n.
uint oas_gf_int(OasField f, uint n) { return n - oas_gf_divp(f, n) * f.p; }

#endif // OAS_GF_GLSL
