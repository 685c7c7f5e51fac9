// The progressive sampler (shaders/oas/oas_faure.glsl, compiled as C++) against its definitions:
// - its digits against the generalized Faure generator matrices written out with binomials and
//   powers in the textbook field (textbook_oa.hpp), not the library's synthetic division;
// - its leading digit against the library's Bush construction (the same polynomial at a);
// - the (0,m,s)-net property of aligned blocks of q^m samples and the orthogonal-array property of
//   prefixes of lambda q^t samples, on the scrambled values, exhaustively where small and on
//   sampled grids where large, for prime bases, GF(4), GF(8), GF(9) and 31;
// - a negative control (q + 1 dimensions) that the net check must reject;
// - the float contract (inside the stratum, never 1.0) and unbiasedness over keys;
// - the GPU computing the same bits (FaureGpu).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "faure_points_spv.h"
#include "faure_points_static_spv.h"
#include "gpu_test_support.hpp"
#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"
#include "library_field.hpp"
#include "test_cases.hpp"
#include "textbook_oa.hpp"
#include "vk/context.hpp"

namespace {

using oas::glsl::OasFaure;
using oas::glsl::OasField;
using oas::test::ipow;
using oas::test::libraryField;

struct Base {
    std::uint32_t p, k;
    std::uint32_t q() const { return ipow(p, k); }
};

/// The bases of the properties: primes small and large, binary and odd extension fields.
std::vector<Base> bases() { return {{2, 1}, {3, 1}, {2, 2}, {5, 1}, {7, 1}, {2, 3}, {3, 2}, {31, 1}}; }

/// The most index digits a base allows: q^K <= 2^24 and K <= OAS_FAURE_MAX_DIGITS.
std::uint32_t maxDigits(std::uint32_t q)
{
    std::uint32_t K = 0;
    for (std::uint64_t n = q; n <= (1u << 24) && K < oas::glsl::OAS_FAURE_MAX_DIGITS; n *= q) ++K;
    return K;
}

OasFaure faureOf(const Base& b, std::uint32_t digits) { return oas::glsl::oas_faure_make(libraryField(b.p, b.k), digits); }

/// Pascal's triangle mod p: C(n, r) mod p for n, r < OAS_FAURE_MAX_DIGITS.
std::vector<std::vector<int>> binomialsModP(int p)
{
    const std::uint32_t n = oas::glsl::OAS_FAURE_MAX_DIGITS;
    std::vector<std::vector<int>> c(n, std::vector<int>(n, 0));
    for (std::uint32_t i = 0; i < n; ++i) {
        c[i][0] = 1;
        for (std::uint32_t r = 1; r <= i; ++r) c[i][r] = (c[i - 1][r - 1] + c[i - 1][r]) % p;
    }
    return c;
}

/// y_r = sum_{k >= r} C(k, r) a^(k - r) d_k in the textbook field: the definition of the generalized
/// Faure generator matrix (the Pascal matrix's a-th power), with C(k, r) taken mod p into the field.
std::vector<int> definitionDigits(const textbook::Field& field, const std::vector<std::vector<int>>& binomials,
                                  std::uint32_t digits, int a, std::uint32_t index)
{
    const int q = field.q();
    std::vector<int> d(digits);
    for (auto& x : d) {
        x = int(index % q);
        index /= q;
    }
    std::vector<int> y(digits, 0);
    for (std::uint32_t r = 0; r < digits; ++r)
        for (std::uint32_t k = r; k < digits; ++k) {
            const int term = field.mul(field.mul(field.fromInt(binomials[k][r]), field.pow(a, k - r)), d[k]);
            y[r] = field.add(y[r], term);
        }
    return y;
}

TEST(Faure, DigitsAreTheGeneratorMatricesTimesTheIndexDigits)
{
    for (const Base& b : bases()) {
        SCOPED_TRACE("GF(" + std::to_string(b.p) + "^" + std::to_string(b.k) + ")");
        const textbook::Field field(int(b.p), int(b.k), oas::primitivePolynomial(b.p, b.k));
        const auto binomials = binomialsModP(int(b.p));
        const std::uint32_t q = b.q();
        // Every index of a small K, then sampled indices at the base's largest K.
        std::uint32_t smallK = 1;
        while (ipow(q, smallK + 1) <= 4096) ++smallK;
        std::mt19937 rng(q);
        for (std::uint32_t digits : {smallK, maxDigits(q)}) {
            const OasFaure fa = faureOf(b, digits);
            const std::uint32_t n = ipow(q, digits);
            for (std::uint32_t t = 0; t < std::min<std::uint32_t>(n, 4096); ++t) {
                const std::uint32_t index = n <= 4096 ? t : rng() % n;
                for (std::uint32_t a = 0; a < q; a += (q > 9 ? 5 : 1)) {
                    const auto got = oas::glsl::oas_faure_digits(fa, a, index);
                    const auto want = definitionDigits(field, binomials, digits, int(a), index);
                    for (std::uint32_t r = 0; r < digits; ++r)
                        ASSERT_EQ(got.y[r], std::uint32_t(want[r])) << "K " << digits << " index " << index << " element " << a
                                                                     << " digit " << r;
                    for (std::uint32_t r = digits; r < oas::glsl::OAS_FAURE_MAX_DIGITS; ++r) ASSERT_EQ(got.y[r], 0u);
                }
            }
        }
    }
}

// The leading digit is the polynomial of the index's digits at the element: Bush's OA, row =
// index, column = element, as the library's Bush construction computes it.
TEST(Faure, TheLeadingDigitIsBushsOrthogonalArray)
{
    const std::vector<std::pair<std::uint32_t, std::uint32_t>> cases = {{3, 3}, {4, 3}, {5, 2}, {7, 3}, {8, 2}, {9, 3}, {31, 2}};
    for (const auto& [q, t] : cases) {
        oas::PatternRequest r;
        r.sampler = "bush";
        r.spp = ipow(q, t);
        r.strength = t;
        r.dims = q;
        const auto pat = oas::glsl::toGlsl(oas::makePattern(r));
        const OasField f = oas::glsl::oas_pattern_field(pat);
        const OasFaure fa = oas::glsl::oas_faure_make(f, t);
        for (std::uint32_t index = 0; index < r.spp; ++index)
            for (std::uint32_t a = 0; a < q; ++a)
                ASSERT_EQ(oas::glsl::oas_faure_digits(fa, a, index).y[0], oas::glsl::oas_bush_level(pat, f, index, a))
                    << "q " << q << " t " << t << " row " << index << " column " << a;
    }
}

/// The scrambled strata of q^K of samples [first, first + n) in dimensions with the given
/// elements and keys, [dim][sample].
std::vector<std::vector<std::uint32_t>> strata(const OasFaure& fa, const std::vector<std::uint32_t>& elements,
                                               const std::vector<std::uint32_t>& keys, std::uint32_t first, std::uint32_t n)
{
    std::vector<std::vector<std::uint32_t>> out(elements.size(), std::vector<std::uint32_t>(n));
    for (std::size_t j = 0; j < elements.size(); ++j)
        for (std::uint32_t i = 0; i < n; ++i)
            out[j][i] = oas::glsl::oas_faure_stratum(fa, elements[j], first + i, keys[j]).stratum;
    return out;
}

/// Whether the points hit every cell of the grid that splits dimension j into q^parts[j] equal
/// intervals exactly `perCell` times (the grid has q^(sum parts) cells).
bool everyCellHitEqually(const std::vector<std::vector<std::uint32_t>>& st, std::uint32_t q, std::uint32_t digits,
                         const std::vector<std::uint32_t>& parts, std::uint32_t perCell)
{
    std::uint64_t cells = 1;
    for (auto k : parts) cells *= ipow(q, k);
    std::vector<std::uint32_t> hits(cells, 0);
    const std::size_t n = st.front().size();
    for (std::size_t i = 0; i < n; ++i) {
        std::uint64_t cell = 0;
        for (std::size_t j = 0; j < parts.size(); ++j)
            if (parts[j] > 0) cell = cell * ipow(q, parts[j]) + st[j][i] / ipow(q, digits - parts[j]);
        ++hits[cell];
    }
    return std::all_of(hits.begin(), hits.end(), [&](std::uint32_t h) { return h == perCell; });
}

/// Every composition of m into `dims` non-negative parts (k_1 + ... + k_dims = m).
void compositions(std::uint32_t m, std::uint32_t dims, std::vector<std::uint32_t>& current,
                  std::vector<std::vector<std::uint32_t>>& out)
{
    if (current.size() + 1 == dims) {
        current.push_back(m);
        out.push_back(current);
        current.pop_back();
        return;
    }
    for (std::uint32_t k = 0; k <= m; ++k) {
        current.push_back(k);
        compositions(m - k, dims, current, out);
        current.pop_back();
    }
}

std::vector<std::uint32_t> keysFor(std::size_t dims, std::uint32_t seed)
{
    std::vector<std::uint32_t> keys(dims);
    for (std::size_t j = 0; j < dims; ++j) keys[j] = oas::glsl::oas_faure_key(seed, 0, std::uint32_t(j));
    return keys;
}

/// The dimensions 0 .. s-1 of a base: one field element each.
std::vector<std::uint32_t> allElements(std::uint32_t s)
{
    std::vector<std::uint32_t> elements(s);
    for (std::uint32_t j = 0; j < s; ++j) elements[j] = j;
    return elements;
}

// In every aligned block of q^m consecutive samples, every grid of q^k1 x ... x q^ks cells with
// k1 + ... + ks = m holds one point per cell. Up to q^m = 2^14: every composition where they are
// few (at most 8 dimensions or m <= 2), 300 sampled ones otherwise, on blocks 0, 1 and the last of
// the base's largest K (so that every index digit is in play). Then at the largest m with
// q^m <= 2^17: 3 sampled grids over two dimensions, on the first and the last block.
TEST(Faure, EveryAlignedBlockOfQToTheMSamplesIsANet)
{
    for (const Base& b : bases()) {
        const std::uint32_t q = b.q(), s = q, digits = maxDigits(q);
        SCOPED_TRACE("q " + std::to_string(q) + ", K " + std::to_string(digits));
        const OasFaure fa = faureOf(b, digits);
        const auto elements = allElements(s);
        const auto keys = keysFor(s, 0x1234u + q);
        std::mt19937 rng(q);
        std::uint32_t m = 1;
        for (; m <= digits && ipow(q, m) <= (1u << 14); ++m) {
            std::vector<std::vector<std::uint32_t>> grids;
            std::vector<std::uint32_t> current;
            if (s <= 8 || m <= 2)
                compositions(m, s, current, grids);
            else  // 9 and 31 dimensions: the parts of m put on random dimensions
                for (int g = 0; g < 300; ++g) {
                    std::vector<std::uint32_t> parts(s, 0);
                    for (std::uint32_t left = m; left > 0; --left) ++parts[rng() % s];
                    grids.push_back(parts);
                }
            const std::uint32_t n = ipow(q, m), blocks = ipow(q, digits) / n;
            for (std::uint32_t block : {0u, 1u, blocks - 1}) {
                if (block >= blocks) continue;
                const auto st = strata(fa, elements, keys, block * n, n);
                for (const auto& parts : grids)
                    ASSERT_TRUE(everyCellHitEqually(st, q, digits, parts, 1))
                        << "m " << m << " block " << block << " grid " << ::testing::PrintToString(parts);
            }
        }
        // The largest blocks: two dimensions at a time.
        while (m < digits && ipow(q, m + 1) <= (1u << 17)) ++m;
        if (m > digits || ipow(q, m) <= (1u << 14)) continue;
        const std::uint32_t n = ipow(q, m), blocks = ipow(q, digits) / n;
        for (int g = 0; g < 3; ++g) {
            const std::uint32_t d0 = rng() % s, d1 = (d0 + 1 + rng() % (s - 1)) % s, k0 = rng() % (m + 1);
            for (std::uint32_t block : {0u, blocks - 1}) {
                const auto st = strata(fa, {d0, d1}, {keys[d0], keys[d1]}, block * n, n);
                ASSERT_TRUE(everyCellHitEqually(st, q, digits, {k0, m - k0}, 1))
                    << "m " << m << " block " << block << " dims " << d0 << ", " << d1 << " parts " << k0 << ", " << m - k0;
            }
        }
    }
}

// Every prefix of lambda q^t samples is an OA of strength t and index lambda in the leading
// digits: in t dimensions, every one of the q^t cells of their leading digits holds lambda
// points. Every t-subset of the dimensions where there are at most 300, 300 sampled ones
// otherwise; prefixes up to 2^15 samples.
TEST(Faure, EveryPrefixOfLambdaQToTheTSamplesIsAnOrthogonalArray)
{
    for (const Base& b : bases()) {
        const std::uint32_t q = b.q(), s = q, digits = maxDigits(q);
        const OasFaure fa = faureOf(b, digits);
        const auto keys = keysFor(s, 0x777u);
        std::mt19937 rng(q + 1);
        for (std::uint32_t t = 2; t <= std::min<std::uint32_t>(3, s); ++t)
            for (std::uint32_t lambda : {1u, 2u, 3u, q - 1}) {
                const std::uint64_t n = std::uint64_t(lambda) * ipow(q, t);
                if (lambda == 0 || n > (1u << 15) || n > ipow(q, digits)) continue;
                const auto st = strata(fa, allElements(s), keys, 0, std::uint32_t(n));
                std::vector<std::vector<std::uint32_t>> subsets;
                std::vector<bool> pick(s, false);
                std::fill(pick.begin(), pick.begin() + t, true);
                do {
                    std::vector<std::uint32_t> parts(s, 0);
                    for (std::uint32_t j = 0; j < s; ++j) parts[j] = pick[j] ? 1 : 0;
                    subsets.push_back(parts);
                } while (std::prev_permutation(pick.begin(), pick.end()));
                if (subsets.size() > 300) {
                    std::shuffle(subsets.begin(), subsets.end(), rng);
                    subsets.resize(300);
                }
                for (const auto& parts : subsets)
                    ASSERT_TRUE(everyCellHitEqually(st, q, digits, parts, lambda))
                        << "q " << q << " t " << t << " lambda " << lambda << " dims " << ::testing::PrintToString(parts);
            }
    }
}

// The check above can fail: q + 1 dimensions cannot form a (0,m,q+1)-net's prefixes in base q
// (a (0,s)-sequence in base q has s <= q; Niederreiter 1987). The extra dimension repeats an
// element with its own key, so its leading digits are a bijection of the first's: the q x q grid
// of those two dimensions has q of its q^2 cells hit q times each.
TEST(Faure, QPlusOneDimensionsAreRejected)
{
    for (const Base& b : bases()) {
        const std::uint32_t q = b.q(), digits = maxDigits(q);
        const OasFaure fa = faureOf(b, digits);
        std::vector<std::uint32_t> elements(q + 1);
        for (std::uint32_t j = 0; j < q; ++j) elements[j] = j;
        elements[q] = 0;
        const auto keys = keysFor(q + 1, 0x99u);
        const auto st = strata(fa, elements, keys, 0, q * q);
        std::vector<std::uint32_t> parts(q + 1, 0);
        parts[0] = parts[q] = 1;
        EXPECT_FALSE(everyCellHitEqually(st, q, digits, parts, 1)) << "q " << q;
        parts[q] = 0;
        parts[1] = 1;  // the same check on two distinct elements passes
        EXPECT_TRUE(everyCellHitEqually(st, q, digits, parts, 1)) << "q " << q;
    }
}

// The faure pattern, as a renderer reads it (oas::sample): its words give the sequence (base q the
// smallest prime power >= d, N = q^K the smallest power >= spp, worked out here by hand), each
// dimension is the sequence at its element of its block under that block's key, with a fresh
// pass seed past N; and, read back from the floats, every prefix of lambda q^2 samples puts
// lambda points in each of the q x q cells of every pair of dimensions of a block, in the first
// block and the second.
TEST(Faure, ThePatternIsTheSequenceInBlocksOfD)
{
    const struct {
        std::uint32_t d, spp, q, N;
    } cases[] = {{2, 100, 2, 128}, {3, 27, 3, 27}, {4, 40, 4, 64}, {7, 50, 7, 343}, {9, 81, 9, 81}, {10, 121, 11, 121}};
    const std::uint32_t seed = 0xc0ffeeu;
    for (const auto& c : cases) {
        const oas::Pattern p = oas::test::faurePattern(c.spp, c.d);
        SCOPED_TRACE(oas::describe(p));
        ASSERT_EQ(p.s, c.q);
        ASSERT_EQ(p.N, c.N);
        ASSERT_EQ(p.blockDims, c.d);
        const OasFaure fa = oas::glsl::oas_faure_make(oas::glsl::oas_pattern_field(oas::glsl::toGlsl(p)), p.aux);
        ASSERT_EQ(fa.strata, c.N);
        std::vector<std::uint32_t> indices;
        for (std::uint32_t i = 0; i < std::min(c.N, 300u); ++i) indices.push_back(i);
        for (std::uint32_t i : {c.N, c.N + 1, 2 * c.N + 3}) indices.push_back(i);
        for (std::uint32_t index : indices)
            for (std::uint32_t dim = 0; dim < 2 * c.d; ++dim) {
                const std::uint32_t pass = index / c.N, block = dim / c.d, element = dim % c.d;
                const std::uint32_t key = oas::glsl::oas_faure_key(oas::glsl::oas_pass_seed(seed, pass), block, element);
                const float want = oas::glsl::oas_faure_value(fa, element, index - pass * c.N, key);
                ASSERT_EQ(oas::sample(p, seed, index, dim), want) << "index " << index << " dim " << dim;
            }
        for (std::uint32_t lambda : {1u, 2u}) {
            const std::uint32_t n = lambda * c.q * c.q;
            if (n > c.N) continue;
            for (std::uint32_t block : {0u, 1u})
                for (std::uint32_t j = 0; j < c.d; ++j)
                    for (std::uint32_t k = j + 1; k < c.d; ++k) {
                        std::vector<std::uint32_t> hits(c.q * c.q, 0);
                        for (std::uint32_t i = 0; i < n; ++i) {
                            const auto cell = [&](std::uint32_t dim) {
                                return std::uint32_t(double(oas::sample(p, seed, i, block * c.d + dim)) * c.q);
                            };
                            ++hits[cell(j) * c.q + cell(k)];
                        }
                        ASSERT_TRUE(std::all_of(hits.begin(), hits.end(), [&](std::uint32_t h) { return h == lambda; }))
                            << "prefix " << n << ", block " << block << ", dims " << j << ", " << k;
                    }
        }
    }
}

// --explain's sentence on a prefix: the largest lambda q^m within spp, worked out by hand (base 11:
// 100 = 9 x 11 + 1, 1000 = 8 x 121 + 32, 121 = 11^2; 5 < 11), and nothing for a sampler whose N is spp.
TEST(Faure, ThePrefixGuaranteeNamesTheLargestWholeNets)
{
    auto guarantee = [](std::uint32_t spp) { return oas::prefixGuarantee(oas::test::faurePattern(spp, 10), spp); };
    EXPECT_NE(guarantee(100).find("the first 99 (9 x 11^1) are 9 (0,1,10)-nets"), std::string::npos) << guarantee(100);
    EXPECT_NE(guarantee(100).find("the 1 after them"), std::string::npos) << guarantee(100);
    EXPECT_NE(guarantee(1000).find("the first 968 (8 x 11^2) are 8 (0,2,10)-nets"), std::string::npos) << guarantee(1000);
    EXPECT_NE(guarantee(121).find("are a (0,2,10)-net"), std::string::npos) << guarantee(121);
    EXPECT_EQ(guarantee(121).find("after them"), std::string::npos) << guarantee(121);
    EXPECT_NE(guarantee(5).find("no dimension is stratified yet"), std::string::npos) << guarantee(5);
    EXPECT_EQ(oas::prefixGuarantee(oas::makePattern({.sampler = "bose", .spp = 121}), 121), "");
}

// The chooser's refusal of a count no orthogonal array makes (the prime 103 at strength 2: CMJND's
// 10^2 and Bose's 11^2 are the nearest) offers the progressive sampler with what its prefix
// guarantees (10 dims: base 11, 103 = 9 x 11 + 4); a count the chooser makes needs no offer.
TEST(Faure, TheChoosersRefusalOffersTheProgressiveSampler)
{
    oas::PatternRequest r;
    r.sampler = "oa";
    r.spp = 103;
    r.dims = 10;
    try {
        oas::chooseOrthogonalArray(r);
        FAIL() << "spp 103 has no orthogonal array of strength 2";
    } catch (const oas::InvalidArgument& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("nearest valid spp: 100, 121"), std::string::npos) << message;
        EXPECT_NE(message.find("--sampler faure"), std::string::npos) << message;
        EXPECT_NE(message.find("the first 99 (9 x 11^1)"), std::string::npos) << message;
    }
    r.spp = 121;
    EXPECT_NO_THROW(oas::chooseOrthogonalArray(r));
}

