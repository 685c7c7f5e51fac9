// The OAS_MULHI hook: this file compiles the GLSL library with OAS_MULHI = oas_mulhi_portable (the
// 16-bit-limb product a target without umulExtended would use), and every sample must equal the
// default build's (oas::sample, compiled with umulExtended in generate_cpu.cpp) bit for bit.
#define OAS_MULHI oas_mulhi_portable
#include <gtest/gtest.h>

#include <cstring>

#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"
#include "test_cases.hpp"

namespace {

TEST(MulHiHook, PortableMulHiGivesTheSameSamples)
{
    std::vector<oas::test::SamplerCase> cases = oas::test::hardCases();
    for (const char* name : {"bose", "random", "jittered2d", "cmj2d", "zerotwo", "halton", "sobol", "sobol-owen", "sobol-burley"})
        cases.push_back({name, 121, 0});
    std::size_t compared = 0;
    for (const auto& c : cases) {
        for (const char* offset : {"j", "cmj"}) {
            const oas::Pattern pattern = oas::test::patternOf(c, offset);
            const auto pat = oas::glsl::toGlsl(pattern);
            for (std::uint32_t seed : {0u, 0x9e3779b9u, 0xffffffffu})
                for (std::uint32_t index : {0u, 1u, pattern.N / 2, pattern.N - 1, pattern.N, 0xffffffffu})
                    for (std::uint32_t dim = 0; dim < 6; ++dim) {
                        const float hooked = oas::glsl::oas_sample(pat, seed, index, dim);
                        const float reference = oas::sample(pattern, seed, index, dim);
                        ASSERT_EQ(0, std::memcmp(&hooked, &reference, sizeof(float)))
                            << oas::describe(pattern) << " seed " << seed << " index " << index << " dim " << dim;
                        ++compared;
                    }
        }
    }
    EXPECT_GT(compared, 1000u);
}

}  // namespace
