// The scene study's time axis: one cost run per scene (study/scene_costs.hpp). Its file round-trips,
// its mean ± s.e. is the textbook one, a scene whose rows mix runs is refused, and the equal-time
// tables take their times from it alone (never from the accuracy renders' pooled times).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <iterator>
#include <fstream>
#include <filesystem>

#include "experiment.hpp"
#include "gpu_test_support.hpp"
#include "scene_costs.hpp"
#include "scene_study.hpp"
#include "scene_tables.hpp"

using namespace oas::study;

namespace {

SamplerSpec specOf(const std::string& label)
{
    for (const auto& s : studySamplers())
        if (s.label == label) return s;
    throw std::invalid_argument("no sampler " + label);
}

SceneRecord cornellRecord()
{
    SceneRecord r;
    r.name = "cornell7d";
    r.width = 8;
    r.height = 8;
    r.dims = 7;
    r.crop = {2, 2, 4, 4};
    r.referenceSpp = 4096;
    r.largestSpp = 4096;
    r.device = "test device";
    r.machine = "test machine";
    r.date = "2026-12-03";
    r.modeLabel = "full mode";
    r.minSpp = 16;
    r.maxSpp = 4096;
    r.minTrials = 3;
    r.maxTrials = 3;
    return r;
}

/// Three renders per point at 16, 128 and 4096 spp: Sobol's error ∝ 1/spp, Random's 3× that; the
/// accuracy renders' own times are deliberately wrong (Random 100× slower), so a table that used
/// them would say so.
std::vector<SceneMeasurement> measurements()
{
    std::vector<SceneMeasurement> out;
    for (const char* sampler : {"Sobol", "Random"})
        for (std::uint32_t spp : {16u, 128u, 4096u})
            for (std::uint32_t t = 0; t < 3; ++t) {
                SceneMeasurement m;
                m.scene = "cornell7d";
                m.sampler = sampler;
                m.spp = spp;
                m.trial = t;
                const double scale = std::string(sampler) == "Sobol" ? 1.0 : 3.0;
                m.relMse = m.relMseRaw = scale / spp * (1 + 0.01 * t);
                m.relMseCrop = m.relMseCropRaw = m.relMse;
                m.seconds = (std::string(sampler) == "Random" ? 100.0 : 1.0) * 1e-3 * spp;
                out.push_back(m);
            }
    return out;
}

/// A cost run where both samplers take 1 ms per spp.
std::vector<SceneCost> costs(const std::string& runId)
{
    std::vector<SceneCost> out;
    for (const char* sampler : {"Sobol", "Random"})
        for (std::uint32_t spp : {16u, 128u, 4096u}) {
            SceneCost c;
            c.scene = "cornell7d";
            c.sampler = sampler;
            c.spp = spp;
            c.seconds = 1e-3 * spp;
            c.se = 1e-5;
            c.rounds = 3;
            c.runId = runId;
            c.machine = "cost machine";
            c.device = "cost device";
            c.date = "2026-12-03 22:00 UTC";
            out.push_back(c);
        }
    return out;
}

}  // namespace

TEST(SceneCosts, MeanAndStandardErrorOverRounds)
{
    const SceneCost c = summarizeTimes({1.0, 2.0, 3.0, 6.0});
    EXPECT_DOUBLE_EQ(c.seconds, 3.0);
    // sample sd = sqrt(((-2)^2 + 1 + 0 + 9) / 3) = sqrt(14/3); s.e. = sd / 2.
    EXPECT_NEAR(c.se, std::sqrt(14.0 / 3.0) / 2.0, 1e-12);
    EXPECT_EQ(c.rounds, 4u);
    EXPECT_EQ(summarizeTimes({2.5}).se, 0.0);
}

