// The scene and cost parts of the study on tiny inputs: the curve helpers (log-log interpolation,
// first crossing, medians) against closed forms, crops, per-trial aggregation, and one tiny scene
// study and cost run on the Vulkan device with the validation layer on.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cost_study.hpp"
#include "gpu_test_support.hpp"
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

class StudyGpu : public oas::test::GpuTest {};

TEST_F(StudyGpu, TinySceneStudyWritesConsistentTables)
{
    const auto dir = std::filesystem::path(::testing::TempDir()) / "oas_scene_study";
    std::filesystem::remove_all(dir);
    SceneStudyOptions o;
    o.scenesDir = OAS_SCENES_DIR;
    o.scenes = {"cornell7d"};
    o.width = 8;
    o.minSpp = 16;
    o.maxSpp = 128;
    o.referenceSpp = 1024;
    o.minTrials = 2;  // a fixed n = 2: the adaptive loop stops at its cap, and the tables mark it
    o.maxTrials = 2;
    o.outDir = dir.string();
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
        ASSERT_EQ(cells.size(), 11u) << rows[i];
        const double seconds = std::stod(cells[5]), rel = std::stod(cells[6]);
        EXPECT_GT(seconds, 0);
        EXPECT_TRUE(std::isfinite(rel));
        err[cells[1]][std::stoul(cells[3])].push_back(std::stod(cells[8]));  // uncorrected: > 0
    }
    ASSERT_EQ(err["Sobol"].size(), 4u);  // 16, 32, 64, 128
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
