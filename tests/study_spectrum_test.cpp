// Tests of the projection power spectra (study/spectrum.*): the periodogram against a direct
// sum, properties that hold for independent reasons (Hermitian symmetry of real point sets,
// E[P(k)] = 1 for independent uniform points, dark axes for Latin-hypercube projections), and the
// spectra.csv writer.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include "experiment.hpp"
#include "spectrum.hpp"

using namespace oas::study;

namespace {

SamplerSpec specOf(const std::string& label)
{
    for (auto& s : studySamplers())
        if (s.label == label) return s;
    ADD_FAILURE() << "no sampler " << label;
    return {};
}

oas::Pattern patternOf(const std::string& label, std::uint32_t n)
{
    return oas::makePattern(patternRequest(specOf(label), n, kProjectionDims));
}

/// Mean power over k = (kx, 0) and (0, ky) with 1 <= |k| <= r: the two 1D projections.
double axisMean(const Spectrum& s)
{
    double sum = 0;
    for (int k = 1; k <= s.radius; ++k) sum += s.at(k, 0) + s.at(-k, 0) + s.at(0, k) + s.at(0, -k);
    return sum / (4.0 * s.radius);
}

/// Mean power over 0 < |k| < kHigh with kx != 0 and ky != 0 (what 2D stratification darkens).
double offAxisMean(const Spectrum& s, double kHigh)
{
    double sum = 0;
    int n = 0;
    for (int ky = -s.radius; ky <= s.radius; ++ky)
        for (int kx = -s.radius; kx <= s.radius; ++kx)
            if (kx != 0 && ky != 0 && std::hypot(kx, ky) < kHigh) sum += s.at(kx, ky), ++n;
    return sum / n;
}

}  // namespace

TEST(StudySpectrum, MatchesDirectSumOnOnePointSet)
{
    // One randomization: the periodogram is |sum_j exp(-2 pi i k.x_j)|^2 / N, here summed with the
    // plain phase 2 pi (kx x + ky y) instead of the implementation's per-axis reduced phasors.
    const auto pat = patternOf("BoseCMJ", 121);
    const int r = 6;
    const std::uint32_t seed = 77;
    const Spectrum s = powerSpectrum(pat, 1, 5, 1, r, seed, 2);
    ASSERT_EQ(s.radius, r);
    ASSERT_EQ(s.power.size(), size_t((2 * r + 1) * (2 * r + 1)));
    const std::uint32_t px = oas::pixelSeed(0, 0, seed);
    for (int ky = -r; ky <= r; ++ky)
        for (int kx = -r; kx <= r; ++kx) {
            std::complex<double> sum = 0;
            for (std::uint32_t j = 0; j < pat.N; ++j) {
                const double x = oas::sample(pat, px, j, 1), y = oas::sample(pat, px, j, 5);
                sum += std::polar(1.0, -2 * std::numbers::pi * (kx * x + ky * y));
            }
            const double want = (kx == 0 && ky == 0) ? 0.0 : std::norm(sum) / pat.N;
            EXPECT_NEAR(s.at(kx, ky), want, 1e-9) << kx << "," << ky;
        }
}

TEST(StudySpectrum, HermitianSymmetryIsExact)
{
    // Real points: S(-k) = conj S(k), so P(-k) = P(k); a layout or sign slip breaks it.
    for (auto [label, n] : {std::pair<std::string, std::uint32_t>{"BoseMJ", 121}, {"Halton", 128}, {"Random", 128}}) {
        const Spectrum s = powerSpectrum(patternOf(label, n), 0, 2, 4, 9, 3, 2);
        for (int ky = -9; ky <= 9; ++ky)
            for (int kx = -9; kx <= 9; ++kx) EXPECT_EQ(s.at(kx, ky), s.at(-kx, -ky)) << label << " " << kx << "," << ky;
        EXPECT_EQ(s.at(0, 0), 0.0);
    }
}

TEST(StudySpectrum, RandomPointsAreWhite)
{
    // For N independent uniform points, E|S(k)|^2 = N at every k != 0 (cross terms vanish), so
    // E[P(k)] = 1; Var P(k) = 1 - 1/N, and P(k), P(k') are uncorrelated unless k' = +-k. The mean
    // over the (W^2 - 1) / 2 distinct frequencies and R randomizations has standard error
    // sqrt((1 - 1/N) / (M R)).
    const std::uint32_t N = 128, R = 64;
    const int r = 16;
    const Spectrum s = powerSpectrum(patternOf("Random", N), 0, 1, R, r, 5, 2);
    const double M = ((2.0 * r + 1) * (2 * r + 1) - 1) / 2;
    const double se = std::sqrt((1 - 1.0 / N) / (M * R));
    EXPECT_NEAR(radialMean(s, 0.5, 1e9), 1.0, 4 * se);
    // The axes (1D projections) of random points are white as well: 2r distinct frequencies.
    EXPECT_NEAR(axisMean(s), 1.0, 4 * std::sqrt(1.0 / (2 * r * R)));
}