// Each value lies in its scrambled stratum of q^K exactly (as real numbers), is below 1, and the
// bits are F * 2^-24; over many keys a sample's value is uniform (its mean within 4 s.e. of 1/2,
// every tenth of [0, 1) within 4 s.e. of its share).
TEST(Faure, ValuesKeepTheStratumContractAndAreUniformOverKeys)
{
    for (const Base& b : bases()) {
        const std::uint32_t q = b.q(), digits = maxDigits(q);
        const OasFaure fa = faureOf(b, digits);
        const double strataCount = double(ipow(q, digits));
        std::mt19937 rng(q + 7);
        for (int trial = 0; trial < 2000; ++trial) {
            const std::uint32_t index = rng() % ipow(q, digits), a = rng() % q, key = rng();
            const float x = oas::glsl::oas_faure_value(fa, a, index, key);
            const auto stratum = oas::glsl::oas_faure_stratum(fa, a, index, key);
            const std::uint32_t m = stratum.stratum;
            // Its definition: the stratum point of the scrambled stratum, jittered by the scramble's
            // last key (oas_faure_value divides by q^K through its reciprocal: the same bits).
            ASSERT_EQ(x, oas::glsl::oas_stratum_point(m, fa.strata, oas::glsl::oas_pcg(stratum.key ^ 0x68e31da4u)))
                << "q " << q << " index " << index;
            ASSERT_LT(x, 1.0f);
            ASSERT_EQ(double(x) * 16777216.0, std::floor(double(x) * 16777216.0));
            ASSERT_LE(double(m) / strataCount, double(x)) << "q " << q << " index " << index;
            ASSERT_LT(double(x), double(m + 1) / strataCount) << "q " << q << " index " << index;
        }
        constexpr int kKeys = 20000;
        for (std::uint32_t index : {0u, 1u, q * q - 1}) {
            const std::uint32_t a = q - 1;
            double total = 0;
            std::vector<int> tenths(10, 0);
            for (int k = 0; k < kKeys; ++k) {
                const double x = oas::glsl::oas_faure_value(fa, a, index, oas::glsl::oas_pcg(std::uint32_t(k)));
                total += x;
                ++tenths[std::min(9, int(x * 10))];
            }
            EXPECT_NEAR(total / kKeys, 0.5, 4 * std::sqrt(1.0 / 12 / kKeys)) << "q " << q << " index " << index;
            for (int h : tenths) EXPECT_NEAR(h, kKeys / 10.0, 4 * std::sqrt(kKeys * 0.1 * 0.9)) << "q " << q;
        }
    }
}

