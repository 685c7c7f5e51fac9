// Properties of the randomized samplers, checked on the CPU twin with exact integer strata:
// strength-t stratification of every t-subset of dimensions within each OA block, the 1D Latin
// hypercube where promised, fresh passes past N, distinct randomization per pixel, dimension and
// block, and the numeric contract over the hard cases (largest fields and N, edge seeds, last
// indices, pixel coordinates up to 16383).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <random>
#include <set>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"
#include "oas/stratification.hpp"
#include "test_cases.hpp"

namespace {

struct Config {
    const char* sampler;
    std::uint32_t spp, strength;
};

std::vector<Config> smallConfigs()
{
    return {{"bose", 4, 0},
            {"bose", 9, 0},
            {"bose", 16, 0},
            {"bose", 25, 0},
            {"bose", 49, 0},
            {"bose", 64, 0},
            {"bose", 81, 0},
            {"bose", 121, 0},
            {"bush", 9, 2},
            {"bush", 27, 3},
            {"bush", 64, 3},
            {"bush", 125, 3},
            {"bush", 256, 4},
            {"bush", 625, 4},
            {"bush", 512, 3},
            {"bose-bush", 8, 0},
            {"bose-bush", 32, 0},
            {"bose-bush", 128, 0},
            {"addelman-kempthorne", 18, 0},
            {"addelman-kempthorne", 50, 0},
            {"addelman-kempthorne", 98, 0},
            {"addelman-kempthorne", 162, 0},
            {"cmjnd", 4, 2},
            {"cmjnd", 8, 3},
            {"cmjnd", 27, 3},
            {"cmjnd", 81, 4},
            {"cmjnd", 32, 5},
            {"cmjnd", 25, 2},
            {"cmjnd", 216, 3}};
}

oas::Pattern patternOf(const Config& c, const char* offset)
{
    return oas::test::patternOf({c.sampler, c.spp, c.strength}, offset);
}

std::vector<float> points(const oas::Pattern& p, std::uint32_t dims, std::uint32_t x, std::uint32_t y, std::uint32_t seed,
                          std::uint32_t firstSample = 0)
{
    oas::SampleRequest r;
    r.x0 = x;
    r.y0 = y;
    r.spp = p.N;
    r.dims = dims;
    r.seed = seed;
    r.firstSample = firstSample;
    std::vector<float> out(std::size_t(p.N) * dims);
    oas::generateCpu(p, r, out.data(), 1);
    return out;
}

/// Every t-subset of columns in [lo, hi) stratified into s^t cells (exhaustive).
void expectStrength(const std::vector<float>& pts, const oas::Pattern& p, std::uint32_t dims, std::uint32_t lo, std::uint32_t hi,
                    const std::string& what)
{
    const std::uint32_t t = p.strength;
    if (hi - lo < t) return;
    std::vector<std::uint32_t> cols(t);
    for (std::uint32_t i = 0; i < t; ++i) cols[i] = lo + i;
    while (true) {
        ASSERT_TRUE(oas::isStratified(pts.data(), p.N, dims, cols, p.s)) << what << ": columns from " << cols[0];
        int i = int(t) - 1;
        while (i >= 0 && cols[i] == hi - t + std::uint32_t(i)) --i;
        if (i < 0) break;
        ++cols[i];
        for (std::uint32_t j = std::uint32_t(i) + 1; j < t; ++j) cols[j] = cols[j - 1] + 1;
    }
}

TEST(Stratification, EveryTSubsetOfEveryBlockForEveryOffset)
{
    for (const Config& c : smallConfigs()) {
        for (const char* offset : {"centered", "j", "mj", "cmj"}) {
            const oas::Pattern p = patternOf(c, offset);
            const std::uint32_t dims = std::min<std::uint32_t>(2 * p.blockDims + 1, 40);  // 2+ blocks
            for (std::uint32_t pixel = 0; pixel < 3; ++pixel) {
                // Pass 0 and pass 1 (indices N .. 2N-1) are each a complete randomized OA.
                for (std::uint32_t pass = 0; pass < 2; ++pass) {
                    const auto pts = points(p, dims, 16383 - pixel, pixel * 7, 0xfffffff0u + pixel, pass * p.N);
                    const std::string what =
                        oas::describe(p) + " pixel " + std::to_string(pixel) + " pass " + std::to_string(pass);
                    for (std::uint32_t lo = 0; lo < dims; lo += p.blockDims)
                        expectStrength(pts, p, dims, lo, std::min(dims, lo + p.blockDims), what);
                    const bool lhs = std::string(offset) == "mj" || std::string(offset) == "cmj";
                    for (std::uint32_t d = 0; d < dims; ++d)
                        ASSERT_TRUE(oas::isStratified(pts.data(), p.N, dims, {d}, lhs ? p.N : p.s)) << what << " 1D dim " << d;
                }
            }
        }
    }
}

TEST(Stratification, BaselinesKeepWhatTheyPromise)
{
    for (std::uint32_t spp : {16u, 64u, 100u, 121u, 128u}) {
        for (const char* sampler : {"jittered2d", "cmj2d", "zerotwo"}) {
            oas::PatternRequest r;
            r.sampler = sampler;
            r.spp = spp;
            const oas::Pattern p = oas::makePattern(r);
            const std::uint32_t dims = 6;
            const auto pts = points(p, dims, 5, 9, 3);
            for (std::uint32_t d = 0; d + 1 < dims; d += 2) {
                if (std::string(sampler) == "zerotwo") {
                    // (0,2)-nets exist for powers of two: every elementary 2D interval holds one point.
                    if ((spp & (spp - 1)) != 0) continue;
                    std::uint32_t bits = 0;
                    while ((1u << bits) < spp) ++bits;
                    for (std::uint32_t bx = 0; bx <= bits; ++bx) {
                        std::set<std::uint64_t> cells;
                        for (std::uint32_t i = 0; i < spp; ++i)
                            cells.insert(std::uint64_t(oas::stratumOf(pts[i * dims + d], 1u << bx)) << 32 |
                                         oas::stratumOf(pts[i * dims + d + 1], 1u << (bits - bx)));
                        EXPECT_EQ(cells.size(), spp) << sampler << " " << spp << " interval 2^" << bx;
                    }
                } else {
                    std::set<std::uint64_t> cells;
                    for (std::uint32_t i = 0; i < spp; ++i)
                        cells.insert(std::uint64_t(oas::stratumOf(pts[i * dims + d], p.aux)) << 32 |
                                     oas::stratumOf(pts[i * dims + d + 1], p.aux2));
                    EXPECT_EQ(cells.size(), spp) << sampler << " " << spp << " pair " << d;
                    if (std::string(sampler) == "cmj2d") {
                        EXPECT_TRUE(oas::isStratified(pts.data(), spp, dims, {d}, spp));
                        EXPECT_TRUE(oas::isStratified(pts.data(), spp, dims, {d + 1}, spp));
                    }
                }
            }
        }
    }
}

TEST(Sobol, FirstDimensionsAreVanDerCorputAndTheZeroTwoPartner)
{
    for (std::uint32_t i = 0; i < 4096; ++i) {
        ASSERT_EQ(oas::glsl::oas_sobol(i, 0), oas::glsl::oas_reverse_bits(i));
        ASSERT_EQ(oas::glsl::oas_sobol(i, 1), oas::glsl::oas_sobol_dim1(i));
    }
}

TEST(Sobol, ReverseBitsMovesEveryBitToItsMirror)
{
    // The C++ twin's bitfieldReverse against the definition, bit by bit (the GPU's builtin is
    // checked against the twin by the GPU-vs-CPU tests of every baseline that reverses).
    std::mt19937 rng(7);
    for (int n = 0; n < 100000; ++n) {
        const std::uint32_t v = n < 32 ? 1u << n : std::uint32_t(rng());
        std::uint32_t expected = 0;
        for (int b = 0; b < 32; ++b) expected |= ((v >> b) & 1u) << (31 - b);
        ASSERT_EQ(oas::glsl::oas_reverse_bits(v), expected) << v;
    }
}

TEST(Sobol, EveryDimensionIsAZeroOneSequenceAndScramblingKeepsIt)
{
    // Each Sobol dimension's first 2^m points hit each of 2^m intervals once; Owen scrambling
    // keeps that, and later blocks (shuffled indices) do too. Every dimension of the table.
    for (std::uint32_t d = 0; d < oas::glsl::OAS_SOBOL_BLOCK; ++d) {
        std::vector<bool> seen(1024, false);
        for (std::uint32_t i = 0; i < 1024; ++i) {
            const std::uint32_t cell = oas::glsl::oas_sobol(i, d) >> 22;
            ASSERT_FALSE(seen[cell]) << "dim " << d;
            seen[cell] = true;
        }
    }
    oas::PatternRequest r;
    r.sampler = "sobol";
    r.spp = 256;
    const oas::Pattern p = oas::makePattern(r);
    const std::uint32_t dims = 2 * oas::glsl::OAS_SOBOL_BLOCK + 12;  // into the third block
    const auto pts = points(p, dims, 3, 4, 5);
    for (std::uint32_t d = 0; d < dims; ++d) ASSERT_TRUE(oas::isStratified(pts.data(), 256, dims, {d}, 256)) << d;
    // Dimensions (0,1) form a (0,8,2)-net: every elementary interval of area 1/256 holds one point.
    for (std::uint32_t bx = 0; bx <= 8; ++bx) {
        std::set<std::uint64_t> cells;
        for (std::uint32_t i = 0; i < 256; ++i)
            cells.insert(std::uint64_t(oas::stratumOf(pts[i * dims], 1u << bx)) << 32 |
                         oas::stratumOf(pts[i * dims + 1], 1u << (8 - bx)));
        EXPECT_EQ(cells.size(), 256u) << bx;
    }
}

/// Elementary intervals of 2^bx x 2^(m - bx) over dims (a, b) of the first 2^m points of `pts`
/// (rows of `dims` values), for every bx: the number of distinct cells each split occupies.
std::vector<std::size_t> occupiedCells(const std::vector<std::uint32_t>& xs, const std::vector<std::uint32_t>& ys, std::uint32_t m)
{
    std::vector<std::size_t> counts;
    for (std::uint32_t bx = 0; bx <= m; ++bx) {
        std::set<std::uint64_t> cells;
        for (std::uint32_t i = 0; i < (1u << m); ++i)
            cells.insert(std::uint64_t(bx == 0 ? 0 : xs[i] >> (32 - bx)) << 32 | (m - bx == 0 ? 0 : ys[i] >> (32 - (m - bx))));
        counts.push_back(cells.size());
    }
    return counts;
}

std::uint32_t fixedOf(float x) { return std::uint32_t(double(x) * 16777216.0) << 8; }

TEST(Sobol, HashScrambleIsANestedUniformScrambleStructure)
{
    // Owen's structure: bit b flips by a function of the bits above it only. So two inputs whose
    // first difference is at bit b keep the same bits above b and still differ at b, for every
    // seed, and the map is a bijection (checked on all 2^16 top-bit patterns).
    std::mt19937 rng(7);
    for (std::uint32_t seed : {0u, 1u, 0x9e3779b9u, 0xffffffffu, std::uint32_t(rng()), std::uint32_t(rng())}) {
        for (int trial = 0; trial < 20000; ++trial) {
            const std::uint32_t x = rng(), y = trial % 2 ? x ^ (1u << (trial % 32)) : std::uint32_t(rng());
            const std::uint32_t fx = oas::glsl::oas_owen_scramble_hash(x, seed), fy = oas::glsl::oas_owen_scramble_hash(y, seed);
            if (x == y) continue;
            ASSERT_EQ(std::countl_zero(x ^ y), std::countl_zero(fx ^ fy)) << std::hex << x << " " << y << " seed " << seed;
        }
        std::vector<bool> seen(1u << 16, false);
        for (std::uint32_t top = 0; top < (1u << 16); ++top) {
            const std::uint32_t image = oas::glsl::oas_owen_scramble_hash(top << 16, seed) >> 16;
            ASSERT_FALSE(seen[image]) << "seed " << seed;
            seen[image] = true;
        }
    }
}

TEST(Sobol, BurleysFourDimensionsAreTheTablesFirstFour)
{
    // oas_sobol4_reversed folds the four dimensions' direction numbers from their recurrences;
    // they must be Joe and Kuo's (the table scipy checks, tests/sobol_scipy_test.py).
    std::mt19937 rng(11);
    for (std::uint32_t n = 0; n < 70000; ++n) {
        const std::uint32_t i = n < 65536 ? n : rng() >> 8;  // all 16-bit indices, then any below 2^24
        for (std::uint32_t k = 0; k < 4; ++k)
            ASSERT_EQ(oas::glsl::oas_sobol4_reversed(oas::glsl::oas_reverse_bits(i), k),
                      oas::glsl::oas_reverse_bits(oas::glsl::oas_sobol(i, k)))
                << "index " << i << ", dim " << k;
    }
}

TEST(Sobol, EveryScrambleKeepsTheNetQualityOfEveryPairAndPowerOfTwoPrefixes)
{
    // A scramble of the kind Owen's is maps elementary intervals onto elementary intervals, so
    // in every pair of dimensions the scrambled points occupy exactly as many cells of every
    // 2^bx x 2^(m - bx) grid as the unscrambled Sobol points (the pair's t-value is kept: (0,m,2)
    // where Joe and Kuo give it, as in dims 0 and 1), for every aligned power-of-two prefix 2^m
    // of a pass. Sobol-Burley pads 4D groups, each group's pairs with the table's first four
    // dimensions, its index shuffle keeping aligned blocks; its second group is checked too.
    const std::uint32_t N = 1024, M = 10;
    for (const char* sampler : {"sobol", "sobol-owen", "sobol-burley"}) {
        const bool burley = std::string(sampler) == "sobol-burley";
        oas::PatternRequest r;
        r.sampler = sampler;
        r.spp = N;
        const oas::Pattern p = oas::makePattern(r);
        const std::uint32_t dims = 8;
        for (std::uint32_t pixel : {0u, 5u}) {
            const auto pts = points(p, dims, pixel, 3, 77, pixel == 0 ? 0 : 3 * N);  // pixel 5: the fourth pass
            for (std::uint32_t a = 0; a < dims; ++a)
                for (std::uint32_t b = a + 1; b < dims; ++b) {
                    if (burley && a / 4 != b / 4) continue;  // different groups: independent shuffles
                    const std::uint32_t ra = burley ? a % 4 : a, rb = burley ? b % 4 : b;
                    std::vector<std::uint32_t> xs(N), ys(N), sx(N), sy(N);
                    for (std::uint32_t i = 0; i < N; ++i) {
                        xs[i] = fixedOf(pts[i * dims + a]);
                        ys[i] = fixedOf(pts[i * dims + b]);
                        sx[i] = oas::glsl::oas_sobol(i, ra);
                        sy[i] = oas::glsl::oas_sobol(i, rb);
                    }
                    for (std::uint32_t m = 1; m <= M; ++m) {
                        // Sobol-Burley's prefix 2^m is its shuffle of some aligned block of 2^m
                        // indices: the same point set up to a digital shift, so the same counts.
                        const auto want = occupiedCells(sx, sy, m);
                        ASSERT_EQ(occupiedCells(xs, ys, m), want)
                            << sampler << " dims (" << a << ", " << b << "), first 2^" << m << " of pixel " << pixel;
                        if ((a == 0 && b == 1) || (burley && a == 4 && b == 5)) {
                            ASSERT_EQ(want, std::vector<std::size_t>(m + 1, std::size_t(1) << m)) << "(0,m,2)-net";
                        }
                    }
                }
        }
    }
}

TEST(Randomization, DistinctPerPixelDimensionAndBlock)
{
    oas::PatternRequest r;
    r.sampler = "bose";
    r.spp = 121;
    const oas::Pattern p = oas::makePattern(r);
    const std::uint32_t dims = 3 * p.blockDims;
    const auto a = points(p, dims, 0, 0, 0);
    const auto b = points(p, dims, 1, 0, 0);
    const auto c = points(p, dims, 0, 1, 0);
    for (std::uint32_t d = 0; d < dims; ++d) {
        // Dimension 0 included: every dimension's strata order differs between pixels.
        std::vector<std::uint32_t> sa, sb, sc;
        for (std::uint32_t i = 0; i < p.N; ++i) {
            sa.push_back(oas::stratumOf(a[i * dims + d], p.s));
            sb.push_back(oas::stratumOf(b[i * dims + d], p.s));
            sc.push_back(oas::stratumOf(c[i * dims + d], p.s));
        }
        EXPECT_NE(sa, sb) << "dim " << d << " has the same strata sequence in pixels (0,0) and (1,0)";
        EXPECT_NE(sa, sc) << "dim " << d << " has the same strata sequence in pixels (0,0) and (0,1)";
    }
    // No repeated columns across blocks: a cross-block pair is not collapsed onto few cells (a
    // repeated column puts all points on q of the q^2 cells) and not identical.
    for (std::uint32_t d = 0; d < p.blockDims; ++d) {
        for (std::uint32_t block = 1; block < 3; ++block) {
            const std::uint32_t e = d + block * p.blockDims;
            std::set<std::uint32_t> cells;
            for (std::uint32_t i = 0; i < p.N; ++i)
                cells.insert(oas::stratumOf(a[i * dims + d], p.s) * p.s + oas::stratumOf(a[i * dims + e], p.s));
            EXPECT_GT(cells.size(), 2 * p.s) << "dims " << d << " and " << e;
        }
    }
    // Different user seeds give different point sets.
    EXPECT_NE(points(p, 2, 0, 0, 0), points(p, 2, 0, 0, 1));
}

TEST(Randomization, SampleIsAPureFunction)
{
    // Evaluating one value alone equals the batched fast path (oas_row + oas_row_dim) value.
    for (const Config& c : smallConfigs()) {
        const oas::Pattern p = patternOf(c, "cmj");
        const std::uint32_t dims = p.blockDims + 3;
        const auto pts = points(p, dims, 12, 34, 56, 7);
        const std::uint32_t seed = oas::pixelSeed(12, 34, 56);
        for (std::uint32_t i = 0; i < p.N; i += 7)
            for (std::uint32_t d = 0; d < dims; ++d)
                ASSERT_EQ(oas::sample(p, seed, 7 + i, d), pts[std::size_t(i) * dims + d]) << oas::describe(p);
    }
}

/// The numeric contract on one value: in [0,1), a multiple of 2^-24 (so exact strata apply).
void expectValid(float x, const std::string& what)
{
    ASSERT_TRUE(x >= 0.0f && x < 1.0f) << what << ": " << x;
    const double scaled = double(x) * 16777216.0;
    ASSERT_EQ(double(std::uint64_t(scaled)), scaled) << what;
}

TEST(HardCases, LargestFieldsAndCountsStayExact)
{
    std::mt19937 rng(99);
    for (const oas::test::SamplerCase& h : oas::test::hardCases()) {
        for (const char* offset : {"j", "cmj"}) {
            const oas::Pattern p = oas::test::patternOf(h, offset);
            const std::uint32_t dims = std::min<std::uint32_t>(p.blockDims, 64) + 2;
            std::vector<std::uint32_t> indices = {0, 1, p.N - 1, p.N - 2, p.N, 2 * p.N - 1, 0xffffffffu};
            for (int i = 0; i < 24; ++i) indices.push_back(rng() % p.N);
            for (std::uint32_t seed : {0u, 1u, 0xffffffffu, 0u - p.N, 0u - p.N - 1}) {
                for (std::uint32_t px : {0u, 16383u}) {
                    const std::uint32_t pixelSeed = oas::pixelSeed(px, 16383 - px, seed);
                    for (std::uint32_t i : indices)
                        for (std::uint32_t d = 0; d < dims; ++d)
                            expectValid(oas::sample(p, pixelSeed, i, d),
                                        oas::describe(p) + " index " + std::to_string(i) + " dim " + std::to_string(d));
                }
            }
        }
    }
}

TEST(HardCases, LargestBoseIsALatinHypercubeIn2Pow24Strata)
{
    // N = 4096^2 = 2^24 points: the finest strata the fixed point can express; and q = 4093,
    // the largest prime, where N is not a power of two.
    for (std::uint32_t q : {4096u, 4093u}) {
        oas::PatternRequest r;
        r.sampler = "bose";
        r.spp = q * q;
        r.dims = 2;
        const oas::Pattern p = oas::makePattern(r);
        const auto pts = points(p, 2, 16383, 16383, 0xffffffffu);
        for (std::uint32_t d = 0; d < 2; ++d)
            EXPECT_TRUE(oas::isStratified(pts.data(), p.N, 2, {d}, p.N)) << oas::describe(p) << " dim " << d;
        EXPECT_TRUE(oas::isStratified(pts.data(), p.N, 2, {0, 1}, p.s)) << oas::describe(p);
    }
}

TEST(Stratification, CheckerCanFail)
{
    // Independent random points are not Latin hypercubes; a duplicated point breaks a stratified set.
    oas::PatternRequest r;
    r.sampler = "random";
    r.spp = 64;
    const oas::Pattern p = oas::makePattern(r);
    const auto pts = points(p, 2, 0, 0, 0);
    EXPECT_FALSE(oas::isStratified(pts.data(), 64, 2, {0}, 64));
    r.sampler = "bose";
    auto good = points(oas::makePattern(r), 2, 0, 0, 0);
    ASSERT_TRUE(oas::isStratified(good.data(), 64, 2, {0, 1}, 8));
    good[2] = good[0];
    good[3] = good[1];
    EXPECT_FALSE(oas::isStratified(good.data(), 64, 2, {0, 1}, 8));
    EXPECT_THROW(oas::stratumOf(1.0f, 8), std::domain_error);
    EXPECT_THROW(oas::stratumOf(0.1f, 8), std::domain_error);  // not a multiple of 2^-24
}

}  // namespace
