#pragma once
// A render's exact per-pixel sums (shaders/pt/pt_accumulate.glsl): what the GPU kernel and the CPU
// reference tracer add samples into, what a shard file stores, and what oas-merge adds. Because
// the sums are integers, adding accumulations is associative: any split of a frame's samples,
// rendered anywhere and added in any order, gives the words of the one-process render.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.hpp"

// The GLSL compiled as C++, as glsl_compat.hpp does for the sampler library: in an anonymous
// namespace, so that every file including this gets private copies of the (non-inline) functions.
// Host APIs therefore take GLM vectors, not PtSum.
namespace oas::pt {
namespace {
using glm::uvec3;
using glm::vec3;
using uint = std::uint32_t;
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include "pt/pt_accumulate.glsl"
#pragma GCC diagnostic pop
}  // namespace
}  // namespace oas::pt

namespace oas::render {

/// Words per pixel (PT_SUM_WORDS): R, G, B as 96-bit fixed point (3 words each, low first, 32
/// fractional bits), samples taken, samples rejected (NaN, infinite, negative or >= 2^64), spare.
constexpr std::uint32_t kSumWords = pt::PT_SUM_WORDS;

struct Accumulation {
    std::uint32_t width = 0, height = 0;
    std::vector<std::uint32_t> words;  ///< width * height * kSumWords, row-major, top row first

    Accumulation() = default;
    /// An all-zero accumulation (throws std::bad_alloc when it cannot be held).
    Accumulation(std::uint32_t w, std::uint32_t h);

    std::size_t pixelCount() const { return std::size_t(width) * height; }
    std::uint32_t* pixel(std::size_t i) { return words.data() + i * kSumWords; }
    const std::uint32_t* pixel(std::size_t i) const { return words.data() + i * kSumWords; }
    std::uint32_t samples(std::size_t i) const { return pixel(i)[pt::PT_SUM_COUNT_WORD]; }
    std::uint32_t rejected(std::size_t i) const { return pixel(i)[pt::PT_SUM_REJECTED_WORD]; }

    /// Adds a PtSum's words (lo, mid, hi), samples taken and samples rejected to pixel i (exact).
    void addToPixel(std::size_t i, glm::uvec3 lo, glm::uvec3 mid, glm::uvec3 hi, std::uint32_t samples, std::uint32_t rejected);
    /// Adds another accumulation of the same size, pixel by pixel (exact). Throws
    /// std::invalid_argument for another size, std::overflow_error when a pixel's sample count
    /// would pass 2^32 - 1 (the sums hold 2^32 samples of up to 2^64 each).
    void add(const Accumulation& other);
    /// The sums of the width x height pixels whose top-left one is (x0, y0) (within this image).
    Accumulation window(std::uint32_t x0, std::uint32_t y0, std::uint32_t w, std::uint32_t h) const;
    /// Samples rejected over the image.
    std::uint64_t rejectedSamples() const;

    /// The mean radiance per pixel (meanValue; alpha 1; pixels with no samples stay black): equal
    /// words give equal pixels on any IEEE machine.
    image::Image image() const;
};

/// Channel c's sum of a pixel's words as a double: its three words scaled by 2^32, 1 and 2^-32,
/// added in that order.
double sumValue(const std::uint32_t* pixelWords, int channel);
/// Channel c's mean of a pixel's words (0 without samples): float(sumValue / samples), the value
/// Accumulation::image() holds.
float meanValue(const std::uint32_t* pixelWords, int channel);

}  // namespace oas::render
