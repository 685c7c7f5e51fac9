// Tests of the analytic-integrand study (study/): slope fits, MSE machinery, references, CSV.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "experiment.hpp"
#include "integrands.hpp"
#include "pair_study.hpp"
#include "progressive_part.hpp"
#include "stats.hpp"

using namespace oas::study;

TEST(StudyStats, SlopeFitExact)
{
    std::vector<double> n, y;
    for (double N : {16.0, 32.0, 64.0, 128.0, 256.0, 1024.0}) {
        n.push_back(N);
        y.push_back(3.5 * std::pow(N, -1.5));
    }
    const SlopeFit f = fitLogLog(n, y);
    EXPECT_EQ(f.n, 6);
    EXPECT_NEAR(f.slope, -1.5, 1e-12);
    EXPECT_NEAR(std::exp(f.intercept), 3.5, 1e-9);
    EXPECT_NEAR(f.ciLow, -1.5, 1e-9);
    EXPECT_NEAR(f.ciHigh, -1.5, 1e-9);
    EXPECT_NEAR(f.r2, 1.0, 1e-12);
}

TEST(StudyStats, SlopeFitNoisyCoversTruth)
{
    // Log-normal noise of 10% on 12 points: the 95% interval should contain the true slope in
    // about 95% of 400 repetitions.
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.1);
    int covered = 0;
    const int reps = 400;
    for (int r = 0; r < reps; ++r) {
        std::vector<double> n, y;
        for (int k = 0; k < 12; ++k) {
            const double N = 16 * std::pow(2.0, k / 2.0);
            n.push_back(N);
            y.push_back(std::pow(N, -1.78) * std::exp(noise(rng)));
        }
        const SlopeFit f = fitLogLog(n, y);
        ASSERT_TRUE(f.valid());
        EXPECT_NEAR(f.slope, -1.78, 0.1);
        if (f.ciLow <= -1.78 && -1.78 <= f.ciHigh) ++covered;
    }
    EXPECT_GE(covered, int(0.91 * reps));
    EXPECT_LE(covered, int(0.99 * reps));
}

TEST(StudyStats, TQuantile)
{
    EXPECT_NEAR(tQuantile975(1), 12.706, 1e-9);
    EXPECT_NEAR(tQuantile975(10), 2.228, 1e-9);
    EXPECT_NEAR(tQuantile975(40), 2.021, 1e-9);
    EXPECT_NEAR(tQuantile975(1000000), 1.960, 1e-3);
    EXPECT_GT(tQuantile975(35), 2.021);
    EXPECT_LT(tQuantile975(35), 2.042);
}

TEST(StudyStats, FitSkipsNonPositive)
{
    const SlopeFit f = fitLogLog({1, 2, 4, 8}, {1, 0, 0.0625, 1.0 / 64});
    EXPECT_EQ(f.n, 3);
    EXPECT_NEAR(f.slope, -2.0, 1e-12);
}

TEST(StudyCsv, WritesSmallTable)
{
    CsvTable t({"a", "b", "c"});
    t.add({"1", "x,y", "say \"hi\""});
    t.add({"2.5", "", "plain"});
    EXPECT_EQ(t.rows(), 2u);
    EXPECT_EQ(t.str(), "a,b,c\n1,\"x,y\",\"say \"\"hi\"\"\"\n2.5,,plain\n");
    EXPECT_THROW(t.add({"only one"}), std::invalid_argument);
    const std::string path = ::testing::TempDir() + "study_test.csv";
    t.write(path);
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    EXPECT_EQ(ss.str(), t.str());
}

TEST(StudyIntegrands, OneAdditiveReferenceMatchesBruteForce)
{
    for (Kernel k : {Kernel::Gaussian, Kernel::LinearStep, Kernel::BinaryStep}) {
        // Midpoint rule with 2^20 cells on [0,1] (the step kernels' jumps cost O(1/n)).
        const int n = 1 << 20;
        double sum = 0;
        for (int i = 0; i < n; ++i) sum += kernel(k, (i + 0.5) / n);
        const double brute = 4 * sum / n;
        const Reference ref = closedFormReference({Combo::Additive1, k, 4});
        EXPECT_TRUE(ref.exact);
        EXPECT_NEAR(ref.value, brute, 1e-5) << kernelName(k);
    }
}

TEST(StudyIntegrands, TwoAdditiveClosedFormMatchesQuadrature)
{
    for (Kernel k : {Kernel::Gaussian, Kernel::LinearStep, Kernel::BinaryStep}) {
        const Reference q = quadrature2D(k);
        const Reference cf = closedFormReference({Combo::Additive2, k, 2});
        EXPECT_LT(q.error, 1e-10) << kernelName(k);
        EXPECT_NEAR(cf.value, q.value, 1e-10) << kernelName(k);
    }
}

