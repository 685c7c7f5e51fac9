// The wavefront path tracer (shaders/pt_wavefront.comp, GpuTracerOptions::Kernel::Wavefront)
// against the megakernel: the same integrator run one step per dispatch over queues of path
// records must give the same exact sums, word for word, however a render is cut (sample counts
// across passes, crop windows, sample shards, strips of a batch too large for the queues), and
// every path it starts must end exactly once. RenderWordsGpu (render_words_test.cpp) compares its
// words with a record the megakernel made before the wavefront existed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "gpu_test_support.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"

namespace {

using namespace oas;
using Kernel = render::GpuTracerOptions::Kernel;

std::vector<std::string> shippedScenes()
{
    std::vector<std::string> scenes;
    for (const auto& entry : std::filesystem::directory_iterator(OAS_SCENES_DIR))
        if (entry.path().extension() == ".json") scenes.push_back(entry.path().filename().string());
    std::sort(scenes.begin(), scenes.end());
    return scenes;
}

struct Setup {
    scene::Scene scene;
    render::DimensionPlan plan;
    render::SceneData data;
    Pattern pattern;
};

/// A scene at `width` px (the height keeps its aspect), its plan and data, and the "oa" pattern for
/// 16 samples (so that 121 samples cross seven passes of it).
Setup prepare(scene::Scene s, std::uint32_t width)
{
    s.height = std::max(1u, s.height * width / s.width);
    s.width = width;
    Setup p{s, render::planDimensions(s), render::flattenScene(s), {}};
    PatternRequest request;
    request.sampler = "oa";
    request.spp = 16;
    request.dims = p.plan.sampleDims;
    p.pattern = makePattern(request);
    return p;
}
Setup prepare(const std::string& name, std::uint32_t width)
{
    return prepare(scene::loadScene(std::string(OAS_SCENES_DIR) + "/" + name), width);
}

render::GpuTracerOptions withKernel(Kernel kernel, std::uint64_t maxWavefrontPaths = 0)
{
    render::GpuTracerOptions options;
    options.kernel = kernel;
    options.maxWavefrontPaths = maxWavefrontPaths;
    return options;
}

/// A rectangle of the image.
struct Window {
    std::uint32_t x0, y0, width, height;
};

/// Samples [first, end) of every pixel of the window, in oas-render's batches (forEachBatch, the
/// window's tiles placed in the frame).
void render(render::GpuTracer& gpu, const Window& w, std::uint32_t first, std::uint32_t end, std::uint32_t seed)
{
    render::forEachBatch(
        w.width, w.height, end, gpu.samplesPerBatch(), seed,
        [&](render::SampleBatch b) {
            b.x0 += w.x0;
            b.y0 += w.y0;
            gpu.trace(b);
        },
        {}, first);
}

double redTotal(const render::Accumulation& a)
{
    double total = 0;
    for (std::size_t i = 0; i < a.pixelCount(); ++i) total += render::meanValue(a.pixel(i), 0);
    return total;
}

class WavefrontGpu : public test::GpuTest {};

TEST_F(WavefrontGpu, EveryShippedSceneGivesTheMegakernelsWordsHoweverTheRenderIsCut)
{
    // Every shipped scene (their plans differ in depth, effects, prefetched or inline draws), at 1,
    // 16 and 121 samples of a pattern of 16 (121 crosses seven passes), over the whole image, in a
    // crop window, and for 121 in two shards ([0, 40) then [40, 121), the way oas-merge adds
    // them): the wavefront's words equal the megakernel's whole render's.
    for (const auto& name : shippedScenes()) {
        const auto p = prepare(name, 12);
        render::GpuTracer mega(context(), p.data, p.plan, p.pattern, withKernel(Kernel::Mega));
        render::GpuTracer wave(context(), p.data, p.plan, p.pattern, withKernel(Kernel::Wavefront));
        const Window whole{0, 0, p.scene.width, p.scene.height};
        const Window crop{3, 2, 7, std::max(1u, p.scene.height - 3)};
        for (const std::uint32_t spp : {1u, 16u, 121u}) {
            for (const Window& w : {whole, crop}) {
                const std::string what = name + ", " + std::to_string(spp) + " spp, window at " + std::to_string(w.x0) + "," +
                                         std::to_string(w.y0);
                mega.clear();
                wave.clear();
                render(mega, w, 0, spp, 9);
                if (spp == 121 && w.x0 == 0) {
                    render(wave, w, 0, 40, 9);
                    render(wave, w, 40, 121, 9);
                } else {
                    render(wave, w, 0, spp, 9);
                }
                const auto a = mega.accumulation(), b = wave.accumulation();
                ASSERT_EQ(a.words.size(), b.words.size()) << what;
                EXPECT_TRUE(a.words == b.words) << what << ": the wavefront's sums differ from the megakernel's";
                EXPECT_GT(redTotal(a), 0.0) << what << " renders black: the comparison would prove nothing";
                const auto stats = wave.wavefrontStats();
                EXPECT_EQ(stats.started, std::uint64_t(w.width) * w.height * spp) << what;
                EXPECT_EQ(stats.finished, stats.started) << what;
                EXPECT_EQ(mega.wavefrontStats().started, 0u) << "the megakernel counts no wavefront paths";
            }
        }
    }
}

TEST_F(WavefrontGpu, EveryPathEndsOnceAndStepsAsFarAsTheSceneLetsIt)
{
    // The white furnace (a diffuse sphere in an environment of radiance 1, no light sampling,
    // depth 4, no roulette) seen from two places. Looking away from the sphere, every camera ray
    // escapes at its first step: one step dispatch, every path in it, each pixel exactly 1.
    // From inside the sphere, every path hits the wall at every vertex and ends at the depth
    // limit: steps 1 .. 4 each take every path, and there is no fifth.
    auto s = scene::loadScene(std::string(OAS_SCENES_DIR) + "/furnace.json");
    const auto away = [&] {
        auto t = s;
        t.camera.lookAt = t.camera.position + (t.camera.position - t.camera.lookAt);
        return prepare(t, 8);
    }();
    const auto inside = [&] {
        auto t = s;
        t.camera.position = {0, 0, 0};
        t.camera.lookAt = {0, 0, -1};
        return prepare(t, 8);
    }();
    ASSERT_EQ(inside.plan.maxDepth, 4u);
    ASSERT_FALSE(inside.plan.nee);
    ASSERT_EQ(inside.plan.roulette, render::kAbsent) << "with roulette, paths could end before the depth limit";
    for (const auto* p : {&away, &inside}) {
        render::GpuTracer wave(context(), p->data, p->plan, p->pattern, withKernel(Kernel::Wavefront));
        render::GpuTracer mega(context(), p->data, p->plan, p->pattern, withKernel(Kernel::Mega));
        const Window whole{0, 0, p->scene.width, p->scene.height};
        render(wave, whole, 0, 16, 3);
        render(mega, whole, 0, 16, 3);
        EXPECT_TRUE(wave.accumulation().words == mega.accumulation().words);
        const auto stats = wave.wavefrontStats();
        const std::uint64_t paths = std::uint64_t(p->scene.width) * p->scene.height * 16;
        EXPECT_EQ(stats.started, paths);
        EXPECT_EQ(stats.finished, paths);
        const std::size_t steps = p == &away ? 1 : 4;
        ASSERT_EQ(stats.stepped.size(), steps + 1) << "step dispatches (stepped[0] is unused)";
        for (std::size_t v = 1; v <= steps; ++v) EXPECT_EQ(stats.stepped[v], paths) << "paths that took step " << v;
        if (p != &away) continue;
        const auto a = wave.accumulation();
        for (std::size_t i = 0; i < a.pixelCount(); ++i)
            for (int c = 0; c < 3; ++c) EXPECT_EQ(render::meanValue(a.pixel(i), c), 1.0) << "pixel " << i << ": the environment";
    }
}

/// The megakernel's counting variant (GpuTracerOptions::countLanes).
render::GpuTracerOptions countingLanes()
{
    render::GpuTracerOptions options;
    options.countLanes = true;
    return options;
}

TEST_F(WavefrontGpu, TheMegakernelsLaneCountsSeeTheWavefrontsPaths)
{
    // The counting variant ballots the lanes that run the megakernel's vertex loop at each vertex.
    // Summed over the subgroups, those are the paths that took that step, which the wavefront
    // counts another way (its queues' atomic counters), so the two must agree path for path; and
    // no subgroup step can have more lanes at work than the subgroup has, or none. The counting
    // variant leaves the sums as they are (the wavefront's equal the megakernel's: the test above).
    // The scenes oas-render-bench --kernels counts (paths of one, two or three steps, and up to
    // seven), at 12 px: edge subgroups are part outside the image.
    if (!context().computeSubgroupBallot()) GTEST_SKIP() << "SKIPPED: this device has no subgroup ballots in compute shaders";
    const std::uint32_t lanes = context().subgroupSize();
    for (const std::string name : {"cornell7d.json", "blue_spheres9d.json", "interior_deep.json"}) {
        const auto p = prepare(name, 12);
        render::GpuTracer counting(context(), p.data, p.plan, p.pattern, countingLanes());
        render::GpuTracer wave(context(), p.data, p.plan, p.pattern, withKernel(Kernel::Wavefront));
        const Window whole{0, 0, p.scene.width, p.scene.height};
        for (auto* tracer : {&counting, &wave}) render(*tracer, whole, 0, 16, 4);
        EXPECT_TRUE(counting.accumulation().words == wave.accumulation().words) << name << ": counting changed the sums";
        const auto counts = counting.laneCounts();
        const auto stats = wave.wavefrontStats();
        EXPECT_EQ(counts.subgroupSize, lanes);
        ASSERT_EQ(counts.liveLanes.size(), p.plan.maxDepth + 2u) << name << ": the vertex loop's iterations, 0 .. maxDepth + 1";
        EXPECT_EQ(counts.liveLanes[0], stats.started) << name << ": every path starts at the camera";
        EXPECT_GT(stats.stepped.size(), 1u) << name;
        for (std::size_t v = 1; v < counts.liveLanes.size(); ++v) {
            const std::uint64_t stepped = v < stats.stepped.size() ? stats.stepped[v] : 0;
            EXPECT_EQ(counts.liveLanes[v], stepped) << name << ": lanes and paths at vertex " << v;
        }
        for (std::size_t v = 0; v < counts.liveLanes.size(); ++v) {
            EXPECT_LE(counts.liveLanes[v], counts.subgroupSteps[v] * lanes) << name << ", vertex " << v;
            EXPECT_LE(counts.subgroupSteps[v], counts.liveLanes[v]) << name << ", vertex " << v << ": a step with no lane";
        }
        counting.clear();
        EXPECT_TRUE(counting.laneCounts().liveLanes.empty()) << "clear() drops the counts";
    }
    // The furnace from inside its sphere at 8 x 8 px, one workgroup: every path lives to the depth
    // limit (4, no roulette), so every subgroup step has all its lanes at work, at the camera and
    // vertices 1 .. 4, and none runs a fifth. Looking away from the sphere, every path escapes at
    // its first step.
    auto s = scene::loadScene(std::string(OAS_SCENES_DIR) + "/furnace.json");
    auto inside = s;
    inside.camera.position = {0, 0, 0};
    inside.camera.lookAt = {0, 0, -1};
    auto away = s;
    away.camera.lookAt = away.camera.position + (away.camera.position - away.camera.lookAt);
    for (const auto* t : {&inside, &away}) {
        const auto p = prepare(*t, 8);
        ASSERT_EQ(p.scene.height, 8u);
        render::GpuTracer counting(context(), p.data, p.plan, p.pattern, countingLanes());
        render(counting, {0, 0, 8, 8}, 0, 16, 3);
        const auto counts = counting.laneCounts();
        const std::uint64_t paths = 8 * 8 * 16;
        const std::size_t lastVertex = t == &inside ? 4 : 1;
        ASSERT_EQ(counts.liveLanes.size(), 6u);
        for (std::size_t v = 0; v < 6; ++v) {
            EXPECT_EQ(counts.liveLanes[v], v <= lastVertex ? paths : 0u) << "vertex " << v;
            EXPECT_EQ(counts.subgroupSteps[v] * lanes, counts.liveLanes[v]) << "vertex " << v << ": a lane idled";
        }
    }
    EXPECT_THROW(render::GpuTracer(context(), prepare("furnace.json", 8).data, prepare("furnace.json", 8).plan,
                                   prepare("furnace.json", 8).pattern,
                                   [] {
                                       auto o = countingLanes();
                                       o.kernel = Kernel::Wavefront;
                                       return o;
                                   }()),
                 std::invalid_argument)
        << "lanes are the megakernel's to count";
}

TEST_F(WavefrontGpu, BatchesOverTheQueuesCapacityGoInStripsOrAreRefused)
{
    // A batch of more paths than the queues hold is traced in strips of rows (the same words); a
    // batch whose single row is over the capacity is refused with a message naming it, never
    // traced in part.
    const auto p = prepare("cornell7d.json", 12);
    render::SampleBatch batch;
    batch.width = p.scene.width;
    batch.height = p.scene.height;
    batch.count = 4;
    batch.seed = 5;
    render::GpuTracer mega(context(), p.data, p.plan, p.pattern, withKernel(Kernel::Mega));
    mega.trace(batch);
    const std::uint64_t twoRows = std::uint64_t(2) * batch.width * batch.count;
    render::GpuTracer strips(context(), p.data, p.plan, p.pattern, withKernel(Kernel::Wavefront, twoRows));
    strips.trace(batch);
    EXPECT_TRUE(strips.accumulation().words == mega.accumulation().words) << "traced in strips of two rows";
    EXPECT_EQ(strips.wavefrontStats().started, std::uint64_t(batch.width) * batch.height * batch.count);
    const std::uint64_t belowOneRow = std::uint64_t(batch.width) * batch.count - 1;
    render::GpuTracer tooSmall(context(), p.data, p.plan, p.pattern, withKernel(Kernel::Wavefront, belowOneRow));
    try {
        tooSmall.trace(batch);
        FAIL() << "a row of " << batch.width * batch.count << " paths was traced with queues of " << belowOneRow;
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("more than the queues hold (" + std::to_string(belowOneRow) + " paths)"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_EQ(redTotal(tooSmall.accumulation()), 0.0) << "a refused batch adds nothing";
    EXPECT_THROW(render::GpuTracer(context(), p.data, p.plan, p.pattern,
                                   {render::KernelStage::Nothing, true, render::GpuTracerOptions::Prefetch::WherePays, 0,
                                    Kernel::Wavefront}),
                 std::invalid_argument)
        << "the wavefront traces paths only; the profile's stages are the megakernel's";
}

}  // namespace
