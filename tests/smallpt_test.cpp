// examples/smallpt, the embedder's path tracer: its prefetch kernel (oas_prefetch) gives the C++
// twin's values bit for bit, drawing inline and drawing prefetched values render the same image
// word for word, and oas's image has the own hash's mean within the hash's own noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <vector>

#include "gpu_test_support.hpp"
#include "oas/pattern.hpp"
#include "smallpt.hpp"

namespace {

using SmallptGpu = oas::test::GpuTest;

OasPattern makePattern(std::uint32_t construction, std::uint32_t spp)
{
    OasPattern p;
    char why[256];
    if (oas_make_pattern(construction, spp, 0, OAS_OFFSET_CMJ, &p, why, sizeof why) != 0) ADD_FAILURE() << why;
    return p;
}

std::uint32_t bits(float v)
{
    std::uint32_t b;
    std::memcpy(&b, &v, 4);
    return b;
}

TEST_F(SmallptGpu, PrefetchedValuesAreOasSampleBitForBit)
{
    // A prime and a binary field, an odd block width (Bose-Bush, Addelman-Kempthorne: 2q + 1
    // dims), a baseline; 5 x 3 pixels (not whole work groups); 11 samples a dispatch starting
    // 3 before the end of a pass, so that every run crosses into the next pass.
    const std::pair<std::uint32_t, std::uint32_t> patterns[] = {
        {OAS_BOSE, 49}, {OAS_BOSE, 64}, {OAS_BOSE_BUSH, 32}, {OAS_ADDELMAN_KEMPTHORNE, 18}, {OAS_RANDOM, 16}};
    for (auto [construction, spp] : patterns) {
        const OasPattern pattern = makePattern(construction, spp);
        smallpt::Renderer renderer(context(), pattern, smallpt::Sampler::OasPrefetch, 5, 3, 11);
        const std::uint32_t first = pattern.N - 3, dims = renderer.dimensions(), frameSeed = 0x5eedu;
        const std::vector<float> values = renderer.prefetch(frameSeed, first);
        std::size_t compared = 0;
        for (std::uint32_t y = 0; y < 3; ++y)
            for (std::uint32_t x = 0; x < 5; ++x)
                for (std::uint32_t k = 0; k < 11; ++k)
                    for (std::uint32_t dim = 0; dim < dims; ++dim, ++compared) {
                        const float expected = oas::sample(oas::Pattern(pattern), oas::pixelSeed(x, y, frameSeed), first + k, dim);
                        const float got = values[((y * 5 + x) * 11 + k) * dims + dim];
                        ASSERT_EQ(bits(got), bits(expected)) << oas_construction_name(construction) << " " << spp << ", pixel (" << x
                                                             << ", " << y << "), sample " << first + k << ", dim " << dim;
                    }
        EXPECT_EQ(compared, std::size_t(15) * 11 * dims);
    }
}

TEST_F(SmallptGpu, InlineAndPrefetchedDrawsRenderTheSameImage)
{
    // The same numbers in the same order make the same sums: word for word, with a dispatch size
    // that does not divide the samples (the last dispatch is short).
    const OasPattern pattern = makePattern(OAS_BOSE, 64);
    smallpt::Renderer inlineDraws(context(), pattern, smallpt::Sampler::OasInline, 12, 10, 24);
    smallpt::Renderer prefetched(context(), pattern, smallpt::Sampler::OasPrefetch, 12, 10, 24);
    const std::vector<float> a = inlineDraws.render(7, 64), b = prefetched.render(7, 64);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_TRUE(std::isfinite(a[i])) << "value " << i;
        ASSERT_EQ(bits(a[i]), bits(b[i])) << "value " << i << ": inline " << a[i] << ", prefetched " << b[i];
    }
}

TEST_F(SmallptGpu, OasImageHasTheOwnHashsMeanWithinItsNoise)
{
    // Both estimate the same integral. The hash's standard error of the image mean comes from two
    // independent hash frames (their difference has twice a frame's variance); oas's error is
    // smaller than the hash's, so five of the hash's standard errors bound it generously.
    const OasPattern pattern = makePattern(OAS_BOSE, 64);
    const std::uint32_t side = 24;
    smallpt::Renderer hash(context(), pattern, smallpt::Sampler::OwnHash, side, side);
    smallpt::Renderer oasDraws(context(), pattern, smallpt::Sampler::OasPrefetch, side, side);
    const std::vector<float> h1 = hash.render(1, 64), h2 = hash.render(2, 64), o = oasDraws.render(3, 64);
    const double n = double(h1.size());
    const double mean1 = std::accumulate(h1.begin(), h1.end(), 0.0) / n, meanOas = std::accumulate(o.begin(), o.end(), 0.0) / n;
    double diffSquares = 0;
    for (std::size_t i = 0; i < h1.size(); ++i) diffSquares += (double(h1[i]) - h2[i]) * (double(h1[i]) - h2[i]);
    const double frameMeanError = std::sqrt(diffSquares / n / 2.0 / n);
    EXPECT_GT(mean1, 0.05) << "the room should be lit";
    EXPECT_LT(std::abs(meanOas - mean1), 5.0 * std::sqrt(2.0) * frameMeanError)
        << "oas mean " << meanOas << ", hash mean " << mean1 << ", hash frame standard error " << frameMeanError;
    for (float v : o) ASSERT_TRUE(std::isfinite(v));
}

TEST(Smallpt, PathDimensionsFollowThePairLayout)
{
    // Bose over GF(7) has 8 dims a block: pairs at even columns (0,1) ... (6,7), so the layout
    // needs no gaps: 2 + 8 vertices x 6 = 50. Bose-Bush 32 has 9 (the 9th column cannot pair):
    // each block's column 8 is skipped by a pair, giving more.
    EXPECT_EQ(smallpt::pathDimensions(makePattern(OAS_BOSE, 49)), 50u);
    EXPECT_GT(smallpt::pathDimensions(makePattern(OAS_BOSE_BUSH, 32)), 50u);
    EXPECT_EQ(smallpt::pathDimensions(makePattern(OAS_RANDOM, 16)), 50u);
}

}  // namespace
