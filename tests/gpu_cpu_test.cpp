// GPU == CPU bit for bit: every sampler and offset over a grid of sizes, many pixels (including
// coordinates up to 16383), every dimension across several OA blocks, and sample indices past N
// (further passes). The CPU side runs the same GLSL source compiled as C++.
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "gpu_test_support.hpp"
#include "oas/generate_gpu.hpp"
#include "oas/pattern.hpp"
#include "test_cases.hpp"

namespace {

using oas::test::GpuTest;

using Case = oas::test::SamplerCase;

std::vector<Case> oaCases()
{
    return {{"bose", 4, 0},
            {"bose", 9, 0},
            {"bose", 16, 0},
            {"bose", 64, 0},
            {"bose", 81, 0},
            {"bose", 121, 0},
            {"bose", 256, 0},
            {"bush", 27, 3},
            {"bush", 64, 3},
            {"bush", 256, 4},
            {"bush", 125, 3},
            {"bush", 49, 2},
            {"bose-bush", 8, 0},
            {"bose-bush", 32, 0},
            {"bose-bush", 128, 0},
            {"addelman-kempthorne", 18, 0},
            {"addelman-kempthorne", 50, 0},
            {"addelman-kempthorne", 162, 0},
            {"cmjnd", 8, 3},
            {"cmjnd", 81, 4},
            {"cmjnd", 25, 2},
            {"cmjnd", 32, 5}};
}

void expectBitIdentical(const std::vector<float>& cpu, const std::vector<float>& gpu, const std::string& what)
{
    ASSERT_EQ(cpu.size(), gpu.size());
    std::size_t mismatches = 0, first = cpu.size();
    for (std::size_t i = 0; i < cpu.size(); ++i) {
        std::uint32_t a, b;
        std::memcpy(&a, &cpu[i], 4);
        std::memcpy(&b, &gpu[i], 4);
        if (a != b) {
            if (first == cpu.size()) first = i;
            ++mismatches;
        }
    }
    EXPECT_EQ(mismatches, 0u) << what << ": first mismatch at " << first << " cpu " << cpu[first] << " gpu "
                              << (first < gpu.size() ? gpu[first] : 0.0f);
}

void compare(oas::GpuGenerator& gpu, const oas::Pattern& pattern, const oas::SampleRequest& r, const std::string& what)
{
    const std::size_t n = std::size_t(r.width) * r.height * r.spp * r.dims;
    std::vector<float> a(n), b(n, -1.0f);
    oas::generateCpu(pattern, r, a.data());
    gpu.generate(pattern, r, b.data());
    expectBitIdentical(a, b, what);
}

/// One generator for the whole file: its specialised pipelines compile once (seconds each on
/// lavapipe with validation), not once per test.
class GpuCpu : public GpuTest {
protected:
    oas::GpuGenerator& generator()
    {
        static std::unique_ptr<oas::GpuGenerator> shared;
        if (!shared) shared = std::make_unique<oas::GpuGenerator>(context());
        return *shared;
    }
};

TEST_F(GpuCpu, EveryOrthogonalArrayAndOffset)
{
    oas::GpuGenerator& gpu = generator();
    for (const Case& c : oaCases()) {
        for (const char* offset : {"centered", "j", "mj", "cmj"}) {
            const oas::Pattern pattern = oas::test::patternOf(c, offset);
            oas::SampleRequest r;
            r.width = 3;
            r.height = 2;
            r.x0 = c.spp % 2 ? 16381 : 5;  // pixel coordinates up to 16383
            r.y0 = c.spp % 3 ? 16382 : 0;
            r.spp = pattern.N + pattern.N / 2;                                // indices past N: a second pass
            r.dims = std::min<std::uint32_t>(2 * pattern.blockDims + 3, 64);  // several blocks
            r.seed = c.spp * 7919u;
            compare(gpu, pattern, r, std::string(c.sampler) + " " + std::to_string(c.spp) + " " + offset);
        }
    }
}

TEST_F(GpuCpu, EveryBaseline)
{
    oas::GpuGenerator& gpu = generator();
    std::vector<std::string> baselines;  // every baseline the library names, so a new one is covered
    for (const auto& name : oas::samplerNames())
        if (!oas::isOrthogonalArray(name) && name != "faure") baselines.push_back(name);  // faure: its own test below
    ASSERT_EQ(baselines.size(), 8u);
    for (const std::string& sampler : baselines) {
        for (std::uint32_t spp : {1u, 7u, 64u, 100u, 1024u}) {
            oas::PatternRequest req;
            req.sampler = sampler;
            req.spp = spp;
            const oas::Pattern pattern = oas::makePattern(req);
            oas::SampleRequest r;
            r.width = 4;
            r.height = 3;
            r.x0 = 16380;
            r.y0 = 16381;
            r.spp = spp + 3;
            r.dims = 70;  // past Halton's 32-dim block
            r.seed = 0xffffffffu - spp;
            compare(gpu, pattern, r, std::string(sampler) + " " + std::to_string(spp));
        }
    }
}

TEST_F(GpuCpu, FaureInEveryKindOfBase)
{
    // The progressive sampler over a prime base (2, 3, 11), GF(2^k) (4, 8) and GF(3^2) (9), with
    // prefixes (spp below N = q^K), whole sequences and indices past N (a second pass), and
    // dimensions over several blocks of d.
    oas::GpuGenerator& gpu = generator();
    const struct {
        std::uint32_t d, spp;
    } cases[] = {{2, 100}, {3, 27}, {4, 40}, {7, 64}, {9, 81}, {10, 121}, {10, 1000}};
    for (const auto& c : cases) {
        const oas::Pattern pattern = oas::test::faurePattern(c.spp, c.d);
        oas::SampleRequest r;
        r.width = 3;
        r.height = 2;
        r.x0 = 7;
        r.spp = pattern.N + 5;
        r.dims = 2 * c.d + 3;
        r.seed = 11u * c.spp;
        compare(gpu, pattern, r, oas::describe(pattern));
    }
}

TEST_F(GpuCpu, Padded2dRunsCrossPassesChunksAndAnOddLastDimension)
{
    // The padded 2D baselines run like the OAs on the GPU: runs of samples x one pair, the pair's
    // state once per pass. Runs here cross pass ends (N = 100 or 128, runs of 128 starting at
    // firstSample), chunk seams fall inside runs' groups, the last pair has one dimension (7
    // dims), and the last indices reach 2^32 - 1.
    oas::GpuGenerator& gpu = generator();
    for (const char* sampler : {"jittered2d", "cmj2d", "zerotwo", "random"}) {  // random: runs too, its 7 dims one group
        oas::PatternRequest req;
        req.sampler = sampler;
        req.spp = std::string(sampler) == "zerotwo" ? 128 : 100;
        const oas::Pattern pattern = oas::makePattern(req);
        for (std::uint32_t firstSample : {0u, 250u, 0xffffffffu - 299u}) {
            oas::SampleRequest r;
            r.width = 5;
            r.height = 3;
            r.x0 = 7;
            r.y0 = 16383;
            r.firstSample = firstSample;
            r.spp = 300;
            r.dims = 7;
            r.seed = 0x9e3779b9u ^ firstSample;
            gpu.setMaxPointsPerDispatch(1001);
            compare(gpu, pattern, r,
                    std::string(sampler) + " from sample " + std::to_string(firstSample) + ", 1001-point chunks");
            gpu.setMaxPointsPerDispatch(0);
            compare(gpu, pattern, r, std::string(sampler) + " from sample " + std::to_string(firstSample));
        }
    }
}

TEST_F(GpuCpu, BaselinesMakeTheDimensionsReadAndLeaveTheUnreadAsTheyWere)
{
    // SampleRequest::unreadDims: a baseline makes the dimensions read, each bit for bit the CPU's,
    // in groups over the made dimensions only (so dims past 32, which are always made, move to
    // other groups), and leaves the unread elements of the device buffer as an earlier request of
    // the same size wrote them: the work is skipped, not made and dropped (the padded 2D baselines
    // skip the pairs of two unread dimensions). blue_spheres9d's plan
    // ({5, 10, 11} of 12 unread), one gap among 40 dims, and every dimension below 32 unread.
    oas::GpuGenerator& gpu = generator();
    const struct {
        std::uint32_t dims, unread;
    } masks[] = {{12, (1u << 5) | (1u << 10) | (1u << 11)}, {40, 1u << 3}, {40, ~0u}, {7, 0x7eu}};
    std::vector<std::string> baselines;
    for (const auto& name : oas::samplerNames())
        if (!oas::isOrthogonalArray(name) && name != "faure") baselines.push_back(name);
    for (const std::string& sampler : baselines) {
        oas::PatternRequest req;
        req.sampler = sampler;
        req.spp = 64;
        const oas::Pattern pattern = oas::makePattern(req);
        const bool padded = sampler == "jittered2d" || sampler == "cmj2d" || sampler == "zerotwo";
        for (const auto& m : masks) {
            oas::SampleRequest all;
            all.width = 3;
            all.height = 2;
            all.spp = 100;  // a second pass
            all.dims = m.dims;
            all.seed = 17;
            oas::SampleRequest some = all;
            some.seed = 18;
            some.unreadDims = m.unread;
            const std::size_t n = std::size_t(all.width) * all.height * all.spp * all.dims;
            std::vector<float> before(n), cpu(n), gpuValues(n);
            gpu.generate(pattern, all, before.data());
            oas::generateCpu(pattern, some, cpu.data());
            gpu.generate(pattern, some, gpuValues.data());
            std::size_t wrong = 0;
            for (std::size_t i = 0; i < n; ++i) {
                const std::uint32_t dim = std::uint32_t(i % all.dims);
                // The padded 2D baselines make a pair whole where either dimension is read.
                const std::uint32_t pairMask = 3u << (dim & ~1u);
                const std::uint32_t unreadOrAbsent = m.dims >= 32 ? m.unread : m.unread | ~((1u << m.dims) - 1u);
                const bool unread = dim < 32 && (padded ? (unreadOrAbsent & pairMask) == pairMask : (m.unread >> dim) & 1u);
                const float expected = unread ? before[i] : cpu[i];
                if (std::memcmp(&expected, &gpuValues[i], 4) != 0) ++wrong;
            }
            EXPECT_EQ(wrong, 0u) << sampler << ", " << m.dims << " dims, unread 0x" << std::hex << m.unread;
        }
    }
}

TEST_F(GpuCpu, SobolReadsTheWholeDirectionTableAndCrossesItsBlock)
{
    // EveryBaseline's 70 dims stay inside Sobol's 1024-dim block: here every dimension of the
    // Joe-Kuo table (the whole storage buffer) and the first of the next block, on the GPU.
    oas::GpuGenerator& gpu = generator();
    for (std::uint32_t spp : {16u, 7u}) {  // a power of two, and one whose later blocks permute 7
        oas::PatternRequest req;
        req.sampler = "sobol";
        req.spp = spp;
        const oas::Pattern pattern = oas::makePattern(req);
        oas::SampleRequest r;
        r.width = 2;
        r.height = 1;
        r.x0 = 16382;
        r.y0 = 9;
        r.spp = spp + 3;
        r.dims = pattern.blockDims + 6;
        r.seed = 12345u + spp;
        compare(gpu, pattern, r, "sobol " + std::to_string(spp) + " x " + std::to_string(r.dims) + " dims");
    }
}

TEST_F(GpuCpu, ManyPixelsInSeveralDispatchChunks)
{
    oas::GpuGenerator& gpu = generator();
    oas::PatternRequest req;
    req.sampler = "bose";
    req.spp = 121;
    const oas::Pattern pattern = oas::makePattern(req);
    oas::SampleRequest r;
    r.width = 40;
    r.height = 30;
    r.spp = 121;
    r.dims = 29;  // three blocks of 12 columns, the last partial; 8-dim groups straddle blocks
    r.seed = 1;
    // 1001 points per dispatch: chunks of 7 runs of 121 samples, seams at odd work-item offsets.
    gpu.setMaxPointsPerDispatch(1001);
    compare(gpu, pattern, r, "bose 121 x 1200 pixels x 29 dims in 1001-point chunks");
    // The default chunking of the same request must agree too.
    gpu.setMaxPointsPerDispatch(0);
    compare(gpu, pattern, r, "bose 121 x 1200 pixels x 29 dims, device-limit chunks");
}

TEST_F(GpuCpu, HardCasesLargestFieldsLastIndicesEdgeSeeds)
{
    oas::GpuGenerator& gpu = generator();
    for (const oas::test::SamplerCase& c : oas::test::hardCases()) {
        for (const char* offset : {"centered", "j", "mj", "cmj"}) {
            const oas::Pattern pattern = oas::test::patternOf(c, offset);
            for (std::uint32_t seed : {0u, 1u, 0xffffffffu, 0u - pattern.N}) {
                oas::SampleRequest r;
                r.x0 = 16382;
                r.y0 = 16383;
                r.width = 2;
                r.height = 1;
                r.firstSample = pattern.N - 20;  // the last indices and the first of the next pass
                r.spp = 40;
                r.dims = std::min<std::uint32_t>(pattern.blockDims, 48) + 2;
                r.seed = seed;
                compare(gpu, pattern, r, oas::describe(pattern) + " seed " + std::to_string(seed));
            }
        }
    }
}

TEST_F(GpuCpu, LargestBoseFullSetOnTheGpu)
{
    // All 2^24 points of Bose q = 4096 in 2 dims, generated on the GPU: a 2^24-strata Latin
    // hypercube in each dimension (the finest strata the fixed point expresses) and equal to the CPU.
    oas::GpuGenerator& gpu = generator();
    oas::PatternRequest req;
    req.sampler = "bose";
    req.spp = 4096u * 4096u;
    const oas::Pattern pattern = oas::makePattern(req);
    oas::SampleRequest r;
    r.spp = pattern.N;
    r.dims = 2;
    r.seed = 0xffffffffu;
    compare(gpu, pattern, r, "bose q=4096 all 2^24 points");
}

}  // namespace