class FaureGpu : public oas::test::GpuTest {};

/// `count` (index, element, key) triples for base b with K = digits: the first 1024 indices, then
/// random ones.
std::vector<std::uint32_t> faureTriples(const Base& b, std::uint32_t digits, std::uint32_t count = 4096)
{
    const std::uint32_t q = b.q();
    std::mt19937 rng(q * 3);
    std::vector<std::uint32_t> triples;
    for (std::uint32_t i = 0; i < count; ++i)
        triples.insert(triples.end(), {i < 1024 ? i : std::uint32_t(rng() % ipow(q, digits)), std::uint32_t(rng() % q),
                                       std::uint32_t(rng())});
    return triples;
}

struct FaurePush {
    OasFaure faure;
    std::uint32_t count, perInvocation, burn;
};
constexpr std::size_t kPushBytes = sizeof(FaurePush);

/// The values the pipeline (tests/shaders/faure_points.comp) makes for the triples, each
/// invocation making `perInvocation` of them after `burn` iterations of a loop of its own.
std::vector<float> gpuFaureValues(oas::vk::Context& ctx, oas::vk::ComputePipeline& pipeline, const OasFaure& fa,
                                  const std::vector<std::uint32_t>& triples, std::uint32_t perInvocation = 1,
                                  std::uint32_t burn = 0)
{
    const std::uint32_t count = std::uint32_t(triples.size() / 3);
    const std::uint32_t invocations = (count + perInvocation - 1) / perInvocation;
    oas::vk::Buffer in(ctx, triples.size() * sizeof(std::uint32_t)), out(ctx, (count + invocations) * sizeof(float));
    std::memcpy(in.data(), triples.data(), triples.size() * sizeof(std::uint32_t));
    std::memset(out.data(), 0xff, (count + invocations) * sizeof(float));  // NaN until written
    const FaurePush push{fa, count, perInvocation, burn};
    oas::vk::Buffer* buffers[] = {&in, &out};
    ctx.dispatch(pipeline, buffers, &push, sizeof(push), (invocations + 63) / 64);
    const auto* got = static_cast<const float*>(out.data());
    return std::vector<float>(got, got + count);
}

