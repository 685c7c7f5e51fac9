// oas_draw (shaders/oas/oas_draw.glsl), the library's one call for a group of dimensions of one
// sample, checked on the CPU twin (the same GLSL compiled as C++): every value equals oas_sample
// bit for bit, for every construction, field kind, offset and baseline, over seeds, sample
// indices past N (further passes), groups that start anywhere in a block and cross into the next
// blocks, and every count 0..OAS_DRAW_MAX; the entries past the count are 0. The GPU runs the
// same code: the tracer's GPU-vs-CPU tests (RenderGpu.*, GoldenGpu.*) and LoopFree.* cover it there.
#include <gtest/gtest.h>

#include <bit>
#include <set>
#include <string>
#include <vector>

#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"
#include "test_cases.hpp"

namespace {

using oas::glsl::OAS_DRAW_MAX;

std::vector<oas::Pattern> everyPattern()
{
    std::vector<oas::Pattern> patterns;
    for (const auto& c : oas::test::oaCases())
        for (const char* offset : {"centered", "j", "mj", "cmj"}) patterns.push_back(oas::test::patternOf(c, offset));
    const std::vector<std::pair<const char*, std::uint32_t>> baselines = {
        {"random", 4096},      {"jittered2d", 1000}, {"cmj2d", 256},       {"cmj2d", 16777213}, {"zerotwo", 64},
        {"zerotwo", 16777216}, {"halton", 100},      {"halton", 16777216}, {"sobol", 121},      {"sobol", 16777216},
        {"sobol-owen", 121},   {"sobol-burley", 121}, {"sobol-burley", 16777216}};
    for (const auto& [sampler, spp] : baselines) {
        oas::PatternRequest r;
        r.sampler = sampler;
        r.spp = spp;
        patterns.push_back(oas::makePattern(r));
    }
    return patterns;
}

/// First dimensions: block starts and ends (groups that cross one or more blocks), and far ones.
std::vector<std::uint32_t> firstDims(const oas::Pattern& p)
{
    std::set<std::uint32_t> dims = {0u, 1u, 5u, 37u, 1000u};
    if (p.construction < oas::glsl::OAS_RANDOM) {
        const std::uint32_t b = p.blockDims;
        for (std::uint32_t d : {b - 1, b > 2 ? b - 3 : 0u, b, b + 1, 2 * b - 2, 3 * b - 1, 7 * b + b / 2}) dims.insert(d);
    }
    return {dims.begin(), dims.end()};
}

TEST(Draw, EqualsOasSampleBitForBitForEveryPatternAndZeroBeyondTheCount)
{
    std::size_t values = 0;
    const auto patterns = everyPattern();
    for (const oas::Pattern& pattern : patterns) {
        const auto p = oas::glsl::toGlsl(pattern);
        const std::vector<std::uint32_t> indices = {
            0u, 1u, pattern.N - 1, pattern.N, pattern.N + 3, 2 * pattern.N + 1, 0xfffffffeu, 0xffffffffu};
        for (std::uint32_t seed : {0u, 0x9e3779b9u, oas::glsl::oas_pixel_seed(16383u, 5u, 42u)}) {
            for (std::uint32_t index : indices) {
                for (std::uint32_t first : firstDims(pattern)) {
                    for (std::uint32_t count = 0; count <= OAS_DRAW_MAX; ++count) {
                        const oas::glsl::OasDraw d = oas::glsl::oas_draw(p, seed, index, first, count);
                        for (std::uint32_t k = 0; k < OAS_DRAW_MAX; ++k) {
                            const float expected = k < count ? oas::glsl::oas_sample(p, seed, index, first + k) : 0.0f;
                            ASSERT_EQ(std::bit_cast<std::uint32_t>(d.u[k]), std::bit_cast<std::uint32_t>(expected))
                                << oas::describe(pattern) << " seed " << seed << " index " << index << " first " << first
                                << " count " << count << " k " << k;
                        }
                        values += count;
                    }
                }
            }
        }
    }
    EXPECT_GE(patterns.size(), 4u * oas::test::oaCases().size() + 10);
    EXPECT_GT(values, 1000000u);
}

TEST(Draw, GroupsCrossEveryBlockBoundaryOfSmallBlocks)
{
    // Small blocks (3 dimensions: Bose over q = 2) put up to four blocks in one group of eight:
    // every start within a block, every count, a run of samples through two passes.
    oas::PatternRequest r;
    r.sampler = "bose";
    r.spp = 4;
    const oas::Pattern pattern = oas::makePattern(r);
    ASSERT_EQ(pattern.blockDims, 3u);
    const auto p = oas::glsl::toGlsl(pattern);
    for (std::uint32_t index = 0; index < 2 * pattern.N; ++index)
        for (std::uint32_t first = 0; first < 4 * pattern.blockDims; ++first)
            for (std::uint32_t count = 0; count <= OAS_DRAW_MAX; ++count) {
                const oas::glsl::OasDraw d = oas::glsl::oas_draw(p, 77u, index, first, count);
                for (std::uint32_t k = 0; k < OAS_DRAW_MAX; ++k)
                    ASSERT_EQ(std::bit_cast<std::uint32_t>(d.u[k]),
                              std::bit_cast<std::uint32_t>(k < count ? oas::glsl::oas_sample(p, 77u, index, first + k) : 0.0f))
                        << "index " << index << " first " << first << " count " << count << " k " << k;
            }
}

}  // namespace
