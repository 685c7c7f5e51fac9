#include "view/points_view.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "view/text.hpp"

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

void fill(Frame& f, std::uint32_t x0, std::uint32_t y0, std::uint32_t w, std::uint32_t h, const std::uint8_t* rgb)
{
    for (std::uint32_t y = y0; y < y0 + h; ++y)
        for (std::uint32_t x = x0; x < x0 + w; ++x) put(f, x, y, rgb);
}

/// A one-pixel rectangle just outside the w x h area at (x, y).
void frameAround(Frame& f, std::uint32_t x, std::uint32_t y, std::uint32_t w, std::uint32_t h)
{
    fill(f, x - 1, y - 1, w + 2, 1, kFrameRgb);
    fill(f, x - 1, y + h, w + 2, 1, kFrameRgb);
    fill(f, x - 1, y - 1, 1, h + 2, kFrameRgb);
    fill(f, x + w, y - 1, 1, h + 2, kFrameRgb);
}

/// Blends `rgb` over the pixel with weight `coverage` in [0, 1].
void blend(Frame& f, int x, int y, const std::uint8_t* rgb, double coverage)
{
    if (x < 0 || y < 0 || x >= int(f.width) || y >= int(f.height) || coverage <= 0) return;
    std::uint8_t* p = f.at(std::uint32_t(x), std::uint32_t(y));
    const double c = std::min(coverage, 1.0);
    for (int i = 0; i < 3; ++i) p[i] = std::uint8_t(std::lround(p[i] + (rgb[i] - p[i]) * c));
}

/// A disc of radius r centred at (cx, cy) in pixel units (pixel (x, y) spans [x, x + 1)): each
/// pixel's coverage is approximated by how far its centre lies inside the circle, over one pixel.
void disc(Frame& f, double cx, double cy, double r, const std::uint8_t* rgb)
{
    for (int y = int(std::floor(cy - r - 1)); y <= int(std::ceil(cy + r + 1)); ++y)
        for (int x = int(std::floor(cx - r - 1)); x <= int(std::ceil(cx + r + 1)); ++x) {
            const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
            blend(f, x, y, rgb, r + 0.5 - d);
        }
}

/// The text scale that fits `text` in `room` pixels: `scale`, or 1 when that is too wide.
std::uint32_t fitting(const std::string& text, std::uint32_t scale, std::uint32_t room)
{
    return textWidth(text, scale) <= room ? scale : 1;
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
                 std::to_string(pattern.s) + " strata, " + std::to_string(pattern.N / (pattern.s * pattern.s)) + " point(s) each";
    } else {
        p.what = a == b ? "the same dimension twice"
                        : "blocks " + std::to_string(a / pattern.blockDims) + " and " + std::to_string(b / pattern.blockDims) +
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

Frame drawProjection(const std::vector<float>& xs, const std::vector<float>& ys, std::uint32_t size, const StrataPromise& promise,
                     std::uint32_t n)
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
    // Centred on the exact position (pixelOf's pixel holds it: floor(v * size)); y up.
    const double r = pointRadius(n, size);
    const std::size_t count = std::min(xs.size(), ys.size());
    for (std::size_t i = 0; i < count; ++i) disc(f, double(xs[i]) * size, size - double(ys[i]) * size, r, kPointRgb);
    return f;
}

double pointRadius(std::uint32_t n, std::uint32_t size)
{
    const double spacing = size / std::sqrt(double(std::max(n, 1u)));
    return std::clamp(spacing / 5, 1.25, 3.5);
}

Frame drawSpectrum(const std::vector<double>& power, int radius, std::uint32_t size)
{
    const std::uint32_t w = std::uint32_t(2 * radius + 1);
    if (power.size() != std::size_t(w) * w) throw std::invalid_argument("drawSpectrum: power has the wrong size");
    Frame f;
    f.resize(size, size, 0);
    for (std::uint32_t y = 0; y < size; ++y)
        for (std::uint32_t x = 0; x < size; ++x) {
            const std::uint32_t kx = x * w / size, ky = (size - 1 - y) * w / size;     // ky up
            if (kx == std::uint32_t(radius) && ky == std::uint32_t(radius)) continue;  // DC: black
            const double p = power[std::size_t(ky) * w + kx];
            const double t = std::clamp((std::log10(std::max(p, 1e-300)) + 2.0) / 3.0, 0.0, 1.0);  // 0.01 .. 10
            const std::uint8_t g = std::uint8_t(std::lround(255 * t));
            std::uint8_t* px = f.at(x, y);
            px[0] = px[1] = px[2] = g;
        }
    return f;
}

