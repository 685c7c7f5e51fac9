// The scene and cost parts of the study on tiny inputs: the curve helpers (log-log interpolation,
// first crossing, medians) against closed forms, crops, per-trial aggregation, and one tiny scene
// study and cost run on the Vulkan device with the validation layer on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "cost_study.hpp"
#include "gpu_test_support.hpp"
#include "image/image.hpp"
#include "scene/scene.hpp"
#include "render/tracer.hpp"
#include "render/scene_data.hpp"
#include "render/plan.hpp"
#include "scene_study.hpp"
#include "stats.hpp"

using namespace oas::study;

namespace {

std::vector<std::string> lines(const std::string& path)
{
    std::ifstream f(path);
    std::vector<std::string> out;
    for (std::string l; std::getline(f, l);) out.push_back(l);
    return out;
}

SamplerSpec specOf(const std::string& label)
{
    for (const auto& s : studySamplers())
        if (s.label == label) return s;
    throw std::invalid_argument(label);
}

}  // namespace

TEST(StudyCurves, InterpLogLogIsExactOnPowerLaws)
{
    // y = 3 x^-1.5 is a straight line in log-log, so interpolation between any points is exact.
    std::vector<double> x = {1, 2, 8, 100}, y;
    for (double v : x) y.push_back(3 * std::pow(v, -1.5));
    for (double at : {1.0, 1.5, 5.0, 77.0, 100.0}) EXPECT_NEAR(interpLogLog(x, y, at), 3 * std::pow(at, -1.5), 1e-12);
    EXPECT_TRUE(std::isnan(interpLogLog(x, y, 0.5)));
    EXPECT_TRUE(std::isnan(interpLogLog(x, y, 101)));
    EXPECT_TRUE(std::isnan(interpLogLog({}, {}, 1)));
}

TEST(StudyCurves, FirstCrossingOfAPowerLaw)
{
    std::vector<double> x = {10, 20, 40, 80}, y;
    for (double v : x) y.push_back(2 / v);
    const Crossing c = firstCrossing(x, y, 2 / 30.0);  // y = 2/x reaches 2/30 at x = 30
    ASSERT_TRUE(c.found);
    EXPECT_FALSE(c.atFirst);
    EXPECT_NEAR(c.x, 30, 1e-9);
    const Crossing early = firstCrossing(x, y, 1.0);  // already below at the first point
    EXPECT_TRUE(early.found && early.atFirst);
    EXPECT_EQ(early.x, 10);
    EXPECT_FALSE(firstCrossing(x, y, 1e-3).found);  // never within the range
    // A noisy, non-monotone curve: the first crossing counts.
    const Crossing bump = firstCrossing({1, 2, 3, 4}, {4, 1, 3, 0.5}, 2);
    ASSERT_TRUE(bump.found);
    EXPECT_GT(bump.x, 1);
    EXPECT_LT(bump.x, 2);
}

TEST(StudyCurves, Median)
{
    EXPECT_EQ(median({3, 1, 2}), 2);
    EXPECT_EQ(median({4, 1, 3, 2}), 2.5);
    EXPECT_TRUE(std::isnan(median({})));
}

TEST(StudyCurves, CropsStayInsideTheImage)
{
    for (const auto& c : studyScenes()) {
        for (auto [w, h] : {std::pair{64u, 64u}, {8u, 6u}, {1u, 1u}}) {
            const auto crop = cropPixels(c, w, h);
            EXPECT_GE(crop.w, 1u);
            EXPECT_GE(crop.h, 1u);
            EXPECT_LE(crop.x + crop.w, w) << c.file;
            EXPECT_LE(crop.y + crop.h, h) << c.file;
        }
    }
    const auto crop = cropPixels(studyScenes()[0], 64, 64);  // the lower right quarter
    EXPECT_EQ(crop.x, 32u);
    EXPECT_EQ(crop.y, 32u);
    EXPECT_EQ(crop.w, 32u);
    EXPECT_EQ(crop.h, 32u);
}

TEST(StudyCurves, CurvesAverageErrorsAndTakeMedianTimes)
{
    std::vector<SceneMeasurement> ms;
    auto add = [&](std::string sampler, std::uint32_t spp, std::uint32_t trial, double sec, double err) {
        SceneMeasurement m;
        m.scene = "s";
        m.sampler = sampler;
        m.spp = spp;
        m.trial = trial;
        m.seconds = sec;
        m.relMse = err;
        m.relMseCrop = 2 * err;
        ms.push_back(m);
    };
    add("A", 16, 0, 1.0, 0.2);
    add("A", 16, 1, 3.0, 0.4);
    add("A", 16, 2, 2.0, 0.6);
    add("A", 32, 0, 5.0, 0.1);
    add("B", 16, 0, 7.0, 0.9);
    const auto curves = curvesOf(ms);
    ASSERT_EQ(curves.size(), 2u);
    EXPECT_EQ(curves[0].sampler, "A");
    ASSERT_EQ(curves[0].spp.size(), 2u);
    EXPECT_EQ(curves[0].spp[0], 16);
    EXPECT_EQ(curves[0].seconds[0], 2.0);
    EXPECT_NEAR(curves[0].relMse[0], 0.4, 1e-15);
    EXPECT_NEAR(curves[0].relMseCrop[0], 0.8, 1e-15);
    EXPECT_EQ(curves[1].relMse[0], 0.9);
}

TEST(StudyCurves, CurvesCarryStandardErrorsAndTheCap)
{
    std::vector<SceneMeasurement> ms;
    for (std::uint32_t t = 0; t < 4; ++t) {
        SceneMeasurement m;
        m.scene = "s";
        m.sampler = "A";
        m.spp = 16;
        m.trial = t;
        m.seconds = 1;
        m.relMse = 1.0 + (t % 2 ? 0.5 : -0.5);  // sd = sqrt(1/3), s.e. = sqrt(1/12) = 29% of the mean
        m.relMseCrop = 2.0;                     // no spread: s.e. 0
        m.relMseWorst = 0.25;
        ms.push_back(m);
    }
    const auto c = curvesOf(ms, 0.1).front();
    EXPECT_EQ(c.relMseE[0].n, 4u);
    EXPECT_NEAR(c.relMseE[0].se, std::sqrt(1.0 / 12), 1e-12);
    EXPECT_TRUE(c.relMseE[0].capped);
    EXPECT_FALSE(c.relMseCropE[0].capped);
    EXPECT_NEAR(c.relMseRestE[0].mean, 0.75, 1e-12);
    EXPECT_NEAR(c.worstE[0].mean, 0.25, 1e-12);
}

TEST(StudyCurves, WorstPixelsContribution)
{
    // 2000 pixels, one of them 1000x the rest: top 0.1% = 2 pixels (ceil).
    std::vector<double> e(2000, 1e-3);
    e[7] = 1.0;
    e[1500] = 0.5;
    EXPECT_NEAR(worstPixelsContribution(e), (1.0 + 0.5) / 2000, 1e-15);
    // At least one pixel, even for tiny images.
    EXPECT_NEAR(worstPixelsContribution({0.1, 0.3, 0.2}), 0.3 / 3, 1e-15);
    // Per-pixel errors average to compare()'s relMSE.
    oas::image::Image ref(4, 2, 0.5f, 0.25f, 1.0f), img(4, 2, 0.6f, 0.25f, 0.9f);
    img.pixel(3, 1)[1] = 2.0f;
    const auto pe = pixelRelErrors(img, ref);
    ASSERT_EQ(pe.size(), 8u);
    double mean = 0;
    for (double v : pe) mean += v / pe.size();
    EXPECT_NEAR(mean, oas::image::compare(img, ref).relMse, 1e-12);
}

