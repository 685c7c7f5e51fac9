#pragma once
// The periodogram of a 2D point set: the power spectrum Jarosz et al. 2019 (and Heck et al. 2013,
// "Blue Noise Sampling with Controlled Aliasing") use to read sample patterns. It sits below both
// of its users: the study averages it over randomizations (study/spectrum.hpp), oas-view shows it
// for the points the GPU made.
#include <cstdint>
#include <vector>

namespace oas {

/// Adds the periodogram |sum_j exp(-2 pi i k.x_j)|^2 / n of the n points x_j = (xs[j], ys[j]) to
/// acc, for every integer k in [-radius, radius]^2. acc holds (2 radius + 1)^2 values, row-major
/// (ky from -radius outer, kx inner); the DC term is included. Throws std::invalid_argument for
/// radius < 0 or acc of another size.
void addPeriodogram(const float* xs, const float* ys, std::uint32_t n, int radius, std::vector<double>& acc);

}  // namespace oas
