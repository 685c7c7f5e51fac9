#pragma once
// Parameter sets shared by several test files, so the CPU and GPU suites cover the same cases.
#include <cstdint>
#include <vector>

#include "oas/pattern.hpp"

namespace oas::test {

/// A sampler request: name, spp, strength (0: the sampler's default).
struct SamplerCase {
    const char* sampler;
    std::uint32_t spp, strength;
};

/// The progressive sampler for spp samples with d dimensions a block (its base: the smallest
/// prime power >= d).
inline Pattern faurePattern(std::uint32_t spp, std::uint32_t d)
{
    PatternRequest r;
    r.sampler = "faure";
    r.spp = spp;
    r.strength = d;
    return makePattern(r);
}

/// The numerically hardest patterns: the largest fields and N, GF(2^k) and GF(3^k), s = 2 and 3.
inline std::vector<SamplerCase> hardCases()
{
    return {{"bose", 4093u * 4093u, 0},                      // largest prime q with q^2 <= 2^24
            {"bose", 4096u * 4096u, 0},                      // largest q: GF(2^12), N = 2^24
            {"bose", 3721u * 3721u, 0},                      // GF(61^2): the largest odd extension field
            {"bose", 625u * 625u, 0},                        // GF(5^4): the fullest digit slots (4 x 8 bits)
            {"bush", 256u * 256u * 256u, 3},                 // N = 2^24, GF(2^8), 257 dims
            {"bush", 243u * 243u * 243u, 3},                 // GF(3^5), N = 14348907
            {"bose-bush", 2u * 2048u * 2048u, 0},            // GF(2^12) mapped to q = 2^11
            {"addelman-kempthorne", 2u * 2809u * 2809u, 0},  // GF(53^2), N = 15780962
            {"addelman-kempthorne", 2u * 2197u * 2197u, 0},  // GF(13^3), N = 9653618
            {"addelman-kempthorne", 2u * 2039u * 2039u, 0},  // a large odd prime
            {"cmjnd", 1u << 24, 24},                         // s = 2, d = 24
            {"cmjnd", 14348907u, 15}};                       // s = 3, d = 15
}

/// Every construction over each field kind (prime, GF(2^k), GF(3^k), GF(5^k), odd p^2), small
/// blocks (where a group of 8 crosses several) and the largest cases.
inline std::vector<SamplerCase> oaCases()
{
    std::vector<SamplerCase> cases = {{"bose", 4, 0},
                                                 {"bose", 9, 0},
                                                 {"bose", 64, 0},
                                                 {"bose", 81, 0},
                                                 {"bose", 121, 0},
                                                 {"bose", 625, 0},
                                                 {"bose", 1024, 0},
                                                 {"bush", 9, 2},
                                                 {"bush", 27, 3},
                                                 {"bush", 125, 3},
                                                 {"bush", 4096, 3},
                                                 {"bush", 729, 3},
                                                 {"bush", 15625, 3},
                                                 {"bush", 16777216, 8},
                                                 {"bose-bush", 8, 0},
                                                 {"bose-bush", 128, 0},
                                                 {"addelman-kempthorne", 18, 0},
                                                 {"addelman-kempthorne", 162, 0},
                                                 {"addelman-kempthorne", 1250, 0},
                                                 {"cmjnd", 4, 2},
                                                 {"cmjnd", 8, 3},
                                                 {"cmjnd", 81, 4},
                                                 {"cmjnd", 32, 5}};
    for (const auto& h : hardCases()) cases.push_back(h);
    return cases;
}

/// The pattern of a case with an offset (dims: the strength, or 2).
inline Pattern patternOf(const SamplerCase& c, const char* offset)
{
    PatternRequest r;
    r.sampler = c.sampler;
    r.spp = c.spp;
    r.strength = c.strength;
    r.dims = c.strength ? c.strength : 2;
    r.offset = offset;
    return makePattern(r);
}

/// Integer power (no overflow checks: test sizes only).
inline std::uint32_t ipow(std::uint32_t base, std::uint32_t exponent)
{
    std::uint32_t r = 1;
    while (exponent--) r *= base;
    return r;
}

}  // namespace oas::test
