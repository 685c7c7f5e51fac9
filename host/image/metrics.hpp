#pragma once
// Error metrics of a rendered image against a reference, and a false-colour error image.
//
// All metrics are over the R, G, B channels (alpha is ignored), averaged over pixels and channels:
//   MSE    = mean (I - R)^2
//   relMSE = mean (I - R)^2 / (R^2 + eps)      (relative MSE, as in Rousselle et al. and in
//                                               Jarosz et al. 2019, "Orthogonal Array Sampling")
//   RMSE   = sqrt(MSE)
// eps (relEpsilon, default 1e-2) keeps near-black reference values from dominating relMSE: where
// R^2 >> eps the term is the squared relative error, where R ~ 0 it is (I - R)^2 / eps. Sums are
// in double; a NaN or infinity in either image makes the affected metrics NaN or infinite.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "image/image.hpp"

namespace oas::image {

/// A rectangle of pixels: columns x .. x+w-1, rows y .. y+h-1 (row 0 is the top row).
struct Crop {
    std::uint32_t x = 0, y = 0, w = 0, h = 0;
};

struct ErrorMetrics {
    double mse = 0, relMse = 0, rmse = 0;
    std::uint64_t pixels = 0;  ///< pixels compared (each contributes 3 channel terms)
};

/// Pixels whose R, G or B is NaN or infinite: how many, and the first few (x, y) in scan order.
struct NonFinitePixels {
    std::uint64_t count = 0;
    std::vector<std::array<std::uint32_t, 2>> first;
};
NonFinitePixels findNonFinite(const Image& image, std::size_t keep = 5);
/// "3 pixels hold NaN or infinite values, first at (1, 2) (4, 0) ...": for messages.
std::string describeNonFinite(const Image& image, const NonFinitePixels& bad);

/// Compares `image` with `reference` over the whole image or `crop`. Throws std::invalid_argument
/// naming the sizes when the images differ in size or are empty, when the crop is empty or not
/// inside the image, or when relEpsilon is not a finite positive number.
ErrorMetrics compare(const Image& image, const Image& reference, std::optional<Crop> crop = {}, double relEpsilon = 1e-2);

/// Per-pixel relative squared error, mean over R, G, B of (I - R)^2 / (R^2 + relEpsilon), shown
/// on a log scale: t = (log10 e - log10 minError) / (log10 maxError - log10 minError), clamped to
/// [0, 1] (so e <= minError, zero included, is the ramp's darkest colour and e >= maxError its
/// brightest). With the defaults the ramp spans 6 decades, 1e-5 .. 10, one sixth per decade.
struct FalseColourOptions {
    double relEpsilon = 1e-2;
    double minError = 1e-5;
    double maxError = 10;
};

/// The colour ramp, linear sRGB, t in [0, 1]: a path through OKLab whose lightness rises linearly
/// (0.18 -> 0.95) while the hue turns from violet through blue, teal and green to yellow, so
/// that order is visible in colour and in lightness alone (it stays readable in greyscale).
/// Colours outside the sRGB gamut are brought in by lowering chroma at constant lightness and hue.
std::array<float, 3> errorRamp(double t);

/// Colour shown for pixels whose error is not finite (NaN or infinity in either image): magenta,
/// which the ramp never produces.
inline constexpr std::array<float, 3> kNonFiniteErrorColour = {1.0f, 0.0f, 1.0f};

/// A linear RGBA image (alpha 1) of the per-pixel error of `image` against `reference` mapped
/// through errorRamp; write it with writePngPreview. Throws std::invalid_argument for mismatched
/// sizes or bad options (minError > 0, maxError > minError, relEpsilon > 0, all finite).
Image falseColourError(const Image& image, const Image& reference, const FalseColourOptions& options = {});

}  // namespace oas::image