TEST(SceneCosts, FileRoundTripsAndMergeReplacesWholeScenes)
{
    const auto dir = std::filesystem::path(::testing::TempDir()) / "oas_scene_costs";
    std::filesystem::create_directories(dir);
    const std::string path = (dir / "scene_costs.csv").string();
    auto a = costs("run-a");
    a[0].machine = "AMD EPYC, \"quoted\"";
    writeSceneCosts(path, a);
    const auto back = readSceneCosts(path);
    ASSERT_EQ(back.size(), a.size());
    EXPECT_EQ(back[0].machine, a[0].machine);
    EXPECT_EQ(back[5].spp, 4096u);
    EXPECT_DOUBLE_EQ(back[5].seconds, a[5].seconds);
    EXPECT_EQ(back[5].runId, "run-a");
    // The header is exactly the documented columns.
    std::ifstream in(path);
    std::string header;
    std::getline(in, header);
    EXPECT_EQ(header, "scene,sampler,spp,seconds,se,rounds,run_id,machine,device,date,commit,sources");
    // The stamps round-trip; a file from before cost runs were stamped reads with empty stamps.
    a[1].commit = "0123456789ab-dirty";
    a[1].sources = "fedcba9876543210";
    writeSceneCosts(path, a);
    EXPECT_EQ(readSceneCosts(path)[1].commit, "0123456789ab-dirty");
    EXPECT_EQ(readSceneCosts(path)[1].sources, "fedcba9876543210");
    std::ofstream(path) << "scene,sampler,spp,seconds,se,rounds,run_id,machine,device,date\ncornell7d,Sobol,16,1,0,3,r,m,d,today\n";
    const auto unstamped = readSceneCosts(path);
    ASSERT_EQ(unstamped.size(), 1u);
    EXPECT_TRUE(unstamped[0].commit.empty() && unstamped[0].sources.empty());
    EXPECT_EQ(staleCostScenes(unstamped), std::vector<std::string>{"cornell7d"});

    // A bad cell names the file, row and column.
    std::ofstream(path) << header << "\ncornell7d,Sobol,16,-1,0,3,r,m,d,today,c,s\n";
    try {
        readSceneCosts(path);
        FAIL() << "a negative time was read";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("row 1, column \"seconds\""), std::string::npos) << e.what();
    }

    auto other = costs("run-b");
    for (auto& c : other) c.scene = "interior_deep";
    const auto merged = mergeSceneCosts(mergeSceneCosts(a, other), costs("run-c"));
    ASSERT_EQ(merged.size(), 12u);
    EXPECT_EQ(costsOfScene(merged, "cornell7d").front().runId, "run-c");
    EXPECT_EQ(costsOfScene(merged, "interior_deep").front().runId, "run-b");
    EXPECT_TRUE(costsOfScene(merged, "blue_spheres9d").empty());
    // Each scene has a run per device kind: a fresh GPU run replaces the scene's GPU run only,
    // and the CPU twin's run is read apart (mixing the two would throw: different runs).
    auto twin = costs("run-cpu");
    for (auto& c : twin) c.device = kCpuTwinDeviceName;
    const auto both = mergeSceneCosts(mergeSceneCosts(merged, twin), costs("run-d"));
    ASSERT_EQ(both.size(), 18u);
    EXPECT_EQ(costsOfScene(both, "cornell7d").front().runId, "run-d");
    EXPECT_EQ(costsOfScene(both, "cornell7d", CostDevice::CpuTwin).front().runId, "run-cpu");
    EXPECT_TRUE(costsOfScene(both, "interior_deep", CostDevice::CpuTwin).empty());
    std::filesystem::remove_all(dir);
}

std::string readText(const std::filesystem::path& path)
{
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(SceneCosts, TheBuildsSourcesHashIsTheScriptsHashOfTheTree)
{
    // The hash compiled in (made by the build when a render-time source changes) equals the hash
    // the script computes now from the source tree: a stale generated header would stamp cost
    // runs with the wrong sources.
    const std::string command = std::string("'") + OAS_CMAKE_COMMAND + "' -DOAS_SOURCE_ROOT='" + OAS_SOURCE_DIR +
                                "' -P '" + OAS_SOURCE_DIR + "/cmake/oas_sources_hash.cmake' 2>&1";
    std::string output;
    if (std::FILE* pipe = ::popen(command.c_str(), "r")) {
        char buf[256];
        for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) output.append(buf, n);
        EXPECT_EQ(::pclose(pipe), 0) << command << ": " << output;
    }
    while (!output.empty() && output.back() == '\n') output.pop_back();
    EXPECT_EQ(output.size(), 16u) << output;
    EXPECT_EQ(output, renderSourcesHash());
}