namespace {

SceneRecord recordOf(const std::string& name, const std::string& mode)
{
    SceneRecord r;
    r.name = name;
    r.width = 32;
    r.height = 24;
    r.dims = 7;
    r.crop = {8, 8, 16, 10};
    r.referenceSpp = 4096;
    r.largestSpp = 256;
    r.refErr = 1.25e-5;
    r.refErrCrop = 2.5e-5;
    r.refSeconds = 10.5;
    r.device = "llvmpipe (test)";
    r.machine = "test CPU, with a comma";
    r.date = "2026-12-01 12:00 UTC";
    r.command = "oas-study --parts scenes --scene " + name;
    r.modeLabel = mode;
    r.minSpp = 16;
    r.maxSpp = 256;
    r.paperHighSpp = name == "interior_deep" ? 0 : 4096;
    r.minTrials = 3;
    r.maxTrials = 16;
    r.relSeTarget = 0.1;
    r.extraSeconds = 120;
    r.runSeconds = 321;
    return r;
}

/// Renders of one sampler at two counts, errors ∝ 1/spp with a little spread between trials.
std::vector<SceneMeasurement> measurementsOf(const std::string& scene, const std::string& sampler, double scale)
{
    std::vector<SceneMeasurement> out;
    for (std::uint32_t spp : {16u, 128u})
        for (std::uint32_t t = 0; t < 3; ++t) {
            SceneMeasurement m;
            m.scene = scene;
            m.sampler = sampler;
            m.pattern = sampler + " N=" + std::to_string(spp) + ", quoted \"part\"";
            m.spp = spp;
            m.trial = t;
            m.seconds = 1e-3 * spp;
            m.relMse = scale / spp * (1 + 0.05 * t);
            m.relMseCrop = 2 * m.relMse;
            m.relMseRaw = m.relMse + 1e-6;
            m.relMseCropRaw = m.relMseCrop + 1e-6;
            m.relMseWorst = 0.25 * m.relMse;
            out.push_back(m);
        }
    return out;
}

}  // namespace

// Shards are merged from the files, so a record and a measurement must come back field for field.
TEST(StudyShards, RecordsAndMeasurementsRoundTripThroughTheirFiles)
{
    const auto dir = std::filesystem::path(::testing::TempDir()) / "oas_scene_records";
    std::filesystem::create_directories(dir);
    const std::vector<SceneRecord> records = {recordOf("cornell7d", "full mode"), recordOf("interior_deep", "quick mode")};
    writeSceneRecords((dir / "refs.csv").string(), records);
    const auto back = readSceneRecords((dir / "refs.csv").string());
    ASSERT_EQ(back.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        const SceneRecord &a = records[i], &b = back[i];
        EXPECT_EQ(a.name, b.name);
        EXPECT_EQ(std::tie(a.width, a.height, a.dims, a.referenceSpp, a.largestSpp, a.minSpp, a.maxSpp, a.paperHighSpp,
                           a.minTrials, a.maxTrials),
                  std::tie(b.width, b.height, b.dims, b.referenceSpp, b.largestSpp, b.minSpp, b.maxSpp, b.paperHighSpp,
                           b.minTrials, b.maxTrials));
        EXPECT_EQ(std::tie(a.crop.x, a.crop.y, a.crop.w, a.crop.h), std::tie(b.crop.x, b.crop.y, b.crop.w, b.crop.h));
        EXPECT_EQ(std::tie(a.device, a.machine, a.date, a.command, a.modeLabel, a.referenceSampler),
                  std::tie(b.device, b.machine, b.date, b.command, b.modeLabel, b.referenceSampler));
        EXPECT_DOUBLE_EQ(a.refErr, b.refErr);
        EXPECT_DOUBLE_EQ(a.refErrCrop, b.refErrCrop);
        EXPECT_DOUBLE_EQ(a.relSeTarget, b.relSeTarget);
        EXPECT_DOUBLE_EQ(a.extraSeconds, b.extraSeconds);
        EXPECT_DOUBLE_EQ(a.runSeconds, b.runSeconds);
        EXPECT_EQ(a.rareCount, b.rareCount);
        EXPECT_EQ(a.rarePixels, b.rarePixels);
    }
    auto ms = measurementsOf("cornell7d", "Random", 1e-2);
    ms[1].relMseRare = 3.5e-4;
    ms[2].rareOnly = true;
    writeSceneMeasurements((dir / "m.csv").string(), ms);
    const auto msBack = readSceneMeasurements((dir / "m.csv").string());
    ASSERT_EQ(msBack.size(), ms.size());
    for (size_t i = 0; i < ms.size(); ++i) {
        EXPECT_EQ(msBack[i].pattern, ms[i].pattern);
        EXPECT_EQ(msBack[i].spp, ms[i].spp);
        EXPECT_EQ(msBack[i].trial, ms[i].trial);
        EXPECT_NEAR(msBack[i].relMse, ms[i].relMse, 1e-5 * ms[i].relMse);  // 6 significant digits
        EXPECT_NEAR(msBack[i].relMseWorst, ms[i].relMseWorst, 1e-5 * ms[i].relMseWorst);
        EXPECT_NEAR(msBack[i].relMseRare, ms[i].relMseRare, 1e-5 * ms[i].relMseRare);
        EXPECT_EQ(msBack[i].rareOnly, ms[i].rareOnly);
    }
}

// The rare-pixel columns came later: files written before them read with the split off.
TEST(StudyShards, FilesWithoutTheRarePixelColumnsStillRead)
{
    const auto dir = std::filesystem::path(::testing::TempDir()) / "oas_scene_old_files";
    std::filesystem::create_directories(dir);
    const std::string m = (dir / "m.csv").string(), r = (dir / "r.csv").string();
    writeSceneMeasurements(m, measurementsOf("cornell7d", "Random", 1e-2));
    writeSceneRecords(r, {recordOf("cornell7d", "full mode")});
    // Drop the last two columns, as the files of 2026-12-02 and before are.
    for (const auto& path : {m, r}) {
        std::string out;
        for (const auto& line : lines(path)) {
            size_t cut = line.size();
            for (int k = 0; k < 2; ++k) cut = line.rfind(',', cut - 1);
            out += line.substr(0, cut) + "\n";
        }
        std::ofstream(path) << out;
    }
    const auto ms = readSceneMeasurements(m);
    ASSERT_EQ(ms.size(), 6u);
    for (const auto& x : ms) {
        EXPECT_EQ(x.relMseRare, 0.0);
        EXPECT_FALSE(x.rareOnly);
    }
    const auto rs = readSceneRecords(r);
    ASSERT_EQ(rs.size(), 1u);
    EXPECT_EQ(rs[0].rareCount, 0u);
    EXPECT_EQ(rs[0].rarePixels, "");
}

// The reference's s.e. against the spread of its estimate over many independent pairs of halves
// (Gaussian pixel noise of 3% of pixel values from 0.5 to 2): equal within sampling error when R,
// G, B share their noise (χ²₁ terms, the case the formula assumes), about √(5/3) = 1.29 too large
// when each channel has its own (χ²₃/3 terms: it errs large, as documented).
TEST(StudyRare, TheReferencesStandardErrorMatchesItsSpreadOverIndependentHalves)
{
    for (const bool sharedNoise : {true, false}) {
        std::mt19937 rng(sharedNoise ? 7 : 8);
        std::normal_distribution<double> noise(0.0, 1.0);
        const std::uint32_t w = 32, h = 32, pairs = 400;
        std::vector<double> estimates, ses;
        for (std::uint32_t k = 0; k < pairs; ++k) {
            oas::image::Image a(w, h), b(w, h);
            for (std::uint32_t p = 0; p < w * h; ++p) {
                const double value = 0.5 + 1.5 * double(p) / (w * h);
                for (auto* img : {&a, &b}) {
                    const double shared = noise(rng);
                    for (int c = 0; c < 3; ++c)
                        img->rgba[4 * p + c] = float(value * (1 + 0.03 * (sharedNoise ? shared : noise(rng))));
                }
            }
            const std::vector<double> e = pixelRelErrors(a, b);
            double sum = 0;
            for (double v : e) sum += v;
            estimates.push_back(sum / double(e.size()) / 4);
            ses.push_back(referenceErrorSe(e));
        }
        const Estimate spread = estimateOf(estimates);
        const double observedSd = spread.se * std::sqrt(double(pairs));
        double meanSe = 0;
        for (double v : ses) meanSe += v / pairs;
        const double ratio = meanSe / observedSd;
        if (sharedNoise)
            EXPECT_NEAR(ratio, 1.0, 0.12) << "s.e. " << meanSe << " vs observed sd " << observedSd;
        else
            EXPECT_NEAR(ratio, 1.29, 0.15) << "s.e. " << meanSe << " vs observed sd " << observedSd;
    }
}

