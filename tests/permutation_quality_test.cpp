// Are the library's hashed permutations as good as truly uniform ones where it counts, in the
// error of an estimate? Owen (1992) derives the variance of randomized-OA integration for
// independent, uniformly random permutations of the levels (and, with MJ/CMJ offsets, of the
// substrata) and uniform jitter. Here every construction is randomized twice over many seeds: by
// the library (oas_sample), and by std::shuffle permutations and std::mt19937 jitter applied to
// the same un-randomized array (oas_oa_level / oas_oa_sublevel). The MSE of integrating
// closed-form integrands must agree within the noise of the two estimates. This is the yardstick
// for replacing the permutations (issue 9 asks for loop-free ones).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <vector>

#include "integrands.hpp"
#include "oas/glsl_compat.hpp"
#include "oas/pattern.hpp"

namespace {

using oas::study::Combo;
using oas::study::Integrand;
using oas::study::Kernel;

constexpr std::uint32_t kDims = 4;

/// Mean and the standard error of the mean of squared errors.
struct Mse {
    double value = 0, standardError = 0;
};

Mse mseOf(const std::vector<double>& errors)
{
    double s2 = 0, s4 = 0;
    for (double e : errors) {
        s2 += e * e;
        s4 += e * e * e * e;
    }
    const double n = double(errors.size()), m2 = s2 / n, m4 = s4 / n;
    return {m2, std::sqrt(std::max(0.0, m4 - m2 * m2) / n)};
}

/// One randomization of the pattern's first kDims columns with uniform permutations: the point
/// set the library would make if its permutations were drawn uniformly (oas_row_dim's recipe).
std::vector<float> uniformlyRandomized(const oas::Pattern& pattern, std::mt19937& rng, bool rotationsOnly = false)
{
    const auto pat = oas::glsl::toGlsl(pattern);
    const std::uint32_t N = pattern.N, s = pattern.s, subCount = N / s;
    std::uniform_real_distribution<double> jitter(0.0, 1.0);
    auto permutation = [&](std::uint32_t n) {
        std::vector<std::uint32_t> p(n);
        std::iota(p.begin(), p.end(), 0u);
        if (rotationsOnly)  // the negative control's weak family: x -> x + r mod n
            std::rotate(p.begin(), p.begin() + std::uniform_int_distribution<std::uint32_t>(0, n - 1)(rng), p.end());
        else
            std::shuffle(p.begin(), p.end(), rng);
        return p;
    };
    std::vector<float> points(std::size_t(N) * kDims);
    for (std::uint32_t c = 0; c < kDims; ++c) {
        const auto stratumOf = permutation(s);
        std::vector<std::vector<std::uint32_t>> subOf;  // CMJ: one; MJ: one per level
        for (std::uint32_t l = 0; l < (pattern.offset == 2 ? s : 1u); ++l) subOf.push_back(permutation(subCount));
        for (std::uint32_t row = 0; row < N; ++row) {
            const std::uint32_t level = oas::glsl::oas_oa_level(pat, row, c);
            const double u = pattern.offset == 0 ? 0.5 : jitter(rng);
            double x;
            if (pattern.offset <= 1) {
                x = (stratumOf[level] + u) / s;
            } else {
                const auto& sub = subOf[pattern.offset == 2 ? level : 0];
                x = (double(stratumOf[level]) * subCount + sub[oas::glsl::oas_oa_sublevel(pat, row, c)] + u) / N;
            }
            points[std::size_t(row) * kDims + c] = float(std::min(x, 1.0 - 0x1p-24));
        }
    }
    return points;
}

double estimate(const Integrand& f, const std::vector<float>& points)
{
    double sum = 0;
    for (std::size_t i = 0; i < points.size(); i += kDims) sum += oas::study::evaluate(f, &points[i]);
    return sum / double(points.size() / kDims);
}

struct Case {
    std::string sampler;
    std::uint32_t spp, strength;
};

TEST(PermutationQuality, LibraryRandomizationMatchesUniformPermutationsInMse)
{
    const std::vector<Case> cases = {
        {"bose", 49, 0},                 // q = 7, prime
        {"bose", 64, 0},                 // q = 8 = 2^3
        {"bose", 81, 0},                 // q = 9 = 3^2
        {"bush", 125, 3},                // q = 5, t = 3
        {"bose-bush", 32, 0},            // q = 4 in GF(8)
        {"addelman-kempthorne", 50, 0},  // q = 5
    };
    const std::vector<Integrand> integrands = {{Combo::Additive2, Kernel::Gaussian, kDims},
                                               {Combo::Additive2, Kernel::BinaryStep, kDims},
                                               {Combo::Multiplicative2, Kernel::Gaussian, kDims},
                                               {Combo::Radial, Kernel::Gaussian, kDims}};
    const std::uint32_t seeds = 1024;
    double worst = 0;  // largest |ratio - 1| in standard errors
    for (const auto& c : cases) {
        for (const std::string offset : {"centered", "j", "mj", "cmj"}) {
            oas::PatternRequest request;
            request.sampler = c.sampler;
            request.spp = c.spp;
            request.dims = kDims;
            request.strength = c.strength;
            request.offset = offset;
            const oas::Pattern pattern = oas::makePattern(request);
            ASSERT_GE(pattern.blockDims, kDims);
            const auto pat = oas::glsl::toGlsl(pattern);
            std::mt19937 rng(0x5eed + pattern.N * 7 + pattern.offset);
            for (const auto& f : integrands) {
                const double truth = oas::study::closedFormReference(f).value;
                ASSERT_TRUE(std::isfinite(truth));
                std::vector<double> ours, uniform;
                for (std::uint32_t m = 0; m < seeds; ++m) {
                    std::vector<float> points(std::size_t(pattern.N) * kDims);
                    const std::uint32_t pixelSeed = oas::glsl::oas_pixel_seed(m, 17, 0xC0FFEE);
                    for (std::uint32_t i = 0; i < pattern.N; ++i)
                        for (std::uint32_t d = 0; d < kDims; ++d)
                            points[std::size_t(i) * kDims + d] = oas::glsl::oas_sample(pat, pixelSeed, i, d);
                    ours.push_back(estimate(f, points) - truth);
                    uniform.push_back(estimate(f, uniformlyRandomized(pattern, rng)) - truth);
                }
                const Mse a = mseOf(ours), b = mseOf(uniform);
                const double ratio = a.value / b.value;
                // Standard error of the ratio of two independent estimates (delta method); 4.5
                // of them either way keeps 48 comparisons from failing by chance.
                const double se = ratio * std::hypot(a.standardError / a.value, b.standardError / b.value);
                // (+ 1e-3: centered offsets on 2-additive integrands give one point set whatever the
                // permutations, so the spread is 0 and only the float placement differs.)
                EXPECT_NEAR(ratio, 1.0, 4.5 * se + 1e-3)
                    << c.sampler << " N=" << pattern.N << " " << offset << ", " << f.name() << ": MSE ours " << a.value << " +- "
                    << a.standardError << ", uniform " << b.value << " +- " << b.standardError;
                worst = std::max(worst, std::abs(ratio - 1.0) / (se + 1e-300));
                std::printf("%-20s N=%-4u %-8s %-32s MSE ratio ours/uniform %.3f +- %.3f\n", c.sampler.c_str(), pattern.N,
                            offset.c_str(), f.name().c_str(), ratio, se);
            }
        }
    }
}

TEST(PermutationQuality, AWeakPermutationFamilyIsCaught)
{
    // The comparison must be able to fail: randomizing with cyclic rotations only (x -> x + r mod
    // n, a family of n permutations instead of n!) keeps a linear OA a translate of itself, and
    // the MSE ratio against uniform permutations leaves the band of the test above.
    oas::PatternRequest request;
    request.sampler = "bose";
    request.spp = 49;
    request.dims = kDims;
    request.offset = "j";
    const oas::Pattern pattern = oas::makePattern(request);
    const Integrand f{Combo::Radial, Kernel::Gaussian, kDims};
    const double truth = oas::study::closedFormReference(f).value;
    std::mt19937 rng(7);
    std::vector<double> weak, uniform;
    for (int m = 0; m < 1024; ++m) {
        weak.push_back(estimate(f, uniformlyRandomized(pattern, rng, true)) - truth);
        uniform.push_back(estimate(f, uniformlyRandomized(pattern, rng)) - truth);
    }
    const Mse a = mseOf(weak), b = mseOf(uniform);
    const double ratio = a.value / b.value;
    const double se = ratio * std::hypot(a.standardError / a.value, b.standardError / b.value);
    std::printf("rotations only / uniform: MSE ratio %.3f +- %.3f\n", ratio, se);
    EXPECT_GT(std::abs(ratio - 1.0), 4.5 * se + 1e-3);
}

}  // namespace
