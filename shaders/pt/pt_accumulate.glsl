// Exact radiance sums: per pixel and channel, the sum of the samples' radiances as a 96-bit
// unsigned fixed-point number with 32 fractional bits (three 32-bit words, low first). Every
// sample is first truncated to a multiple of 2^-32 (floor(v * 2^32)), then added as an integer.
// Integer addition is associative, so the sums do not depend on how the samples were grouped:
// rendering samples [0, N) in one process, or [0, a) and [a, N) in two and adding the words,
// gives the same words, bit for bit. (A float sum cannot: (x + y) + z != x + (y + z) in general.)
//
// Range and precision: a sample is summable when every channel is in [0, 2^64); the sum of up to
// 2^32 such samples stays below 2^96, so no sum can overflow (a pixel receives at most 2^24
// samples, the largest spp). Truncation loses less than 2^-32 (2.3e-10) per sample and channel:
// far below the float32 rounding of any radiance above ~1e-3 that a float sum would make. A
// sample that is NaN, infinite, negative or >= 2^64 in any channel is not summable: it is left
// out of the sums but still counted as a sample (the pixel is divided by every sample taken), and
// counted as rejected, so a render reports it.
//
// Compiled as GLSL (pt_render.comp) and as C++ with GLM (the CPU reference tracer): both sides
// add the same words.

#ifndef PT_ACCUMULATE_GLSL
#define PT_ACCUMULATE_GLSL

/// Words per pixel in an accumulation buffer: R, G, B sums (3 words each, low first), the
/// samples taken, the samples rejected, one spare word (keeps a pixel 16-byte aligned).
const uint PT_SUM_WORDS = 12u;
const uint PT_SUM_COUNT_WORD = 9u;
const uint PT_SUM_REJECTED_WORD = 10u;

/// A pixel's radiance sums: channel c's value is (hi[c] * 2^64 + mid[c] * 2^32 + lo[c]) / 2^32.
struct PtSum {
    uvec3 lo;
    uvec3 mid;
    uvec3 hi;
};

PtSum pt_sum_zero()
{
    PtSum s;
    s.lo = uvec3(0u);
    s.mid = uvec3(0u);
    s.hi = uvec3(0u);
    return s;
}

/// Whether a radiance can be summed exactly: every channel in [0, 2^64) (false for NaN and inf,
/// whose comparisons fail).
bool pt_summable(vec3 l)
{
    return all(greaterThanEqual(l, vec3(0.0f))) && all(lessThan(l, vec3(18446744073709551616.0f)));
}

/// a + b on 96-bit words, carries propagated (the top carry cannot occur: see the range above).
PtSum pt_sum_add(PtSum a, PtSum b)
{
    PtSum s;
    s.lo = a.lo + b.lo;
    uvec3 carryLo = uvec3(lessThan(s.lo, a.lo));
    uvec3 mid = a.mid + b.mid;
    uvec3 carryMid = uvec3(lessThan(mid, a.mid));
    s.mid = mid + carryLo;
    carryMid += uvec3(lessThan(s.mid, mid));
    s.hi = a.hi + b.hi + carryMid;
    return s;
}

/// floor(l * 2^32) of a summable radiance as 96-bit words. Each step is exact in float32: scaling
/// by a power of two, and subtracting from l the part of it above a power of two (the
/// difference is l's own low bits), so CPU and GPU make the same words from the same l.
PtSum pt_sum_of(vec3 l)
{
    PtSum s;
    s.hi = uvec3(l * (1.0f / 4294967296.0f));           // floor(l / 2^32)
    vec3 belowHi = l - vec3(s.hi) * 4294967296.0f;      // l mod 2^32
    s.mid = uvec3(belowHi);                             // its integer part
    s.lo = uvec3((belowHi - vec3(s.mid)) * 4294967296.0f);  // 32 fractional bits, truncated
    return s;
}

#endif // PT_ACCUMULATE_GLSL
