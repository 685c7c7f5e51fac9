// Integer building blocks, checked exhaustively or against exact 64-bit arithmetic:
// permutations are bijections for every seed (including the seeds near 2^32 - l that break
// Kensler's final `(i + p) % l` in other renderers), reciprocal division equals hardware
// division, and fixed-point stratum placement is exact as real numbers for every K <= 2^24.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"

namespace {
using namespace oas::glsl;

std::vector<std::uint32_t> seedsFor(std::uint32_t l)
{
    return {0u,          1u,          0xffffffffu, 0xfffffffeu, 0u - l,     0u - l - 1u,
            0u - l + 1u, 0x80000000u, 0x7fffffffu, 0x9e3779b9u, 0xdeadbeefu};
}

TEST(Permutation, BijectiveForEveryLengthUpTo4096AndEdgeSeeds)
{
    std::vector<std::uint32_t> seen(4096);
    std::uint32_t stamp = 0;
    for (std::uint32_t l = 1; l <= 4096; ++l) {
        for (std::uint32_t seed : seedsFor(l)) {
            ++stamp;
            for (std::uint32_t i = 0; i < l; ++i) {
                const std::uint32_t v = oas_permute(i, l, seed);
                ASSERT_LT(v, l) << "l " << l << " seed " << seed << " i " << i;
                ASSERT_NE(seen[v], stamp) << "not a bijection: l " << l << " seed " << seed << " value " << v;
                seen[v] = stamp;
            }
        }
    }
}

TEST(Permutation, BijectiveForLargeLengths)
{
    for (std::uint32_t l : {65521u, 65536u, 1000003u, 1u << 24}) {
        for (std::uint32_t seed : {0u, 0u - l, 0xffffffffu}) {
            std::vector<bool> seen(l, false);
            for (std::uint32_t i = 0; i < l; ++i) {
                const std::uint32_t v = oas_permute(i, l, seed);
                ASSERT_LT(v, l);
                ASSERT_FALSE(seen[v]) << "l " << l << " seed " << seed;
                seen[v] = true;
            }
        }
    }
    // The largest lengths: values stay in range (the walk terminates and never wraps).
    for (std::uint32_t l : {0x80000001u, 0xfffffffeu, 0xffffffffu})
        for (std::uint32_t i : {0u, 1u, l / 2, l - 1})
            for (std::uint32_t seed : {0u, 0u - l, 0xffffffffu}) EXPECT_LT(oas_permute(i, l, seed), l);
}

TEST(Permutation, EveryInputIsUniformOverSeeds)
{
    // A family that ignored its seed, or favoured some outputs, would pass the bijection tests;
    // this counts where each input lands over 20000 seeds.
    for (std::uint32_t l : {2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 11u, 13u, 16u, 17u, 33u, 64u, 121u}) {
        std::vector<std::uint32_t> counts(l * l, 0);  // counts[i * l + value]
        const std::uint32_t trials = 20000;
        for (std::uint32_t s = 0; s < trials; ++s) {
            const std::uint32_t seed = oas_pcg(s);
            for (std::uint32_t i = 0; i < l; ++i) ++counts[i * l + oas_permute(i, l, seed)];
        }
        // Each input should land on each output about trials / l times (loose 5-sigma-ish bound).
        const double expected = double(trials) / l;
        for (std::uint32_t c : counts) EXPECT_NEAR(double(c), expected, 6 * std::sqrt(expected) + 2) << "l " << l;
    }
}

TEST(MulHi, PortableLimbsEqualThe64BitProduct)
{
    // The OAS_MULHI fallback for targets without umulExtended must agree everywhere: edge words
    // (carries out of every 16-bit column) and random pairs.
    std::vector<std::uint32_t> edges = {0u,          1u,          2u,          0xffffu,     0x10000u,    0x10001u,   0x7fffffffu,
                                        0x80000000u, 0x80000001u, 0xfffeffffu, 0xffff0000u, 0xfffffffeu, 0xffffffffu};
    for (std::uint32_t a : edges)
        for (std::uint32_t b : edges)
            ASSERT_EQ(oas_mulhi_portable(a, b), std::uint32_t((std::uint64_t(a) * b) >> 32)) << a << " * " << b;
    std::mt19937 rng(99);
    for (int i = 0; i < 1000000; ++i) {
        const std::uint32_t a = rng(), b = rng();
        ASSERT_EQ(oas_mulhi_portable(a, b), std::uint32_t((std::uint64_t(a) * b) >> 32)) << a << " * " << b;
    }
}

TEST(FastDivision, EqualsHardwareDivision)
{
    std::mt19937 rng(12345);
    std::vector<std::uint32_t> divisors;
    for (std::uint32_t d = 1; d <= 70000; ++d) divisors.push_back(d);
    for (std::uint32_t d :
         {(1u << 24) - 1, 1u << 24, (1u << 24) + 1, 4093u * 4093u, 0x7fffffffu, 0x80000000u, 0xfffffffeu, 0xffffffffu})
        divisors.push_back(d);
    for (std::uint32_t d : divisors) {
        const oas::Divisor div = oas::makeDivisor(d);
        auto check = [&](std::uint32_t x) { ASSERT_EQ(oas_fastdiv(x, div.recip, div.shift), x / d) << x << " / " << d; };
        for (std::uint32_t x :
             {0u, 1u, d - 1, d, d + 1, 2 * d - 1, 2 * d, 0xffffffffu, 0xfffffffeu, 1u << 24, (1u << 24) - 1, 0x80000000u})
            check(x);
        for (int i = 0; i < 64; ++i) check(rng());
        for (std::uint32_t m = 1; m < 64 && std::uint64_t(m) * d < 0xffffffffull; ++m) {
            check(m * d);
            check(m * d - 1);
        }
    }
}

TEST(FastDivision, ShaderMadeReciprocalsEqualTheHostsForEveryDivisorUpTo2Pow16)
{
    // Halton makes its bases' reciprocals in the shader (oas_fastdiv_recip, two 32-bit divisions);
    // they must be the host's 64-bit Granlund-Montgomery constants exactly.
    for (std::uint32_t d = 1; d <= 65536; ++d) {
        const oas::Divisor div = oas::makeDivisor(d);
        const std::uint32_t shift = std::uint32_t(oas::glsl::findMSB(d - 1)) + 1u;
        ASSERT_EQ(shift, div.shift) << d;
        ASSERT_EQ(oas::glsl::oas_fastdiv_recip(d, shift), div.recip) << d;
    }
}

TEST(FastDivision, ShaderMadeReciprocalsEqualTheHostsForEveryDivisorUpTo2Pow24)
{
    // The 2D baselines make their grid sides' reciprocals in the shader (oas_fastdiv_recip24,
    // four 32-bit divisions, sides up to N = 2^24): every one must be the host's 64-bit constant.
    for (std::uint32_t d = 1; d <= (1u << 24); ++d) {
        const oas::Divisor div = oas::makeDivisor(d);
        const std::uint32_t shift = oas::glsl::oas_fastdiv_shift(d);
        ASSERT_EQ(shift, div.shift) << d;
        ASSERT_EQ(oas::glsl::oas_fastdiv_recip24(d, shift), div.recip) << d;
    }
}

/// Exact real-number check: x = F / 2^24 lies in [m / K, (m + 1) / K) iff m 2^24 <= F K < (m + 1) 2^24.
void expectInsideStratum(float x, std::uint32_t m, std::uint32_t K)
{
    ASSERT_GE(x, 0.0f);
    ASSERT_LT(x, 1.0f);
    const double scaled = double(x) * 16777216.0;
    const auto F = std::uint64_t(scaled);
    ASSERT_EQ(double(F), scaled) << "not a multiple of 2^-24";
    ASSERT_GE(F * K, std::uint64_t(m) << 24) << "below stratum " << m << " of " << K;
    ASSERT_LT(F * K, std::uint64_t(m + 1) << 24) << "above stratum " << m << " of " << K;
}

TEST(FixedPoint, StratumPointIsExactForEveryKUpTo2Pow24)
{
    std::mt19937 rng(777);
    std::vector<std::uint32_t> Ks;
    for (std::uint32_t K = 1; K <= 4096; ++K) Ks.push_back(K);
    // Around 2^16, where oas_stratum_point_fast switches from one division to three.
    for (std::uint32_t K : {46341u, 65521u, 65535u, 65536u, 65537u, 65539u, 99991u}) Ks.push_back(K);
    for (std::uint32_t K : {16769025u /* 4095^2 */, 16752649u /* 4093^2 */, (1u << 24) - 1, 1u << 24, 14348907u, 9565938u,
                            8388608u, 11184810u, 16777213u})
        Ks.push_back(K);
    for (int i = 0; i < 2000; ++i) Ks.push_back(1 + rng() % (1u << 24));
    for (std::uint32_t K : Ks) {
        const oas::Divisor div = oas::makeDivisor(K);
        std::vector<std::uint32_t> ms = {0, K - 1, K / 2, K / 3};
        // Every m for small K, and for the largest K of the one-division path (m B nears 2^32).
        if (K <= 64 || K == 65521u || K == 65535u)
            for (std::uint32_t m = 0; m < K; ++m) ms.push_back(m);
        for (std::uint32_t m : ms) {
            for (std::uint32_t u : {0u, 1u, 0x80000000u, 0xfffffffeu, 0xffffffffu, std::uint32_t(rng())}) {
                const float slow = oas_stratum_point(m, K, u);
                const float fast = oas_stratum_point_fast(m, K, div.recip, div.shift, u);
                expectInsideStratum(slow, m, K);
                ASSERT_EQ(slow, fast) << "m " << m << " K " << K << " u " << u;
            }
        }
    }
}

TEST(FixedPoint, NeverOneAndTheWholeStratumIsReachable)
{
    // u = 0 gives the lowest representable point of a stratum, u = 2^32 - 1 the highest, and the
    // highest point of the last stratum of any K is 1 - 2^-24 exactly.
    for (std::uint32_t K : {1u, 3u, 121u, 1u << 24, (1u << 24) - 1}) {
        EXPECT_EQ(oas_stratum_point(K - 1, K, 0xffffffffu), 1.0f - 5.9604644775390625e-8f) << K;
        EXPECT_EQ(oas_stratum_point(0, K, 0u), 0.0f) << K;
    }
}

}  // namespace
