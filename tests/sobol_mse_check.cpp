// sobol_mse_check - integration error of one of our samplers and of points read from stdin, on
// the same analytic integrands, for tests/sobol_mse_scipy_test.py to compare our hash-scrambled
// Sobol with scipy.stats.qmc.Sobol(scramble=True).
//
//   sobol_mse_check SAMPLER N SETS < points
//
// reads SETS point sets of N points in 4 dimensions (float64, little-endian, [set][point][dim])
// from stdin and prints, per integrand, one line:
//   NAME  MSE_OURS  SE_OURS  MSE_THEIRS  SE_THEIRS
// where ours are SETS independently randomized pixels of SAMPLER at N samples (pixel seeds
// oas_pixel_seed(set, 29, 0xB0B), dimensions 0-3), and the MSEs are against closed-form
// references. This program judges nothing; the driver does.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "integrands.hpp"
#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"

namespace {
constexpr std::uint32_t kDims = 4;

struct Mse {
    double value, standardError;
};
Mse mseOf(const std::vector<double>& errors)
{
    double sum = 0, sumSq = 0;
    for (double e : errors) {
        sum += e * e;
        sumSq += e * e * e * e;
    }
    const double n = double(errors.size()), mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sumSq / n - mean * mean) / n)};
}
}  // namespace

int main(int argc, char** argv)
{
    if (argc != 4) {
        std::fprintf(stderr, "usage: %s SAMPLER N SETS < points\n", argv[0]);
        return 2;
    }
    try {
        oas::PatternRequest request;
        request.sampler = argv[1];
        request.spp = std::uint32_t(std::strtoul(argv[2], nullptr, 10));
        request.dims = kDims;
        const std::uint32_t sets = std::uint32_t(std::strtoul(argv[3], nullptr, 10));
        const oas::Pattern pattern = oas::makePattern(request);
        const std::uint32_t n = pattern.N;
        if (sets < 2) throw std::invalid_argument("SETS must be at least 2");
        const std::vector<oas::study::Integrand> integrands = {{oas::study::Combo::Additive2, oas::study::Kernel::Gaussian, kDims},
                                                               {oas::study::Combo::Additive2, oas::study::Kernel::BinaryStep, kDims},
                                                               {oas::study::Combo::Multiplicative2, oas::study::Kernel::Gaussian, kDims},
                                                               {oas::study::Combo::Radial, oas::study::Kernel::Gaussian, kDims}};
        std::vector<double> truth;
        for (const auto& f : integrands) truth.push_back(oas::study::closedFormReference(f).value);
        std::vector<std::vector<double>> ours(integrands.size()), theirs(integrands.size());
        std::vector<double> input(std::size_t(n) * kDims), sum(integrands.size()), values(integrands.size());
        const auto pat = oas::glsl::toGlsl(pattern);
        for (std::uint32_t set = 0; set < sets; ++set) {
            if (std::fread(input.data(), sizeof(double), input.size(), stdin) != input.size())
                throw std::runtime_error("stdin ended before " + std::to_string(sets) + " sets of " + std::to_string(n) +
                                         " 4D float64 points");
            for (int side = 0; side < 2; ++side) {
                std::fill(sum.begin(), sum.end(), 0.0);
                const std::uint32_t seed = oas::glsl::oas_pixel_seed(set, 29, 0xB0B);
                for (std::uint32_t i = 0; i < n; ++i) {
                    float x[kDims];
                    for (std::uint32_t d = 0; d < kDims; ++d)
                        x[d] = side == 0 ? oas::glsl::oas_sample(pat, seed, i, d) : float(input[std::size_t(i) * kDims + d]);
                    oas::study::evaluateAll(integrands, x, kDims, values.data());
                    for (std::size_t k = 0; k < integrands.size(); ++k) sum[k] += values[k];
                }
                for (std::size_t k = 0; k < integrands.size(); ++k)
                    (side == 0 ? ours : theirs)[k].push_back(sum[k] / n - truth[k]);
            }
        }
        for (std::size_t k = 0; k < integrands.size(); ++k) {
            const Mse a = mseOf(ours[k]), b = mseOf(theirs[k]);
            std::string name = integrands[k].name();
            for (char& c : name)
                if (c == ' ') c = '_';
            std::printf("%s %.9e %.9e %.9e %.9e\n", name.c_str(), a.value, a.standardError, b.value, b.standardError);
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "sobol_mse_check: %s\n", e.what());
        return 2;
    }
    return 0;
}
