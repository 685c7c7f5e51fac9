// Lavapipe (Mesa 22.3) silently ends an invocation's loops after 65535 iterations in all. With
// the old cycle-walking permutations, one invocation evaluating 121 samples x 12 dims returned
// zeros from sample 33 on, with no validation message. The per-sample path is loop-free now (the
// OA constructions over prime fields, in a shader specialised on the pattern kind), so one
// invocation may evaluate a whole pixel: this runs tests/shaders/one_invocation_per_pixel.comp and
// compares every value with the CPU twin, bit for bit, through the one-shot API and through the
// hoisted OasBlock/OasColumn API. Binary and extension fields, Bush and CMJND keep loops whose
// trip counts the pattern fixes (k, t, d); they are checked at sizes within the bound oas.glsl
// documents. The test can fail: built unspecialised, the same shader got its first wrong value at
// sample 37 (oas_sample) and at dimension 4 of sample 0 (hoisted API, dimension-major).
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "gpu_test_support.hpp"
#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"
#include "one_invocation_per_pixel_spv.h"

namespace {

class LoopCap : public oas::test::GpuTest {};

struct Push {
    oas::Pattern pattern;
    std::uint32_t pixels, spp, dims, mode;
};

TEST_F(LoopCap, OneInvocationEvaluatesAWholePixel)
{
    struct Case {
        const char* sampler;
        std::uint32_t spp, strength, samples, dims;
    };
    // Six passes of Bose 121 (726 samples) x 12 dims is 8712 values per invocation, 22x the
    // point where the cycle walk ran out (sample 33 of 121 x 12 dims).
    const std::vector<Case> cases = {{"bose", 121, 0, 726, 12}, {"bose", 49, 0, 490, 16},
                                     {"bose", 64, 0, 64, 9}, {"bose-bush", 32, 0, 32, 9}, {"bush", 125, 3, 125, 4}};
    oas::vk::Context& ctx = context();
    for (const Case& c : cases) {
        for (const char* offset : {"j", "mj", "cmj"}) {
            if (std::string(offset) != "cmj" && c.spp != 121) continue;  // other offsets: Bose 121 only
            oas::PatternRequest request;
            request.sampler = c.sampler;
            request.spp = c.spp;
            request.strength = c.strength;
            request.dims = c.dims;
            request.offset = offset;
            const oas::Pattern pattern = oas::makePattern(request);
            const auto pat = oas::glsl::toGlsl(pattern);
            const auto key = oas::specializationKey(pattern);
            oas::vk::ComputePipeline pipeline(
                ctx, one_invocation_per_pixel_spv, sizeof(one_invocation_per_pixel_spv), 1, sizeof(Push),
                {{0, std::get<0>(key)}, {1, std::get<1>(key)}, {2, std::get<2>(key)}});
            const std::uint32_t pixels = 16;  // two lavapipe SIMD groups of 8
            std::vector<float> expected(std::size_t(pixels) * c.samples * c.dims);
            for (std::uint32_t p = 0; p < pixels; ++p)
                for (std::uint32_t i = 0; i < c.samples; ++i)
                    for (std::uint32_t d = 0; d < c.dims; ++d)
                        expected[(std::size_t(p) * c.samples + i) * c.dims + d] =
                            oas::glsl::oas_sample(pat, oas::glsl::oas_pixel_seed(p, 7u, 0x5eedu), i, d);
            oas::vk::Buffer buffer(ctx, expected.size() * sizeof(float));
            for (std::uint32_t mode : {0u, 1u}) {
                std::memset(buffer.data(), 0xff, expected.size() * sizeof(float));  // NaN until written
                const Push push{pattern, pixels, c.samples, c.dims, mode};
                oas::vk::Buffer* buffers[] = {&buffer};
                ctx.dispatch(pipeline, buffers, &push, sizeof(push), (pixels + 7) / 8);
                const auto* got = static_cast<const float*>(buffer.data());
                std::size_t mismatches = 0, first = expected.size();
                for (std::size_t k = 0; k < expected.size(); ++k)
                    if (std::memcmp(&got[k], &expected[k], sizeof(float)) != 0 && mismatches++ == 0) first = k;
                EXPECT_EQ(mismatches, 0u) << oas::describe(pattern) << (mode ? ", hoisted API" : ", oas_sample")
                                          << ": first mismatch at value " << first << " (sample "
                                          << (first / c.dims) % c.samples << ", dim " << first % c.dims << ")";
            }
        }
    }
}

}  // namespace