PointsLayout pointsLayout(std::uint32_t n, int radius)
{
    // Margins: two label lines above; tick labels and the rotated y-axis name on the left; tick
    // labels, the x-axis name and the spectrum's two lines below.
    constexpr std::uint32_t kLeft = 84, kTop = 72, kGap = 56, kRight = 16, kBottom = 64;
    const std::uint32_t cells = std::uint32_t(2 * radius + 1);
    PointsLayout l;
    l.panel = panelSize(n);
    l.panelX = kLeft;
    l.panelY = kTop;
    l.spectrum = cells * std::max(1u, 600 / cells);
    l.spectrumX = kLeft + l.panel + kGap;
    l.spectrumY = kTop;
    l.width = kLeft + kMaxPanel + kGap + l.spectrum + kRight;
    l.height = kTop + kMaxPanel + kBottom;
    return l;
}

Frame drawPointsView(const std::vector<float>& xs, const std::vector<float>& ys, const StrataPromise& promise, std::uint32_t n,
                     const std::vector<double>& power, int radius, const PointsLabels& labels)
{
    const PointsLayout l = pointsLayout(n, radius);
    const std::uint32_t s = l.textScale, line = textHeight(s);
    Frame f;
    f.resize(l.width, l.height);
    fill(f, 0, 0, l.width, l.height, kBackgroundRgb);

    const Frame panel = drawProjection(xs, ys, l.panel, promise, n);
    for (std::uint32_t y = 0; y < panel.height; ++y)
        std::copy_n(panel.at(0, y), std::size_t(panel.width) * 3, f.at(l.panelX, l.panelY + y));
    frameAround(f, l.panelX, l.panelY, l.panel, l.panel);
    const Frame spectrum = drawSpectrum(power, radius, l.spectrum);
    for (std::uint32_t y = 0; y < spectrum.height; ++y)
        std::copy_n(spectrum.at(0, y), std::size_t(spectrum.width) * 3, f.at(l.spectrumX, l.spectrumY + y));
    frameAround(f, l.spectrumX, l.spectrumY, l.spectrum, l.spectrum);

    // Ticks at 0, 1/2 and 1 outside the frame (0 and 1 on the frame's lines), labelled.
    constexpr std::uint32_t kTick = 6, kPad = 4;
    const char* names[3] = {"0", "1/2", "1"};
    const std::uint32_t bottom = l.panelY + l.panel, left = l.panelX - 1;
    for (std::uint32_t i = 0; i < 3; ++i) {
        // The frame's lines stand for 0 and 1; 1/2 is the line between the two middle halves.
        const std::uint32_t x = i == 0 ? left : i == 1 ? l.panelX + l.panel / 2 : l.panelX + l.panel;
        const std::uint32_t y = i == 0 ? bottom : i == 1 ? l.panelY + l.panel / 2 : l.panelY - 1;
        fill(f, x, bottom, 1, kTick + 1, kFrameRgb);        // x axis, downwards
        fill(f, left - kTick, y, kTick + 1, 1, kFrameRgb);  // y axis, leftwards
        const std::uint32_t w = textWidth(names[i], s);
        drawText(f, int(x) - int(w / 2), int(bottom + kTick + kPad), names[i], kTextRgb, s);
        drawText(f, int(left - kTick - kPad - w), int(y) - int(line / 2), names[i], kTextRgb, s);
    }
    const std::uint32_t xName = textWidth(labels.xAxis, s), yName = textWidth(labels.yAxis, s);
    drawText(f, int(l.panelX + l.panel / 2 - xName / 2), int(bottom + kTick + kPad + line + kPad + 2), labels.xAxis, kTextRgb, s);
    drawText(f, int(left - kTick - kPad - textWidth("1/2", s) - 3 * kPad - line), int(l.panelY + l.panel / 2 + yName / 2),
             labels.yAxis, kTextRgb, s, /*upward=*/true);

    // The two header lines span the window; the spectrum's lines go under it.
    const std::uint32_t room = l.width - 2 * kPad;
    drawText(f, int(kPad + 8), 10, labels.header, kTextRgb, fitting(labels.header, s, room - 8));
    drawText(f, int(kPad + 8), int(10 + line + 8), labels.detail, kTextRgb, fitting(labels.detail, s, room - 8));
    const std::uint32_t spectrumRoom = l.width - l.spectrumX - kPad;
    const std::uint32_t below = l.spectrumY + l.spectrum + kTick + kPad;
    drawText(f, int(l.spectrumX), int(below), labels.spectrum, kTextRgb, fitting(labels.spectrum, s, spectrumRoom));
    drawText(f, int(l.spectrumX), int(below + line + 8), labels.spectrumScale, kTextRgb,
             fitting(labels.spectrumScale, s, spectrumRoom));
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
