// The periodogram of a 2D point set (see periodogram.hpp).
#include "oas/periodogram.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace oas {

namespace {

/// exp(-2 pi i k x) for k = -r..r into re/im[k + r]. The phase is reduced as frac(k x) before
/// scaling by 2 pi: x is a float (24-bit fraction), so k x and its fractional part are exact in
/// double and the phase error stays at one rounding however large k is. Negative k take the exact
/// conjugate, so that P(-k) == P(k) bit for bit (real points have a Hermitian transform).
void phasors(double x, int r, double* re, double* im)
{
    re[r] = 1.0;
    im[r] = 0.0;
    for (int k = 1; k <= r; ++k) {
        const double t = double(k) * x;
        const double a = 2.0 * std::numbers::pi * (t - std::floor(t));
        re[r + k] = std::cos(a);
        im[r + k] = -std::sin(a);
        re[r - k] = re[r + k];
        im[r - k] = -im[r + k];
    }
}

}  // namespace

void addPeriodogram(const float* xs, const float* ys, std::uint32_t n, int radius, std::vector<double>& acc)
{
    if (radius < 0) throw std::invalid_argument("addPeriodogram: radius " + std::to_string(radius) + " < 0");
    const size_t W = size_t(2 * radius + 1);
    if (acc.size() != W * W) throw std::invalid_argument("addPeriodogram: acc must hold (2 radius + 1)^2 values");
    if (n == 0) return;
    std::vector<double> xr(size_t(n) * W), xi(size_t(n) * W), yr(size_t(n) * W), yi(size_t(n) * W);
    std::vector<double> sr(W * W, 0.0), si(W * W, 0.0);
    for (std::uint32_t j = 0; j < n; ++j) {
        phasors(xs[j], radius, &xr[size_t(j) * W], &xi[size_t(j) * W]);
        phasors(ys[j], radius, &yr[size_t(j) * W], &yi[size_t(j) * W]);
    }
    // S(k) = sum_j e^{-2 pi i kx x_j} e^{-2 pi i ky y_j}: one rank-1 update of the (ky, kx) grid
    // per point, (2r+1)^2 n complex multiply-adds in all (a direct transform; an FFT would need the
    // points binned, which the exact phases avoid).
    for (std::uint32_t j = 0; j < n; ++j) {
        const double* ar = &xr[size_t(j) * W];
        const double* ai = &xi[size_t(j) * W];
        for (size_t ky = 0; ky < W; ++ky) {
            const double br = yr[size_t(j) * W + ky], bi = yi[size_t(j) * W + ky];
            double* rr = &sr[ky * W];
            double* ri = &si[ky * W];
            for (size_t kx = 0; kx < W; ++kx) {
                rr[kx] += ar[kx] * br - ai[kx] * bi;
                ri[kx] += ar[kx] * bi + ai[kx] * br;
            }
        }
    }
    for (size_t c = 0; c < W * W; ++c) acc[c] += (sr[c] * sr[c] + si[c] * si[c]) / n;
}

}  // namespace oas
