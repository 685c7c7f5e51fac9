// The study's error-bar logic on synthetic data: the standard error of a mean (hand-computed and
// against a known variance), the verdict rule (a tie while the intervals overlap), the adaptive
// number of draws (stops at s.e. <= 10% of the mean, reports the cap otherwise), and the
// propagation of s.e. through ratios and log-log interpolation.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "stats.hpp"

using namespace oas::study;

namespace {
Estimate est(double mean, double se, std::uint32_t n = 16)
{
    Estimate e;
    e.mean = mean;
    e.se = se;
    e.n = n;
    return e;
}
}  // namespace

TEST(StudyStats, StandardErrorOfASmallSetByHand)
{
    // {1, 2, 3, 4, 5}: mean 3, squared deviations 4+1+0+1+4 = 10, sample variance 10/4 = 2.5,
    // s.e. = sqrt(2.5 / 5) = sqrt(0.5).
    const Estimate e = estimateOf({1, 2, 3, 4, 5});
    EXPECT_EQ(e.n, 5u);
    EXPECT_DOUBLE_EQ(e.mean, 3);
    EXPECT_NEAR(e.se, std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(e.relSe(), std::sqrt(0.5) / 3, 1e-15);
    // Constant values: s.e. 0; one value: s.e. unknown; none: nothing known.
    EXPECT_EQ(estimateOf({2, 2, 2}).se, 0);
    EXPECT_TRUE(std::isnan(estimateOf({7}).se));
    EXPECT_EQ(estimateOf({7}).mean, 7);
    EXPECT_TRUE(std::isnan(estimateOf({}).mean));
    EXPECT_EQ(estimateOf({}).n, 0u);
}

TEST(StudyStats, KnownVarianceGivesTheStatedStandardError)
{
    // n draws of N(5, sd = 2): the s.e. estimate is sd_hat / sqrt(n), and sd_hat is within a few
    // per cent of 2 for n = 20000 (its own relative s.e. is about 1 / sqrt(2n) = 0.5%).
    std::mt19937_64 rng(12345);
    std::normal_distribution<double> g(5.0, 2.0);
    const std::uint32_t n = 20000;
    std::vector<double> v(n);
    for (auto& x : v) x = g(rng);
    const Estimate e = estimateOf(v);
    const double expected = 2.0 / std::sqrt(double(n));
    EXPECT_NEAR(e.se, expected, 0.03 * expected);
    EXPECT_NEAR(e.mean, 5.0, 4 * expected);

    // And the s.e. means what it says: over 4000 repeated means of 16 exponential(1) draws (sd 1),
    // the spread of the means is 1/4, and the stated s.e.² is unbiased for the variance of a mean,
    // E[s²/n] = σ²/n = 1/16, for any distribution (s.e. itself is biased low for small n).
    std::exponential_distribution<double> ex(1.0);
    std::vector<double> means, se2;
    for (int r = 0; r < 4000; ++r) {
        std::vector<double> w(16);
        for (auto& x : w) x = ex(rng);
        const Estimate m = estimateOf(w);
        means.push_back(m.mean);
        se2.push_back(m.se * m.se);
    }
    const double sdOfMeans = estimateOf(means).se * std::sqrt(double(means.size()));
    EXPECT_NEAR(sdOfMeans, 0.25, 0.01);
    EXPECT_NEAR(estimateOf(se2).mean, 1.0 / 16, 0.004);
}

TEST(StudyStats, VerdictIsATieWhileTheIntervalsOverlap)
{
    // Combined s.e. sqrt(0.3² + 0.4²) = 0.5: a difference must exceed 1.0 to count.
    EXPECT_EQ(compare(est(10, 0.3), est(10.9, 0.4)), Verdict::Tie);
    EXPECT_EQ(compare(est(10, 0.3), est(11.0, 0.4)), Verdict::Tie);  // exactly 2 s.e.: still a tie
    EXPECT_EQ(compare(est(10, 0.3), est(11.1, 0.4)), Verdict::FirstLower);
    EXPECT_EQ(compare(est(11.1, 0.3), est(10, 0.4)), Verdict::SecondLower);
    // The same means with smaller error bars flip from tie to a win.
    EXPECT_EQ(compare(est(1.0, 0.2), est(1.3, 0.2)), Verdict::Tie);
    EXPECT_EQ(compare(est(1.0, 0.05), est(1.3, 0.05)), Verdict::FirstLower);
    // Unknown s.e. (one draw) or missing values: no verdict.
    EXPECT_EQ(compare(est(1, NAN), est(5, 0.01)), Verdict::Tie);
    EXPECT_EQ(compare(est(NAN, 0.1), est(5, 0.01)), Verdict::Tie);
    EXPECT_EQ(verdictWord(Verdict::Tie), "tie");
    EXPECT_EQ(verdictWord(Verdict::FirstLower), "lower");
}

TEST(StudyStats, FamilyWiseBoundIsTheNormalQuantileAtAlphaOverTheComparisons)
{
    // Printed normal tables: z_0.95 = 1.6449, z_0.995 = 2.5758; 1 - 0.05/48 gives 3.0781.
    EXPECT_NEAR(familyWiseOneSidedBound(1), 1.6449, 1e-4);
    EXPECT_NEAR(familyWiseOneSidedBound(10), 2.5758, 1e-4);
    EXPECT_NEAR(familyWiseOneSidedBound(48), 3.0781, 1e-4);
    EXPECT_GT(familyWiseOneSidedBound(49), familyWiseOneSidedBound(48));
    EXPECT_NEAR(familyWiseOneSidedBound(1, 0.9), -1.2816, 1e-4);  // a tail above one half: z below 0
    EXPECT_THROW(familyWiseOneSidedBound(0), std::invalid_argument);
    EXPECT_THROW(familyWiseOneSidedBound(4, 1.5), std::invalid_argument);
    // Combined s.e. sqrt(0.3² + 0.4²) = 0.5.
    EXPECT_DOUBLE_EQ(excessInStandardErrors(est(11.5, 0.3), est(10, 0.4)), 3.0);
    EXPECT_DOUBLE_EQ(excessInStandardErrors(est(10, 0.3), est(11.5, 0.4)), -3.0);
    EXPECT_TRUE(std::isnan(excessInStandardErrors(est(1, NAN), est(5, 0.01))));
}

TEST(StudyStats, AdaptiveDrawsStopAtTenPerCent)
{
    // Draws alternate 1 - a, 1 + a: mean 1, sample sd close to a, s.e. ~ a / sqrt(n). With a = 0.5
    // the s.e. reaches 0.1 at about n = 25, well under the cap.
    const double a = 0.5;
    std::uint32_t calls = 0;
    auto draw = [&](std::uint32_t i) {
        EXPECT_EQ(i, calls);  // draws are numbered in order, each asked for once
        ++calls;
        return i % 2 ? 1 + a : 1 - a;
    };
    AdaptiveOptions o;
    o.relTarget = 0.1;
    o.nMin = 4;
    o.nMax = 200;
    const AdaptiveResult r = adaptiveMean(draw, o);
    EXPECT_FALSE(r.estimate.capped);
    EXPECT_LE(r.estimate.relSe(), 0.1);
    EXPECT_EQ(r.values.size(), r.estimate.n);
    EXPECT_EQ(calls, r.estimate.n);
    // The first n at which s.e. <= 0.1: one fewer draw would not have been enough.
    std::vector<double> fewer(r.values.begin(), r.values.end() - 1);
    EXPECT_GT(estimateOf(fewer).relSe(), 0.1);
    EXPECT_GE(r.estimate.n, 20u);
    EXPECT_LE(r.estimate.n, 30u);

    // Zero spread: stops at nMin.
    const AdaptiveResult flat = adaptiveMean([](std::uint32_t) { return 3.0; }, o);
    EXPECT_EQ(flat.estimate.n, 4u);
    EXPECT_FALSE(flat.estimate.capped);
}

TEST(StudyStats, AdaptiveDrawsReportTheCap)
{
    // A rare event: 1 draw in 50 is 100, the rest 0.01. The s.e. stays far above 10% of the mean
    // for 16 draws, so the loop stops at the cap and says so.
    AdaptiveOptions o;
    o.nMin = 4;
    o.nMax = 16;
    const AdaptiveResult r = adaptiveMean([](std::uint32_t i) { return i % 50 == 3 ? 100.0 : 0.01; }, o);
    EXPECT_EQ(r.estimate.n, 16u);
    EXPECT_TRUE(r.estimate.capped);
    EXPECT_GT(r.estimate.relSe(), 0.1);
    const std::string text = fmtEstimate(r.estimate);
    EXPECT_NE(text.find("n=16"), std::string::npos) << text;
    EXPECT_NE(text.find("cap"), std::string::npos) << text;
    // A zero mean never reaches a relative target: capped, not a division by zero.
    const AdaptiveResult zero = adaptiveMean([](std::uint32_t) { return 0.0; }, o);
    EXPECT_TRUE(zero.estimate.capped);
    EXPECT_EQ(zero.estimate.n, 16u);
}

TEST(StudyStats, FormatsCarryTheErrorBarAndN)
{
    EXPECT_EQ(fmtEstimate(est(0.0123, 0.0008, 16)), "0.0123 ± 0.0008 (n=16)");
    Estimate c = est(1.0, 0.14, 64);
    c.capped = true;
    EXPECT_EQ(fmtEstimate(c), "1 ± 0.14 (n=64, cap; s.e. 14%)");
    EXPECT_EQ(fmtEstimate(est(NAN, 0)), "—");
    EXPECT_EQ(fmtRatio(est(0.5, 0.04)), "0.50 ± 0.04");
}

TEST(StudyStats, RatioAndInterpolationPropagateTheError)
{
    // Delta method: r = 2/4 = 0.5, relative s.e. sqrt(0.1² + 0.05²).
    const Estimate r = ratioOf(est(2, 0.2, 8), est(4, 0.2, 32));
    EXPECT_DOUBLE_EQ(r.mean, 0.5);
    EXPECT_NEAR(r.se, 0.5 * std::sqrt(0.01 + 0.0025), 1e-15);
    EXPECT_EQ(r.n, 8u);
    // Halfway (in log) between two points of 10% relative s.e. each: sqrt(0.05² + 0.05²) relative.
    const std::vector<double> x = {1, 4};
    const std::vector<Estimate> y = {est(1, 0.1, 10), est(0.25, 0.025, 20)};
    const Estimate mid = interpEstimate(x, y, 2);
    EXPECT_NEAR(mid.mean, 0.5, 1e-12);
    EXPECT_NEAR(mid.se / mid.mean, std::sqrt(2 * 0.05 * 0.05), 1e-12);
    EXPECT_EQ(mid.n, 10u);
    // At a measured point: that point's estimate.
    const Estimate end = interpEstimate(x, y, 4);
    EXPECT_NEAR(end.mean, 0.25, 1e-15);
    EXPECT_NEAR(end.se, 0.025, 1e-15);
    EXPECT_EQ(end.n, 20u);
    EXPECT_TRUE(std::isnan(interpEstimate(x, y, 8).mean));
    // Next to a capped point: "cap" only while the value's own s.e. is above the target. Halfway
    // between a capped point at 14% and a converged one at 2% the s.e. is sqrt(0.07² + 0.01²) = 7%.
    std::vector<Estimate> yc = {est(1, 0.14, 10), est(0.25, 0.005, 20)};
    yc[0].capped = true;
    const Estimate midC = interpEstimate(x, yc, 2);
    EXPECT_NEAR(midC.se / midC.mean, std::sqrt(0.07 * 0.07 + 0.01 * 0.01), 1e-12);
    EXPECT_FALSE(midC.capped);
    EXPECT_TRUE(interpEstimate(x, yc, 2, 0.05).capped);       // 7% is above a 5% target
    EXPECT_TRUE(interpEstimate(x, yc, 1.1).capped);           // mostly the capped point: ~13%
    EXPECT_FALSE(interpEstimate({1, 4}, y, 2, 0.01).capped);  // no capped neighbour: never capped
}

TEST(StudyStats, AStratifiedSumAddsVariances)
{
    // 3 ± 0.3 plus 1 ± 0.4: 4 ± 0.5 (a 3-4-5 triangle), counted by the first estimate's n.
    const Estimate s = sumOf(est(3, 0.3, 12), est(1, 0.4, 400));
    EXPECT_DOUBLE_EQ(s.mean, 4);
    EXPECT_NEAR(s.se, 0.5, 1e-15);
    EXPECT_EQ(s.n, 12u);
    EXPECT_FALSE(s.capped);
}

TEST(StudyStats, JointAdaptiveDrawsWaitForEveryTargetedQuantity)
{
    // Quantity 0 is constant (met at nMin); quantity 1 alternates 1 ± 0.5 (needs ~26 draws);
    // quantity 2 is carried along untargeted and would never meet the target.
    AdaptiveOptions o;
    o.nMin = 4;
    o.nMax = 100;
    const auto r = adaptiveMeans(
        [](std::uint32_t i) {
            return std::vector<double>{2.0, i % 2 ? 1.5 : 0.5, i == 0 ? 1e6 : 0.0};
        },
        2, o);
    ASSERT_EQ(r.size(), 3u);
    EXPECT_EQ(r[0].estimate.n, r[1].estimate.n);
    EXPECT_GE(r[1].estimate.n, 20u);
    EXPECT_FALSE(r[0].estimate.capped);
    EXPECT_FALSE(r[1].estimate.capped);
    EXPECT_TRUE(r[2].estimate.capped);  // marked, but it did not drive the loop to the cap
    EXPECT_LT(r[2].estimate.n, 100u);
}

TEST(StudyStats, CrossingTimeCarriesAnErrorBar)
{
    // y = 1/x through (1, 1) and (4, 0.25), slope b = -1: the target 0.5 is crossed at x = 2, and
    // se(log x) = sqrt(se(log y)² + se(log target)²) / 1.
    const std::vector<Estimate> y = {est(1, 0.1, 10), est(0.25, 0.025, 10)};
    const auto c = firstCrossing(std::vector<double>{1, 4}, y, est(0.5, 0.05, 10));
    ASSERT_TRUE(c.crossing.found);
    EXPECT_NEAR(c.x.mean, 2, 1e-12);
    EXPECT_NEAR(c.x.se / 2, std::sqrt(2 * 0.05 * 0.05 + 0.1 * 0.1), 1e-12);
    // Below the target at the first point: a bound without an error bar.
    const auto first = firstCrossing(std::vector<double>{1, 4}, y, est(2, 0.1, 10));
    EXPECT_TRUE(first.crossing.atFirst);
    EXPECT_TRUE(std::isnan(first.x.se));
    // A capped neighbour marks the time "cap" whatever its s.e. (the slope it divides by is unsure).
    std::vector<Estimate> yc = y;
    yc[0].capped = true;
    EXPECT_TRUE(firstCrossing(std::vector<double>{1, 4}, yc, est(0.5, 0.05, 10)).x.capped);
    EXPECT_FALSE(firstCrossing(std::vector<double>{1, 4}, y, est(0.5, 0.05, 10)).x.capped);
    EXPECT_TRUE(firstCrossing(std::vector<double>{1, 4}, yc, est(2, 0.1, 10)).x.capped);  // a bound, too
}

TEST(StudyStats, SharedBudgetGoesWhereItShrinksTheErrorMostPerSecond)
{
    // Three points: 0 is quiet (constant, meets the target at nMin), 1 alternates 1 ± 0.5 and is
    // cheap (1 s per draw), 2 alternates the same way but costs 10 s per draw. With a budget of 40
    // s most extra draws go to point 1 (ten times the improvement per second at equal n), some to
    // point 2 once point 1's n is large; point 0 gets none.
    AdaptiveOptions o;
    o.nMin = 4;
    o.nMax = 200;
    std::vector<std::uint32_t> calls(3, 0);
    const double costs[3] = {1, 1, 10};
    auto draw = [&](std::size_t p, std::uint32_t i) {
        EXPECT_EQ(i, calls[p]);  // each point's draws are numbered in order
        ++calls[p];
        CostedDraw d;
        d.values = {p == 0 ? 2.0 : (i % 2 ? 1.5 : 0.5)};
        d.cost = costs[p];
        return d;
    };
    const auto r = budgetedMeans(3, draw, 1, o, 40);
    ASSERT_EQ(r.size(), 3u);
    EXPECT_EQ(r[0][0].estimate.n, 4u);
    EXPECT_FALSE(r[0][0].estimate.capped);
    EXPECT_GE(r[1][0].estimate.n, 16u);
    EXPECT_GT(r[2][0].estimate.n, 4u);
    EXPECT_GT(r[1][0].estimate.n, r[2][0].estimate.n + 8);
    EXPECT_LT(r[1][0].estimate.relSe(), r[2][0].estimate.relSe());
    // The whole budget, within one draw of it.
    const double spent = (r[1][0].estimate.n - 4) * 1.0 + (r[2][0].estimate.n - 4) * 10.0;
    EXPECT_GE(spent, 40.0);
    EXPECT_LT(spent, 40.0 + 10.0);
    EXPECT_TRUE(r[2][0].estimate.capped);  // the budget ran out before point 2 met the target
    for (std::size_t p = 0; p < 3; ++p) EXPECT_EQ(calls[p], r[p][0].estimate.n);

    // No budget: every point stops at nMin, and a point above target is marked.
    std::fill(calls.begin(), calls.end(), 0u);
    const auto none = budgetedMeans(3, draw, 1, o, 0);
    for (std::size_t p = 0; p < 3; ++p) EXPECT_EQ(none[p][0].estimate.n, 4u);
    EXPECT_TRUE(none[1][0].estimate.capped);

    // An endless budget: the cap nMax bounds every point, rare events stay marked.
    o.nMax = 16;
    const auto capped = budgetedMeans(
        2,
        [](std::size_t, std::uint32_t i) {
            return CostedDraw{{i % 50 == 3 ? 100.0 : 0.01}, 1.0};
        },
        1, o, 1e9);
    EXPECT_EQ(capped[0][0].estimate.n, 16u);
    EXPECT_EQ(capped[1][0].estimate.n, 16u);
    EXPECT_TRUE(capped[0][0].estimate.capped);
}

// A top-up (the scene study's --scene-top-up) continues a run: its earlier draws are handed back
// as draws 0 .. kept-1, cost nothing from the new budget, and the new draws continue the numbering.
TEST(StudyStats, KeptDrawsAreNotChargedToTheBudget)
{
    AdaptiveOptions o;
    o.nMin = 2;
    o.nMax = 100;
    std::vector<std::uint32_t> calls(2, 0);
    auto draw = [&](std::size_t p, std::uint32_t i) {
        EXPECT_EQ(i, calls[p]);
        ++calls[p];
        return CostedDraw{{i % 2 ? 1.5 : 0.5}, 1.0};  // relative s.e. 0.5/sqrt(n): 10% at n = 25
    };
    // No budget: each point stops at its kept count (or nMin), none charged.
    const auto kept = budgetedMeans(2, draw, 1, o, 0, {10, 0});
    EXPECT_EQ(kept[0][0].estimate.n, 10u);
    EXPECT_EQ(kept[1][0].estimate.n, 2u);
    // A budget of 5 one-second draws buys exactly 5 new draws beyond the kept ones.
    std::fill(calls.begin(), calls.end(), 0u);
    const auto more = budgetedMeans(2, draw, 1, o, 5, {10, 0});
    EXPECT_EQ(more[0][0].estimate.n + more[1][0].estimate.n, 10u + 2u + 5u);
    EXPECT_THROW(budgetedMeans(2, draw, 1, o, 0, {1, 2, 3}), std::invalid_argument);
}

// With an unlimited budget each point stops on its own values, so a run capped at 8 draws and then
// topped up to a cap of 64 ends exactly where one run capped at 64 does.
TEST(StudyStats, ATopUpEndsWhereOneLargerRunEnds)
{
    auto value = [](std::size_t p, std::uint32_t i) { return 1.0 + 0.3 * std::sin(double(7 * i + 3 * p)) * (p + 1); };
    auto draw = [&](std::size_t p, std::uint32_t i) { return CostedDraw{{value(p, i)}, 1.0}; };
    AdaptiveOptions small;
    small.nMin = 4;
    small.nMax = 8;
    const double inf = std::numeric_limits<double>::infinity();
    const auto first = budgetedMeans(3, draw, 1, small, inf);
    AdaptiveOptions large = small;
    large.nMax = 64;
    std::vector<std::uint32_t> keptCounts;
    for (const auto& r : first) keptCounts.push_back(r[0].estimate.n);
    const auto topUp = budgetedMeans(3, draw, 1, large, inf, keptCounts);
    const auto once = budgetedMeans(3, draw, 1, large, inf);
    for (std::size_t p = 0; p < 3; ++p) {
        EXPECT_EQ(topUp[p][0].values, once[p][0].values) << p;
        EXPECT_EQ(topUp[p][0].estimate.capped, once[p][0].estimate.capped) << p;
    }
    EXPECT_GT(once[2][0].estimate.n, 8u);  // the cap of the first run mattered
}

TEST(StudyStats, CrossingErrorBarWithNonAscendingTimes)
{
    // Times out of order (noise between two close counts): the crossing still gets an s.e. and n.
    const std::vector<double> t = {1.0, 3.0, 2.5, 8.0};
    const std::vector<Estimate> y = {est(1, 0.1, 5), est(0.5, 0.05, 6), est(0.45, 0.045, 7), est(0.1, 0.01, 8)};
    const auto c = firstCrossing(t, y, est(0.5, 0.05, 6));  // reached exactly at the second point
    ASSERT_TRUE(c.crossing.found);
    EXPECT_NEAR(c.x.mean, 3.0, 1e-9);
    EXPECT_TRUE(std::isfinite(c.x.se));
    EXPECT_GT(c.x.n, 0u);
}

// The scene data are read back to merge shards, so what CsvTable writes must come back cell for
// cell, including cells with commas, quotes and line breaks (RFC 4180 quoting).
TEST(StudyCsv, WhatCsvTableWritesParsesBackCellForCell)
{
    CsvTable t({"name", "pattern", "value"});
    t.add({"a", "bose q=11 N=121 t=2 cmj, 12 dims/block", "1.5"});
    t.add({"say \"hi\"", "two\nlines", ""});
    t.add({"", "", "x"});
    const CsvRows r = parseCsv(t.str(), "t.csv");
    EXPECT_EQ(r.header, (std::vector<std::string>{"name", "pattern", "value"}));
    ASSERT_EQ(r.rows.size(), 3u);
    EXPECT_EQ(r.rows[0][1], "bose q=11 N=121 t=2 cmj, 12 dims/block");
    EXPECT_EQ(r.rows[1][0], "say \"hi\"");
    EXPECT_EQ(r.rows[1][1], "two\nlines");
    EXPECT_EQ(r.rows[1][2], "");
    EXPECT_EQ(r.rows[2], (std::vector<std::string>{"", "", "x"}));
    EXPECT_EQ(r.column("value", "t.csv"), 2u);
    // CRLF line ends and a missing final newline read the same.
    const CsvRows crlf = parseCsv("a,b\r\n1,2\r\n3,4", "crlf.csv");
    ASSERT_EQ(crlf.rows.size(), 2u);
    EXPECT_EQ(crlf.rows[1], (std::vector<std::string>{"3", "4"}));
}

TEST(StudyCsv, BadCsvNamesTheFileAndTheLine)
{
    auto message = [](const std::string& text) {
        try {
            parseCsv(text, "bad.csv");
        } catch (const std::runtime_error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(message("a,b\n1,2\n3\n"), "bad.csv:3: 1 cells, the header has 2");
    EXPECT_EQ(message("a,b\n1,\"2\n"), "bad.csv:2: unterminated quoted cell");
    const CsvRows ok = parseCsv("a,b\n1,2\n", "ok.csv");
    try {
        ok.column("c", "ok.csv");
        FAIL() << "no error for a missing column";
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "ok.csv: no column \"c\"");
    }
    EXPECT_THROW(readCsv("/nonexistent/dir/x.csv"), std::runtime_error);
}
