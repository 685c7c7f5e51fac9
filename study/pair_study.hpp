#pragma once
// Where Bose-CMJ loses its slope: the MSE of each 2D projection of a 4D Bose pattern, measured
// separately for the column pairs that CMJ offsets were built for (the partner pairs (0,1) and
// (2,3), whose substrata come from each other's levels) and for the cross pairs ((0,2), (0,3),
// (1,2), (1,3)), with the library's affine permutations and with a textbook randomization that
// draws every permutation uniformly (std::shuffle). It answers issue 11's question about
// BoseCMJ's 2-additive Gaussian slope in 4D (-1.58 against BoseMJ's -2.06): the construction,
// the correlated offsets, or our randomization; a periodic integrand tests the explanation.
#include <cstdint>
#include <string>
#include <vector>

namespace oas::study {

struct PairStudyOptions {
    std::uint32_t trials = 4096;  ///< independent randomizations per (variant, q)
    unsigned threads = 0;
    std::string outDir = "docs/study";
    std::string command;
    bool quick = false;
};

/// Per-pair MSE of a projection integral (the 2-additive Gaussian's terms g(||(x_a, x_b)||), or a
/// smooth periodic integrand of (x_a, x_b)) for one variant at one q; pairs in the order (0,1) (2,3)
/// (0,2) (0,3) (1,2) (1,3).
struct PairMse {
    std::string variant;
    int integrand = 0;  ///< 0: the Gaussian term g(||(x_a, x_b)||); 1: a smooth periodic integrand
    std::uint32_t q = 0, n = 0;
    std::vector<double> mse, mseSe;   ///< per pair
    double sumMse = 0, sumMseSe = 0;  ///< the 2-additive sum over the six pairs
};

/// The textbook randomized Bose OA(q^2, 4, q, 2) for prime q (columns i + k j mod q, k = 0..3),
/// every permutation uniform: x_c = (pi_c(a_c) q + sigma(b_c) + u) / q^2 with b_c the partner
/// column's level and sigma = sigma_c (CMJ) or sigma_{c, a_c} (MJ). Writes q^2 x 4 values.
void textbookBose4(std::uint32_t q, bool correlated, std::uint64_t seed, std::vector<double>& points);

/// Runs the measurement and writes outDir/pairs.csv; returns the markdown section.
std::string runPairStudy(const PairStudyOptions& options);

}  // namespace oas::study