TEST(StudyRare, PicksThePixelsWhoseHalvesDifferMostRelativeToTheirValue)
{
    oas::image::Image a(4, 2, 1, 1, 1), b(4, 2, 1, 1, 1);
    // Pixel 5 (1, 1): halves 0 and 2 around a mean of 1, relative difference 2² / (1 + 0.01).
    a.pixel(1, 1)[0] = a.pixel(1, 1)[1] = a.pixel(1, 1)[2] = 0;
    b.pixel(1, 1)[0] = b.pixel(1, 1)[1] = b.pixel(1, 1)[2] = 2;
    // Pixel 2 (2, 0): a larger absolute difference (10 vs 14) but a smaller relative one.
    a.pixel(2, 0)[0] = a.pixel(2, 0)[1] = a.pixel(2, 0)[2] = 10;
    b.pixel(2, 0)[0] = b.pixel(2, 0)[1] = b.pixel(2, 0)[2] = 14;
    oas::image::Image ref(4, 2, 1, 1, 1);
    for (size_t i = 0; i < ref.rgba.size(); ++i) ref.rgba[i] = 0.5f * (a.rgba[i] + b.rgba[i]);
    EXPECT_EQ(rarePixelsOf(a, b, ref, 2), (std::vector<std::uint32_t>{5, 2}));
    EXPECT_EQ(rarePixelsOf(a, b, ref, 1), (std::vector<std::uint32_t>{5}));
    // Ties (every other pixel: no difference) go by index; k beyond the image gives every pixel.
    EXPECT_EQ(rarePixelsOf(a, b, ref, 4), (std::vector<std::uint32_t>{5, 2, 0, 1}));
    EXPECT_EQ(rarePixelsOf(a, b, ref, 100).size(), 8u);
    EXPECT_THROW(rarePixelsOf(a, oas::image::Image(2, 2), ref, 1), std::invalid_argument);
}

TEST(StudyRare, MoreRareRendersOnlyWhileTheyCanStillReachTheTarget)
{
    auto est = [](double mean, double se, std::uint32_t n = 8) { return Estimate{mean, se, n, false}; };
    // The sum 1.0 +- 0.05: there already.
    EXPECT_FALSE(moreRareRendersHelp(est(0.5, 0.03), est(0.5, 0.04), 0.1));
    // The rare part's s.e. keeps the sum above the target: more of its renders help.
    EXPECT_TRUE(moreRareRendersHelp(est(0.5, 0.03), est(0.5, 0.2), 0.1));
    // The image renders' part alone is above the target (0.15 of 1.0) and the rare part's s.e. is a
    // third of it or less: only image renders can help.
    EXPECT_FALSE(moreRareRendersHelp(est(0.5, 0.15), est(0.5, 0.04), 0.1));
    // ... but while the rare part's s.e. is larger than that, it still shrinks the sum's.
    EXPECT_TRUE(moreRareRendersHelp(est(0.5, 0.15), est(0.5, 0.06), 0.1));
    // One batch has no s.e. yet (NaN): draw on.
    EXPECT_TRUE(moreRareRendersHelp(est(0.5, 0.03), est(0.5, std::nan(""), 1), 0.1));
}

TEST(StudyRare, PixelListsRoundTripAndBadOnesAreNamed)
{
    EXPECT_EQ(formatPixels({5, 2, 63}, 8), "5:0 2:0 7:7");
    EXPECT_EQ(parsePixels("5:0 2:0 7:7", 8, 8), (std::vector<std::uint32_t>{5, 2, 63}));
    EXPECT_TRUE(parsePixels("", 8, 8).empty());
    for (const std::string bad : {"8:0", "0:8", "1", "1:", ":1", "a:1", "1:2x", "-1:2", "1:-2", "1::2"}) {
        try {
            parsePixels("0:0 " + bad, 8, 8);
            ADD_FAILURE() << bad << " was accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find("\"" + bad + "\" is not x:y inside the 8x8 image"), std::string::npos)
                << e.what();
        }
    }
}

TEST(StudyRare, CurvesAddTheRarePixelsShareFromTheirOwnRenders)
{
    // 4 image renders: relMSE = rest + rare share, the share known per render.
    std::vector<SceneMeasurement> ms;
    const double rest[] = {1.0e-3, 1.2e-3, 0.9e-3, 1.1e-3}, share[] = {0, 5e-3, 0, 0};
    for (std::uint32_t t = 0; t < 4; ++t) {
        SceneMeasurement m;
        m.scene = "cornell7d";
        m.sampler = "Random";
        m.spp = 64;
        m.trial = t;
        m.seconds = 1.0 + t;
        m.relMse = rest[t] + share[t];
        m.relMseCrop = 2e-3;
        m.relMseRare = share[t];
        m.relMseWorst = share[t];
        ms.push_back(m);
    }
    // 3 rare-only rows (batch means of the share), with CPU times that must not count as render time.
    const double rareRows[] = {2e-4, 4e-4, 3e-4};
    for (std::uint32_t j = 0; j < 3; ++j) {
        SceneMeasurement m = ms[0];
        m.trial = 65536 + j;
        m.rareOnly = true;
        m.relMseRare = rareRows[j];
        m.relMse = m.relMseCrop = m.relMseWorst = 0;
        m.seconds = 100;
        ms.push_back(m);
    }
    const auto curves = curvesOf(ms, 0.1);
    ASSERT_EQ(curves.size(), 1u);
    const SceneCurve& c = curves[0];
    ASSERT_EQ(c.spp.size(), 1u);
    const Estimate a = estimateOf({rest[0], rest[1], rest[2], rest[3]}), b = estimateOf({2e-4, 4e-4, 3e-4});
    EXPECT_NEAR(c.relMseE[0].mean, a.mean + b.mean, 1e-15);
    EXPECT_NEAR(c.relMseE[0].se, std::sqrt(a.se * a.se + b.se * b.se), 1e-15);
    EXPECT_EQ(c.relMseE[0].n, 4u);  // the image renders
    EXPECT_EQ(c.rareRenders[0], 3 * kRareBatch);
    EXPECT_DOUBLE_EQ(c.seconds[0], 2.5);  // median of the image renders only
    EXPECT_DOUBLE_EQ(c.relMseCropE[0].mean, 2e-3);
    EXPECT_EQ(c.worstE[0].n, 4u);
    // Without rare rows the same image renders give the plain mean (the one hit dominates it).
    ms.resize(4);
    const auto plain = curvesOf(ms, 0.1);
    EXPECT_NEAR(plain[0].relMseE[0].mean, (4.2e-3 + 5e-3) / 4, 1e-15);
    EXPECT_EQ(plain[0].rareRenders[0], 0u);
}

