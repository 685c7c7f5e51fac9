#pragma once
// The analytic part of the study (`oas-study --parts analytic`): MSE convergence slopes of every
// sampler on the paper's analytic integrands (Jarosz et al. 2019, Sec. on variance slopes), the
// 2-additive binary-step goal and the comparison with the paper's slopes.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "experiment.hpp"

namespace oas::study {

struct AnalyticOptions {
    std::vector<std::uint32_t> dims = {4, 8, 16};  ///< dimensions to study
    std::uint32_t trials = 4096;                   ///< independent randomizations per (sampler, N)
    std::uint32_t minSpp = 16, maxSpp = 4096;      ///< the sample counts' range
    std::uint32_t rqmcLog2 = 16, rqmcReps = 64;    ///< RQMC reference: log2 of points per replicate, replicates
    unsigned threads = 1;
    std::string outDir = "docs/study";
    std::string studyMd = "docs/STUDY.md";  ///< the summary the section's links are relative to (empty: docs/STUDY.md)
    std::string command;                    ///< how the study was invoked (for the markdown)
    bool quick = false;
    /// When the run started: the section's run time counts from it.
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
};

/// Measures every sampler on every integrand of the chosen dimensions and writes outDir's
/// analytic.csv (every measurement), references.csv, slopes.csv, slopes.md and the section
/// analytic.md; prints the goal's verdict to stderr.
void runAnalyticStudy(const AnalyticOptions& opt, const std::vector<SamplerSpec>& samplers);

}  // namespace oas::study