/// How many of the GPU's values differ in any bit from the CPU twin's.
std::size_t mismatchesWithTheTwin(const OasFaure& fa, const std::vector<std::uint32_t>& triples, const std::vector<float>& got)
{
    std::size_t mismatches = 0;
    for (std::size_t i = 0; i < got.size(); ++i) {
        const float want = oas::glsl::oas_faure_value(fa, triples[3 * i + 1], triples[3 * i], triples[3 * i + 2]);
        std::uint32_t a, c;
        std::memcpy(&a, &got[i], 4);
        std::memcpy(&c, &want, 4);
        mismatches += a != c;
    }
    return mismatches;
}

// The GPU computes the same bits: the shader calls the library's oas_faure_value on (index,
// element, key) triples for every base above at its largest K.
TEST_F(FaureGpu, GpuValuesEqualTheCpuTwinBitForBit)
{
    oas::vk::Context& ctx = context();
    oas::vk::ComputePipeline pipeline(ctx, faure_points_spv, sizeof(faure_points_spv), 2, kPushBytes);
    for (const Base& b : bases()) {
        const std::uint32_t digits = maxDigits(b.q());
        const OasFaure fa = faureOf(b, digits);
        const auto triples = faureTriples(b, digits);
        EXPECT_EQ(mismatchesWithTheTwin(fa, triples, gpuFaureValues(ctx, pipeline, fa, triples)), 0u)
            << "q " << b.q() << ": GPU and CPU values differ";
    }
}