TEST(StudyShards, BadDataFilesNameTheFileRowAndColumn)
{
    const auto dir = std::filesystem::path(::testing::TempDir()) / "oas_scene_bad";
    std::filesystem::create_directories(dir);
    auto messageOf = [&](const std::string& text, bool records) {
        const std::string path = (dir / "x.csv").string();
        std::ofstream(path) << text;
        try {
            if (records)
                readSceneRecords(path);
            else
                readSceneMeasurements(path);
        } catch (const std::runtime_error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string path = (dir / "x.csv").string();
    // The scene_references.csv of before shards had no settings columns: it is refused, by name.
    EXPECT_EQ(messageOf("scene,width,height,dims,reference_sampler,reference_spp,ref_rel_mse,ref_rel_mse_crop,seconds,"
                        "crop_x,crop_y,crop_w,crop_h\ncornell7d,32,32,7,sobol,4096,1e-5,1e-5,10,16,16,16,16\n",
                        true),
              path + ": no column \"largest_spp\"");
    const std::string header = "scene,sampler,pattern,spp,trial,seconds,rel_mse,rel_mse_crop,rel_mse_raw,rel_mse_crop_raw,"
                               "rel_mse_worst\n";
    EXPECT_EQ(messageOf(header + "c,Random,p,16,0,0.1,1e-3,1e-3,1e-3,1e-3,abc\n", false),
              path + ": row 1, column \"rel_mse_worst\": \"abc\" is not a number");
    EXPECT_EQ(messageOf(header + "c,Random,p,16,0,0.1,1e-3,1e-3,1e-3,1e-3,1\nc,Random,p,-3,0,0.1,1,1,1,1,1\n", false),
              path + ": row 2, column \"spp\": -3 is not a count in [0, 2^32 - 1]");
    EXPECT_EQ(messageOf(header + "c,Random,p,0,0,0.1,1,1,1,1,1\n", false), path + ": row 1: spp must be >= 1 and seconds >= 0");
    // A crop outside the image, and a scene twice.
    auto bad = recordOf("cornell7d", "full mode");
    bad.crop.x = 30;
    writeSceneRecords(path, {bad});
    EXPECT_THROW(readSceneRecords(path), std::runtime_error);
    writeSceneRecords(path, {recordOf("cornell7d", "full mode"), recordOf("cornell7d", "quick mode")});
    EXPECT_EQ(messageOf(lines(path)[0] + "\n" + lines(path)[1] + "\n" + lines(path)[2] + "\n", true),
              path + ": scene \"cornell7d\" appears twice");
}

TEST(StudyShards, AShardReplacesOnlyItsScenesAndKeepsTheStudyOrder)
{
    auto a = recordOf("cornell7d", "quick mode"), b = recordOf("interior_deep", "quick mode");
    auto a2 = recordOf("cornell7d", "full mode"), c = recordOf("blue_spheres9d", "full mode");
    const auto merged = mergeSceneRecords({a, b}, {c, a2});
    ASSERT_EQ(merged.size(), 3u);
    EXPECT_EQ(merged[0].name, "cornell7d");
    EXPECT_EQ(merged[0].modeLabel, "full mode");  // the fresh run's record, not the kept one
    EXPECT_EQ(merged[1].name, "blue_spheres9d");
    EXPECT_EQ(merged[2].name, "interior_deep");
    EXPECT_EQ(merged[2].modeLabel, "quick mode");

    auto kept = measurementsOf("cornell7d", "Random", 1e-2);
    for (const auto& m : measurementsOf("interior_deep", "Random", 3e-2)) kept.push_back(m);
    const auto fresh = measurementsOf("cornell7d", "Sobol", 5e-3);
    const auto mm = mergeSceneMeasurements(kept, fresh);
    ASSERT_EQ(mm.size(), 12u);  // cornell7d: only the fresh Sobol rows; interior_deep: kept
    for (size_t i = 0; i < 6; ++i) EXPECT_EQ(mm[i].sampler, "Sobol");
    for (size_t i = 6; i < 12; ++i) EXPECT_EQ(mm[i].scene, "interior_deep");
    EXPECT_EQ(mm[6].trial, 0u);  // rows keep their order within a scene
    EXPECT_EQ(mm[7].trial, 1u);
}

TEST(StudyShards, TheSectionSaysHowEachSceneWasMeasured)
{
    std::vector<SceneMeasurement> ms;
    for (const std::string scene : {"cornell7d", "interior_deep"})
        for (const std::string sampler : {"Random", "Sobol", "CMJ2D-pad"})
            for (const auto& m : measurementsOf(scene, sampler, sampler == "Random" ? 1e-2 : 4e-3)) ms.push_back(m);
    const std::vector<SamplerSpec> samplers = {specOf("Random"), specOf("Sobol"), specOf("CMJ2D-pad")};
    auto full = recordOf("cornell7d", "full mode"), reduced = recordOf("interior_deep", "reduced settings: see the command");
    const std::string mixed = sceneSection({full, reduced}, ms, samplers);
    EXPECT_NE(mixed.find("**not every scene is from the full mode with every sampler**"), std::string::npos);
    EXPECT_EQ(mixed.find("- Mode: full mode for every scene"), std::string::npos);
    EXPECT_NE(mixed.find("`build/oas-study --parts scenes --scene cornell7d` (full mode)"), std::string::npos);
    EXPECT_NE(mixed.find("`build/oas-study --parts scenes --scene interior_deep` (reduced settings: see the command)"),
              std::string::npos);
    EXPECT_NE(mixed.find("| 16–256 and the count nearest 4096 |"), std::string::npos);  // cornell7d only
    EXPECT_NE(mixed.find("| interior_deep | llvmpipe (test) |"), std::string::npos);
    // Every measured scene has its rows; a scene without a record is left out.
    EXPECT_EQ(sceneSection({full}, ms, samplers).find("| interior_deep |"), std::string::npos);
    auto fullToo = recordOf("interior_deep", "full mode");
    const std::string allFull = sceneSection({full, fullToo}, ms, samplers);
    EXPECT_NE(allFull.find("- Mode: full mode for every scene"), std::string::npos);
    // The Random curve (1e-2/spp) against Sobol's (4e-3/spp): 0.4x, decided by the error bars.
    EXPECT_NE(allFull.find("| cornell7d | Sobol | 128 |"), std::string::npos);
}

// A sampler without a count near the paper's 4096 (Bose-Bush: 2q^2, so 2048 or 8192) gets no row in
// that table, and the table names it instead of dropping it silently.
TEST(StudyShards, ThePaperCountTableNamesSamplersWithoutANearCount)
{
    std::vector<SceneMeasurement> ms;
    const std::vector<std::pair<std::string, std::vector<std::uint32_t>>> ladders = {
        {"Random", {128, 4096}}, {"CMJ2D-pad", {128, 4096}}, {"BoseBushCMJ", {128, 512}}};
    for (const auto& [sampler, counts] : ladders)
        for (std::uint32_t spp : counts)
            for (std::uint32_t t = 0; t < 3; ++t) {
                SceneMeasurement m = measurementsOf("cornell7d", sampler, 1e-2)[0];
                m.spp = spp;
                m.trial = t;
                m.relMse = 1e-2 / spp * (1 + 0.05 * t);
                m.relMseCrop = 2 * m.relMse;
                m.relMseWorst = 0.25 * m.relMse;
                ms.push_back(m);
            }
    const std::vector<SamplerSpec> samplers = {specOf("Random"), specOf("CMJ2D-pad"), specOf("BoseBushCMJ")};
    auto rec = recordOf("cornell7d", "full mode");
    rec.largestSpp = 4096;
    const std::string md = sceneSection({rec}, ms, samplers);
    const auto table = md.find("### At the paper's high count");
    ASSERT_NE(table, std::string::npos);
    const std::string rest = md.substr(table, md.find("### Rare events") - table);
    EXPECT_NE(rest.find("| cornell7d | CMJ2D-pad | 4096 |"), std::string::npos);
    EXPECT_EQ(rest.find("| cornell7d | BoseBushCMJ |"), std::string::npos);
    EXPECT_NE(rest.find("No row for BoseBushCMJ (measured up to 512): no valid count within a quarter octave of 4096"),
              std::string::npos);
    // With every sampler near 4096 there is nothing to name.
    const std::vector<SamplerSpec> two = {specOf("Random"), specOf("CMJ2D-pad")};
    EXPECT_EQ(sceneSection({rec}, ms, two).find("No row for"), std::string::npos);
}

TEST(StudyShards, SamplerShardsJoinOnlyWithTheSameSettings)
{
    const auto kept = recordOf("interior_deep", "full mode");
    auto fresh = kept;
    fresh.date = "2026-12-02 08:00 UTC";
    fresh.command = "oas-study --parts scenes --scene interior_deep --only Sobol";
    fresh.machine = "another CPU";
    fresh.runSeconds = 100;
    fresh.extraSeconds = 30;
    fresh.refErr = 9e-3;  // a shard that joins renders no reference: kept's stays
    std::string why;
    EXPECT_TRUE(sameSceneSettings(kept, fresh, &why)) << why;  // dates, machines, commands may differ
    for (int field = 0; field < 6; ++field) {
        auto other = fresh;
        const char* expect[] = {"size", "crop", "reference", "spp ladder", "renders per point", "mode"};
        if (field == 0) other.height = 25;
        if (field == 1) other.crop.x = 9;
        if (field == 2) other.referenceSpp = 8192;
        if (field == 3) other.maxSpp = 512;
        if (field == 4) other.maxTrials = 64;
        if (field == 5) other.modeLabel = "quick mode";
        why.clear();
        EXPECT_FALSE(sameSceneSettings(kept, other, &why)) << field;
        EXPECT_EQ(why.rfind(expect[field], 0), 0u) << why;
    }

    const SceneRecord joined = joinShardRecord(kept, fresh);
    EXPECT_DOUBLE_EQ(joined.refErr, kept.refErr);
    EXPECT_DOUBLE_EQ(joined.refSeconds, kept.refSeconds);
    EXPECT_DOUBLE_EQ(joined.runSeconds, 321 + 100);
    EXPECT_DOUBLE_EQ(joined.extraSeconds, 120 + 30);
    EXPECT_EQ(joined.date, "2026-12-01 12:00 UTC + 2026-12-02 08:00 UTC");
    EXPECT_EQ(joined.machine, "test CPU, with a comma + another CPU");
    EXPECT_EQ(joined.command, kept.command + " ; " + fresh.command);
    // A third shard on the same day and machine lists them once each.
    auto third = fresh;
    third.command = "oas-study --parts scenes --scene interior_deep --only Random";
    const SceneRecord again = joinShardRecord(joined, third);
    EXPECT_EQ(again.date, joined.date);
    EXPECT_EQ(again.machine, joined.machine);
    EXPECT_EQ(again.command, joined.command + " ; " + third.command);

    // Only the shard's (scene, sampler) rows are replaced; other samplers and scenes are kept.
    auto rows = measurementsOf("interior_deep", "Random", 1e-2);
    for (const auto& m : measurementsOf("interior_deep", "Sobol", 5e-3)) rows.push_back(m);
    for (const auto& m : measurementsOf("cornell7d", "Sobol", 5e-3)) rows.push_back(m);
    auto redo = measurementsOf("interior_deep", "Sobol", 4e-3);
    const auto merged = mergeSamplerShard(rows, redo);
    ASSERT_EQ(merged.size(), 18u);
    for (size_t i = 0; i < 6; ++i) EXPECT_EQ(merged[i].scene, "cornell7d");  // study order: cornell7d first
    for (size_t i = 6; i < 12; ++i) EXPECT_EQ(merged[i].sampler, "Random");
    for (size_t i = 12; i < 18; ++i) {
        EXPECT_EQ(merged[i].sampler, "Sobol");
        EXPECT_DOUBLE_EQ(merged[i].relMse, redo[i - 12].relMse);
    }
}

// scripts/study_cluster.py's merge: every task folder is a copy of the base after one sampler
// shard; the base's part (rows, seconds, date, command) counts once, and a folder whose reference
// is not the base's is refused.
TEST(StudyShards, MergingTaskFoldersCountsTheBaseOnceAndRefusesAnotherReference)
{
    namespace fs = std::filesystem;
    const fs::path root = fs::path(::testing::TempDir()) / "oas_merge_scene_shards";
    fs::remove_all(root);
    auto folder = [&](const std::string& name, const std::vector<SceneRecord>& records,
                      const std::vector<SceneMeasurement>& rows) {
        fs::create_directories(root / name / "scenes");
        writeSceneRecords((root / name / "scene_references.csv").string(), records);
        writeSceneMeasurements((root / name / "scenes.csv").string(), rows);
        return (root / name).string();
    };
    const SceneRecord base = recordOf("cornell7d", "full mode");  // runSeconds 321, extraSeconds 120
    const auto sobol = measurementsOf("cornell7d", "Sobol", 5e-3);
    const std::string baseDir = folder("base", {base}, sobol);
    std::vector<std::string> shardDirs;
    for (const std::string sampler : {"BoseCMJ", "Random"}) {
        SceneRecord own = base;
        own.runSeconds = 50;
        own.extraSeconds = 10;
        own.date = "2026-12-04 01:00 UTC";
        own.command = "oas-study --only " + sampler;
        auto rows = sobol;
        for (const auto& m : measurementsOf("cornell7d", sampler, 1e-2)) rows.push_back(m);
        shardDirs.push_back(folder(sampler, {joinShardRecord(base, own)}, rows));
    }
    const fs::path out = root / "out";
    fs::create_directories(out);
    // A scene outside the base stays as it was.
    writeSceneRecords((out / "scene_references.csv").string(), {recordOf("interior_deep", "full mode")});
    writeSceneMeasurements((out / "scenes.csv").string(), measurementsOf("interior_deep", "Sobol", 1e-3));
    mergeSceneShards(out.string(), baseDir, shardDirs, studySamplers(), "scripts/study_cluster.py --workers 2");
    const auto records = readSceneRecords((out / "scene_references.csv").string());
    ASSERT_EQ(records.size(), 2u);
    EXPECT_EQ(records[0].name, "cornell7d");
    EXPECT_DOUBLE_EQ(records[0].runSeconds, 321 + 50 + 50);
    EXPECT_DOUBLE_EQ(records[0].extraSeconds, 120 + 10 + 10);
    EXPECT_EQ(records[0].date, base.date + " + 2026-12-04 01:00 UTC");
    EXPECT_EQ(records[0].command, "scripts/study_cluster.py --workers 2");
    EXPECT_EQ(records[1].name, "interior_deep");
    const auto rows = readSceneMeasurements((out / "scenes.csv").string());
    std::map<std::string, int> perSampler;
    for (const auto& m : rows) perSampler[m.scene + " " + m.sampler]++;
    EXPECT_EQ(perSampler,
              (std::map<std::string, int>{
                  {"cornell7d Sobol", 6}, {"cornell7d BoseCMJ", 6}, {"cornell7d Random", 6}, {"interior_deep Sobol", 6}}));

    // A task folder whose reference differs (it started the scene over) is refused, by name.
    SceneRecord other = base;
    other.refErr *= 2;
    const std::string stray = folder("stray", {other}, sobol);
    try {
        mergeSceneShards(out.string(), baseDir, {stray}, studySamplers());
        FAIL() << "a folder with another reference merged";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(stray), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("reference"), std::string::npos) << e.what();
    }
}

TEST(StudyShards, TheSectionNamesTheSamplersAShardedSceneLacks)
{
    std::vector<SceneMeasurement> ms;
    for (const std::string sampler : {"Random", "Sobol"})
        for (const auto& m : measurementsOf("interior_deep", sampler, sampler == "Random" ? 1e-2 : 4e-3)) ms.push_back(m);
    const std::vector<SamplerSpec> samplers = {specOf("Random"), specOf("Sobol"), specOf("CMJ2D-pad")};
    const std::string md = sceneSection({recordOf("interior_deep", "full mode")}, ms, samplers);
    EXPECT_NE(md.find("**interior_deep has 2 of the 3 samplers so far** (sampler shards); not yet measured, so absent "
                      "from its tables: CMJ2D-pad."),
              std::string::npos);
    // A full-mode record with a sampler missing is not "full mode for every scene".
    EXPECT_EQ(md.find("full mode for every scene"), std::string::npos);
    const std::string complete = sceneSection({recordOf("interior_deep", "full mode")}, ms, {specOf("Random"), specOf("Sobol")});
    EXPECT_EQ(complete.find("so far"), std::string::npos);
    EXPECT_NE(complete.find("full mode for every scene"), std::string::npos);
    // A joined record's commands each get their own code span.
    auto rec = recordOf("interior_deep", "full mode");
    rec.command = "oas-study --only Random ; oas-study --only Sobol";
    EXPECT_NE(sceneSection({rec}, ms, samplers).find("`build/oas-study --only Random` then `build/oas-study --only Sobol`"),
              std::string::npos);
}

class StudyGpu : public oas::test::GpuTest {};

namespace {

/// A tiny cornell7d scene study (8 px wide, 2 renders per point) writing into a fresh temp folder.
SceneStudyOptions tinyCornell(const std::string& folder, std::uint32_t maxSpp, std::uint32_t referenceSpp)
{
    const auto dir = std::filesystem::path(::testing::TempDir()) / folder;
    std::filesystem::remove_all(dir);
    SceneStudyOptions o;
    o.scenesDir = OAS_SCENES_DIR;
    o.scenes = {"cornell7d"};
    o.width = 8;
    o.minSpp = 16;
    o.maxSpp = maxSpp;
    o.referenceSpp = referenceSpp;
    o.minTrials = 2;  // a fixed n = 2: the adaptive loop stops at its cap, and the tables mark it
    o.maxTrials = 2;
    o.rarePixels = 0;  // image renders only, unless a test asks for the rare-pixel split
    o.outDir = dir.string();
    return o;
}

}  // namespace

TEST_F(StudyGpu, TinySceneStudyWritesConsistentTables)
{
    SceneStudyOptions o = tinyCornell("oas_scene_study", 128, 1024);
    const std::filesystem::path dir = o.outDir;
    o.command = "test";
    const std::string md = runSceneStudy(o, {specOf("Random"), specOf("Sobol")}, context());

    // Random: powers of two 16..128 plus Bose's counts in [16, 128]; Sobol: powers of two.
    const auto rows = lines((dir / "scenes.csv").string());
    ASSERT_GT(rows.size(), 1u);
    std::map<std::string, std::map<std::uint32_t, std::vector<double>>> err;
    for (size_t i = 1; i < rows.size(); ++i) {
        std::stringstream ss(rows[i]);
        std::vector<std::string> cells;
        for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
        ASSERT_EQ(cells.size(), 13u) << rows[i];
        const double seconds = std::stod(cells[5]), rel = std::stod(cells[6]);
        EXPECT_GT(seconds, 0);
        EXPECT_TRUE(std::isfinite(rel));
        err[cells[1]][std::stoul(cells[3])].push_back(std::stod(cells[8]));  // uncorrected: > 0
    }
    ASSERT_EQ(err["Sobol"].size(), 4u);     // 16, 32, 64, 128
    EXPECT_TRUE(err["Random"].count(121));  // a Bose count: matched spp
    for (auto& [sampler, bySpp] : err)
        for (auto& [spp, v] : bySpp) {
            EXPECT_EQ(v.size(), 2u);
            for (double e : v) EXPECT_GT(e, 0) << sampler << " " << spp;
        }
    // Independent samples: relMSE ∝ 1/spp, so 8x the samples must lower it clearly (both trials).
    for (size_t t = 0; t < 2; ++t) EXPECT_LT(err["Random"][128][t], 0.5 * err["Random"][16][t]);
    // No OA sampler ran, so the 7D goal is not measured, and the report says so.
    EXPECT_NE(md.find("not measured"), std::string::npos);
    EXPECT_NE(md.find("### Error at equal time"), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(dir / "scenes" / "cornell7d_reference.png"));
    EXPECT_TRUE(std::filesystem::exists(dir / "scenes" / "cornell7d_Random_error.png"));
    EXPECT_EQ(lines((dir / "scene_equal_time.csv").string()).size(), 3u);  // header + 2 samplers
    // Every relMSE carries its n, and the worst-pixel table is there.
    EXPECT_NE(md.find("(n=2"), std::string::npos);
    EXPECT_NE(md.find("### Rare events"), std::string::npos);
    const auto curveRows = lines((dir / "scene_curves.csv").string());
    ASSERT_GT(curveRows.size(), 1u);
    EXPECT_NE(curveRows[0].find("rel_mse_se"), std::string::npos);
    // The section is a function of the data files alone (what `--parts none` reassembles).
    EXPECT_EQ(sceneSectionFromFiles(dir.string(), {specOf("Random"), specOf("Sobol")}), md);

    // A second shard: another scene, run alone, merges in; cornell7d's rows stay as they were.
    const auto before = lines((dir / "scenes.csv").string());
    o.scenes = {"blue_spheres9d"};
    o.maxSpp = 128;
    // (Random only, to keep the test short: one pipeline fewer; the reference still needs Sobol's.)
    const std::string merged = runSceneStudy(o, {specOf("Random")}, context());
    const auto after = lines((dir / "scenes.csv").string());
    ASSERT_GT(after.size(), before.size());
    for (size_t i = 0; i < before.size(); ++i) EXPECT_EQ(after[i], before[i]) << i;  // cornell7d first, unchanged
    for (size_t i = before.size(); i < after.size(); ++i) EXPECT_EQ(after[i].rfind("blue_spheres9d,", 0), 0u) << after[i];
    EXPECT_EQ(readSceneRecords((dir / "scene_references.csv").string()).size(), 2u);
    // cornell7d's equal-time rows are kept; blue_spheres9d has none (no Sobol curve, so no budget).
    EXPECT_EQ(lines((dir / "scene_equal_time.csv").string()).size(), 3u);
    // The section has both scenes, for the samplers it was asked about.
    EXPECT_NE(merged.find("| cornell7d | Random | 128 |"), std::string::npos);
    EXPECT_NE(merged.find("| blue_spheres9d | Random | 128 |"), std::string::npos);
    EXPECT_EQ(merged.find("| cornell7d | Sobol |"), std::string::npos);
    EXPECT_NE(merged.find("(n=2"), std::string::npos);
}

TEST_F(StudyGpu, TinyCostRunMeasuresEverySampler)
{
    const auto dir = std::filesystem::path(::testing::TempDir()) / "oas_cost_study";
    std::filesystem::create_directories(dir);
    CostOptions o;
    o.pixels = 256;
    o.dims = 4;
    o.repeats = 1;
    o.outDir = dir.string();
    const std::string md = runCostStudy(o, {specOf("Random"), specOf("BoseCMJ")}, context());
    const auto rows = lines((dir / "cost.csv").string());
    ASSERT_EQ(rows.size(), 3u);
    EXPECT_NE(rows[2].find("bose q=11"), std::string::npos);  // 121 spp: the count nearest 128
    EXPECT_NE(md.find("| BoseCMJ |"), std::string::npos);
}

// A sampler shard run with the full mode's defaults takes the kept record's reference count and
// renders-per-point range: its own default reference would follow its own largest count (a shard
// of baselines computed 65536 where the scene's record, set by Addelman-Kempthorne's 4418, had
// 131072) and the scene would start over, dropping every other sampler's rows.
TEST_F(StudyGpu, AShardWithDefaultSettingsTakesTheKeptReferenceAndRendersPerPoint)
{
    SceneStudyOptions o = tinyCornell("oas_shard_takes_kept", 32, 2048);  // default would be 16 x 32 = 512
    const std::filesystem::path dir = o.outDir;
    o.samplerShard = true;
    runSceneStudy(o, {specOf("Random")}, context());
    const auto first = readSceneRecords((dir / "scene_references.csv").string()).at(0);
    ASSERT_EQ(first.referenceSpp, 2048u);
    o.referenceSpp = 0;  // the defaults: 512 and 2 to 3 renders, neither the record's
    o.maxTrials = 3;
    o.mustJoin = true;  // an error instead of a restart where it cannot join
    EXPECT_THROW(runSceneStudy(o, {specOf("Sobol")}, context()), std::invalid_argument);
    o.shardTakesKeptSettings = true;
    runSceneStudy(o, {specOf("Sobol")}, context());
    const auto joined = readSceneRecords((dir / "scene_references.csv").string()).at(0);
    EXPECT_EQ(joined.referenceSpp, 2048u);
    EXPECT_EQ(joined.maxTrials, first.maxTrials);
    std::set<std::string> samplers;
    for (const auto& m : readSceneMeasurements((dir / "scenes.csv").string())) samplers.insert(m.sampler);
    EXPECT_EQ(samplers, (std::set<std::string>{"Random", "Sobol"}));
}

// The Dask driver's first task renders the reference with Sobol alone; the reference count must
// be the one the whole run picks, 16x the largest count over every sampler of the mode. With a
// high count of 98 (the study's 4096 in miniature), Addelman-Kempthorne has 2 x 7^2 = 98, so
// 16 x 98 = 1568 rounds up to 2048; Sobol has no power of two within 2^(1/4) of 98, so its own
// largest is the ladder's 32, which gives 512.
TEST_F(StudyGpu, AFirstShardTakesTheWholeModesReferenceCount)
{
    SceneStudyOptions o = tinyCornell("oas_first_shard_reference", 32, 0);
    const std::filesystem::path dir = o.outDir;
    o.paperHighSpp = 98;
    o.samplerShard = true;
    o.modeSamplers = {specOf("Sobol"), specOf("AddelmanKempthorneCMJ")};
    runSceneStudy(o, {specOf("Sobol")}, context());
    EXPECT_EQ(readSceneRecords((dir / "scene_references.csv").string()).at(0).referenceSpp, 2048u);
    // Negative control: without the mode's samplers the shard's own largest count decides.
    std::filesystem::remove_all(dir);
    o.modeSamplers.clear();
    runSceneStudy(o, {specOf("Sobol")}, context());
    EXPECT_EQ(readSceneRecords((dir / "scene_references.csv").string()).at(0).referenceSpp, 512u);
}

// A shard whose scene's reference image is gone can render it again, and joins only if it is the
// same image: with the record's sampler it is (renders are deterministic); with another it stops.
TEST_F(StudyGpu, AMissingReferenceIsRebuiltOnlyAsTheSameImage)
{
    SceneStudyOptions o = tinyCornell("oas_shard_rebuild", 32, 1024);
    const std::filesystem::path dir = o.outDir;
    o.samplerShard = true;
    runSceneStudy(o, {specOf("Random")}, context());
    const auto exr = dir / "scenes" / "cornell7d_reference.exr";
    const oas::image::Image original = oas::image::readExr(exr.string());
    std::filesystem::remove(exr);
    o.mustJoin = true;
    EXPECT_THROW(runSceneStudy(o, {specOf("Sobol")}, context()), std::invalid_argument);  // no image, no rebuild
    o.rebuildReferenceWith = "sobol-owen";  // another scramble: another image
    EXPECT_THROW(runSceneStudy(o, {specOf("Sobol")}, context()), std::invalid_argument);
    o.rebuildReferenceWith = "sobol";
    runSceneStudy(o, {specOf("Sobol")}, context());
    EXPECT_EQ(oas::image::readExr(exr.string()).rgba, original.rgba);
    std::set<std::string> samplers;
    for (const auto& m : readSceneMeasurements((dir / "scenes.csv").string())) samplers.insert(m.sampler);
    EXPECT_EQ(samplers, (std::set<std::string>{"Random", "Sobol"}));
}

TEST_F(StudyGpu, ASamplerShardReusesTheReferenceAndReplacesOnlyItsSamplers)
{
    SceneStudyOptions o = tinyCornell("oas_sampler_shards", 128, 512);  // the equal-time budget is Sobol at 128
    const std::filesystem::path dir = o.outDir;
    o.command = "first";
    o.samplerShard = true;  // nothing to join yet: the scene starts, with its own reference
    runSceneStudy(o, {specOf("Random"), specOf("Sobol")}, context());
    const auto exr = dir / "scenes" / "cornell7d_reference.exr";
    ASSERT_TRUE(std::filesystem::exists(exr));
    const auto firstRecord = readSceneRecords((dir / "scene_references.csv").string()).at(0);
    const auto firstRows = readSceneMeasurements((dir / "scenes.csv").string());
    const oas::image::Image firstReference = oas::image::readExr(exr.string());

    // Shard 2: Sobol again and CMJ2D-pad; Random's rows stay, Sobol's are replaced.
    o.command = "second";
    runSceneStudy(o, {specOf("Sobol"), specOf("CMJ2D-pad")}, context());
    const auto record = readSceneRecords((dir / "scene_references.csv").string()).at(0);
    EXPECT_EQ(record.command, "first ; second");
    EXPECT_EQ(record.refErr, firstRecord.refErr);  // the same reference, not rendered again
    EXPECT_EQ(record.refSeconds, firstRecord.refSeconds);
    EXPECT_GT(record.runSeconds, firstRecord.runSeconds);
    EXPECT_EQ(oas::image::readExr(exr.string()).rgba, firstReference.rgba);
    const auto rows = readSceneMeasurements((dir / "scenes.csv").string());
    std::map<std::string, size_t> count;
    for (const auto& m : rows) ++count[m.sampler];
    size_t randomRows = 0;
    for (const auto& m : firstRows) randomRows += m.sampler == "Random";
    EXPECT_EQ(count["Random"], randomRows);
    EXPECT_EQ(count["Sobol"], 4u * 2u);  // 16 ... 128 x 2 renders
    EXPECT_EQ(count["CMJ2D-pad"], 4u * 2u);
    for (const auto& m : rows) {
        if (m.sampler != "Random") continue;
        EXPECT_TRUE(std::any_of(firstRows.begin(), firstRows.end(), [&](const SceneMeasurement& f) {
            return f.sampler == "Random" && f.spp == m.spp && f.trial == m.trial && f.relMse == m.relMse;
        }));
    }
    // Seeds come from the sampler's place in the study's list, not in the run's: Sobol, second in
    // shard 1 and first in shard 2, renders the same images against the same reference.
    for (const auto& m : rows) {
        if (m.sampler != "Sobol") continue;
        EXPECT_TRUE(std::any_of(firstRows.begin(), firstRows.end(),
                                [&](const SceneMeasurement& f) {
                                    return f.sampler == "Sobol" && f.spp == m.spp && f.trial == m.trial &&
                                           f.relMseRaw == m.relMseRaw;
                                }))
            << m.spp << " " << m.trial;
    }
    // Equal-time rows: all three samplers (the budget is Sobol's), in table order.
    const auto eq = lines((dir / "scene_equal_time.csv").string());
    ASSERT_EQ(eq.size(), 4u);
    EXPECT_EQ(eq[1].rfind("cornell7d,Random,", 0), 0u);
    EXPECT_EQ(eq[3].rfind("cornell7d,Sobol,", 0), 0u);

    // Other settings: the scene starts over, with only this shard's sampler.
    o.maxTrials = 3;
    o.command = "third";
    runSceneStudy(o, {specOf("Random")}, context());
    const auto restarted = readSceneRecords((dir / "scene_references.csv").string()).at(0);
    EXPECT_EQ(restarted.command, "third");
    for (const auto& m : readSceneMeasurements((dir / "scenes.csv").string())) EXPECT_EQ(m.sampler, "Random");
}

TEST_F(StudyGpu, ATopUpAddsRendersWhereASingleLargerRunWould)
{
    // Target 0.1% (unreachable in a few renders): every point draws up to its cap.
    SceneStudyOptions o = tinyCornell("oas_top_up", 32, 512);
    const std::filesystem::path dir = o.outDir;
    o.relSeTarget = 1e-3;
    o.command = "first";
    runSceneStudy(o, {specOf("Random"), specOf("Sobol")}, context());
    const auto firstRecord = readSceneRecords((dir / "scene_references.csv").string()).at(0);
    const auto firstRows = readSceneMeasurements((dir / "scenes.csv").string());
    const auto firstEq = lines((dir / "scene_equal_time.csv").string());

    // A top-up may not lower the cap, nor change what the renders measure.
    o.topUp = true;
    o.maxTrials = 1;
    o.minTrials = 1;
    EXPECT_THROW(runSceneStudy(o, {specOf("Random")}, context()), std::invalid_argument);
    o.minTrials = o.maxTrials = 2;
    o.width = 16;
    EXPECT_THROW(runSceneStudy(o, {specOf("Random")}, context()), std::invalid_argument);
    o.width = 8;
    EXPECT_EQ(readSceneMeasurements((dir / "scenes.csv").string()).size(), firstRows.size());  // nothing written

    // Cap 2 -> 4 with an ample budget: two more renders per point, numbered on.
    o.maxTrials = 4;
    o.extraSecondsPerScene = 1e6;
    o.command = "second";
    runSceneStudy(o, {specOf("Random"), specOf("Sobol")}, context());
    const auto record = readSceneRecords((dir / "scene_references.csv").string()).at(0);
    EXPECT_EQ(record.command, "first ; second");
    EXPECT_EQ(record.maxTrials, 4u);
    EXPECT_EQ(record.refErr, firstRecord.refErr);  // the kept reference
    EXPECT_EQ(record.extraSeconds, firstRecord.extraSeconds + 1e6);
    const auto rows = readSceneMeasurements((dir / "scenes.csv").string());
    ASSERT_EQ(rows.size(), 2 * firstRows.size());
    for (const auto& f : firstRows)  // the earlier renders, unchanged
        EXPECT_TRUE(std::any_of(rows.begin(), rows.end(),
                                [&](const SceneMeasurement& m) {
                                    return m.sampler == f.sampler && m.spp == f.spp && m.trial == f.trial &&
                                           m.relMseRaw == f.relMseRaw && m.seconds == f.seconds;
                                }))
            << f.sampler << "@" << f.spp << " trial " << f.trial;
    EXPECT_EQ(lines((dir / "scene_equal_time.csv").string()), firstEq);  // no new trial-0 images

    // One run with the cap of 4 from the start renders the same trials 2 and 3 (the same seeds).
    SceneStudyOptions once = tinyCornell("oas_top_up_once", 32, 512);
    once.relSeTarget = 1e-3;
    once.maxTrials = 4;
    once.extraSecondsPerScene = 1e6;
    runSceneStudy(once, {specOf("Random"), specOf("Sobol")}, context());
    const auto onceRows = readSceneMeasurements((std::filesystem::path(once.outDir) / "scenes.csv").string());
    ASSERT_EQ(onceRows.size(), rows.size());
    for (const auto& m : onceRows)
        EXPECT_TRUE(std::any_of(rows.begin(), rows.end(),
                                [&](const SceneMeasurement& r) {
                                    return r.sampler == m.sampler && r.spp == m.spp && r.trial == m.trial &&
                                           r.relMseRaw == m.relMseRaw;
                                }))
            << m.sampler << "@" << m.spp << " trial " << m.trial;

    // A scene without an earlier record cannot be topped up.
    o.scenes = {"blue_spheres9d"};
    EXPECT_THROW(runSceneStudy(o, {specOf("Random")}, context()), std::invalid_argument);
}

TEST_F(StudyGpu, TheRarePixelsShareOnTheCpuIsTheGpuRendersShare)
{
    // The study adds the rare pixels' share from CPU renders of just those pixels to the GPU
    // renders' rest: that is only the same estimator if a CPU render with a seed gives those
    // pixels what the GPU render with that seed gives them.
    auto scene = oas::scene::loadScene(std::string(OAS_SCENES_DIR) + "/cornell7d.json");
    scene.width = scene.height = 16;
    const auto plan = oas::render::planDimensions(scene);
    const auto data = oas::render::flattenScene(scene);
    const auto pattern = oas::makePattern(patternRequest(specOf("BoseCMJ"), 121, plan.sampleDims));
    oas::render::GpuTracer gpu(context(), data, plan, pattern);
    auto renderWith = [&](std::uint32_t seed) {
        gpu.clear();
        oas::render::forEachBatch(16, 16, 121, gpu.samplesPerBatch(), seed,
                                  [&](const oas::render::SampleBatch& b) { gpu.trace(b); });
        return gpu.accumulation().image();
    };
    // Against another render as the "reference", so that the error is all noise and a render
    // with another seed has a clearly different one.
    const oas::image::Image reference = renderWith(0x7654321u);
    const std::uint32_t seed = 0x1234567u;
    const auto image = renderWith(seed);
    const auto errors = pixelRelErrors(image, reference);
    const std::vector<std::uint32_t> pixels = {0, 17, 8 * 16 + 8, 15 * 16 + 3, 255};
    double gpuShare = 0;
    for (auto p : pixels) gpuShare += errors[p] / 256.0;
    oas::render::Accumulation scratch;
    const double cpuShare = rarePixelsShareCpu(data, plan, pattern, pixels, 121, seed, reference, scratch);
    ASSERT_GT(gpuShare, 0.0);
    EXPECT_NEAR(cpuShare, gpuShare, 1e-3 * gpuShare);  // float evaluation order only
    // Another seed is another render: a check that the seed is what ties them.
    const double other = rarePixelsShareCpu(data, plan, pattern, pixels, 121, seed + 1, reference, scratch);
    EXPECT_GT(std::abs(other - gpuShare), 0.1 * gpuShare);
}

TEST_F(StudyGpu, TheRarePixelSplitAddsRendersOfThosePixelsToEveryPoint)
{
    SceneStudyOptions o = tinyCornell("oas_rare_pixels", 32, 512);
    const std::filesystem::path dir = o.outDir;
    o.rarePixels = 2;
    o.maxRareRenders = 64;
    o.command = "test";
    const std::string md = runSceneStudy(o, {specOf("Sobol")}, context());
    const auto record = readSceneRecords((dir / "scene_references.csv").string()).at(0);
    EXPECT_EQ(record.rareCount, 2u);
    EXPECT_EQ(parsePixels(record.rarePixels, 8, 8).size(), 2u);
    std::map<std::uint32_t, std::uint32_t> rareRows, imageRows;
    for (const auto& m : readSceneMeasurements((dir / "scenes.csv").string())) {
        (m.rareOnly ? rareRows : imageRows)[m.spp]++;
        if (m.rareOnly) {
            EXPECT_GE(m.relMseRare, 0.0);
            EXPECT_GE(m.trial, 65536u);
        } else {
            EXPECT_LE(m.relMseRare, m.relMseRaw + 1e-12);  // a part of the render's error
        }
    }
    for (std::uint32_t spp : {16u, 32u}) {
        EXPECT_EQ(imageRows[spp], 2u);
        EXPECT_GE(rareRows[spp], 2u);               // at least two batches
        EXPECT_LE(rareRows[spp], 64 / kRareBatch);  // at most maxRareRenders
    }
    EXPECT_NE(md.find("rare-pixel split"), std::string::npos);
    EXPECT_NE(md.find(record.rarePixels), std::string::npos);
    const auto curves = lines((dir / "scene_curves.csv").string());
    EXPECT_NE(curves[0].find("rare_renders"), std::string::npos);
}

// The section says, per scene, how many points hit the cap and what finishing them would cost:
// with s.e. ∝ 1/√n a point at relative s.e. r after n renders needs n·(r/0.1)² renders in all.
TEST(StudyShards, TheSectionStatesWhatTheCappedPointsWouldCost)
{
    auto ms = measurementsOf("cornell7d", "Random", 1e-2);  // 128 spp: s.e. 2.7% of the mean, not capped
    ms.erase(std::remove_if(ms.begin(), ms.end(), [](const SceneMeasurement& m) { return m.spp == 16; }), ms.end());
    // 16 spp: relMSE 1, 1, 1, 3 (mean 1.5, sd 1, s.e. 0.5: a third of the mean), 100 s per render.
    for (std::uint32_t t = 0; t < 4; ++t) {
        SceneMeasurement m = ms[0];
        m.spp = 16;
        m.trial = t;
        m.seconds = 100;
        m.relMse = m.relMseCrop = t == 3 ? 3.0 : 1.0;
        m.relMseWorst = 0;
        ms.push_back(m);
    }
    const std::string md = sceneSection({recordOf("cornell7d", "full mode")}, ms, {specOf("Random")});
    // 4 × ((1/3 ÷ 0.1)² − 1) × 100 s = 4044 s = 1.1 h.
    EXPECT_NE(md.find("1 of 2 points hit the cap (per scene: cornell7d 1 of 2, about 1.1 h more of renders on its "
                      "device to finish them;"),
              std::string::npos)
        << md.substr(md.find("points hit the cap") - 10, 300);
    // With the rare-pixel split the same: its rare stage stops once the image renders' part has the
    // larger s.e. (moreRareRendersHelp), so image renders are what a capped point lacks there too.
    auto split = recordOf("cornell7d", "full mode");
    split.rareCount = 2;
    split.rarePixels = "1:1 2:2";
    const std::string md2 = sceneSection({split}, ms, {specOf("Random")});
    EXPECT_NE(md2.find("cornell7d 1 of 2, about 1.1 h more of renders on its device to finish them;"), std::string::npos);
    // Under an hour it is said in minutes (the quick study's caps cost seconds: "0.0 h" said nothing).
    for (auto& m : ms) m.seconds /= 100;  // 40 s: "about 1 min"
    const std::string md3 = sceneSection({recordOf("cornell7d", "full mode")}, ms, {specOf("Random")});
    EXPECT_NE(md3.find("cornell7d 1 of 2, about 1 min more of renders on its device to finish them;"), std::string::npos)
        << md3.substr(md3.find("points hit the cap") - 10, 300);
}
