// The library adds no loop iterations to its includer's shader. Lavapipe (Mesa 22.3) ends an
// invocation's loops after 65535 iterations in all, silently, counting every iteration of every
// loop the compiler did not unroll; a renderer that loops over a pixel's samples in one invocation
// then got wrong values once the library's own loops added up (from ~430 values unspecialised, and
// even specialised over GF(2^5), GF(5^2), GF(3^4)). Every library loop now has a compile-time trip
// count and is marked [[unroll]].
//
// For every construction x field kind x offset and every baseline (Sobol with its direction
// numbers), at small and at the largest q each construction allows, this runs
// tests/shaders/one_invocation_per_pixel.comp, built unspecialised and specialised, with 16
// pixels x at least 4096 values per invocation, through oas_sample and through the hoisted
// OasBlock/OasColumn API, and compares every value with the CPU twin bit for bit. Before each
// run it calibrates the shader's own burn loop so that only a few spare iterations remain: a
// single library loop left in, anywhere, would end the sampling loops early.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "gpu_test_support.hpp"
#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"
#include "one_invocation_per_pixel_spv.h"
#include "one_invocation_per_pixel_specialized_spv.h"

namespace {

class LoopFree : public oas::test::GpuTest {};

struct Push {
    oas::Pattern pattern;
    std::uint32_t spp, dims, dimBase, mode, burn;
};

constexpr std::uint32_t kPixels = 16;          // two lavapipe SIMD groups of 8
constexpr std::uint32_t kMinValues = 4096;     // per invocation
constexpr std::uint32_t kSpareIterations = 8;  // left between the burn and the cap

struct Case {
    const char* sampler;
    std::uint32_t spp, strength;
    const char* field;  // what the case covers, for the failure message
};

// Small and largest fields of every kind each construction takes (N <= 2^24; odd extension
// fields up to the largest whose digit slots fit a word, see oas_gf_slots_fit).
const std::vector<Case>& oaCases()
{
    static const std::vector<Case> cases = {
        {"bose", 121, 0, "prime 11"},
        {"bose", 16752649, 0, "prime 4093 (largest)"},
        {"bose", 64, 0, "GF(2^3)"},
        {"bose", 1024, 0, "GF(2^5)"},
        {"bose", 16777216, 0, "GF(2^12) (largest)"},
        {"bose", 81, 0, "GF(3^2)"},
        {"bose", 59049, 0, "GF(3^5) (largest p = 3)"},
        {"bose", 625, 0, "GF(5^2)"},
        {"bose", 390625, 0, "GF(5^4) (largest p = 5)"},
        {"bose", 13845841, 0, "GF(61^2) (largest odd extension)"},
        {"bush", 125, 3, "prime 5, t = 3"},
        {"bush", 16752649, 2, "prime 4093, t = 2"},
        {"bush", 16777216, 8, "GF(2^3), t = 8 (largest t)"},
        {"bush", 4096, 3, "GF(2^4), t = 3"},
        {"bush", 729, 3, "GF(3^2), t = 3"},
        {"bush", 14348907, 3, "GF(3^5), t = 3"},
        {"bush", 15625, 3, "GF(5^2), t = 3"},
        {"bose-bush", 8, 0, "GF(2^2) over q = 2"},
        {"bose-bush", 128, 0, "GF(2^4) over q = 8"},
        {"bose-bush", 8388608, 0, "GF(2^12) over q = 2048 (largest)"},
        {"addelman-kempthorne", 18, 0, "prime 3"},
        {"addelman-kempthorne", 16669538, 0, "prime 2887 (largest)"},
        {"addelman-kempthorne", 162, 0, "GF(3^2)"},
        {"addelman-kempthorne", 118098, 0, "GF(3^5)"},
        {"addelman-kempthorne", 1250, 0, "GF(5^2)"},
        {"addelman-kempthorne", 781250, 0, "GF(5^4)"},
        {"addelman-kempthorne", 15780962, 0, "GF(53^2) (largest odd extension)"},
        {"cmjnd", 256, 4, "s = 4, d = 4"},
        {"cmjnd", 16777216, 24, "s = 2, d = 24 (most digits)"},
        {"cmjnd", 16777216, 2, "s = 4096, d = 2"},
    };
    return cases;
}

const std::vector<Case>& baselineCases()
{
    static const std::vector<Case> cases = {
        {"random", 4096, 0, ""}, {"jittered2d", 1000, 0, ""},  {"cmj2d", 16777213, 0, "prime N"},
        {"cmj2d", 256, 0, ""},   {"zerotwo", 16777216, 0, ""}, {"halton", 16777216, 0, "24 base-2 digits"},
        {"halton", 100, 0, ""},  {"sobol", 16777216, 0, ""},   {"sobol", 121, 0, ""},
        {"sobol-owen", 16777216, 0, ""}, {"sobol-burley", 16777216, 0, ""}, {"sobol-burley", 121, 0, ""},
    };
    return cases;
}

class Runner {
public:
    explicit Runner(oas::vk::Context& ctx) : ctx_(ctx), directions_(ctx, oas::sobolDirections().size() * sizeof(std::uint32_t))
    {
        std::memcpy(directions_.data(), oas::sobolDirections().data(), oas::sobolDirections().size() * sizeof(std::uint32_t));
    }

