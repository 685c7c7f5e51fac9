#pragma once
// The progressive part of the study (`oas-study --parts progressive`): the MSE of the
// Owen-scrambled generalized Faure sequence (shaders/oas/oas_faure.glsl) at every checkpoint
// N = q^m of ONE progressive run per randomization, on the paper's analytic integrands, against
// what a renderer has without it: independent Bose orthogonal arrays of q^2 points repeated as
// passes (oas's answer to N > q^2 until now), and Owen-scrambled Sobol cut at N.
//
// Why: an orthogonal array is a finite point set (Jarosz et al. 2019, section 8, their first
// limitation), so a render that stops at N = lambda q^2 has lambda unrelated arrays; a (0,s)-
// sequence in base q makes every aligned block of q^m samples a (0,m,s)-net and every prefix of
// lambda q^t samples an orthogonal array of strength t (Faure 1982; Niederreiter 1987). Whether
// that buys a lower error at the checkpoints is what this part measures.
#include <cstdint>
#include <string>
#include <vector>

#include "integrands.hpp"

namespace oas::study {

struct ProgressiveOptions {
    std::uint32_t trials = 2048;   ///< independent randomizations per (dims, base, sampler, N)
    std::uint32_t maxSpp = 4096;   ///< the largest checkpoint
    unsigned threads = 0;          ///< 0: all hardware threads
    std::string outDir = "docs/study";
    std::string command;           ///< how the study was invoked (for the markdown)
    bool quick = false;
};

/// The checkpoints of base q up to maxSpp: q^m for m >= 2 (the first count an orthogonal array
/// of strength 2 in base q has), ascending.
std::vector<std::uint32_t> progressiveCheckpoints(std::uint32_t q, std::uint32_t maxSpp);

/// One progressive run per trial of the Faure sequence in base q (a prime power; its field is
/// the library's, as a Bose pattern over GF(q) has it) in `dims` <= q dimensions (dimension d is
/// field element d, scrambled by oas_faure_key(pixel seed of trial t, 0, d), the pixel seeds of
/// oas::pixelSeed(t, 0, seed)), with K digits where q^K is the last checkpoint. Returns, per
/// checkpoint, every trial's estimate of every integrand from the run's first N samples:
/// [checkpoint][trial * fs.size() + f]. The runs are not repeated per checkpoint: each
/// checkpoint's estimate is the running sum at that sample.
std::vector<std::vector<double>> faurePrefixEstimates(std::uint32_t q, const std::vector<Integrand>& fs, std::uint32_t dims,
                                                      const std::vector<std::uint32_t>& checkpoints, std::uint32_t trials,
                                                      std::uint32_t seed, unsigned threads);

/// Measures the Faure sequence, Bose passes and Sobol at every checkpoint, writes
/// outDir/progressive.csv and returns the markdown section.
std::string runProgressiveStudy(const ProgressiveOptions& options);

}  // namespace oas::study