TEST(SceneCosts, CommittedCostRunsAreCurrentOrTheFirstScreenSaysTheyAreStale)
{
    // A cost run timed on other render-time sources than today's is stale. Today's verdicts may
    // rest on one only if the first screen says so: the README's answer section and the top of
    // docs/STUDY.md carry "**Stale cost runs:**" and the command that reruns them; when every
    // scene's run is current, neither does.
    const std::filesystem::path root = OAS_SOURCE_DIR;
    const auto stale = staleCostScenes(readSceneCosts((root / "docs/study/scene_costs.csv").string()));
    const std::string readme = readText(root / "README.md"), study = readText(root / "docs/STUDY.md");
    const std::size_t from = readme.find("## Which sampler, at what cost"), to = readme.find("\n## ", from + 1);
    ASSERT_NE(from, std::string::npos) << "README.md has no answer section";
    const std::string answer = readme.substr(from, to - from);
    const std::string studyTop = study.substr(0, study.find("\n|"));  // the text before its first table
    const std::string marker = "**Stale cost runs:**", rerun = "scripts/study.sh --parts scene-costs";
    std::string names;
    for (const auto& scene : stale) names += " " + scene;
    for (const auto& [name, text] : {std::pair{"README.md's answer section", answer}, std::pair{"docs/STUDY.md's top", studyTop}}) {
        if (!stale.empty()) {
            EXPECT_NE(text.find(marker), std::string::npos)
                << "the cost runs of" << names << " were timed on other sources than this build's (" << renderSourcesHash()
                << "), and " << name << " does not say " << marker << "; rerun them: " << rerun;
            EXPECT_NE(text.find(rerun), std::string::npos) << name << " must name the command that reruns them: " << rerun;
        } else {
            EXPECT_EQ(text.find(marker), std::string::npos)
                << "every cost run is current (" << renderSourcesHash() << "), but " << name << " still says " << marker;
        }
    }
}

TEST(SceneCosts, TheErrorTimeCurveSkipsACountThatALargerCountBeatsOnTime)
{
    // Bose CMJ's cost run on lavapipe, blue_spheres9d, 2026-12-07: 81 spp (over GF(3^2)) took
    // 145 ms, 121 spp (GF(11)) 132 ms. A renderer with 145 ms renders 121 spp, so the curve runs
    // 64 -> 121 -> 169 and leaves 81 out; a tie in time keeps the larger count.
    oas::study::SceneCurve c;
    c.spp = {16, 64, 81, 121, 169};
    c.seconds = {0.030, 0.104, 0.145, 0.132, 0.183};
    EXPECT_EQ(oas::study::detail::errorTimeCurvePoints(c), (std::vector<std::size_t>{0, 1, 3, 4}));
    c.seconds = {0.030, 0.104, 0.132, 0.132, 0.183};
    EXPECT_EQ(oas::study::detail::errorTimeCurvePoints(c), (std::vector<std::size_t>{0, 1, 3, 4}));
    c.seconds = {0.030, 0.104, 0.120, 0.132, 0.183};  // monotone: every point
    EXPECT_EQ(oas::study::detail::errorTimeCurvePoints(c), (std::vector<std::size_t>{0, 1, 2, 3, 4}));
}

TEST(SceneCosts, AScenesTimesMustComeFromOneRun)
{
    auto mixed = costs("run-a");
    mixed[3].runId = "run-b";
    try {
        costsOfScene(mixed, "cornell7d");
        FAIL() << "mixed run ids were accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("run-a and run-b"), std::string::npos) << e.what();
    }
    EXPECT_THROW(sceneSection({cornellRecord()}, measurements(), {specOf("Sobol"), specOf("Random")}, mixed), std::runtime_error);
}

