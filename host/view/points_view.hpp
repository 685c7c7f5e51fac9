#pragma once
// What oas-view's points mode draws, as pure functions of the points (testable without a window):
// the 2D projection of two dimensions as small anti-aliased discs, with the strata the
// construction promises drawn under them, a frame with ticks at 0, 1/2 and 1 on both axes, the
// projection's power spectrum beside it, and labels naming the sampler, spp, offset and
// dimension pair (in the picture, so that screenshots say what they show).
#include <cstdint>
#include <string>
#include <vector>

#include "oas/pattern.hpp"
#include "view/presenter.hpp"

namespace oas::view {

/// The stratification a pattern promises for the projection onto dimensions (a, b).
struct StrataPromise {
    std::uint32_t grid = 0;       ///< s: every s x s cell holds N / s^2 points (0: no promise)
    bool latinHypercube = false;  ///< each axis's N strata hold one point each (MJ / CMJ offsets)
    std::string what;             ///< one line for the title
};
/// OA constructions only: the same block (d / blockDims) and strength >= 2 give the s x s grid
/// (Bose, Bush, Bose-Bush, Addelman-Kempthorne, CMJND); MJ and CMJ offsets give every dimension the
/// N-strata Latin hypercube. Pairs across blocks are independent: no promise.
StrataPromise strataPromise(const Pattern& pattern, std::uint32_t a, std::uint32_t b);

/// Side of the square projection panel for N points: the largest multiple of N not above 768
/// (so that every one of the N strata, and so every one of the s cells, is a whole number of
/// pixels), or 768 when N > 768.
std::uint32_t panelSize(std::uint32_t n);

/// Pixel column of coordinate v in [0, 1) on a panel of `size` pixels: floor(v * size), exact for
/// floats (v has a 24-bit fraction). Rows count from the top, so y maps to size - 1 - pixel(y).
std::uint32_t pixelOf(float v, std::uint32_t size);

/// Colours of the points view (tests look for them).
constexpr std::uint8_t kPointRgb[3] = {255, 255, 255};
constexpr std::uint8_t kGridRgb[3] = {40, 70, 140};
constexpr std::uint8_t kTickRgb[3] = {150, 110, 40};
constexpr std::uint8_t kFrameRgb[3] = {170, 170, 170};
constexpr std::uint8_t kTextRgb[3] = {230, 230, 230};
constexpr std::uint8_t kBackgroundRgb[3] = {24, 24, 24};

/// Radius in pixels of a point's disc: a fifth of the mean spacing of n points on a panel of
/// `size` pixels, at least 1.25 (still a disc, not a pixel) and at most 3.5.
double pointRadius(std::uint32_t n, std::uint32_t size);

/// The projection panel: black, the promised s x s grid lines, the N Latin-hypercube strata as
/// ticks along the left and bottom edges (when N <= size / 3, so that they stay apart), then each
/// point as an anti-aliased white disc of pointRadius(n, size) centred on its exact position (on
/// top; the pixel holding the centre is fully white).
Frame drawProjection(const std::vector<float>& xs, const std::vector<float>& ys, std::uint32_t size, const StrataPromise& promise,
                     std::uint32_t n);

/// The power spectrum (addPeriodogram's (2 radius + 1)^2 values, DC in the middle) as a grey
/// image of `size` x `size` pixels, log scale from 0.01 to 10 times the power of independent points
/// (1), the DC term black.
Frame drawSpectrum(const std::vector<double>& power, int radius, std::uint32_t size);

/// The spectrum shows wavenumbers kx, ky in -kSpectrumRadius .. kSpectrumRadius.
constexpr int kSpectrumRadius = 32;

/// Where the points view puts its parts. The picture's size depends on the spectrum's radius
/// only, so the window keeps its size when the + and - keys change the count.
struct PointsLayout {
    std::uint32_t width = 0, height = 0;              ///< the whole picture (the window)
    std::uint32_t panelX = 0, panelY = 0, panel = 0;  ///< the projection: top-left corner and side
    std::uint32_t spectrumX = 0, spectrumY = 0, spectrum = 0;
    std::uint32_t textScale = 2;  ///< labels: stb_easy_font's glyphs at this integer scale
};
/// The panel is panelSize(n); the spectrum a whole number of pixels per wavenumber, about 600.
PointsLayout pointsLayout(std::uint32_t n, int radius);

/// What the labels say (composed by the caller, which knows the request).
struct PointsLabels {
    std::string header;                   ///< above the panels: sampler, spp, offset and dimension pair
    std::string detail;                   ///< second line: the construction and the strata it promises
    std::string xAxis, yAxis;             ///< under the x axis; up the y axis
    std::string spectrum, spectrumScale;  ///< under the spectrum
};

/// The whole points view: the labels, the projection panel in its frame with ticks and tick
/// labels at 0, 1/2 and 1, and the framed spectrum, on a dark grey background.
Frame drawPointsView(const std::vector<float>& xs, const std::vector<float>& ys, const StrataPromise& promise, std::uint32_t n,
                     const std::vector<double>& power, int radius, const PointsLabels& labels);

/// Integer-zoomed copy (nearest neighbour).
Frame zoomed(const Frame& f, std::uint32_t zoom);

}  // namespace oas::view