// A shader specialised on K (OAS_STATIC_FAURE_DIGITS, with the stratum point's short division,
// OAS_STATIC_SMALL_N = 1, or the long one) gives the twin's bits for a sequence with that K, and
// NaN in every value for one with another K: never the values of a K it is not.
TEST_F(FaureGpu, ASpecialisedShaderGivesTheTwinsBitsForItsKAndNaNForAnother)
{
    oas::vk::Context& ctx = context();
    for (const Base& b : bases()) {
        for (std::uint32_t smallStrata : {0u, 1u}) {
            const std::uint32_t digits = std::min<std::uint32_t>(maxDigits(b.q()), 3);
            ASSERT_LE(ipow(b.q(), digits), 65536u);
            oas::vk::ComputePipeline pipeline(ctx, faure_points_static_spv, sizeof(faure_points_static_spv), 2, kPushBytes,
                                              oas::vk::ComputePipeline::SpecConstants{{0, digits}, {1, smallStrata}});
            const OasFaure fa = faureOf(b, digits);
            const auto triples = faureTriples(b, digits);
            EXPECT_EQ(mismatchesWithTheTwin(fa, triples, gpuFaureValues(ctx, pipeline, fa, triples)), 0u)
                << "q " << b.q() << " K " << digits << ": the specialised shader's values differ from the twin's";
            for (std::uint32_t other : {digits - 1, digits + 1}) {
                if (other == 0 || ipow(b.q(), other) > (1u << 24)) continue;
                const OasFaure wrong = faureOf(b, other);
                const auto values = gpuFaureValues(ctx, pipeline, wrong, faureTriples(b, other));
                const auto nan = std::count_if(values.begin(), values.end(), [](float v) { return std::isnan(v); });
                EXPECT_EQ(std::size_t(nan), values.size()) << "q " << b.q() << ": a shader specialised on K " << digits
                                                           << " handed K " << other << " gave numbers, not NaN";
            }
        }
    }
}