    /// The CPU twin's values for every pixel, sample and dimension of a run, [pixel][sample][dim].
    static std::vector<float> expectedValues(const oas::Pattern& pattern, std::uint32_t dims, std::uint32_t dimBase)
    {
        const std::uint32_t spp = samplesFor(dims);
        const auto glslPattern = oas::glsl::toGlsl(pattern);
        std::vector<float> expected(std::size_t(kPixels) * spp * dims);
        for (std::uint32_t p = 0; p < kPixels; ++p)
            for (std::uint32_t i = 0; i < spp; ++i)
                for (std::uint32_t d = 0; d < dims; ++d)
                    expected[(std::size_t(p) * spp + i) * dims + d] =
                        oas::glsl::oas_sample(glslPattern, oas::glsl::oas_pixel_seed(p, 7u, 0x5eedu), i, dimBase + d);
        return expected;
    }

    static std::uint32_t samplesFor(std::uint32_t dims) { return (kMinValues + dims - 1) / dims; }

    /// Runs one case against `expected` (expectedValues); returns "" or the first mismatch.
    std::string run(const oas::Pattern& pattern, bool specialized, std::uint32_t mode, std::uint32_t dims, std::uint32_t dimBase,
                    const std::vector<float>& expected)
    {
        const std::uint32_t spp = samplesFor(dims);
        oas::vk::Buffer samples(ctx_, (expected.size() + kPixels) * sizeof(float));
        Push push{pattern, spp, dims, dimBase, mode, 0};

        // Calibrate: the largest burn with which the same loops, without the library, still finish.
        // The loops' trip counts depend on the shape only (and, for the hoisted API, on N's passes).
        const CalibrationKey calibrationKey{specialized, mode, spp, dims, mode == 0 ? 0u : pattern.N};
        auto known = burns_.find(calibrationKey);
        if (known == burns_.end())
            known =
                burns_
                    .emplace(calibrationKey, largestBurn(pipeline(pattern, specialized, true), samples, push, spp, dims, dimBase))
                    .first;
        const std::uint32_t burn = known->second;
        if (burn < kSpareIterations) return "calibration found no burn that lets the loops finish";
        push.burn = burn - kSpareIterations;
        const std::size_t mismatch = dispatch(pipeline(pattern, specialized, false), samples, push, &expected);
        if (mismatch == expected.size()) return "";
        return "first mismatch at value " + std::to_string(mismatch) + " (pixel " + std::to_string(mismatch / (spp * dims)) +
               ", sample " + std::to_string((mismatch / dims) % spp) + ", dim " + std::to_string(dimBase + mismatch % dims) +
               "), burn " + std::to_string(push.burn) + " of a calibrated " + std::to_string(burn);
    }

private:
    using Key = std::tuple<bool, bool, std::uint32_t, std::uint32_t, std::uint32_t>;
    using CalibrationKey = std::tuple<bool, std::uint32_t, std::uint32_t, std::uint32_t, std::uint32_t>;

    oas::vk::ComputePipeline& pipeline(const oas::Pattern& pattern, bool specialized, bool calibrate)
    {
        // Calibration runs no library code, so one pipeline per build serves every pattern.
        // This shader is specialised on the first three (it leaves the field degree and the size of
        // N to run time).
        const auto kind =
            specialized && !calibrate ? oas::specializationKey(pattern) : decltype(oas::specializationKey(pattern)){};
        const Key key{specialized, calibrate, std::get<0>(kind), std::get<1>(kind), std::get<2>(kind)};
        auto found = pipelines_.find(key);
        if (found != pipelines_.end()) return found->second;
        oas::vk::ComputePipeline::SpecConstants constants = {{3, calibrate ? 1u : 0u}};
        if (specialized && !calibrate)
            for (std::uint32_t id : {0u, 1u, 2u})
                constants.push_back({id, id == 0 ? std::get<0>(kind) : id == 1 ? std::get<1>(kind) : std::get<2>(kind)});
        const std::uint32_t* code = specialized ? one_invocation_per_pixel_specialized_spv : one_invocation_per_pixel_spv;
        const std::size_t bytes =
            specialized ? sizeof(one_invocation_per_pixel_specialized_spv) : sizeof(one_invocation_per_pixel_spv);
        return pipelines_.try_emplace(key, ctx_, code, bytes, 2, sizeof(Push), constants).first->second;
    }

