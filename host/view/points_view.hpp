#pragma once
// What oas-view's points mode draws, as pure functions of the points (testable without a window):
// the 2D projection of two dimensions with the strata the construction promises drawn under it,
// and the projection's power spectrum beside it.
#include <cstdint>
#include <string>
#include <vector>

#include "oas/pattern.hpp"
#include "view/presenter.hpp"

namespace oas::view {

/// The stratification a pattern promises for the projection onto dimensions (a, b).
struct StrataPromise {
    std::uint32_t grid = 0;    ///< s: every s x s cell holds N / s^2 points (0: no promise)
    bool latinHypercube = false;  ///< each axis's N strata hold one point each (MJ / CMJ offsets)
    std::string what;          ///< one line for the title
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

/// Colours of the points panel (tests look for them).
constexpr std::uint8_t kPointRgb[3] = {255, 255, 255};
constexpr std::uint8_t kGridRgb[3] = {40, 70, 140};
constexpr std::uint8_t kTickRgb[3] = {150, 110, 40};

/// The projection panel: black, the promised s x s grid lines, the N Latin-hypercube strata as
/// ticks along the left and bottom edges (when N <= size / 3, so that they stay apart), then one
/// white pixel per point (on top).
Frame drawProjection(const std::vector<float>& xs, const std::vector<float>& ys, std::uint32_t size,
                     const StrataPromise& promise, std::uint32_t n);

/// The power spectrum (addPeriodogram's (2 radius + 1)^2 values, DC in the middle) as a grey
/// image of `size` x `size` pixels, log scale from 0.01 to 10 times the power of independent points
/// (1), the DC term black.
Frame drawSpectrum(const std::vector<double>& power, int radius, std::uint32_t size);

/// a and b side by side with a gap of `gap` dark pixels; the height is the taller one's.
Frame sideBySide(const Frame& a, const Frame& b, std::uint32_t gap);

/// Integer-zoomed copy (nearest neighbour).
Frame zoomed(const Frame& f, std::uint32_t zoom);

}  // namespace oas::view
