// OaColumns (host/oas/oa_columns.hpp), the CPU's bulk OA evaluation compiled once per
// construction and field kind and vectorized across samples: every value equals oas_sample (the
// library's one-value definition) bit for bit, for every construction, field kind and offset,
// with each instruction set's build of the loops (baseline and, where the CPU has it, AVX2),
// over seeds, runs that start anywhere in a pass (pass 0, later passes, the last pass before the
// index wraps) and dimensions at block starts, ends and far blocks; the variant is the
// specialised one wherever N <= 2^16 (per degree for binary fields with CMJ offsets, k = 2 .. 5);
// bad runs and baselines are refused with the valid range.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <set>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/baseline_columns.hpp"
#include "oas/oa_columns.hpp"
#include "test_cases.hpp"

namespace {

/// Dimensions to check: every column of the first block for small blocks, else its first and
/// last columns; the next block's first columns; a far block.
std::vector<std::uint32_t> dimsOf(const oas::Pattern& p)
{
    std::set<std::uint32_t> dims;
    const std::uint32_t b = p.blockDims;
    for (std::uint32_t c = 0; c < std::min(b, 10u); ++c) dims.insert(c);
    for (std::uint32_t d : {b - 2, b - 1, b, b + 1, 5 * b + b / 2}) dims.insert(d);
    return {dims.begin(), dims.end()};
}

/// (first index, count) runs: a whole first pass (at most 600 samples of it), a run inside pass
/// 1, a pass's last samples, one sample, and the last full pass below 2^32.
std::vector<std::pair<std::uint32_t, std::uint32_t>> runsOf(const oas::Pattern& p)
{
    const std::uint32_t n = p.N, lastPass = (0xffffffffu / n - 1) * n;
    return {{0u, std::min(n, 600u)},
            {n + n / 3, std::min(n - n / 3, 77u)},
            {3 * n - std::min(n, 13u), std::min(n, 13u)},
            {2 * n + 1, 1u},
            {lastPass + n - std::min(n, 40u), std::min(n, 40u)}};
}

/// Checks every value of `pattern`'s OaColumns with instruction set `isa` against oas_sample, over
/// seeds, runs (runsOf) and dimensions (dimsOf); returns how many values it compared.
std::size_t expectEqualToOasSample(const oas::Pattern& pattern, oas::CpuIsa isa)
{
    const oas::OaColumns columns(pattern, isa);
    const auto p = oas::glsl::toGlsl(pattern);
    std::size_t values = 0;
    for (std::uint32_t seed : {0u, 0x9e3779b9u, oas::glsl::oas_pixel_seed(511u, 7u, 3u)})
        for (const auto& [first, count] : runsOf(pattern)) {
            std::vector<std::uint32_t> rows(count);
            std::vector<float> out(count);
            std::uint32_t rowsBlock = ~0u;
            for (std::uint32_t dim : dimsOf(pattern)) {
                const std::uint32_t block = dim / pattern.blockDims;
                if (block != rowsBlock) columns.rows(seed, block, first, count, rows.data());
                rowsBlock = block;
                columns.values(seed, dim, first, count, rows.data(), out.data());
                for (std::uint32_t k = 0; k < count; ++k) {
                    const float expected = oas::glsl::oas_sample(p, seed, first + k, dim);
                    EXPECT_EQ(std::bit_cast<std::uint32_t>(out[k]), std::bit_cast<std::uint32_t>(expected))
                        << oas::describe(pattern) << " (" << columns.variantName() << ", isa " << int(columns.isa()) << ") seed "
                        << seed << " index " << first + k << " dim " << dim;
                    if (std::bit_cast<std::uint32_t>(out[k]) != std::bit_cast<std::uint32_t>(expected)) return values;
                }
                values += count;
            }
        }
    return values;
}

/// Binary-field patterns with CMJ offsets at every degree that has its own variant
/// (OAS_OA_COLUMN_DEGREE_VARIANTS, k = 2 .. 5) and the next one up (k = 6, which takes the
/// variant that runs every multiply step), for Bose (q = 2^k, N = q^2) and Bose-Bush (its field
/// is GF(2q): q = 2^(k-1), N = 2 q^2); with the variant name each must get.
std::vector<std::pair<oas::test::SamplerCase, std::string>> binaryDegreeCases()
{
    std::vector<std::pair<oas::test::SamplerCase, std::string>> cases;
    for (std::uint32_t k = 2; k <= 6; ++k) {
        const std::uint32_t q = 1u << k, qBoseBush = q / 2;
        const std::string suffix = k <= 5 ? "_cmj_k" + std::to_string(k) : "_cmj";
        cases.push_back({{"bose", q * q, 0}, "bose_binary" + suffix});
        cases.push_back({{"bose-bush", 2 * qBoseBush * qBoseBush, 0}, "bose_bush_binary" + suffix});
    }
    return cases;
}

TEST(OaColumns, EqualBitForBitToOasSampleForEveryOaPatternAndOffset)
{
    std::size_t values = 0, patterns = 0;
    for (const auto& c : oas::test::oaCases())
        for (const char* offset : {"centered", "j", "mj", "cmj"})
            for (oas::CpuIsa isa : {oas::CpuIsa::Baseline, oas::CpuIsa::Avx2}) {
                patterns += isa == oas::CpuIsa::Baseline;
                values += expectEqualToOasSample(oas::test::patternOf(c, offset), isa);
            }
    EXPECT_EQ(patterns, 4 * oas::test::oaCases().size());
    EXPECT_GT(values, 1000000u);
}

TEST(OaColumns, BinaryFieldVariantsOfFixedDegreeEqualOasSample)
{
    for (const auto& [c, variant] : binaryDegreeCases()) {
        const oas::Pattern pattern = oas::test::patternOf(c, "cmj");
        EXPECT_EQ(oas::OaColumns(pattern).variantName(), variant) << oas::describe(pattern);
        for (oas::CpuIsa isa : {oas::CpuIsa::Baseline, oas::CpuIsa::Avx2})
            EXPECT_GT(expectEqualToOasSample(pattern, isa), 500u) << oas::describe(pattern);
    }
}

TEST(OaColumns, EveryPatternUpTo65536SamplesHasItsOwnVariant)
{
    // The speed of the CPU tracer's OA dimensions rests on this (a generic variant gives the same
    // values but keeps every pattern switch in the loop, which stops g++ vectorizing it).
    std::set<std::string> names;
    std::vector<oas::test::SamplerCase> cases = oas::test::oaCases();
    for (const auto& binary : binaryDegreeCases()) cases.push_back(binary.first);
    for (const auto& c : cases)
        for (const char* offset : {"centered", "j", "mj", "cmj"}) {
            const oas::Pattern pattern = oas::test::patternOf(c, offset);
            const oas::OaColumns columns(pattern);
            EXPECT_EQ(columns.specialised(), pattern.N <= 65536u) << oas::describe(pattern) << " " << columns.variantName();
            names.insert(columns.variantName());
        }
    // Per offset: Bose over prime, GF(2^k) and GF(3^k)/GF(5^k); Bush the same; Bose-Bush; AK
    // prime and odd extension; CMJND. The generic variant for the hard cases. With CMJ offsets,
    // Bose and Bose-Bush over GF(2^k) for k = 2 .. 5.
    EXPECT_EQ(names.size(), 4u * 10u + 1u + 2u * 4u);
}

TEST(OaColumns, RefusesRunsThatLeaveTheirPassAndBaselinesNamingTheLimit)
{
    oas::PatternRequest r;
    r.sampler = "bose";
    r.spp = 121;
    const oas::OaColumns columns(oas::makePattern(r));
    std::vector<std::uint32_t> rows(200);
    std::vector<float> out(200);
    EXPECT_EQ(columns.samplesLeftInPass(120u), 1u);
    EXPECT_EQ(columns.samplesLeftInPass(121u), 121u);
    try {
        columns.rows(1u, 0u, 100u, 22u, rows.data());
        FAIL() << "a run of 22 samples from index 100 with N = 121 was accepted";
    } catch (const oas::InvalidArgument& e) {
        EXPECT_NE(std::string(e.what()).find("at most 21"), std::string::npos) << e.what();
    }
    EXPECT_THROW(columns.values(1u, 0u, 0u, 122u, rows.data(), out.data()), oas::InvalidArgument);
    r.sampler = "sobol";
    EXPECT_THROW(oas::OaColumns{oas::makePattern(r)}, oas::InvalidArgument);
}

TEST(BaselineColumns, EveryBaselineEqualsOasSampleBitForBit)
{
    // Every baseline the library names, N a square, a prime, a power of two and 2^24; runs that
    // start anywhere in a pass (pass 0, a later pass, the last whole pass before the index wraps,
    // the pass's last 600 indices, where every index bit below N takes part) and are longer than the Sobol loop's 256-point stretches; dimensions across the Halton (32),
    // Sobol-Burley (4) and Sobol (1024) blocks; both instruction sets' loops.
    std::size_t compared = 0;
    for (const auto& name : oas::samplerNames()) {
        if (oas::isOrthogonalArray(name)) continue;
        for (std::uint32_t spp : {121u, 127u, 128u, 16777216u})
            for (oas::CpuIsa isa : {oas::CpuIsa::Baseline, oas::CpuIsa::Avx2}) {
                oas::PatternRequest r;
                r.sampler = name;
                r.spp = spp;
                if (name == "faure") r.strength = 4;  // base 4, GF(2^2): its sequences reach 4^12 = 2^24
                const oas::Pattern p = oas::makePattern(r);
                const std::uint32_t N = p.N;  // spp, but for faure the power of its base q^K >= spp
                const oas::BaselineColumns columns(p, isa);
                std::vector<float> out(600);
                const std::uint32_t lastPass = (0xffffffffu / N - 1) * N;  // the last whole pass
                for (std::uint32_t firstIndex : {0u, 5u, 3 * N + 1, lastPass + 2, N - std::min(N, 600u)})
                    for (std::uint32_t dim : {0u, 1u, 2u, 3u, 4u, 7u, 31u, 32u, 33u, 1023u, 1024u, 1025u, 5000u})
                        for (std::uint32_t seed : {0u, 0x9e3779b9u}) {
                            const std::uint32_t count = std::min({columns.samplesLeftInPass(firstIndex), 600u, N});
                            columns.values(seed, dim, firstIndex, count, out.data());
                            for (std::uint32_t k = 0; k < count; ++k, ++compared)
                                ASSERT_EQ(out[k], oas::sample(p, seed, firstIndex + k, dim))
                                    << oas::describe(p) << ", sample " << firstIndex + k << ", dim " << dim << ", seed "
                                    << seed << ", " << (isa == oas::CpuIsa::Avx2 ? "AVX2" : "baseline") << " loops";
                        }
            }
    }
    EXPECT_GT(compared, 100000u);
}

TEST(BaselineColumns, FaureRunsEqualOasSampleForEveryK)
{
    // Faure's run loops: one per K = 1 .. 6 over prime fields (K a constant there), the library's
    // per-value code for longer sequences and extension fields. Bases 2 (K up to 12), 3, 5 and
    // 11, and GF(2^2), GF(3^2); every K each base allows up to 2^14 samples (base 2: its longest,
    // 2^12); runs from a pass's start, its middle and up to its end, and in the next pass; two
    // blocks of dimensions.
    std::size_t compared = 0;
    for (std::uint32_t d : {2u, 3u, 4u, 5u, 9u, 11u})
        for (std::uint32_t spp = 2; spp <= (d == 2 ? 4096u : (1u << 14)); spp *= d == 2 ? 2 : d)
            for (oas::CpuIsa isa : {oas::CpuIsa::Baseline, oas::CpuIsa::Avx2}) {
                const oas::Pattern p = oas::test::faurePattern(spp, d);
                const oas::BaselineColumns columns(p, isa);
                std::vector<float> out(300);
                for (std::uint32_t firstIndex : {0u, p.N / 2, p.N - std::min(p.N, 300u), p.N + 1})
                    for (std::uint32_t dim : {0u, 1u, d - 1, d, 2 * d + 1}) {
                        const std::uint32_t count = std::min(columns.samplesLeftInPass(firstIndex), 300u);
                        columns.values(0x5eedu, dim, firstIndex, count, out.data());
                        for (std::uint32_t k = 0; k < count; ++k, ++compared)
                            ASSERT_EQ(out[k], oas::sample(p, 0x5eedu, firstIndex + k, dim))
                                << oas::describe(p) << ", sample " << firstIndex + k << ", dim " << dim << ", "
                                << (isa == oas::CpuIsa::Avx2 ? "AVX2" : "baseline") << " loops";
                    }
            }
    EXPECT_GT(compared, 100000u);
}

TEST(BaselineColumns, PairValuesAreEachDimensionsValues)
{
    // The padded 2D baselines' two dimensions of a pair at once (one shared cell per sample)
    // equal values() of each dimension, for grids square, 1 x N (a prime N) and N = 2^24.
    for (const char* name : {"jittered2d", "cmj2d", "zerotwo"})
        for (std::uint32_t spp : {121u, 127u, 16777216u}) {
            oas::PatternRequest r;
            r.sampler = name;
            r.spp = spp;
            for (oas::CpuIsa isa : {oas::CpuIsa::Baseline, oas::CpuIsa::Avx2}) {
                const oas::BaselineColumns columns(oas::makePattern(r), isa);
                ASSERT_TRUE(columns.padded2d());
                std::vector<float> x(100), y(100), one(100);
                for (std::uint32_t firstIndex : {0u, 7u, 2 * spp + 3})
                    for (std::uint32_t dim : {0u, 2u, 36u}) {
                        columns.pairValues(0xabcu, dim, firstIndex, 100, x.data(), y.data());
                        columns.values(0xabcu, dim, firstIndex, 100, one.data());
                        ASSERT_EQ(x, one) << name << " " << spp << " dim " << dim;
                        columns.values(0xabcu, dim + 1, firstIndex, 100, one.data());
                        ASSERT_EQ(y, one) << name << " " << spp << " dim " << dim + 1;
                    }
                EXPECT_THROW(columns.pairValues(1u, 1u, 0u, 10u, x.data(), y.data()), oas::InvalidArgument);  // odd dim
            }
        }
    oas::PatternRequest r;
    r.sampler = "halton";
    r.spp = 121;
    const oas::BaselineColumns halton(oas::makePattern(r));
    EXPECT_FALSE(halton.padded2d());
    std::vector<float> x(10), y(10);
    EXPECT_THROW(halton.pairValues(1u, 0u, 0u, 10u, x.data(), y.data()), oas::InvalidArgument);
}

TEST(BaselineColumns, RefusesRunsThatLeaveTheirPassAndOrthogonalArrays)
{
    oas::PatternRequest r;
    r.sampler = "random";
    r.spp = 121;
    const oas::BaselineColumns columns(oas::makePattern(r));
    std::vector<float> out(200);
    EXPECT_EQ(columns.samplesLeftInPass(120u), 1u);
    try {
        columns.values(1u, 0u, 100u, 22u, out.data());
        FAIL() << "a run of 22 samples from index 100 with N = 121 was accepted";
    } catch (const oas::InvalidArgument& e) {
        EXPECT_NE(std::string(e.what()).find("at most 21"), std::string::npos) << e.what();
    }
    r.sampler = "bose";
    EXPECT_THROW(oas::BaselineColumns{oas::makePattern(r)}, oas::InvalidArgument);
}

}  // namespace

