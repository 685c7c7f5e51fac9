// examples/smallpt, the embedder's path tracer: its prefetch kernel (oas_prefetch) gives the C++
// twin's values bit for bit, drawing inline and drawing prefetched values render the same image
// word for word (oas throughout and for a path's first vertices only), oas for no vertex is the
// own hash's image word for word, and oas's image has the own hash's mean within the hash's own
// noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
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
    // A prime and a binary field, odd block widths (Bose 64: q + 1 = 9, cut into groups of 5 and
    // 4; Bose-Bush, Addelman-Kempthorne: 2q + 1), a baseline, and the first vertices only (8
    // dims, less than Bose 64's block); 5 x 3 pixels (not whole work groups); 11 samples a
    // dispatch starting 3 before the end of a pass, so that every run crosses into the next pass.
    struct Case {
        std::uint32_t construction, spp, vertices;
    };
    const Case cases[] = {{OAS_BOSE, 49, smallpt::kPathVertices},
                          {OAS_BOSE, 64, smallpt::kPathVertices},
                          {OAS_BOSE, 64, 2},
                          {OAS_BOSE_BUSH, 32, smallpt::kPathVertices},
                          {OAS_ADDELMAN_KEMPTHORNE, 18, smallpt::kPathVertices},
                          {OAS_RANDOM, 16, smallpt::kPathVertices},
                          {OAS_RANDOM, 16, 3}};
    for (auto [construction, spp, vertices] : cases) {
        const OasPattern pattern = makePattern(construction, spp);
        smallpt::Renderer renderer(context(), pattern, smallpt::Sampler::OasPrefetch, 5, 3, 11, vertices);
        const std::uint32_t first = pattern.N - 3, dims = renderer.dimensions(), frameSeed = 0x5eedu;
        const std::vector<float> values = renderer.prefetch(frameSeed, first);
        std::size_t compared = 0;
        for (std::uint32_t y = 0; y < 3; ++y)
            for (std::uint32_t x = 0; x < 5; ++x)
                for (std::uint32_t k = 0; k < 11; ++k)
                    for (std::uint32_t dim = 0; dim < dims; ++dim, ++compared) {
                        const float expected = oas::sample(oas::Pattern(pattern), oas::pixelSeed(x, y, frameSeed), first + k, dim);
                        const float got = values[((y * 5 + x) * 11 + k) * dims + dim];
                        ASSERT_EQ(bits(got), bits(expected)) << oas_construction_name(construction) << " " << spp << ", " << vertices
                                                             << " vertices, pixel (" << x << ", " << y << "), sample " << first + k
                                                             << ", dim " << dim;
                    }
        EXPECT_EQ(compared, std::size_t(15) * 11 * dims);
    }
}

void expectSameWords(const std::vector<float>& a, const std::vector<float>& b, const char* what)
{
    ASSERT_EQ(a.size(), b.size()) << what;
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_TRUE(std::isfinite(a[i])) << what << ", value " << i;
        ASSERT_EQ(bits(a[i]), bits(b[i])) << what << ", value " << i << ": " << a[i] << " against " << b[i];
    }
}

TEST_F(SmallptGpu, InlineAndPrefetchedDrawsRenderTheSameImage)
{
    // The same numbers in the same order make the same sums: word for word, with a dispatch size
    // that does not divide the samples (the last dispatch is short); with oas throughout, and with
    // oas for the camera and the first two bounces only (3 vertices; the own hash beyond).
    const OasPattern pattern = makePattern(OAS_BOSE, 64);
    for (std::uint32_t vertices : {smallpt::kPathVertices, 3u}) {
        smallpt::Renderer inlineDraws(context(), pattern, smallpt::Sampler::OasInline, 12, 10, 24, vertices);
        smallpt::Renderer prefetched(context(), pattern, smallpt::Sampler::OasPrefetch, 12, 10, 24, vertices);
        EXPECT_EQ(prefetched.dimensions(), smallpt::pathDimensions(pattern, vertices));
        expectSameWords(inlineDraws.render(7, 64), prefetched.render(7, 64),
                        vertices == 3u ? "3 oas vertices" : "oas throughout");
    }
}

TEST_F(SmallptGpu, OasForNoVertexIsTheOwnHashsImage)
{
    // With oas for no vertex every number is the own hash's (the same function of pixel seed,
    // sample and dimension), so the image is the own-hash renderer's, word for word; and oas for
    // the camera alone is not (a control: the switch reaches the numbers).
    const OasPattern pattern = makePattern(OAS_BOSE, 49);
    const std::vector<float> own = smallpt::Renderer(context(), pattern, smallpt::Sampler::OwnHash, 9, 7, 16).render(5, 49);
    for (auto sampler : {smallpt::Sampler::OasInline, smallpt::Sampler::OasPrefetch})
        expectSameWords(smallpt::Renderer(context(), pattern, sampler, 9, 7, 16, 0).render(5, 49), own,
                        smallpt::samplerName(sampler));
    const std::vector<float> cameraOnly =
        smallpt::Renderer(context(), pattern, smallpt::Sampler::OasInline, 9, 7, 16, 1).render(5, 49);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < own.size(); ++i) differ += bits(own[i]) != bits(cameraOnly[i]);
    EXPECT_GT(differ, own.size() / 2) << "oas for the camera should move most pixels' sums";
}