TEST(StudyIntegrands, EvaluateAllMatchesDirectDefinition)
{
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    const auto fs = paperIntegrands(5);
    std::vector<double> out(fs.size());
    for (int t = 0; t < 200; ++t) {
        float x[5];
        for (auto& v : x) v = u(rng) * 0.8f;
        evaluateAll(fs, x, 5, out.data());
        for (size_t f = 0; f < fs.size(); ++f) {
            double want = fs[f].combo == Combo::Multiplicative2 ? 1 : 0, n2 = 0;
            for (int i = 0; i < 5; ++i) {
                n2 += double(x[i]) * x[i];
                if (fs[f].combo == Combo::Additive1) want += kernel(fs[f].kernel, x[i]);
                for (int j = i + 1; j < 5; ++j) {
                    const double r = std::hypot(double(x[i]), double(x[j]));
                    if (fs[f].combo == Combo::Additive2) want += kernel(fs[f].kernel, r);
                    if (fs[f].combo == Combo::Multiplicative2) want *= kernel(fs[f].kernel, r);
                }
            }
            if (fs[f].combo == Combo::Radial) want = kernel(fs[f].kernel, std::sqrt(n2));
            EXPECT_NEAR(out[f], want, 1e-12 * std::max(1.0, std::abs(want))) << fs[f].name();
        }
    }
}

TEST(StudyExperiment, ConstantIntegrandHasZeroMseForEverySampler)
{
    const std::vector<Integrand> fs = {{Combo::Additive1, Kernel::Constant, 4},
                                       {Combo::Additive2, Kernel::Constant, 4},
                                       {Combo::Multiplicative2, Kernel::Constant, 4},
                                       {Combo::Radial, Kernel::Constant, 4}};
    std::vector<double> refs;
    for (auto& f : fs) refs.push_back(closedFormReference(f).value);
    EXPECT_EQ(refs, (std::vector<double>{4, 6, 1, 1}));
    for (auto& spec : studySamplers()) {
        const auto ladder = countLadder(spec, 4, 16, 300);
        ASSERT_FALSE(ladder.empty()) << spec.label;
        const auto pat = oas::makePattern(patternRequest(spec, ladder.front(), 4));
        const auto st = measure(pat, fs, refs, 4, ladder.front(), 8, 1, 2);
        for (size_t f = 0; f < fs.size(); ++f) {
            EXPECT_EQ(st[f].mse, 0.0) << spec.label << " " << fs[f].name();
            EXPECT_EQ(st[f].mean, refs[f]) << spec.label;
        }
    }
}

TEST(StudyExperiment, LaddersAreValidCounts)
{
    for (auto& spec : studySamplers()) {
        const auto ladder = countLadder(spec, 4, 16, 1024);
        EXPECT_GE(ladder.size(), 3u) << spec.label;
        for (auto n : ladder) EXPECT_NO_THROW(oas::makePattern(patternRequest(spec, n, 4))) << spec.label << " " << n;
    }
}

TEST(StudyExperiment, UnbiasedOnTwoAdditiveBinaryStep)
{
    // A small strength-2 OA run: the mean estimate is within 5 standard errors of the reference.
    const std::vector<Integrand> fs = {{Combo::Additive2, Kernel::BinaryStep, 4}};
    const double ref = closedFormReference(fs[0]).value;
    const auto pat = oas::makePattern(patternRequest(studySamplers()[0], 64, 4));
    const auto st = measure(pat, fs, {ref}, 4, 64, 256, 9, 2);
    EXPECT_NEAR(st[0].mean, ref, 5 * std::sqrt(st[0].variance / 256));
    EXPECT_GT(st[0].mse, 0.0);
}

// The pair study's textbook randomization must itself be what it claims: a randomized OA of
// strength 2 (every pair of columns puts one point in each of the q x q cells) whose columns are
// Latin hypercubes in N = q^2 strata, with CMJ's substrata shared by every stratum of a column.
TEST(PairStudy, TextbookBoseIsAStrength2LatinHypercubeOA)
{
    for (bool correlated : {true, false})
        for (std::uint32_t q : {5u, 7u, 11u}) {
            std::vector<double> x;
            textbookBose4(q, correlated, 1234 + q, x);
            const std::uint32_t n = q * q;
            ASSERT_EQ(x.size(), size_t(n) * 4);
            for (int a = 0; a < 4; ++a) {
                std::vector<int> fine(n, 0);
                for (std::uint32_t i = 0; i < n; ++i) {
                    const double v = x[size_t(i) * 4 + a];
                    ASSERT_GE(v, 0.0);
                    ASSERT_LT(v, 1.0);
                    ++fine[std::uint32_t(v * n)];
                }
                for (int c : fine) EXPECT_EQ(c, 1) << "column " << a << " is not a Latin hypercube, q = " << q;
                for (int b = a + 1; b < 4; ++b) {
                    std::vector<int> cells(n, 0);
                    for (std::uint32_t i = 0; i < n; ++i)
                        ++cells[std::uint32_t(x[size_t(i) * 4 + a] * q) * q + std::uint32_t(x[size_t(i) * 4 + b] * q)];
                    for (int c : cells) EXPECT_EQ(c, 1) << "pair (" << a << "," << b << "), q = " << q;
                }
            }
            // CMJ: the substratum of column 0 depends on the partner's level only, through one
            // permutation: points in the same column-1 stratum share column 0's substratum.
            std::vector<int> subOfRow(q, -1);
            bool shared = true;
            for (std::uint32_t i = 0; i < n; ++i) {
                const std::uint32_t row = std::uint32_t(x[size_t(i) * 4 + 1] * q);
                const int sub = int(std::uint32_t(x[size_t(i) * 4 + 0] * n) % q);
                if (subOfRow[row] < 0) subOfRow[row] = sub;
                shared = shared && subOfRow[row] == sub;
            }
            EXPECT_EQ(shared, correlated) << "q = " << q;
        }
}