TEST(HaltonCursor, EachCarryLandsOnTheDigitsThatDividingGives)
{
    // The generation kernel steps a Halton column's cursor from sample to sample by carries
    // (oas_halton_cursor_next) instead of dividing each index into digits (oas_halton_cursor). The
    // two must agree in every digit, permuted digit and high part, and so in the value, at every
    // index: exhaustively through whole passes where N is small (bases 2 .. 29, N a power of the
    // base, one past it, prime), and over stretches that cross the carries into digit 15 and
    // beyond where N is large (base 2 with 17 and 24 digits; base 3 capped at 15 digits, where
    // indices pass 3^15 and the carry leaves the digits).
    namespace glsl = oas::glsl;
    std::size_t compared = 0;
    for (std::uint32_t spp : {1u, 2u, 121u, 128u, 243u, 244u, 131075u, 16777216u}) {
        oas::PatternRequest request;
        request.sampler = "halton";
        request.spp = spp;
        const oas::Pattern p = oas::makePattern(request);
        const glsl::OasPattern pat = glsl::toGlsl(p);
        std::vector<std::uint32_t> starts = {0u};
        std::uint32_t stretch = spp - 1;
        if (spp > 4096) {
            starts = {0u, 32768u - 2000u, 14348907u - 2000u, spp - 4001u};  // 2^15, 3^15
            stretch = 4000;
        }
        for (std::uint32_t dim = 0; dim < 10; ++dim)
            for (std::uint32_t seed : {0u, 0x51ed270bu}) {
                const glsl::OasHaltonColumn column = glsl::oas_halton_column(pat, seed, dim);
                for (std::uint32_t first : starts) {
                    if (first >= spp) continue;
                    glsl::OasHaltonCursor stepped = glsl::oas_halton_cursor(column, first);
                    for (std::uint32_t k = 1; k <= stretch && first + k < spp; ++k, ++compared) {
                        stepped = glsl::oas_halton_cursor_next(column, stepped);
                        const glsl::OasHaltonCursor divided = glsl::oas_halton_cursor(column, first + k);
                        ASSERT_TRUE(std::equal(std::begin(stepped.digit), std::end(stepped.digit), std::begin(divided.digit)) &&
                                    std::equal(std::begin(stepped.permuted), std::end(stepped.permuted),
                                               std::begin(divided.permuted)) &&
                                    stepped.high == divided.high)
                            << "N " << spp << ", dim " << dim << " (base " << column.base << "), index " << first + k;
                        ASSERT_EQ(glsl::oas_halton_cursor_value(pat, column, stepped, first + k),
                                  glsl::oas_halton_column_dim(pat, column, first + k));
                    }
                }
            }
    }
    EXPECT_GT(compared, 500000u);
}

