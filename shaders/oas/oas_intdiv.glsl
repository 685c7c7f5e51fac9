// oas_intdiv.glsl - 32-bit integer division without a divide instruction: the high word of a
// product (oas_mulhi) and division by a divisor fixed per pattern (oas_fastdiv).
// Part of the oas GLSL library; include "oas.glsl" rather than this file. Depends on nothing; an
// includer may supply its own multiply-high through OAS_MULHI (see oas.glsl).
// Shared verbatim with C++ through host/oas/glsl_compat.hpp: keep to the GLSL/C++ common subset
// (scalar uint/float, structs built member by member, no in/out/inout qualifiers).
#ifndef OAS_INTDIV_GLSL
#define OAS_INTDIV_GLSL

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
    // A conversion, not l == 0 ? 0 : 1: the same shifts, and g++ vectorizes a loop over x around
    // it, where its vectorizer rejects a select on the loop-invariant l (host/oas/oa_columns.hpp).
    uint shift1 = uint(l != 0u);
    uint shift2 = l - shift1;
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

/// oas_fastdiv_recip for any divisor d in [1, 2^24] (shift l = ceil(log2 d)): the same long
/// division in four 8-bit steps, each partial remainder below d <= 2^24 so that remainder * 256
/// fits 32 bits. For divisors the shader derives from a pattern once per column (the 2D
/// baselines' grid sides): four integer divisions once, then none per value.
uint oas_fastdiv_recip24(uint d, uint l)
{
    uint r = (1u << l) - d;  // < d
    uint q = 0u;
    OAS_UNROLL for (uint step = 0u; step < 4u; ++step) {
        r <<= 8u;
        uint digit = r / d;
        q = (q << 8u) | digit;
        r -= digit * d;
    }
    return q + 1u;
}

/// ceil(log2 d) for d >= 1: the shift oas_fastdiv takes with a divisor d.
uint oas_fastdiv_shift(uint d) { return d <= 1u ? 0u : uint(findMSB(d - 1u)) + 1u; }

#endif // OAS_INTDIV_GLSL