    /// Dispatches and returns the index of the first value that differs from `expected`, or
    /// expected->size() when all agree.
    std::size_t dispatch(oas::vk::ComputePipeline& pipe, oas::vk::Buffer& samples, const Push& push,
                         const std::vector<float>* expected)
    {
        std::memset(samples.data(), 0xff, samples.size());  // NaN until written
        oas::vk::Buffer* buffers[] = {&samples, &directions_};
        ctx_.dispatch(pipe, buffers, &push, sizeof(push), kPixels / 8);
        const auto* got = static_cast<const float*>(samples.data());
        for (std::size_t k = 0; k < expected->size(); ++k)
            if (std::memcmp(&got[k], &(*expected)[k], sizeof(float)) != 0) return k;
        return expected->size();
    }

    std::uint32_t largestBurn(oas::vk::ComputePipeline& pipe, oas::vk::Buffer& samples, Push push, std::uint32_t spp,
                              std::uint32_t dims, std::uint32_t dimBase)
    {
        std::vector<float> standIn(std::size_t(kPixels) * spp * dims);
        for (std::uint32_t p = 0; p < kPixels; ++p) {
            const std::uint32_t seed = oas::glsl::oas_pixel_seed(p, 7u, 0x5eedu);
            for (std::uint32_t i = 0; i < spp; ++i)
                for (std::uint32_t d = 0; d < dims; ++d)
                    standIn[(std::size_t(p) * spp + i) * dims + d] =
                        float(oas::glsl::oas_hash3(seed, i, dimBase + d) >> 8u) * oas::glsl::OAS_INV_2POW24;
        }
        std::uint32_t good = 0, bad = 65536;  // burn 0 must finish; 65536 cannot
        push.burn = 0;
        if (dispatch(pipe, samples, push, &standIn) != standIn.size()) return 0;
        while (bad - good > 1) {
            push.burn = good + (bad - good) / 2;
            (dispatch(pipe, samples, push, &standIn) == standIn.size() ? good : bad) = push.burn;
        }
        return good;
    }

    oas::vk::Context& ctx_;
    oas::vk::Buffer directions_;
    std::map<Key, oas::vk::ComputePipeline> pipelines_;
    std::map<CalibrationKey, std::uint32_t> burns_;
};

oas::Pattern makePattern(const Case& c, const char* offset)
{
    oas::PatternRequest request;
    request.sampler = c.sampler;
    request.spp = c.spp;
    request.strength = c.strength;
    request.offset = offset;
    return oas::makePattern(request);
}

/// Every offset of every case of the given constructions, both builds, both APIs.
void checkConstructions(oas::vk::Context& ctx, const std::vector<std::string>& samplers)
{
    Runner runner(ctx);
    for (const Case& c : oaCases()) {
        if (std::find(samplers.begin(), samplers.end(), c.sampler) == samplers.end()) continue;
        for (const char* offset : {"centered", "j", "mj", "cmj"}) {
            const oas::Pattern pattern = makePattern(c, offset);
            // 8 dimensions from the start (partner pairs, several blocks when blocks are small),
            // and the last 8 columns of the first block (Bush's leading coefficient, AK's
            // quadratic columns, the highest field elements).
            const std::uint32_t dims = 8;
            for (std::uint32_t dimBase : {0u, pattern.blockDims > dims ? pattern.blockDims - dims : 0u}) {
                const std::vector<float> expected = Runner::expectedValues(pattern, dims, dimBase);
                for (bool specialized : {false, true})
                    for (std::uint32_t mode : {0u, 1u}) {
                        const std::string failure = runner.run(pattern, specialized, mode, dims, dimBase, expected);
                        EXPECT_EQ(failure, "")
                            << oas::describe(pattern) << " [" << c.field << "], dims " << dimBase << ".." << dimBase + dims - 1
                            << (specialized ? ", specialised" : ", unspecialised") << (mode ? ", hoisted API" : ", oas_sample");
                    }
                if (pattern.blockDims <= dims) break;
            }
        }
    }
}

// Two halves of similar cost, so that ctest can run them side by side.
TEST_F(LoopFree, BoseBoseBushAndCmjndInOneInvocation)
{
    checkConstructions(context(), {"bose", "bose-bush", "cmjnd"});
}

TEST_F(LoopFree, BushAndAddelmanKempthorneInOneInvocation)
{
    checkConstructions(context(), {"bush", "addelman-kempthorne"});
}

TEST_F(LoopFree, EveryBaselineInOneInvocation)
{
    Runner runner(context());
    for (const Case& c : baselineCases()) {
        const oas::Pattern pattern = makePattern(c, "cmj");
        // 12 dimensions from 0 and from just below the Halton and Sobol block ends (block 1 shuffles
        // its indices, block 0 does not).
        for (std::uint32_t dimBase : {0u, 26u, 1018u}) {
            const std::vector<float> expected = Runner::expectedValues(pattern, 12, dimBase);
            for (bool specialized : {false, true}) {
                const std::string failure = runner.run(pattern, specialized, 0, 12, dimBase, expected);
                EXPECT_EQ(failure, "") << oas::describe(pattern) << " " << c.field << ", dims from " << dimBase
                                       << (specialized ? ", specialised" : ", unspecialised");
            }
        }
    }
}

}  // namespace