// The accuracy part's extra budget prices a render by the cost run (--scene-render-cost cost-run):
// a timed point its mean, another count the sampler's nearest timed seconds per spp, scaled.
TEST(SceneCosts, ARenderCostsItsPointsCostRunSeconds)
{
    std::vector<SceneCost> rows;
    for (auto [spp, seconds] : {std::pair{16u, 0.4}, {64u, 1.2}, {256u, 4.0}}) {
        SceneCost c;
        c.scene = "cornell7d";
        c.sampler = "Sobol";
        c.spp = spp;
        c.seconds = seconds;
        rows.push_back(c);
    }
    EXPECT_DOUBLE_EQ(costRunSeconds(rows, "Sobol", 64), 1.2);
    EXPECT_DOUBLE_EQ(costRunSeconds(rows, "Sobol", 100), 1.2 / 64 * 100);  // nearest in log: 64
    EXPECT_DOUBLE_EQ(costRunSeconds(rows, "Sobol", 4096), 4.0 / 256 * 4096);
    EXPECT_DOUBLE_EQ(costRunSeconds(rows, "Sobol", 8), 0.4 / 16 * 8);
    try {
        costRunSeconds(rows, "Halton", 64);
        FAIL() << "a sampler the cost run lacks got a price";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("Halton"), std::string::npos) << e.what();
    }
}

TEST(SceneCosts, EqualTimeTablesUseTheCostRunAndNothingElse)
{
    const std::vector<SamplerSpec> samplers = {specOf("Sobol"), specOf("Random")};
    // Without a cost run the time tables say so instead of using the accuracy renders' times.
    const std::string without = sceneSection({cornellRecord()}, measurements(), samplers);
    EXPECT_NE(without.find("no cost run: `oas-study --parts scene-costs --scene cornell7d`"), std::string::npos);
    EXPECT_EQ(without.find("*budgets*"), std::string::npos);
    // With one: equal times are equal spp here, so Random is 3× Sobol at every budget (with the
    // accuracy renders' times it would be about 300×), T₁ is Sobol's 128 spp = 128 ms and T₃ the
    // longest every sampler with a count >= 3969 reached, 4096 ms.
    const std::string with = sceneSection({cornellRecord()}, measurements(), samplers, costs("run-a"));
    EXPECT_NE(with.find("T₁ = 128 ms"), std::string::npos) << with;
    EXPECT_NE(with.find("T₃ = 4096 ms"), std::string::npos);
    const auto row = with.find("| cornell7d | Random | ", with.find("### Error at equal time"));
    ASSERT_NE(row, std::string::npos);
    const std::string line = with.substr(row, with.find('\n', row) - row);
    EXPECT_NE(line.find("| 3.0"), std::string::npos) << line;
    // The short answer names where the times were measured.
    EXPECT_NE(with.find("### The short answer"), std::string::npos);
    EXPECT_NE(with.find("cost device, cost machine, 2026-12-03 22:00 UTC"), std::string::npos);
}