// Lavapipe ends an invocation's loops after 65535 iterations in all, silently (DESIGN-NOTES' lavapipe
// facts): a renderer that makes many values in one invocation gets wrong ones once the library's
// own loops add up. Eight invocations make 8192 values each after a burn that leaves 64 spare
// iterations, with K at run time and specialised: a single library loop iteration per value would
// end the value loop thousands of values early. (Nested Taylor-shift loops did, before they were
// made one flat loop: NIR unrolled neither.)
TEST_F(FaureGpu, ManyValuesInOneInvocationAddNoLoopIterations)
{
    oas::vk::Context& ctx = context();
    constexpr std::uint32_t kPerInvocation = 8192, kInvocations = 8, kSpare = 64;
    const Base b = bases().front();
    const std::uint32_t digits = std::min<std::uint32_t>(maxDigits(b.q()), 3);
    const OasFaure fa = faureOf(b, digits);
    const auto triples = faureTriples(b, digits, kPerInvocation * kInvocations);
    oas::vk::ComputePipeline runtimeK(ctx, faure_points_spv, sizeof(faure_points_spv), 2, kPushBytes);
    oas::vk::ComputePipeline specialisedK(ctx, faure_points_static_spv, sizeof(faure_points_static_spv), 2, kPushBytes,
                                          oas::vk::ComputePipeline::SpecConstants{{0, digits}, {1, 1}});
    for (auto* pipeline : {&runtimeK, &specialisedK}) {
        const char* what = pipeline == &runtimeK ? "K at run time" : "K specialised";
        const std::uint32_t burn = 65535 - kPerInvocation - kSpare;
        EXPECT_EQ(mismatchesWithTheTwin(fa, triples, gpuFaureValues(ctx, *pipeline, fa, triples, kPerInvocation, burn)), 0u)
            << what << ": values after a near-cap burn differ from the twin's (the library added loop iterations)";
        // The check can fail: on lavapipe a burn past the cap leaves the last values unwritten
        // (other drivers have no such cap, and nothing to check here).
        if (ctx.isLavapipe()) {
            const auto pastCap = gpuFaureValues(ctx, *pipeline, fa, triples, kPerInvocation, burn + 2 * kSpare);
            EXPECT_GT(mismatchesWithTheTwin(fa, triples, pastCap), 0u)
                << what << ": a burn past lavapipe's cap still gave every value, so this test cannot see a loop";
        }
    }
}

}  // namespace