TEST(StudySpectrum, LatinHypercubeAxesAreDarkForOrthogonalArrays)
{
    // Each 1D projection of a strength-2 OA with MJ/CMJ offsets is a Latin hypercube: one point
    // in each of the N strata [m/N, (m+1)/N). With x_j = (pi(j) + u_j) / N the stratum centres sum
    // to zero at 0 < |k| < N, so only the jitter is left: E[P(k, 0)] <= 1 - sinc^2(pi k / N),
    // about 0.02 on average for |k| <= 16 and N = 121, against 1 for random points.
    const int r = 16;
    for (auto [label, n] :
         {std::pair<std::string, std::uint32_t>{"BoseCMJ", 121}, {"BoseMJ", 121}, {"BushMJ(t=2)", 121}, {"BoseBushCMJ", 128}}) {
        const auto pat = patternOf(label, n);
        for (const auto& pair : projectionPairs(specOf(label), pat)) {
            const Spectrum s = powerSpectrum(pat, pair.a, pair.b, 16, r, 11, 2);
            EXPECT_LT(axisMean(s), 0.2) << label << " " << pair.name;
        }
    }
    const Spectrum rnd = powerSpectrum(patternOf("Random", 128), 0, 2, 16, r, 11, 2);
    EXPECT_GT(axisMean(rnd), 0.8);
    EXPECT_LT(axisMean(rnd), 1.2);
}

TEST(StudySpectrum, StrengthTwoDarkensLowFrequenciesOnlyWithinABlock)
{
    // Strength 2 stratifies every pair within a block into s x s cells (Jarosz et al. 2019), so
    // the low frequencies off the axes lose power too: for one uniformly jittered point per cell,
    // E[P(k)] = 1 - sinc^2(pi kx / s) sinc^2(pi ky / s), 0.13 on average over 0 < |kx|, |ky|,
    // |k| < 3 with s = 11 (about 0.15 measured). A pair across independently randomized blocks is
    // two Latin hypercubes paired at random: white off the axes (about 1).
    for (const char* label : {"BoseCMJ", "BoseMJ", "BushMJ(t=2)"}) {
        const auto pat = patternOf(label, 121);
        const auto pairs = projectionPairs(specOf(label), pat);
        ASSERT_EQ(pairs.size(), 4u);
        ASSERT_EQ(pairs.back().name, "cross-block (0,12)");
        for (const auto& pair : pairs) {
            const double m = offAxisMean(powerSpectrum(pat, pair.a, pair.b, 32, 3, 13, 2), 3.0);
            if (pair.b == 12)
                EXPECT_GT(m, 0.7) << label << " " << pair.name;
            else
                EXPECT_LT(m, 0.3) << label << " " << pair.name;
        }
    }
}

TEST(StudySpectrum, ResultDoesNotDependOnThreadCount)
{
    const auto pat = patternOf("Sobol", 128);
    const Spectrum a = powerSpectrum(pat, 0, 1, 20, 5, 1, 1);
    const Spectrum b = powerSpectrum(pat, 0, 1, 20, 5, 1, 3);
    EXPECT_EQ(a.power, b.power);
}

TEST(StudySpectrum, RejectsBadArguments)
{
    const auto pat = patternOf("Random", 128);
    EXPECT_THROW(powerSpectrum(pat, 0, 1, 4, -1, 0, 1), std::invalid_argument);
    EXPECT_THROW(powerSpectrum(pat, 0, 1, 0, 4, 0, 1), std::invalid_argument);
    EXPECT_THROW(powerSpectrum(oas::Pattern{}, 0, 1, 4, 4, 0, 1), std::invalid_argument);
    // Radius 0 is just the (zeroed) DC term.
    EXPECT_EQ(powerSpectrum(pat, 0, 1, 1, 0, 0, 1).power, std::vector<double>{0.0});
}