// The scene study's paper-count points: the valid count nearest the target, in log.
TEST(StudyLadder, NearestCountPicksTheClosestValidCountInLog)
{
    const auto specs = studySamplers();
    auto spec = [&](const std::string& label) {
        for (const auto& s : specs)
            if (s.label == label) return s;
        throw std::runtime_error("no sampler " + label);
    };
    EXPECT_EQ(nearestCount(spec("BoseCMJ"), 7, 4096), 4096u);  // 64^2
    EXPECT_EQ(nearestCount(spec("BoseCMJ"), 7, 512), 529u);    // 23^2 (above the target: 22^2 is no Bose count)
    EXPECT_EQ(nearestCount(spec("Sobol"), 7, 600), 512u);
    // Addelman-Kempthorne makes 2 q^2 for odd prime powers q: 2 * 43^2 = 3698 and 2 * 47^2 = 4418
    // are its neighbours of 4096 (q = 45 is no prime power); 4418 is nearer in log.
    EXPECT_EQ(nearestCount(spec("AddelmanKempthorneCMJ"), 7, 4096), 4418u);
    // Nothing within 2^(1/4): 0.
    EXPECT_EQ(nearestCount(spec("Sobol"), 7, 724), 0u);
}

TEST(ProgressiveStudy, EveryCheckpointIsStratifiedInEachDimension)
{
    // Every prefix of q^m samples of a (0,s)-sequence in base q is a (0,m,s)-net, so in each
    // dimension exactly one of its points lies in each interval [k / q^m, (k + 1) / q^m). A
    // binary step's estimate then errs only in the interval holding the step: by at most 1 / N
    // per dimension, D / N for the 1-additive sum. An unstratified prefix (independent points, or
    // q independent arrays of q^2 points at N = q^3) errs by about sqrt(D / N) / 4 and breaks it
    // in most trials. The checkpoint estimates are running sums of one run each, so this also
    // checks that each is its own prefix's mean and not the last's.
    for (const auto& [q, dims] : {std::pair{4u, 4u}, std::pair{5u, 4u}, std::pair{3u, 3u}, std::pair{8u, 8u}}) {
        const std::vector<Integrand> fs = {{Combo::Additive1, Kernel::BinaryStep, dims}};
        const double reference = closedFormReference(fs[0]).value;
        EXPECT_NEAR(reference, dims * kREnd, 1e-12);
        const auto checkpoints = progressiveCheckpoints(q, 1024);
        ASSERT_GE(checkpoints.size(), 2u);
        EXPECT_EQ(checkpoints.front(), q * q);
        const auto est = faurePrefixEstimates(q, fs, dims, checkpoints, 64, 7, 2);
        ASSERT_EQ(est.size(), checkpoints.size());
        for (std::size_t c = 0; c < checkpoints.size(); ++c)
            for (std::uint32_t t = 0; t < 64; ++t)
                ASSERT_LE(std::abs(est[c][t] - reference), double(dims) / checkpoints[c] + 1e-12)
                    << "q " << q << ", N " << checkpoints[c] << ", trial " << t;
    }
    EXPECT_THROW(faurePrefixEstimates(4, {{Combo::Additive1, Kernel::BinaryStep, 5}}, 5, {16}, 1, 0, 1), std::invalid_argument);
    EXPECT_THROW(faurePrefixEstimates(2, {{Combo::Additive1, Kernel::BinaryStep, 2}}, 2, {1u << 13}, 1, 0, 1),
                 std::invalid_argument);  // 13 digits: more than OAS_FAURE_MAX_DIGITS
    EXPECT_THROW(faurePrefixEstimates(4, {{Combo::Additive1, Kernel::BinaryStep, 4}}, 4, {16, 16}, 1, 0, 1), std::invalid_argument);
}
