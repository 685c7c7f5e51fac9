#include "render/accumulation.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace oas::render {
namespace {

/// A pixel's sums from its words and back: channel c's lo, mid, hi are words 3c, 3c + 1, 3c + 2
/// (PT_SUM_WORDS' layout; pt_render.comp reads and writes the same words).
pt::PtSum loadSum(const std::uint32_t* p)
{
    pt::PtSum s;
    s.lo = {p[0], p[3], p[6]};
    s.mid = {p[1], p[4], p[7]};
    s.hi = {p[2], p[5], p[8]};
    return s;
}

void storeSum(std::uint32_t* p, const pt::PtSum& s)
{
    for (int c = 0; c < 3; ++c) {
        p[3 * c] = s.lo[c];
        p[3 * c + 1] = s.mid[c];
        p[3 * c + 2] = s.hi[c];
    }
}

}  // namespace

Accumulation::Accumulation(std::uint32_t w, std::uint32_t h) : width(w), height(h), words(std::size_t(w) * h * kSumWords, 0u) {}

void Accumulation::addToPixel(std::size_t i, glm::uvec3 lo, glm::uvec3 mid, glm::uvec3 hi, std::uint32_t samples,
                              std::uint32_t rejected)
{
    pt::PtSum sum;
    sum.lo = lo;
    sum.mid = mid;
    sum.hi = hi;
    std::uint32_t* p = pixel(i);
    storeSum(p, pt::pt_sum_add(loadSum(p), sum));
    p[pt::PT_SUM_COUNT_WORD] += samples;
    p[pt::PT_SUM_REJECTED_WORD] += rejected;
}

Accumulation Accumulation::window(std::uint32_t x0, std::uint32_t y0, std::uint32_t w, std::uint32_t h) const
{
    if (std::uint64_t(x0) + w > width || std::uint64_t(y0) + h > height)
        throw std::invalid_argument("Accumulation::window: outside the " + std::to_string(width) + "x" + std::to_string(height) +
                                    " image");
    Accumulation out(w, h);
    for (std::uint32_t y = 0; y < h; ++y)
        std::copy_n(pixel(std::size_t(y0 + y) * width + x0), std::size_t(w) * kSumWords, out.pixel(std::size_t(y) * w));
    return out;
}

void Accumulation::add(const Accumulation& other)
{
    if (other.width != width || other.height != height || other.words.size() != words.size())
        throw std::invalid_argument("cannot add a " + std::to_string(other.width) + "x" + std::to_string(other.height) +
                                    " accumulation to a " + std::to_string(width) + "x" + std::to_string(height) + " one");
    constexpr std::uint32_t kMax = std::numeric_limits<std::uint32_t>::max();
    for (std::size_t i = 0; i < pixelCount(); ++i)
        if (samples(i) > kMax - other.samples(i))
            throw std::overflow_error("pixel " + std::to_string(i % width) + "," + std::to_string(i / width) +
                                      " would hold more than 2^32 - 1 samples");
    for (std::size_t i = 0; i < pixelCount(); ++i) {
        const std::uint32_t* q = other.pixel(i);
        const pt::PtSum s = loadSum(q);
        addToPixel(i, s.lo, s.mid, s.hi, q[pt::PT_SUM_COUNT_WORD], q[pt::PT_SUM_REJECTED_WORD]);
    }
}

std::uint64_t Accumulation::rejectedSamples() const
{
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < pixelCount(); ++i) total += rejected(i);
    return total;
}

double sumValue(const std::uint32_t* p, int c)
{
    return double(p[3 * c + 2]) * 4294967296.0 + double(p[3 * c + 1]) + double(p[3 * c]) * (1.0 / 4294967296.0);
}

float meanValue(const std::uint32_t* p, int c)
{
    const std::uint32_t n = p[pt::PT_SUM_COUNT_WORD];
    return n == 0 ? 0.0f : float(sumValue(p, c) / double(n));
}

image::Image Accumulation::image() const
{
    image::Image out(width, height, 0.0f, 0.0f, 0.0f, 1.0f);
    for (std::size_t i = 0; i < pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) out.rgba[i * 4 + c] = meanValue(pixel(i), c);
    return out;
}

}  // namespace oas::render
