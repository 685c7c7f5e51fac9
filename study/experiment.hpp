#pragma once
// The convergence experiment: samplers under test, the sample-count ladder each supports, and
// the MSE of the N-sample estimator over independent randomizations (one per pixel seed).
#include <cstdint>
#include <string>
#include <vector>

#include "integrands.hpp"
#include "oas/pattern.hpp"

namespace oas::study {

struct SamplerSpec {
    std::string label;    ///< "BoseCMJ", "Sobol", ...
    std::string sampler;  ///< oas sampler name
    std::string offset = "cmj";
    std::uint32_t strength = 0;
    bool oaStrength2 = false;  ///< a fixed strength-2 OA construction: counts toward the goal
    bool powersOfTwo = false;  ///< ladder of powers of two only (baselines)
};

/// The samplers of the study, in table order.
std::vector<SamplerSpec> studySamplers();

oas::PatternRequest patternRequest(const SamplerSpec& s, std::uint32_t spp, std::uint32_t dims);

/// Sample counts in [lo, hi] for the sampler: the valid count nearest (in log, within a factor
/// 2^(1/4)) to each half-octave target lo * 2^(k/2); powers of two for the baselines.
std::vector<std::uint32_t> countLadder(const SamplerSpec& s, std::uint32_t dims, std::uint32_t lo, std::uint32_t hi);

/// The sampler's valid count nearest (in log) to `target`, within a factor 2^(1/4) either side
/// (powers of two for the baselines); 0 if it has none there.
std::uint32_t nearestCount(const SamplerSpec& s, std::uint32_t dims, std::uint32_t target);

struct Stats {
    double mean = 0;       ///< mean estimate over trials
    double mse = 0;        ///< mean of (estimate - reference)^2
    double mseStderr = 0;  ///< standard error of mse
    double variance = 0;   ///< unbiased sample variance of the estimates (no reference needed)
};

/// Per-integrand statistics of `trials` estimates of nf integrands (est[trial * nf + f]) against
/// `references` (nf values).
std::vector<Stats> statsOf(const std::vector<double>& est, std::size_t nf, std::uint32_t trials,
                           const std::vector<double>& references);

/// Runs `trials` independent N-sample estimates of every integrand (same point sets for all),
/// one pixel seed each (pixels [0, trials) of row 0, user seed `seed`), and returns per-integrand
/// statistics against `references` (same order as fs).
std::vector<Stats> measure(const oas::Pattern& pattern, const std::vector<Integrand>& fs, const std::vector<double>& references,
                           std::uint32_t dims, std::uint32_t spp, std::uint32_t trials, std::uint32_t seed, unsigned threads);

/// Randomized-QMC reference: `reps` independent Owen-scrambled Sobol point sets of 2^log2n
/// points; value = mean of the replicate estimates, error = their standard error.
std::vector<Reference> rqmcReference(const std::vector<Integrand>& fs, std::uint32_t dims, std::uint32_t log2n,
                                     std::uint32_t reps, unsigned threads);

}  // namespace oas::study
