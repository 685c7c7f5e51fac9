#pragma once
// Averaged power spectra (periodograms) of 2D projections of the samplers: the picture Jarosz et
// al. 2019 use to explain orthogonal-array sampling (and Heck et al. 2013, "Blue Noise Sampling
// with Controlled Aliasing", use to read sample patterns). A strength-2 OA stratifies every 2D
// projection of a block, so its spectrum is dark along the axes (the 1D Latin-hypercube
// projections) and near the origin; pairs across blocks, or random points, stay white (power 1).
#include <cstdint>
#include <string>
#include <vector>

#include "experiment.hpp"
#include "oas/pattern.hpp"
#include "oas/periodogram.hpp"
#include "stats.hpp"

namespace oas::study {

/// Averaged periodogram on the integer frequencies k = (kx, ky) in [-radius, radius]^2.
struct Spectrum {
    int radius = 0;
    /// (2 radius + 1)^2 values, row-major: ky from -radius..radius outer, kx inner. The DC term
    /// (k = 0), which is N for every point set, is stored as 0 so that a colour scale fits the rest.
    std::vector<double> power;

    int width() const { return 2 * radius + 1; }
    double at(int kx, int ky) const { return power[size_t(ky + radius) * size_t(width()) + size_t(kx + radius)]; }
};

/// The periodogram P(k) = |sum_j exp(-2 pi i k.x_j)|^2 / N of the N = pattern.N points
/// x_j = (sample(j, dimA), sample(j, dimB)), averaged over `randomizations` independent
/// randomizations (pixel seeds oas::pixelSeed(i, 0, userSeed), i < randomizations), for every
/// integer k in [-radius, radius]^2; DC set to 0 (see Spectrum). Normalised so that independent
/// uniform points have expectation exactly 1 at every k != 0. Double precision; `threads` workers
/// over randomizations (0: all hardware threads). The result does not depend on `threads`.
/// Throws std::invalid_argument for radius < 0, randomizations == 0 or an empty pattern.
Spectrum powerSpectrum(const oas::Pattern& pattern, std::uint32_t dimA, std::uint32_t dimB, std::uint32_t randomizations,
                       int radius, std::uint32_t userSeed, unsigned threads);

/// Mean power over the frequencies k != 0 with kLow <= |k| < kHigh (Euclidean |k|); 0 if none.
double radialMean(const Spectrum& s, double kLow, double kHigh);
/// Radially averaged power: element b is radialMean(s, b - 0.5, b + 0.5) for b = 0..radius
/// (element 0 is therefore 0: it holds only the zeroed DC term).
std::vector<double> radialProfile(const Spectrum& s);

/// One 2D projection to show: dimensions (a, b) and its name in points.csv / spectra.csv.
struct ProjectionPair {
    std::uint32_t a = 0, b = 0;
    std::string name;  ///< "(a,b)", or "cross-block (0,B)" for the pair (0, first dim of block 1)
};

/// The samplers (labels of studySamplers()) and point counts shown as 2D projections, in order.
std::vector<std::pair<std::string, std::uint32_t>> projectionSamplers();
/// Dimensions the projection patterns are requested with (patternRequest(spec, N, this)).
constexpr std::uint32_t kProjectionDims = 8;
/// User seed of the projections: randomization 0 (pixel (0, 0)) is the point set points.csv shows.
constexpr std::uint32_t kProjectionSeed = 12345;

/// The pairs shown for a sampler: (0,1), (0,2), (1,5) and (0,B) with B the first dimension of
/// the second block (the pattern's blockDims; 32 for Halton, 64 for Sobol, whose blocks the shader
/// fixes; 1 for Random, whose every dimension is independent). Pairs equal to an earlier one are
/// dropped (Random's (0,1) and CMJ2D's (0,2) are their cross-block pairs); a pair (0,B) is always
/// named "cross-block (0,B)".
std::vector<ProjectionPair> projectionPairs(const SamplerSpec& spec, const oas::Pattern& pattern);

/// Header of spectra.csv: sampler,pattern,N,pair,kx,ky,power.
std::vector<std::string> spectrumColumns();
/// Appends one row per frequency of `s` (ky outer, kx inner, as stored) to `table`, which must
/// have spectrumColumns(). `pattern` is written as oas::describe(pattern).
void appendSpectrumRows(CsvTable& table, const std::string& sampler, const oas::Pattern& pattern, const ProjectionPair& pair,
                        const Spectrum& s);

/// Spectra of every projectionPairs() pair of every projectionSamplers() sampler, `randomizations`
/// each (user seed kProjectionSeed), written to outDir/spectra.csv (outDir is created). A sampler
/// whose pattern cannot be made is skipped with a message on stderr, as in the points dump.
void writeSpectra(const std::string& outDir, std::uint32_t randomizations, int radius, unsigned threads);

}  // namespace oas::study