// Each device's cost run gives its own equal-time verdicts, and the short answer puts both
// devices' rows side by side and names where they disagree. Here the CPU twin makes Random 10x
// cheaper than Sobol (Sobol's error is a third of Random's at equal spp), so at equal time Random
// wins on the twin (0.3x Sobol) while Sobol wins on the GPU (equal costs).
TEST(SceneCosts, EachDeviceHasItsOwnVerdictsAndTheAnswerSaysWhereTheyDisagree)
{
    const std::vector<SamplerSpec> samplers = {specOf("Sobol"), specOf("Random")};
    auto all = costs("run-gpu");
    for (auto c : costs("run-cpu")) {
        c.device = kCpuTwinDeviceName;
        if (c.sampler == "Random") c.seconds /= 10;
        all.push_back(c);
    }
    const std::string md = sceneSection({cornellRecord()}, measurements(), samplers, all);
    const std::size_t from = md.find("### The short answer"), to = md.find("### Error at equal time");
    const std::string answer = md.substr(from, to - from);
    EXPECT_NE(answer.find("| Sobol at ≈ 128 spp | 1.00"), std::string::npos) << answer;
    EXPECT_NE(answer.find("| Random at ≈ 4096 spp | 0.30"), std::string::npos) << answer;  // its timed point nearest 1280 spp
    EXPECT_NE(answer.find("| CPU twin, cost machine, 2026-12-03 22:00 UTC |"), std::string::npos) << answer;
    EXPECT_NE(answer.find("Where the devices disagree (3 of 3): cornell7d at T₁: Sobol on the GPU, Random on the CPU twin"),
              std::string::npos)
        << answer;
    EXPECT_NE(md.find("### Error at equal time on the CPU twin"), std::string::npos);
    EXPECT_NE(md.find("### Sampler cost inside a frame on the CPU twin"), std::string::npos);
    EXPECT_NE(md.find("**Goal (at equal time on the CPU twin, "), std::string::npos);
    // With the GPU's run alone there is nothing to compare: no twin tables, no disagreement line.
    const std::string gpuOnly = sceneSection({cornellRecord()}, measurements(), samplers, costs("run-gpu"));
    EXPECT_EQ(gpuOnly.find("### Error at equal time on the CPU twin"), std::string::npos);
    EXPECT_EQ(gpuOnly.find("devices disagree"), std::string::npos);
}

class SceneCostsGpu : public oas::test::GpuTest {};

TEST_F(SceneCostsGpu, ACostRunTimesEveryMeasuredPointInRounds)
{
    const auto rows = measureSceneCosts(
        cornellRecord(), measurements(), {specOf("Sobol"), specOf("Random")},
        [] {
            SceneCostOptions o;
            o.scenesDir = OAS_SCENES_DIR;
            o.rounds = 3;
            o.runId = "test-run";
            o.commit = "abc";
            return o;
        }(),
        &context());
    ASSERT_EQ(rows.size(), 6u);  // 2 samplers × 3 counts
    for (const auto& c : rows) {
        EXPECT_EQ(c.rounds, 3u);
        EXPECT_EQ(c.runId, "test-run");
        EXPECT_EQ(c.commit, "abc");
        EXPECT_EQ(c.sources, renderSourcesHash());
        EXPECT_GT(c.seconds, 0.0);
        EXPECT_GE(c.se, 0.0);
        EXPECT_FALSE(c.device.empty());
    }
    EXPECT_THROW(measureSceneCosts(
                     cornellRecord(), measurements(), {specOf("Sobol")},
                     [] {
                         SceneCostOptions o;
                         o.rounds = 2;
                         return o;
                     }(),
                     &context()),
                 std::invalid_argument);
}

// The CPU twin's cost run needs no Vulkan device: a machine without a GPU can time the scenes as
// `oas-render --device cpu` renders them, and its rows say which device they timed.
TEST(SceneCosts, TheCpuTwinTimesEveryPointWithoutAVulkanDevice)
{
    SceneCostOptions o;
    o.scenesDir = OAS_SCENES_DIR;
    o.runId = "cpu-run";
    o.device = CostDevice::CpuTwin;
    o.cpuThreads = 1;
    const auto rows = measureSceneCosts(cornellRecord(), measurements(), {specOf("Sobol"), specOf("Random")}, o, nullptr);
    ASSERT_EQ(rows.size(), 6u);  // 2 samplers × 3 counts
    for (const auto& c : rows) {
        EXPECT_EQ(c.device, kCpuTwinDeviceName);
        EXPECT_EQ(costDeviceOf(c), CostDevice::CpuTwin);
        EXPECT_EQ(c.rounds, 3u);
        EXPECT_GT(c.seconds, 0.0);
    }
    o.device = CostDevice::Gpu;  // the GPU tracer without a device is refused, not dereferenced
    EXPECT_THROW(measureSceneCosts(cornellRecord(), measurements(), {specOf("Sobol")}, o, nullptr), std::invalid_argument);
}