TEST_F(SmallptGpu, OasImageHasTheOwnHashsMeanWithinItsNoise)
{
    // Both estimate the same integral. The hash's standard error of the image mean comes from two
    // independent hash frames (their difference has twice a frame's variance); oas's error is
    // smaller than the hash's, so five of the hash's standard errors bound it generously.
    const OasPattern pattern = makePattern(OAS_BOSE, 64);
    const std::uint32_t side = 24;
    smallpt::Renderer hash(context(), pattern, smallpt::Sampler::OwnHash, side, side);
    const std::vector<float> h1 = hash.render(1, 64), h2 = hash.render(2, 64);
    const double n = double(h1.size());
    const double mean1 = std::accumulate(h1.begin(), h1.end(), 0.0) / n;
    double diffSquares = 0;
    for (std::size_t i = 0; i < h1.size(); ++i) diffSquares += (double(h1[i]) - h2[i]) * (double(h1[i]) - h2[i]);
    const double frameMeanError = std::sqrt(diffSquares / n / 2.0 / n);
    EXPECT_GT(mean1, 0.05) << "the room should be lit";
    // oas throughout, and for the camera and the first bounce only (the own hash beyond).
    for (std::uint32_t vertices : {smallpt::kPathVertices, 2u}) {
        const std::vector<float> o =
            smallpt::Renderer(context(), pattern, smallpt::Sampler::OasPrefetch, side, side, 8, vertices).render(3, 64);
        const double meanOas = std::accumulate(o.begin(), o.end(), 0.0) / n;
        EXPECT_LT(std::abs(meanOas - mean1), 5.0 * std::sqrt(2.0) * frameMeanError)
            << "oas for " << vertices << " vertices: mean " << meanOas << ", hash mean " << mean1
            << ", hash frame standard error " << frameMeanError;
        for (float v : o) ASSERT_TRUE(std::isfinite(v));
    }
}

TEST(Smallpt, PathDimensionsFollowThePairLayout)
{
    // Bose over GF(7) has 8 dims a block: pairs at even columns (0,1) ... (6,7), so the layout
    // needs no gaps: 2 + 8 vertices x 6 = 50. Bose-Bush 32 has 9 (the 9th column cannot pair):
    // each block's column 8 is skipped by a pair, giving more.
    EXPECT_EQ(smallpt::pathDimensions(makePattern(OAS_BOSE, 49)), 50u);
    EXPECT_GT(smallpt::pathDimensions(makePattern(OAS_BOSE_BUSH, 32)), 50u);
    EXPECT_EQ(smallpt::pathDimensions(makePattern(OAS_RANDOM, 16)), 50u);
    // The first vertices only: none; the camera's pair; the camera and one bounce (2 + 6); and
    // every vertex, the default.
    const OasPattern bose49 = makePattern(OAS_BOSE, 49);
    EXPECT_EQ(smallpt::pathDimensions(bose49, 0), 0u);
    EXPECT_EQ(smallpt::pathDimensions(bose49, 1), 2u);
    EXPECT_EQ(smallpt::pathDimensions(bose49, 2), 8u);
    EXPECT_EQ(smallpt::pathDimensions(bose49, smallpt::kPathVertices), 50u);
    EXPECT_THROW(smallpt::pathDimensions(bose49, smallpt::kPathVertices + 1), std::invalid_argument);
}

TEST(Smallpt, DrawBlocksCountsTheBlocksOfTheWidestDraw)
{
    // Bose 49, blocks of 8: the third vertex's draw is dims [14, 20), across the block start 16.
    EXPECT_EQ(smallpt::drawBlocks(makePattern(OAS_BOSE, 49)), 2u);
    // Bose 4, blocks of 3 whose only pair is columns (0, 1): the first vertex's light pair moves
    // from 2 to the next block's 3, its bounce from 5 to 6, so its draw is [2, 10): blocks 0-3.
    EXPECT_EQ(smallpt::drawBlocks(makePattern(OAS_BOSE, 4)), 4u);
    EXPECT_EQ(smallpt::drawBlocks(makePattern(OAS_RANDOM, 16)), 1u);  // no blocks
}

TEST(Smallpt, PrefetchGroupsCutBlocksEvenly)
{
    // Bose 49: blocks of 8 columns, one group each; 50 dims = 6 blocks and 2 columns of a 7th.
    const OasPattern bose49 = makePattern(OAS_BOSE, 49), bose64 = makePattern(OAS_BOSE, 64);
    EXPECT_EQ(smallpt::prefetchWidth(bose49, 50), 8u);
    EXPECT_EQ(smallpt::prefetchGroups(bose49, 50), 7u);
    // Bose 64: blocks of 9 columns as groups of 5 and 4, not 8 and 1; 55 dims = 6 blocks and 1.
    EXPECT_EQ(smallpt::prefetchWidth(bose64, 55), 5u);
    EXPECT_EQ(smallpt::prefetchGroups(bose64, 55), 13u);
    // 8 dims, fewer than a block's 9: one group of 8.
    EXPECT_EQ(smallpt::prefetchWidth(bose64, 8), 8u);
    EXPECT_EQ(smallpt::prefetchGroups(bose64, 8), 1u);
    // A baseline has no blocks: runs of 8.
    EXPECT_EQ(smallpt::prefetchGroups(makePattern(OAS_RANDOM, 16), 50), 7u);
}

}  // namespace
