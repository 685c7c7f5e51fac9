#include "view/points_view.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace oas::view {
namespace {

constexpr std::uint32_t kMaxPanel = 768;
constexpr std::uint32_t kFirstBaseline = 16;  // OAS_RANDOM: constructions below it are OAs

void put(Frame& f, std::uint32_t x, std::uint32_t y, const std::uint8_t* rgb)
{
    if (x >= f.width || y >= f.height) return;
    std::uint8_t* p = f.at(x, y);
    p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2];
}

}  // namespace

StrataPromise strataPromise(const Pattern& pattern, std::uint32_t a, std::uint32_t b)
{
    StrataPromise p;
    if (pattern.construction == 0 || pattern.construction >= kFirstBaseline || pattern.blockDims == 0) {
        p.what = "no OA strata promised for this sampler";
        return p;
    }
    p.latinHypercube = pattern.offset == 2 || pattern.offset == 3;  // OAS_OFFSET_MJ, OAS_OFFSET_CMJ
    const bool sameBlock = a / pattern.blockDims == b / pattern.blockDims && a != b;
    if (sameBlock && pattern.strength >= 2) {
        p.grid = pattern.s;
        p.what = "same block " + std::to_string(a / pattern.blockDims) + ": " + std::to_string(pattern.s) + "x" +
                 std::to_string(pattern.s) + " strata, " + std::to_string(pattern.N / (pattern.s * pattern.s)) +
                 " point(s) each";
    } else {
        p.what = a == b ? "the same dimension twice" : "blocks " + std::to_string(a / pattern.blockDims) + " and " +
                                                          std::to_string(b / pattern.blockDims) +
                                                          ": independent OAs, no joint strata";
    }
    if (p.latinHypercube) p.what += "; " + std::to_string(pattern.N) + " strata per axis";
    return p;
}

std::uint32_t panelSize(std::uint32_t n)
{
    if (n == 0) throw std::invalid_argument("panelSize: no points");
    return n > kMaxPanel ? kMaxPanel : n * (kMaxPanel / n);
}

std::uint32_t pixelOf(float v, std::uint32_t size)
{
    // v = F / 2^24 exactly for our samples (any float in [0, 1) is F / 2^24 up to its own
    // precision, so double arithmetic is exact here).
    const double p = std::floor(double(v) * size);
    return std::uint32_t(std::clamp(p, 0.0, double(size - 1)));
}

Frame drawProjection(const std::vector<float>& xs, const std::vector<float>& ys, std::uint32_t size,
                     const StrataPromise& promise, std::uint32_t n)
{
    Frame f;
    f.resize(size, size, 0);
    if (promise.grid > 1)
        for (std::uint32_t c = 1; c < promise.grid; ++c) {
            const std::uint32_t at = std::uint32_t(std::uint64_t(c) * size / promise.grid);
            for (std::uint32_t t = 0; t < size; ++t) {
                put(f, at, t, kGridRgb);             // vertical line at x = c / s
                put(f, t, size - 1 - at, kGridRgb);  // horizontal line at y = c / s (y up)
            }
        }
    if (promise.latinHypercube && n >= 2 && n * 3 <= size)
        for (std::uint32_t c = 1; c < n; ++c) {
            const std::uint32_t at = std::uint32_t(std::uint64_t(c) * size / n);
            for (std::uint32_t t = 0; t < 4; ++t) {
                put(f, at, size - 1 - t, kTickRgb);  // bottom edge: x strata
                put(f, t, size - 1 - at, kTickRgb);  // left edge: y strata
            }
        }
    const std::size_t count = std::min(xs.size(), ys.size());
    for (std::size_t i = 0; i < count; ++i)
        put(f, pixelOf(xs[i], size), size - 1 - pixelOf(ys[i], size), kPointRgb);
    return f;
}

Frame drawSpectrum(const std::vector<double>& power, int radius, std::uint32_t size)
{
    const std::uint32_t w = std::uint32_t(2 * radius + 1);
    if (power.size() != std::size_t(w) * w) throw std::invalid_argument("drawSpectrum: power has the wrong size");
    Frame f;
    f.resize(size, size, 0);
    for (std::uint32_t y = 0; y < size; ++y)
        for (std::uint32_t x = 0; x < size; ++x) {
            const std::uint32_t kx = x * w / size, ky = (size - 1 - y) * w / size;  // ky up
            if (kx == std::uint32_t(radius) && ky == std::uint32_t(radius)) continue;  // DC: black
            const double p = power[std::size_t(ky) * w + kx];
            const double t = std::clamp((std::log10(std::max(p, 1e-300)) + 2.0) / 3.0, 0.0, 1.0);  // 0.01 .. 10
            const std::uint8_t g = std::uint8_t(std::lround(255 * t));
            std::uint8_t* px = f.at(x, y);
            px[0] = px[1] = px[2] = g;
        }
    return f;
}

Frame sideBySide(const Frame& a, const Frame& b, std::uint32_t gap)
{
    Frame f;
    f.resize(a.width + gap + b.width, std::max(a.height, b.height), 24);
    for (std::uint32_t y = 0; y < a.height; ++y) std::copy_n(a.at(0, y), std::size_t(a.width) * 3, f.at(0, y));
    for (std::uint32_t y = 0; y < b.height; ++y)
        std::copy_n(b.at(0, y), std::size_t(b.width) * 3, f.at(a.width + gap, y));
    return f;
}

Frame zoomed(const Frame& src, std::uint32_t zoom)
{
    if (zoom <= 1) return src;
    Frame f;
    f.resize(src.width * zoom, src.height * zoom);
    for (std::uint32_t y = 0; y < f.height; ++y)
        for (std::uint32_t x = 0; x < f.width; ++x) std::copy_n(src.at(x / zoom, y / zoom), 3, f.at(x, y));
    return f;
}

}  // namespace oas::view
