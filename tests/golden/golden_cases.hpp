#pragma once
// The requests behind tests/golden/patterns.json: every construction and baseline, every offset,
// each kind of field (prime, GF(2^k), odd extension), the shapes that change the value choices
// (a prime N for the 2D grids, AK over GF(9), Bose-Bush's GF(2q)), and the sample indices and
// dimensions that cross a pass and a block. Shared by the writer and the tests.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace oas::golden {

struct Case {
    std::string sampler;
    std::uint32_t spp;
    std::uint32_t strength;  ///< 0: the sampler's default (as PatternRequest)
    std::string offset;
    std::uint32_t dims;  ///< PatternRequest::dims (only CMJND's default strength reads it)
};

inline const std::vector<Case>& cases()
{
    static const std::vector<Case> list = {
        {"bose", 4, 0, "cmj", 3},
        {"bose", 9, 0, "centered", 4},
        {"bose", 9, 0, "j", 4},
        {"bose", 9, 0, "mj", 4},
        {"bose", 9, 0, "cmj", 4},
        {"bose", 16, 0, "cmj", 5},
        {"bose", 49, 0, "cmj", 8},
        {"bose", 64, 0, "mj", 9},
        {"bose", 81, 0, "cmj", 10},
        {"bose", 121, 0, "cmj", 12},
        {"bush", 27, 3, "j", 4},
        {"bush", 64, 3, "cmj", 5},
        {"bush", 125, 3, "cmj", 6},
        {"bush", 256, 4, "mj", 5},
        {"bose-bush", 8, 0, "cmj", 5},
        {"bose-bush", 32, 0, "cmj", 9},
        {"bose-bush", 128, 0, "centered", 17},
        {"addelman-kempthorne", 18, 0, "cmj", 7},
        {"addelman-kempthorne", 50, 0, "mj", 11},
        {"addelman-kempthorne", 98, 0, "cmj", 15},
        {"addelman-kempthorne", 162, 0, "cmj", 19},
        {"cmjnd", 9, 2, "cmj", 2},
        {"cmjnd", 27, 3, "cmj", 3},
        {"cmjnd", 16, 4, "j", 4},
        {"cmjnd", 32, 5, "centered", 5},
        {"random", 7, 0, "cmj", 3},
        {"jittered2d", 12, 0, "cmj", 4},
        {"jittered2d", 7, 0, "cmj", 2},
        {"jittered2d", 16, 0, "cmj", 3},
        {"cmj2d", 12, 0, "cmj", 4},
        {"cmj2d", 16, 0, "cmj", 2},
        {"zerotwo", 16, 0, "cmj", 3},
        {"zerotwo", 10, 0, "cmj", 3},
        {"halton", 16, 0, "cmj", 3},
        {"sobol", 16, 0, "cmj", 3},
        {"sobol", 10, 0, "cmj", 3},
        {"sobol-owen", 16, 0, "cmj", 3},
        {"sobol-owen", 10, 0, "cmj", 3},
        {"sobol-burley", 16, 0, "cmj", 3},
        {"sobol-burley", 10, 0, "cmj", 3},
        {"faure", 4, 0, "cmj", 2},     // base 2 (the C API's default d = 2), a whole sequence
        {"faure", 27, 3, "cmj", 4},    // base 3, d = 3 of 4 dims: a second block
        {"faure", 10, 4, "cmj", 4},    // GF(2^2), N = 16 > spp: a prefix
        {"faure", 81, 9, "cmj", 9},    // GF(3^2)
        {"faure", 100, 0, "cmj", 10},  // the C++ default d = dims: base 11, N = 121
    };
    return list;
}

/// The pixel every case samples: oas_pixel_seed(x, y, seed).
constexpr std::uint32_t kPixelX = 3, kPixelY = 5, kSeed = 7;

/// The first min(size, few) of [0, size), then size and size + 1: the start of the next pass
/// (for sample indices, size = N) or of the next block (for dimensions, size = blockDims).
inline std::vector<std::uint32_t> firstFewThenNext(std::uint32_t size, std::uint32_t few)
{
    std::vector<std::uint32_t> out;
    for (std::uint32_t i = 0; i < std::min(size, few); ++i) out.push_back(i);
    out.push_back(size);
    out.push_back(size + 1);
    return out;
}
/// Sample indices: five of pass 0, then two of pass 1 (a fresh randomization).
inline std::vector<std::uint32_t> indicesFor(std::uint32_t N)
{
    return firstFewThenNext(N, 5);
}
/// Dimensions: four of block 0, then two of block 1 (an independent block).
inline std::vector<std::uint32_t> dimsFor(std::uint32_t blockDims)
{
    return firstFewThenNext(blockDims, 4);
}

}  // namespace oas::golden