TEST(StudySpectrum, RadialMeanAndProfile)
{
    // Synthetic spectrum P(k) = |k|^2: bin b of the profile averages |k|^2 over b-1/2 <= |k| < b+1/2.
    Spectrum s;
    s.radius = 3;
    for (int ky = -3; ky <= 3; ++ky)
        for (int kx = -3; kx <= 3; ++kx) s.power.push_back(kx * kx + ky * ky);
    s.power[24] = 0;
    EXPECT_DOUBLE_EQ(s.at(2, -1), 5.0);
    EXPECT_DOUBLE_EQ(radialMean(s, 0.5, 1.2), 1.0);    // the four |k| = 1
    EXPECT_DOUBLE_EQ(radialMean(s, 1.2, 1.5), 2.0);    // the four diagonals
    EXPECT_DOUBLE_EQ(radialMean(s, 0.0, 1.5), 1.5);    // DC excluded
    EXPECT_DOUBLE_EQ(radialMean(s, 10.0, 20.0), 0.0);  // empty
    const auto p = radialProfile(s);
    ASSERT_EQ(p.size(), 4u);
    EXPECT_EQ(p[0], 0.0);
    EXPECT_DOUBLE_EQ(p[1], (4 * 1 + 4 * 2) / 8.0);            // |k| in {1, sqrt 2}: sqrt 2 < 1.5
    EXPECT_DOUBLE_EQ(p[2], (4 * 4 + 8 * 5) / 12.0);           // |k| in {2, sqrt 5}
    EXPECT_DOUBLE_EQ(p[3], (4 * 9 + 4 * 8 + 8 * 10) / 16.0);  // |k| in {sqrt 8, 3, sqrt 10}
}

TEST(StudySpectrum, ProjectionPairsFollowThePointsDump)
{
    auto names = [](const std::string& label, std::uint32_t n) {
        std::vector<std::string> out;
        for (auto& p : projectionPairs(specOf(label), patternOf(label, n))) out.push_back(p.name);
        return out;
    };
    using V = std::vector<std::string>;
    EXPECT_EQ(names("BoseCMJ", 121), (V{"(0,1)", "(0,2)", "(1,5)", "cross-block (0,12)"}));
    EXPECT_EQ(names("CMJND(t=4)", 81), (V{"(0,1)", "(0,2)", "(1,5)", "cross-block (0,4)"}));
    EXPECT_EQ(names("Halton", 128), (V{"(0,1)", "(0,2)", "(1,5)", "cross-block (0,32)"}));
    EXPECT_EQ(names("Sobol", 128), (V{"(0,1)", "(0,2)", "(1,5)", "cross-block (0,1024)"}));
    // Duplicates dropped: Random's (0,1) and CMJ2D's (0,2) are their cross-block pairs.
    EXPECT_EQ(names("Random", 128), (V{"cross-block (0,1)", "(0,2)", "(1,5)"}));
    EXPECT_EQ(names("CMJ2D-pad", 128), (V{"(0,1)", "cross-block (0,2)", "(1,5)"}));
    for (auto& [label, n] : projectionSamplers()) EXPECT_NO_THROW(patternOf(label, n)) << label;
}

TEST(StudySpectrum, WriteSpectraCsv)
{
    const std::string dir = ::testing::TempDir() + "oas_spectra_test";
    std::filesystem::remove_all(dir);
    writeSpectra(dir, 2, 2, 2);
    std::ifstream f(dir + "/spectra.csv");
    ASSERT_TRUE(f.good());
    std::string line;
    std::getline(f, line);
    EXPECT_EQ(line, "sampler,pattern,N,pair,kx,ky,power");
    // Rows per (sampler, pair): 25 frequencies; the pattern description is quoted (it has commas),
    // so split from the right: ...,pair,kx,ky,power with pair quoted too.
    std::map<std::string, int> perCase;
    int dcRows = 0, rows = 0;
    while (std::getline(f, line)) {
        ++rows;
        const std::string sampler = line.substr(0, line.find(','));
        const size_t q = line.rfind('"');
        ASSERT_NE(q, std::string::npos) << line;
        const size_t q0 = line.rfind('"', q - 1);
        const std::string pair = line.substr(q0 + 1, q - q0 - 1);
        ++perCase[sampler + " " + pair];
        if (line.compare(q + 1, std::string::npos, ",0,0,0") == 0) ++dcRows;
    }
    size_t cases = 0;
    for (auto& [label, n] : projectionSamplers()) cases += projectionPairs(specOf(label), patternOf(label, n)).size();
    EXPECT_EQ(perCase.size(), cases);
    for (auto& [k, c] : perCase) EXPECT_EQ(c, 25) << k;
    EXPECT_EQ(rows, int(cases) * 25);
    EXPECT_EQ(dcRows, int(cases));
    EXPECT_TRUE(perCase.count("BoseCMJ cross-block (0,12)"));
    EXPECT_TRUE(perCase.count("Random cross-block (0,1)"));
}