TEST(Columns, AnEmptyRunWritesNothingForEverySampler)
{
    // A run of no samples is a valid request (a caller's loop may end on one): it must write
    // nothing and return, from the start, the middle and the end of a pass.
    for (const auto& name : oas::samplerNames()) {
        oas::PatternRequest r;
        r.sampler = name;
        r.spp = name == "cmjnd" ? 64 : 121;
        if (name == "bush") r.strength = 3, r.spp = 125;
        if (name == "bose-bush") r.spp = 128;
        if (name == "addelman-kempthorne") r.spp = 98;
        const oas::Pattern p = oas::makePattern(r);
        std::vector<std::uint32_t> rows(4, 7u);
        std::vector<float> out(4, -1.0f), outY(4, -1.0f);
        for (std::uint32_t firstIndex : {0u, p.N / 2, p.N - 1, p.N}) {
            for (oas::CpuIsa isa : {oas::CpuIsa::Baseline, oas::CpuIsa::Avx2}) {
                if (oas::isOrthogonalArray(name)) {
                    const oas::OaColumns columns(p, isa);
                    columns.rows(1u, 0u, firstIndex, 0u, rows.data());
                    columns.values(1u, 0u, firstIndex, 0u, rows.data(), out.data());
                } else {
                    const oas::BaselineColumns columns(p, isa);
                    columns.values(1u, 0u, firstIndex, 0u, out.data());
                    if (columns.padded2d()) columns.pairValues(1u, 0u, firstIndex, 0u, out.data(), outY.data());
                }
                EXPECT_EQ(rows, std::vector<std::uint32_t>(4, 7u)) << name;
                EXPECT_EQ(out, std::vector<float>(4, -1.0f)) << name;
                EXPECT_EQ(outY, std::vector<float>(4, -1.0f)) << name;
            }
        }
    }
}
