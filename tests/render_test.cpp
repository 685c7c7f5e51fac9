// The path tracer against known answers, GPU against the CPU reference, the dimension plan, and
// oas-render's handling of bad scenes. Scenes come from scenes/.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <csignal>
#include <spawn.h>
#include <sys/wait.h>
#include <cstring>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "image/image.hpp"

#include "apps/checkpoints.hpp"
#include "gpu_test_support.hpp"
#include "test_cases.hpp"
#include "render/plan.hpp"
#include "render/render_file.hpp"
#include "render/scene_data.hpp"
#include "render/scene_pattern.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"

namespace {

using namespace oas;

scene::Scene loadTestScene(const std::string& name)
{
    return scene::loadScene(std::string(OAS_SCENES_DIR) + "/" + name);
}

Pattern patternFor(const scene::Scene& s, const render::DimensionPlan& plan, std::uint32_t spp, const std::string& sampler = "oa")
{
    PatternRequest r;
    r.sampler = sampler;
    r.spp = spp;
    r.dims = plan.sampleDims;
    return makePattern(r);
}

/// All of the scene's pixels, samples [0, count), and an accumulation buffer for them.
struct WholeImage {
    render::SampleBatch batch;
    render::Accumulation accumulation;
};
WholeImage wholeImage(const scene::Scene& s, std::uint32_t count, std::uint32_t seed = 0)
{
    WholeImage w;
    w.batch.width = s.width;
    w.batch.height = s.height;
    w.batch.count = count;
    w.batch.seed = seed;
    w.accumulation = render::Accumulation(s.width, s.height);
    return w;
}

/// Mean radiance (red channel) and its standard error at pixel (px, py) over n samples.
std::pair<double, double> pixelEstimate(const scene::Scene& s, std::uint32_t px, std::uint32_t py, std::uint32_t n,
                                        const std::string& sampler = "random")
{
    const auto plan = render::planDimensions(s);
    const auto data = render::flattenScene(s);
    const auto pattern = patternFor(s, plan, n, sampler);
    double sum = 0, sum2 = 0;
    for (std::uint32_t i = 0; i < n; ++i) {
        const double v = render::radianceCpu(data, plan, pattern, px, py, 7, i).x;
        sum += v;
        sum2 += v * v;
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1))};
}

TEST(Render, WhiteFurnaceIsExact)
{
    // A convex diffuse sphere (albedo 0.5) in a uniform environment of radiance 1: every path that
    // hits the sphere scatters once and escapes, so its radiance is exactly 0.5; misses see 1.
    const auto s = loadTestScene("furnace.json");
    const auto centre = pixelEstimate(s, s.width / 2, s.height / 2, 64, "oa");
    EXPECT_NEAR(centre.first, 0.5, 1e-6);
    EXPECT_NEAR(centre.second, 0.0, 1e-6);
    const auto corner = pixelEstimate(s, 0, 0, 64, "oa");
    EXPECT_NEAR(corner.first, 1.0, 1e-6);
}

/// Configuration factor from a point to an axis-aligned rectangle [x1,x2] x [z1,z2] in a parallel
/// plane at height h (coordinates relative to the point; Howell's catalogue, case B-3, combined
/// over the four corner rectangles with signs).
double parallelRectangleFactor(double x1, double x2, double z1, double z2, double h)
{
    auto corner = [h](double u, double v) {
        const double a = std::abs(u) / h, b = std::abs(v) / h;
        const double f = (a / std::sqrt(1 + a * a) * std::atan(b / std::sqrt(1 + a * a)) +
                          b / std::sqrt(1 + b * b) * std::atan(a / std::sqrt(1 + b * b))) /
                         (2 * M_PI);
        return (u < 0 ? -1 : 1) * (v < 0 ? -1 : 1) * f;
    };
    return corner(x2, z2) - corner(x1, z2) - corner(x2, z1) + corner(x1, z1);
}

TEST(Render, PlaneUnderRectangularLightMatchesAnalyticIrradiance)
{
    // scenes/plane_rect_light.json: albedo-1 plane y = 0, a 2 x 2 light of radiance 1 at height 2,
    // camera at height 1.5 looking straight down with a 90 degree field of view (x right, z down
    // the image), so pixel (px, py) sees the plane around (x, z) below.
    const auto s = loadTestScene("plane_rect_light.json");
    for (auto [px, py] : {std::pair{32u, 32u}, {10u, 40u}, {50u, 5u}, {3u, 60u}}) {
        const double sx = (px + 0.5) / s.width * 2 - 1, sy = 1 - (py + 0.5) / s.height * 2;
        const double x = sx * 1.5, z = -sy * 1.5;
        const double expected = parallelRectangleFactor(-1 - x, 1 - x, -1 - z, 1 - z, 2.0);  // albedo * L * F
        const auto [mean, se] = pixelEstimate(s, px, py, 65536);
        // 4 standard errors plus 0.5% for the radiance varying across the pixel's footprint.
        EXPECT_NEAR(mean, expected, 4 * se + 0.005 * expected) << "pixel " << px << "," << py;
    }
}

TEST(Render, ShadingPointsInTheLightsPlaneGiveFiniteRadiance)
{
    // Regression (issue 8): next-event estimation tested the light's facing at the offset ray
    // origin but took its pdf at the shading point; a point lying in the light's plane (in
    // interior_deep, the sloped ceiling meeting the window light) passed with a cosine of 0, whose
    // clamped pdf of ~3e30 squared to inf in the MIS weight: inf / inf = NaN for every light sample.
    // Here: a wall light in the plane x = 0 facing +x, and a ceiling rising into the room from the
    // line (0, 1.5, z) where it meets that plane; its lower side faces both the camera and the
    // light's front. The edge-on light gives such a point exactly nothing.
    const std::string text = R"({
      "resolution": [8, 8],
      "camera": {"type": "pinhole", "position": [3, 0.5, 0], "lookAt": [0, 0.5, 0], "fovY": 60},
      "materials": [{"name": "ceiling", "type": "diffuse", "albedo": 0.8},
                    {"name": "light", "type": "diffuse", "albedo": 0, "emission": 5}],
      "shapes": [
        {"type": "quad", "material": "light", "corner": [0, 0, -1], "edgeU": [0, 1, 0], "edgeV": [0, 0, 2]},
        {"type": "quad", "material": "ceiling", "corner": [0, 1.5, -1], "edgeU": [0, 0, 2], "edgeV": [2, 1, 0]}
      ],
      "integrator": {"type": "direct", "nextEventEstimation": true, "mis": true},
      "sampler": {"name": "random", "spp": 64}
    })";
    const auto s = scene::parseScene(text, "in_plane.json", ".");
    const auto plan = render::planDimensions(s);
    ASSERT_TRUE(plan.mis);
    const auto data = render::flattenScene(s);
    const auto pattern = patternFor(s, plan, 256, "random");
    const glm::vec3 n = glm::normalize(glm::vec3(1, -2, 0));  // the ceiling's lower side
    EXPECT_NEAR(std::abs(glm::dot(glm::normalize(glm::cross(glm::vec3(0, 0, 2), glm::vec3(2, 1, 0))), n)), 1.0f, 1e-6f);
    const glm::vec3 wo = glm::normalize(glm::vec3(3, 0.5, 0) - glm::vec3(0, 1.5, 0));
    ASSERT_GT(glm::dot(n, wo), 0.0f);
    std::uint32_t nonFinite = 0;
    for (const float z : {0.0f, 0.25f, -0.7f})
        for (std::uint32_t i = 0; i < 256; ++i) {
            const glm::vec3 l = render::nextEventCpu(data, plan, pattern, 9, i, 1, 0, glm::vec3(0, 1.5f, z), n, wo);
            if (!std::isfinite(l.x) || !std::isfinite(l.y) || !std::isfinite(l.z))
                ++nonFinite;
            else
                EXPECT_EQ(l, glm::vec3(0.0f)) << "an edge-on light gives nothing";
        }
    EXPECT_EQ(nonFinite, 0u) << "of 768 light samples at points in the light's plane";
    // The whole render of the scene: no sample is lost.
    auto [batch, acc] = wholeImage(s, 64);
    EXPECT_EQ(render::traceCpu(data, plan, pattern, batch, acc), 0u);
}

TEST(Render, ShippedScenesHaveNoNonFiniteSamples)
{
    // Every scene in scenes/, small, on the CPU reference (the GPU runs the same code; RenderGpu
    // checks its counter): no sample may be NaN or infinite.
    for (const auto& entry : std::filesystem::directory_iterator(OAS_SCENES_DIR)) {
        if (entry.path().extension() != ".json") continue;
        auto s = scene::loadScene(entry.path());
        s.width = 24;
        s.height = 18;
        const auto plan = render::planDimensions(s);
        const auto data = render::flattenScene(s);
        const auto pattern = patternFor(s, plan, 16);
        auto [batch, acc] = wholeImage(s, 16, 11);
        EXPECT_EQ(render::traceCpu(data, plan, pattern, batch, acc), 0u) << entry.path();
    }
}

TEST(Render, TilesAndSampleBatchesEqualOneWholePass)
{
    // oas-render dispatches tiles x sample batches; any split must accumulate the same sums, bit
    // for bit (they are integers).
    auto s = loadTestScene("cornell7d.json");
    s.width = 20;
    s.height = 14;
    const auto plan = render::planDimensions(s);
    const auto data = render::flattenScene(s);
    const auto pattern = patternFor(s, plan, 121);
    render::SampleBatch whole;
    whole.width = s.width;
    whole.height = s.height;
    whole.count = 10;
    render::Accumulation a(s.width, s.height), b = a;
    render::traceCpu(data, plan, pattern, whole, a, 1);
    for (std::uint32_t first = 0; first < 10; first += 5)
        for (std::uint32_t ty = 0; ty < s.height; ty += 8)
            for (std::uint32_t tx = 0; tx < s.width; tx += 8) {
                render::SampleBatch tile;
                tile.x0 = tx;
                tile.y0 = ty;
                tile.width = std::min(8u, s.width - tx);
                tile.height = std::min(8u, s.height - ty);
                tile.firstSample = first;
                tile.count = 5;
                render::traceCpu(data, plan, pattern, tile, b, 2);
            }
    for (std::size_t i = 0; i < a.pixelCount(); ++i) ASSERT_EQ(a.samples(i), 10u);
    EXPECT_EQ(a.words, b.words);
}

TEST(RenderCpu, AllThreadsGiveTheSameBitsAsOneThread)
{
    // Rows go to threads dynamically and each thread caches the per-pass sampler state of the
    // pixel it traces, so only an exact comparison shows that neither the split nor the cache
    // changes a sum. Two scenes: the OA pattern over blocks of cornell7d, Halton in interior_deep.
    for (const char* name : {"cornell7d.json", "interior_deep.json"}) {
        auto s = loadTestScene(name);
        s.width = 24;
        s.height = 17;
        const auto plan = render::planDimensions(s);
        const auto data = render::flattenScene(s);
        for (const char* sampler : {"oa", "halton"}) {
            oas::PatternRequest request;
            request.sampler = sampler;
            request.spp = std::string(sampler) == "oa" ? 49 : 16;
            request.dims = plan.sampleDims;
            const auto pattern = oas::makePattern(request);
            render::SampleBatch batch;
            batch.width = s.width;
            batch.height = s.height;
            batch.count = pattern.N + 3;  // into a second pass
            render::Accumulation one(s.width, s.height);
            render::traceCpu(data, plan, pattern, batch, one, 1);
            for (unsigned threads : {2u, 5u}) {
                render::Accumulation many(s.width, s.height);
                render::traceCpu(data, plan, pattern, batch, many, threads);
                EXPECT_EQ(one.words, many.words) << name << " " << sampler << " with " << threads << " threads";
            }
        }
    }
}

TEST(RenderCpu, FourLaneBoxTestsEqualTheScalarPtBox)
{
    // The CPU walk tests each child box four lanes at once (tracer_cpu.cpp); the shared GLSL's
    // scalar pt_box is the definition. Boxes: random, flat on an axis, and with the node's index
    // bits in lane w as the BVH stores them (small integers: denormals as floats, and all ones: a
    // NaN). Rays: from inside and outside, with direction components from 1e-20 (inverse 1e20, as
    // pt_trace clamps them) to 1, either sign, half of them aimed into a box; tMax from 0.1 to 10,
    // or PT_INF. Equal means equal as
    // floats (a zero's sign may differ) or both PT_INF.
    std::mt19937 rng(20261204u);
    std::uniform_real_distribution<float> coord(-4.0f, 4.0f), unit(0.0f, 1.0f);
    render::SceneData data;
    const std::uint32_t indexBits[] = {0u, 1u, 7u, 123456u, 0xffffffffu, 0x3f800000u};
    for (int i = 0; i < 64; ++i) {
        oas::pt::PtNode n;
        glm::vec3 a(coord(rng), coord(rng), coord(rng)), b(coord(rng), coord(rng), coord(rng));
        if (i % 4 == 1) b.y = a.y;  // flat
        if (i % 8 == 3) b = a;      // a point
        const glm::vec3 lo = glm::min(a, b), hi = glm::max(a, b);
        std::uint32_t loW = indexBits[i % 6], hiW = indexBits[(i / 6) % 6];
        float loWf, hiWf;
        std::memcpy(&loWf, &loW, 4);
        std::memcpy(&hiWf, &hiW, 4);
        n.lo = glm::vec4(lo, loWf);
        n.hi = glm::vec4(hi, hiWf);
        data.nodes.push_back(n);
    }
    std::size_t hits = 0, misses = 0;
    for (int ray = 0; ray < 20000; ++ray) {
        const glm::vec3 o(coord(rng), coord(rng), coord(rng));
        const std::uint32_t first = std::uint32_t(ray) % (data.nodes.size() - 1);
        glm::vec3 invD;
        for (int axis = 0; axis < 3; ++axis) {
            float d = std::pow(10.0f, -20.0f * unit(rng) * unit(rng) * unit(rng)) * (unit(rng) < 0.5f ? -1.0f : 1.0f);
            if (ray % 2 == 0) {  // aimed at a point of the first child's box, so that about half hit
                const auto& n = data.nodes[first];
                d = n.lo[axis] + (n.hi[axis] - n.lo[axis]) * unit(rng) - o[axis];
                if (std::abs(d) < 1e-20f) d = 1e-20f;  // pt_trace's clamp
            }
            invD[axis] = 1.0f / d;
        }
        const float tMax = ray % 5 == 0 ? 1e30f : std::pow(10.0f, 2.0f * unit(rng) - 1.0f);
        const glm::vec2 simd = render::childrenBoxCpu(data, first, o, invD, tMax);
        const glm::vec2 scalar = render::childrenBoxScalar(data, first, o, invD, tMax);
        for (int c = 0; c < 2; ++c) {
            ASSERT_TRUE(simd[c] == scalar[c])
                << "ray " << ray << " child " << c << ": " << simd[c] << " vs " << scalar[c] << " (tMax " << tMax << ")";
            (scalar[c] == 1e30f ? misses : hits) += 1;
        }
    }
    EXPECT_GT(hits, 8000u);
    EXPECT_GT(misses, 8000u);
}

TEST(RenderCpu, RunsOfSamplesGiveTheSumsOfOneSampleAtATime)
{
    // The CPU tracer makes each OA dimension for a run of up to 128 samples of a pixel at once
    // (OaColumns), from the first sample that asks for it, and keeps the run per thread. Tracing
    // each sample as a batch of its own makes runs of one sample, so an exact comparison of the
    // sums shows that the runs' bookkeeping (where a run starts and ends, which samples a
    // dimension was made for) changes no value. The shipped scenes' patterns: Bose over GF(11)
    // and GF(2^3), Bose-Bush over GF(2^4); 300 samples cross runs and passes.
    for (const char* name : {"cornell7d.json", "blue_spheres9d.json", "interior_deep.json"}) {
        auto s = loadTestScene(name);
        s.height = std::max(1u, s.height * 5 / s.width);
        s.width = 5;
        const auto plan = render::planDimensions(s);
        const auto data = render::flattenScene(s);
        const auto pattern = patternFor(s, plan, s.sampler.spp);
        render::SampleBatch batch;
        batch.width = s.width;
        batch.height = s.height;
        batch.count = 300;
        render::Accumulation runs(s.width, s.height), single(s.width, s.height);
        render::traceCpu(data, plan, pattern, batch, runs, 2);
        for (std::uint32_t i = 0; i < 300; ++i) {
            batch.firstSample = i;
            batch.count = 1;
            render::traceCpu(data, plan, pattern, batch, single, 2);
        }
        EXPECT_TRUE(runs.words == single.words) << name << " (" << oas::describe(pattern) << ")";
    }
}

TEST(Render, ForEachBatchCoversEveryPixelAndSampleOnce)
{
    // oas-render and the study both drive dispatches through forEachBatch: every (pixel, sample)
    // must be visited exactly once, tiles must stay within kRenderTile, and a false afterPass
    // must stop after the current pass.
    const std::uint32_t width = 2 * render::kRenderTile + 17, height = render::kRenderTile + 3, spp = 10;
    std::vector<std::uint32_t> visits(std::size_t(width) * height * spp, 0);
    std::vector<std::uint32_t> passEnds;
    const std::uint32_t done = render::forEachBatch(
        width, height, spp, 3, 7,
        [&](const render::SampleBatch& b) {
            EXPECT_LE(b.width, render::kRenderTile);
            EXPECT_LE(b.height, render::kRenderTile);
            EXPECT_EQ(b.seed, 7u);
            for (std::uint32_t y = b.y0; y < b.y0 + b.height; ++y)
                for (std::uint32_t x = b.x0; x < b.x0 + b.width; ++x)
                    for (std::uint32_t i = b.firstSample; i < b.firstSample + b.count; ++i)
                        ++visits[(std::size_t(y) * width + x) * spp + i];
        },
        [&](std::uint32_t samplesDone) {
            passEnds.push_back(samplesDone);
            return true;
        });
    EXPECT_EQ(done, spp);
    EXPECT_EQ(passEnds, (std::vector<std::uint32_t>{3, 6, 9, 10}));
    for (auto v : visits) ASSERT_EQ(v, 1u);
    const std::uint32_t stopped = render::forEachBatch(
        8, 8, spp, 4, 0, [](const render::SampleBatch&) {}, [](std::uint32_t) { return false; });
    EXPECT_EQ(stopped, 4u);
}

TEST(DimensionPlan, TheSevenDimensionalSceneAndRemovingEffects)
{
    auto s = loadTestScene("cornell7d.json");
    auto names = [](const render::DimensionPlan& p) {
        std::string out;
        for (const auto& e : p.entries) out += e.name + " ";
        return out;
    };
    auto plan = render::planDimensions(s);
    EXPECT_EQ(names(plan), "pixel.xy lens.uv time light.uv ");
    EXPECT_EQ(plan.usedDims, 7u);
    // 2D effects start on even dimensions (OA partner columns).
    for (const auto& e : plan.entries) {
        if (e.count == 2) {
            EXPECT_EQ(e.first % 2, 0u) << e.name;
        }
    }

    auto noLens = s;
    noLens.camera.apertureRadius = 0;
    const auto p1 = render::planDimensions(noLens);
    EXPECT_EQ(names(p1), "pixel.xy time light.uv ");
    EXPECT_EQ(p1.usedDims, 5u);
    EXPECT_EQ(p1.lens, render::kAbsent);

    auto still = s;
    for (auto& shape : still.shapes) shape.velocity = glm::vec3(0);
    const auto p2 = render::planDimensions(still);
    EXPECT_EQ(names(p2), "pixel.xy lens.uv light.uv ");
    EXPECT_EQ(p2.time, render::kAbsent);

    auto closedShutter = s;
    closedShutter.shutterClose = closedShutter.shutterOpen;
    EXPECT_EQ(render::planDimensions(closedShutter).time, render::kAbsent);

    auto twoLights = s;
    twoLights.lights.push_back(scene::Light{});
    EXPECT_EQ(names(render::planDimensions(twoLights)), "pixel.xy lens.uv time light.select light.uv ");

    auto misOn = s;
    misOn.integrator.mis = true;
    EXPECT_EQ(names(render::planDimensions(misOn)), "pixel.xy lens.uv time light.uv bsdf.uv ");

    auto path = s;
    path.integrator.type = scene::Integrator::Type::Path;
    path.integrator.maxDepth = 3;
    path.integrator.mis = false;
    path.integrator.rouletteStartDepth = 2;
    EXPECT_EQ(names(render::planDimensions(path)),
              "pixel.xy lens.uv time v1.light.uv v1.bsdf.uv v2.light.uv v2.bsdf.uv v2.roulette v3.light.uv ");
}

TEST(DimensionPlan, EveryScenesIntegrandDimension)
{
    // The scenes mirror the paper's integrands: 7D Cornell box, 9D blue spheres, a deep interior.
    const std::vector<std::pair<std::string, std::uint32_t>> expected = {{"cornell7d.json", 7},        {"blue_spheres9d.json", 9},
                                                                         {"interior_deep.json", 41},   {"furnace.json", 8},
                                                                         {"plane_rect_light.json", 4}, {"mesh_demo.json", 22}};
    for (const auto& [name, dims] : expected) {
        const auto plan = render::planDimensions(loadTestScene(name));
        EXPECT_EQ(plan.usedDims, dims) << name << ": " << plan.explain();
        std::uint32_t counted = 0;
        for (const auto& e : plan.entries) {
            counted += e.count;
            EXPECT_LT(e.first + e.count - 1, plan.sampleDims) << name << " " << e.name;
        }
        EXPECT_EQ(counted, plan.usedDims) << name;
    }
    // The 9D scene: antialiasing, lens, time and two BSDF bounces, no light sampling.
    const auto nine = render::planDimensions(loadTestScene("blue_spheres9d.json"));
    EXPECT_NE(nine.lens, render::kAbsent);
    EXPECT_NE(nine.time, render::kAbsent);
}

class RenderGpu : public test::GpuTest {
protected:
    /// Every shipped scene: their plans differ in depth, NEE, MIS, lens, motion and roulette.
    static constexpr const char* kShippedScenes[] = {"cornell7d.json",      "blue_spheres9d.json",   "interior_deep.json",
                                                     "furnace.json",        "plane_rect_light.json", "mesh_demo.json"};

    /// `batch` traced with the prefetched samples (the generation kernel's) and with the inline
    /// fetch (oas_draw per sample): the values are the same bits, so the sums must be too.
    void expectPrefetchedSumsEqualInline(const render::SceneData& data, const render::DimensionPlan& plan, const Pattern& pattern,
                                         const render::SampleBatch& batch, const std::string& what)
    {
        using Prefetch = render::GpuTracerOptions::Prefetch;
        render::GpuTracer inlineFetch(context(), data, plan, pattern, {render::KernelStage::PathTrace, true, Prefetch::Never});
        render::GpuTracer prefetched(context(), data, plan, pattern, {render::KernelStage::PathTrace, true, Prefetch::Always});
        inlineFetch.trace(batch);
        prefetched.trace(batch);
        EXPECT_TRUE(prefetched.accumulation().words == inlineFetch.accumulation().words)
            << what << ": the prefetched samples' sums differ";
    }
};

TEST_F(RenderGpu, AgreesWithTheCpuReference)
{
    // The same scene, plan and OA samples on both sides: per pixel the two estimates differ only by
    // floating-point evaluation order and the GPU's sin/cos/sqrt precision, far below the noise.
    auto s = loadTestScene("cornell7d.json");
    s.width = 24;
    s.height = 24;
    const auto plan = render::planDimensions(s);
    const auto data = render::flattenScene(s);
    const auto pattern = patternFor(s, plan, 121);
    auto [batch, cpu] = wholeImage(s, 121, 3);
    EXPECT_EQ(render::traceCpu(data, plan, pattern, batch, cpu), 0u);
    render::GpuTracer gpu(context(), data, plan, pattern);
    for (std::uint32_t first = 0; first < 121; first += 11) {
        batch.firstSample = first;
        batch.count = 11;
        gpu.trace(batch);
    }
    EXPECT_EQ(gpu.rejectedSamples(), 0u);
    const auto g = gpu.accumulation();
    double sumAbs = 0, sum = 0;
    std::size_t far = 0;
    for (std::size_t i = 0; i < cpu.pixelCount(); ++i) {
        ASSERT_EQ(g.samples(i), 121u);
        for (int c = 0; c < 3; ++c) {
            const double a = render::meanValue(cpu.pixel(i), c), b = render::meanValue(g.pixel(i), c);
            sumAbs += std::abs(a - b);
            sum += std::abs(a);
            if (std::abs(a - b) > 0.02 * std::abs(a) + 1e-4) ++far;
        }
    }
    ASSERT_GT(sum, 0.0) << "the reference image is black";
    EXPECT_LT(sumAbs / sum, 1e-3) << "mean relative difference";
    EXPECT_LE(far, cpu.pixelCount() * 3 / 100) << "pixels differing by more than 2%";
}

TEST_F(RenderGpu, SceneFeatureSpecialisationKeepsEverySumBitForBit)
{
    // The kernel compiles away the shape types, conductor materials, point/spot lights and shape
    // motion a scene lacks (PT_SCENE_FEATURES: pt_trace.glsl, read by pt_intersect, pt_bsdf and
    // pt_light.glsl). The code that remains is the same, so every shipped scene, which between them have every feature
    // and lack each of them somewhere, gives the same exact sums, word for word, with and without
    // the specialisation.
    bool sawSpecialised = false;
    for (const char* name : {"cornell7d.json", "blue_spheres9d.json", "interior_deep.json", "furnace.json",
                             "plane_rect_light.json", "mesh_demo.json"}) {
        auto s = loadTestScene(name);
        s.height = std::max(1u, s.height * 16 / s.width);
        s.width = 16;
        const auto plan = render::planDimensions(s);
        const auto data = render::flattenScene(s);
        const auto f = render::sceneFeatures(data);
        sawSpecialised |= !(f.spheres && f.quads && f.triangles && f.conductors && f.pointLights && f.movingShapes);
        const auto pattern = patternFor(s, plan, 16);
        auto [batch, unused] = wholeImage(s, 16, 7);
        render::GpuTracer specialised(context(), data, plan, pattern);
        render::GpuTracer everything(context(), data, plan, pattern, {render::KernelStage::PathTrace, false});
        specialised.trace(batch);
        everything.trace(batch);
        const auto a = specialised.accumulation(), b = everything.accumulation();
        ASSERT_EQ(a.words.size(), b.words.size()) << name;
        EXPECT_TRUE(a.words == b.words) << name << ": the specialised kernel's sums differ";
        double total = 0;
        for (std::size_t i = 0; i < a.pixelCount(); ++i) total += render::meanValue(a.pixel(i), 0);
        EXPECT_GT(total, 0.0) << name << " renders black: the comparison would prove nothing";
    }
    EXPECT_TRUE(sawSpecialised) << "no shipped scene lacks a feature: the test compares a kernel with itself";
}

TEST_F(RenderGpu, PrefetchedSamplesGiveTheSumsOfTheInlineFetch)
{
    // The GPU tracer has the generation kernel make each batch's OA values first and reads them
    // (GpuTracerOptions::prefetch); without it every sample draws its own with oas_draw.
    // The values are the same bits, so the sums must agree word for word: on every shipped scene
    // (their plans differ in depth and effects, so in which dimensions the kernel reads, all of
    // which prefetchDims must cover), across a pass boundary (the batch starts one sample before
    // the end of the first pass), and in strips (a cap on the points of one generation dispatch
    // splits the batch's rows, here into strips of two rows and a last one of one).
    for (const char* name : kShippedScenes) {
        auto s = loadTestScene(name);
        s.width = 16;
        s.height = 9;
        const auto plan = render::planDimensions(s);
        const auto data = render::flattenScene(s);
        const auto pattern = patternFor(s, plan, 16);
        ASSERT_NE(render::prefetchDims(plan, pattern), 0u) << name << ": an OA pattern is prefetched";
        ASSERT_EQ(render::prefetchDims(plan, pattern) % 4, 0u) << name << ": whole texels per sample";
        using Prefetch = render::GpuTracerOptions::Prefetch;
        render::GpuTracer inlineFetch(context(), data, plan, pattern, {render::KernelStage::PathTrace, true, Prefetch::Never});
        render::SampleBatch batch;
        batch.width = s.width;
        batch.height = s.height;
        batch.count = std::max(2u, inlineFetch.samplesPerBatch());
        batch.firstSample = pattern.N - 1;
        batch.seed = 11;
        inlineFetch.trace(batch);
        const auto expected = inlineFetch.accumulation();
        // Uncapped, a batch is one strip (the other RenderGpu tests render that way).
        const std::uint64_t cap = std::uint64_t(2) * s.width * batch.count;
        render::GpuTracer prefetched(context(), data, plan, pattern,
                                     {render::KernelStage::PathTrace, true, Prefetch::Always, cap});
        prefetched.trace(batch);
        const auto a = prefetched.accumulation();
        ASSERT_EQ(a.words.size(), expected.words.size()) << name;
        EXPECT_TRUE(a.words == expected.words) << name << ": the prefetched samples' sums differ";
        double total = 0;
        for (std::size_t i = 0; i < expected.pixelCount(); ++i) total += render::meanValue(expected.pixel(i), 0);
        EXPECT_GT(total, 0.0) << name << " renders black: the comparison would prove nothing";
    }
    // The padded 2D baselines, the table-driven Sobols and Halton are prefetched by default too
    // (their pairs' keys, direction numbers, digit permutations are per pass); the others draw
    // inline (nothing to share), but any of them prefetched gives the inline sums, across a pass.
    auto s = loadTestScene("blue_spheres9d.json");
    s.width = 16;
    s.height = 9;
    const auto plan = render::planDimensions(s);
    const auto data = render::flattenScene(s);
    for (const auto& sampler : oas::samplerNames()) {
        if (oas::isOrthogonalArray(sampler)) continue;
        const auto pattern = patternFor(s, plan, 16, sampler.c_str());
        const bool perPassState = sampler == "jittered2d" || sampler == "cmj2d" || sampler == "zerotwo" || sampler == "sobol" ||
                                  sampler == "sobol-owen" || sampler == "halton";
        ASSERT_EQ(render::prefetchDims(plan, pattern) != 0u, perPassState) << sampler;
        render::SampleBatch batch;
        batch.width = s.width;
        batch.height = s.height;
        batch.count = 3;
        batch.firstSample = pattern.N - 1;
        batch.seed = 5;
        expectPrefetchedSumsEqualInline(data, plan, pattern, batch, sampler);
    }
}

TEST_F(RenderGpu, PrefetchedBaselinesGiveTheSumsOfTheInlineFetch)
{
    // The generation kernel's baselines leave the dimensions no path uses unmade
    // (render::unusedDims, SampleRequest::unreadDims): whatever the buffer held there must reach
    // no sum. On every shipped scene (in which dimensions of a fetched group a path reads), Sobol
    // (a dimension a group) and cmj2d (a pair a group) prefetched give the sums of the inline
    // fetch, across a pass.
    for (const char* name : kShippedScenes) {
        auto s = loadTestScene(name);
        s.width = 16;
        s.height = 9;
        const auto plan = render::planDimensions(s);
        const auto data = render::flattenScene(s);
        if (std::string(name) == "blue_spheres9d.json")  // its plan: dims 0-4 and 6-9 (explain), 12 prefetched
            EXPECT_EQ(render::unusedDims(plan) & 0xfffu, (1u << 5) | (1u << 10) | (1u << 11));
        for (const char* sampler : {"sobol", "cmj2d"}) {
            const auto pattern = patternFor(s, plan, 16, sampler);
            render::SampleBatch batch;
            batch.width = s.width;
            batch.height = s.height;
            batch.count = 3;
            batch.firstSample = pattern.N - 1;
            batch.seed = 7;
            expectPrefetchedSumsEqualInline(data, plan, pattern, batch, std::string(name) + ", " + sampler);
        }
    }
}

TEST_F(RenderGpu, BatchesOfSamplesPerDispatchGiveTheSumsOfOneSampleAtATime)
{
    // Lavapipe ends an invocation's loops after 65535 iterations in all, silently: a batch too large
    // for a scene would lose path vertices and change the sums. samplesPerBatch sizes the batch
    // from a worst-case bound per sample; here each shipped scene renders in those batches and one
    // sample per dispatch, and the exact sums must agree word for word.
    std::uint32_t largestBatch = 0;
    for (const char* name : {"cornell7d.json", "blue_spheres9d.json", "interior_deep.json", "mesh_demo.json"}) {
        auto s = loadTestScene(name);
        s.height = std::max(1u, s.height * 12 / s.width);
        s.width = 12;
        const auto plan = render::planDimensions(s);
        const auto data = render::flattenScene(s);
        const auto pattern = patternFor(s, plan, 16);
        render::GpuTracer gpu(context(), data, plan, pattern);
        const std::uint32_t perBatch = gpu.samplesPerBatch();
        EXPECT_EQ(perBatch, render::samplesPerBatch(plan, data)) << name;
        EXPECT_GE(perBatch, 1u) << name;
        EXPECT_LE(perBatch, render::kMaxSamplesPerBatch) << name;
        largestBatch = std::max(largestBatch, perBatch);
        auto [batch, unused] = wholeImage(s, 16, 5);
        for (std::uint32_t first = 0; first < 16; first += perBatch) {
            batch.firstSample = first;
            batch.count = std::min(perBatch, 16 - first);
            gpu.trace(batch);
        }
        const auto batched = gpu.accumulation();
        gpu.clear();
        for (std::uint32_t first = 0; first < 16; ++first) {
            batch.firstSample = first;
            batch.count = 1;
            gpu.trace(batch);
        }
        EXPECT_TRUE(batched.words == gpu.accumulation().words) << name << ": " << perBatch << " samples per dispatch";
    }
    EXPECT_GT(largestBatch, 1u) << "every scene got one sample per dispatch: the comparison would prove nothing";
}

TEST_F(RenderGpu, RejectsNonFiniteNegativeAndHugeSamples)
{
    // With the light's radiance NaN, negative or 1e30 (>= 2^64) in the flattened scene (the loader
    // refuses such scenes; this is the one way to make light samples unsummable), both tracers
    // count the samples as taken and as rejected, and keep them out of the sums: every sum stays
    // what the other samples give. clear() resets the counts.
    auto s = loadTestScene("cornell7d.json");
    s.width = 8;
    s.height = 8;
    const auto plan = render::planDimensions(s);
    const auto pattern = patternFor(s, plan, 121);
    for (const float bad : {std::numeric_limits<float>::quiet_NaN(), -1.0f, 1e30f}) {
        auto hot = render::flattenScene(s);
        for (auto& m : hot.materials)
            if (m.emission.x > 0) m.emission.x = bad;
        auto [batch, cpuHot] = wholeImage(s, 11);
        const std::uint64_t cpuRejected = render::traceCpu(hot, plan, pattern, batch, cpuHot);
        EXPECT_GT(cpuRejected, 0u) << bad;
        EXPECT_EQ(cpuHot.rejectedSamples(), cpuRejected);
        for (std::size_t i = 0; i < cpuHot.pixelCount(); ++i) {
            ASSERT_EQ(cpuHot.samples(i), 11u);
            ASSERT_LE(cpuHot.rejected(i), 11u);
        }
        for (float v : cpuHot.image().rgba) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v < 1e3f) << bad;
        render::GpuTracer gpuHot(context(), hot, plan, pattern);
        gpuHot.trace(batch);
        EXPECT_GT(gpuHot.rejectedSamples(), 0u) << bad;
        const auto g = gpuHot.accumulation();
        for (std::size_t i = 0; i < g.pixelCount(); ++i) ASSERT_EQ(g.samples(i), 11u);
        for (float v : g.image().rgba) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v < 1e3f) << bad;
        gpuHot.clear();
        EXPECT_EQ(gpuHot.rejectedSamples(), 0u);
    }
}

/// Runs oas-render with arguments; returns the exit status.
int runRender(const std::string& args)
{
    const std::string command = std::string(OAS_RENDER_EXE) + " " + args + " >/dev/null 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(RenderCli, BadScenesExitNonZeroAndWriteNothing)
{
    const auto dir = std::filesystem::temp_directory_path() / ("oas_render_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::string good = std::string(OAS_SCENES_DIR) + "/furnace.json";
    std::ifstream in(good);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"malformed", text.substr(0, text.size() / 2)},
        {"unknown_key", "{\"resolution\": [8, 8], \"bogus\": 1}"},
        {"absurd_resolution", "{\"resolution\": [0, 8]}"},
    };
    for (const auto& [name, body] : bad) {
        const auto scenePath = dir / (name + ".json");
        std::ofstream(scenePath) << body;
        const auto out = dir / (name + ".exr");
        EXPECT_EQ(runRender(scenePath.string() + " -o " + out.string() + " --device cpu"), 2) << name;
        EXPECT_FALSE(std::filesystem::exists(out)) << name;
        EXPECT_FALSE(std::filesystem::exists(dir / (name + ".png"))) << name;
    }
    EXPECT_EQ(runRender((dir / "missing.json").string()), 2);
    EXPECT_EQ(runRender(good + " --spp 0"), 2);
    EXPECT_EQ(runRender(good + " --sampler bose --spp 100"), 2);
    // A good scene renders on the CPU and writes both files.
    const auto out = dir / "furnace.exr";
    EXPECT_EQ(runRender(good + " --device cpu --spp 16 -o " + out.string()), 0);
    EXPECT_TRUE(std::filesystem::exists(out));
    EXPECT_TRUE(std::filesystem::exists(dir / "furnace.png"));
    std::filesystem::remove_all(dir);
}

TEST(RenderCli, StopSignalsWriteTheImageAccumulatedSoFar)
{
    // SIGINT (Ctrl-C), and since issue 8 also SIGTERM (kill, systemd, CI timeouts) and SIGHUP (a
    // closed terminal): stop after the current pass, write the image with its real spp, exit 128 +
    // the signal. Before, SIGTERM and SIGHUP lost the whole render.
    for (const int sig : {SIGINT, SIGTERM, SIGHUP}) {
        const auto dir =
            std::filesystem::temp_directory_path() / ("oas_render_int_" + std::to_string(::getpid()) + "_" + std::to_string(sig));
        std::filesystem::create_directories(dir);
        const std::string out = (dir / "partial.exr").string();
        const std::string scenePath = std::string(OAS_SCENES_DIR) + "/furnace.json";
        // A CPU render far too long to finish (1M spp); signal it once the output would be partial.
        std::vector<std::string> args = {OAS_RENDER_EXE, scenePath, "--device", "cpu", "--spp", "1000000", "-o", out};
        std::vector<char*> argv;
        for (auto& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        pid_t pid = 0;
        ASSERT_EQ(posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ), 0);
        std::this_thread::sleep_for(std::chrono::milliseconds(1500));
        ::kill(pid, sig);
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        ASSERT_TRUE(WIFEXITED(status)) << "signal " << sig << " killed the render";
        EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
        // A valid shard of the finished passes: oas-merge reads it, and it says which samples it
        // holds, so that the rest can be rendered with --samples and merged.
        const render::RenderFile shard = render::readRenderFile(out);
        const std::map<std::string, std::string>& attributes = shard.attributes;
        const image::Image img = shard.sums.image();
        const std::uint32_t spp = std::uint32_t(std::stoul(attributes.at("oas.spp")));
        EXPECT_GT(spp, 0u);
        EXPECT_LT(spp, 1000000u);
        EXPECT_EQ(attributes.at("oas.samples"), "0:" + std::to_string(spp));
        EXPECT_EQ(attributes.at("oas.sppRequested"), "1000000");
        EXPECT_EQ(attributes.at("oas.rejectedSamples"), "0");
        // The furnace's exact answer holds for whatever number of samples was reached.
        EXPECT_NEAR(img.rgba[(std::size_t(16) * img.width + 16) * 4], 0.5f, 1e-5f);
        // Nothing but the two outputs is left.
        std::vector<std::string> names;
        for (const auto& e : std::filesystem::directory_iterator(dir)) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        EXPECT_EQ(names, (std::vector<std::string>{"partial.exr", "partial.png"}));
        std::filesystem::remove_all(dir);
    }
}

/// Every file under `dir`, as paths relative to it, sorted.
std::vector<std::string> filesUnder(const std::filesystem::path& dir)
{
    std::vector<std::string> names;
    for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
        if (e.is_regular_file()) names.push_back(std::filesystem::relative(e.path(), dir).string());
    std::sort(names.begin(), names.end());
    return names;
}

TEST(RenderCli, OutputNamesStayWhereTheUserSaid)
{
    // Regression (issue 8): without -o a scene named "../../escaped" wrote two directories up, a
    // NUL in the name made the PNG overwrite the EXR, and -o x.png overwrote the EXR with the PNG.
    const auto root = std::filesystem::temp_directory_path() / ("oas_render_names_" + std::to_string(::getpid()));
    std::filesystem::remove_all(root);
    const auto work = root / "a" / "b";
    std::filesystem::create_directories(work);
    std::ifstream in(std::string(OAS_SCENES_DIR) + "/furnace.json");
    const nlohmann::json furnace = nlohmann::json::parse(in);
    const std::vector<std::pair<std::string, std::string>> names = {
        {"../../escaped", "_.._escaped"},
        {std::string("a\0b", 3), "a_b"},
        {"/abs/olute", "_abs_olute"},
        {"..", "scene3"},  // nothing left after the dots: the scene file's stem
        {".hidden", "hidden"},
        {"spaces and ü", "spaces_and___"}};
    for (std::size_t i = 0; i < names.size(); ++i) {
        nlohmann::json j = furnace;
        j["name"] = names[i].first;
        std::ofstream(work / ("scene" + std::to_string(i) + ".json")) << j.dump();
        const std::string command = "cd '" + work.string() + "' && " + OAS_RENDER_EXE + " scene" + std::to_string(i) +
                                    ".json --device cpu --spp 4 >/dev/null 2>&1";
        const int status = std::system(command.c_str());
        ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << names[i].second;
        const std::string stem = "out/" + names[i].second;
        EXPECT_TRUE(std::filesystem::exists(work / (stem + ".exr"))) << stem;
        EXPECT_TRUE(std::filesystem::exists(work / (stem + ".png"))) << stem;
    }
    // Nothing outside the working directory, and two outputs per scene.
    const auto all = filesUnder(root);
    for (const auto& f : all) EXPECT_EQ(f.rfind("a/b/", 0), 0u) << f;
    EXPECT_EQ(all.size(), names.size() * 3);

    // -o must name the EXR; its PNG goes beside it, so the two can never be one file.
    const std::string scene0 = (work / "scene0.json").string();
    for (const std::string& bad : std::vector<std::string>{"x.png", "x", "x.exr.png", (work / "out").string(), ".exr"}) {
        const auto before = filesUnder(root);
        EXPECT_EQ(runRender(scene0 + " --device cpu --spp 4 -o '" + bad + "'"), 2) << bad;
        EXPECT_EQ(filesUnder(root), before) << bad;
    }
    EXPECT_EQ(runRender(scene0 + " --device cpu --spp 4 -o '" + (work / "X.EXR").string() + "'"), 0);
    EXPECT_TRUE(std::filesystem::exists(work / "X.png"));
    std::filesystem::remove_all(root);
}

TEST(RenderCli, FuzzerFindingsExitWithAMessageNamingTheScene)
{
    // The structured mutator's reproducers (fuzz/regressions/cli): a sampler count no OA makes,
    // a mesh that is a device, bytes after a NUL. Each exits 2 within the time a load takes,
    // with a message that starts with the scene file's name (the sampler errors named none).
    const auto dir = std::filesystem::path(OAS_FUZZ_REGRESSIONS_DIR) / "cli";
    const auto errFile = std::filesystem::temp_directory_path() / ("oas_fuzz_cli_" + std::to_string(::getpid()));
    std::size_t checked = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (entry.path().extension() != ".json") continue;
        const std::string command = "timeout 20 " + std::string(OAS_RENDER_EXE) + " '" + entry.path().string() +
                                    "' --explain >/dev/null 2>'" + errFile.string() + "'";
        const int status = std::system(command.c_str());
        ASSERT_TRUE(WIFEXITED(status));
        EXPECT_EQ(WEXITSTATUS(status), 2) << entry.path();
        std::ifstream in(errFile);
        const std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        EXPECT_EQ(err.rfind("oas-render: error: " + entry.path().string() + ": ", 0), 0u) << err;
        ++checked;
    }
    std::filesystem::remove(errFile);
    EXPECT_GE(checked, 3u);
}

/// Runs oas-render with arguments; returns the exit status and what it wrote on stderr.
std::pair<int, std::string> runRenderStderr(const std::string& args)
{
    const auto errFile = std::filesystem::temp_directory_path() / ("oas_render_err_" + std::to_string(::getpid()));
    const int status =
        std::system((std::string(OAS_RENDER_EXE) + " " + args + " >/dev/null 2>'" + errFile.string() + "'").c_str());
    std::ifstream in(errFile);
    std::string err((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::filesystem::remove(errFile);
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, err};
}

/// A fresh directory for one test's outputs.
std::filesystem::path freshDir(const std::string& name)
{
    const auto dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

TEST(RenderCli, BadOverridesExitWithStatus2NameTheValueAndTheRangeAndWriteNothing)
{
    const auto dir = freshDir("oas_render_overrides");
    const std::string good = std::string(OAS_SCENES_DIR) + "/furnace.json --spp 4 -o '" + (dir / "x.exr").string() + "' ";
    // Each bad value, with a part of the message it must give (option, value, valid range).
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"--device cpu --resolution 0x8", "--resolution 0x8: valid WxH, the image's width and height in pixels, each 1 .. 16384"},
        {"--device cpu --resolution -8x8", "--resolution -8x8: valid WxH"},
        {"--device cpu --resolution 8", "--resolution 8: valid WxH"},
        {"--device cpu --resolution x8", "--resolution x8: valid WxH"},
        {"--device cpu --resolution 8x", "--resolution 8x: valid WxH"},
        {"--device cpu --resolution 8x8px", "--resolution 8x8px: valid WxH"},
        {"--device cpu --resolution 4294967304x8", "--resolution 4294967304x8: valid WxH"},
        {"--device cpu --resolution 16385x8", "1 .. 16384"},
        {"--device cpu --resolution 64X64", "--resolution 64X64: valid WxH"},
        {"--device cpu --resolution ' 8x8'", "valid WxH"},
        {"--device cpu --cropwindow 0.5 0.2 0 1", "--cropwindow 0.5 0.2 0 1: valid x0 x1 y0 y1, fractions of the image "
                                                  "with 0 <= x0 < x1 <= 1 and 0 <= y0 < y1 <= 1"},
        {"--device cpu --cropwindow 0 1 0.5 0.5", "--cropwindow 0 1 0.5 0.5: valid x0 x1 y0 y1"},
        {"--device cpu --cropwindow -0.1 0.5 0 1", "--cropwindow -0.1 0.5 0 1: valid"},
        {"--device cpu --cropwindow 0 1 0 1.5", "--cropwindow 0 1 0 1.5: valid"},
        {"--device cpu --cropwindow 0 1 0 nan", "--cropwindow 0 1 0 nan: valid"},
        {"--device cpu --cropwindow 0 1 0 0.5x", "--cropwindow 0 1 0 0.5x: valid"},
        {"--device cpu --cropwindow 0 1 0", "--cropwindow"},
        {"--device cpu --resolution 8x8 --cropwindow 0.01 0.1 0 1", "--cropwindow 0.01 0.1 0 1 holds no pixel of the 8x8 image"},
        {"--threads 2", "--threads 2: the CPU tracer's workers: valid with --device cpu only"},
        {"--device gpu --threads 0", "--threads 0: the CPU tracer's workers: valid with --device cpu only"},
        {"--device cpu --threads 1025", "--threads: Value 1025 not in range 0 to 1024"},
        {"--device cpu --threads -1", "--threads"},
        {"--kernel warp", "--kernel \"warp\": valid mega (one invocation traces whole paths) or wavefront"},
        {"--device cpu --kernel wavefront", "--kernel wavefront: the GPU path tracer's kernel: valid with --device gpu only"},
    };
    for (const auto& [args, message] : bad) {
        const auto [status, err] = runRenderStderr(good + args);
        EXPECT_EQ(status, 2) << args << "\n" << err;
        EXPECT_NE(err.find(message), std::string::npos) << args << "\n" << err;
        EXPECT_TRUE(filesUnder(dir).empty()) << args;
    }
    std::filesystem::remove_all(dir);
}

TEST(RenderCli, ScenesWithoutLightWarnAndStillRender)
{
    // pbrt's warning: a scene with no emitting shape, no point or spot light and no environment
    // renders black. Say so, naming the file, and render anyway. An emitting material that no
    // shape uses is no light.
    const auto dir = freshDir("oas_render_dark");
    std::ifstream in(std::string(OAS_SCENES_DIR) + "/cornell7d.json");
    nlohmann::json j = nlohmann::json::parse(in);
    j.erase("lights");
    j.erase("environment");
    for (auto& shape : j["shapes"])
        if (shape.contains("material") && shape["material"] == "light") shape["material"] = "white";
    const std::string scene = (dir / "dark.json").string();
    std::ofstream(scene) << j.dump();
    const auto [status, err] =
        runRenderStderr(scene + " --device cpu --spp 4 --resolution 8x8 -o '" + (dir / "dark.exr").string() + "'");
    EXPECT_EQ(status, 0) << err;
    EXPECT_NE(err.find("oas-render: warning: " + scene + ": the scene has no light"), std::string::npos) << err;
    const auto dark = render::readRenderFile((dir / "dark.exr").string());
    for (float v : dark.sums.image().rgba) ASSERT_TRUE(v == 0.0f || v == 1.0f);  // black, alpha 1
    // The scenes that have light say nothing of the kind.
    for (const char* lit : {"cornell7d.json", "furnace.json"}) {
        const auto [litStatus, litErr] =
            runRenderStderr(std::string(OAS_SCENES_DIR) + "/" + lit + " --device cpu --spp 4 --resolution 4x4 -o '" +
                            (dir / "lit.exr").string() + "'");
        EXPECT_EQ(litStatus, 0) << litErr;
        EXPECT_EQ(litErr.find("warning"), std::string::npos) << lit << ": " << litErr;
    }
    std::filesystem::remove_all(dir);
}

/// Renders cornell7d at 24x16 on `device` whole and as the crop window 0.25 0.6 0.5 1 (pixels
/// [6, 15) x [8, 16)) and checks that the crop holds the window's pixels of the whole frame, bit
/// for bit, that it says where it lies, and that crops of one window merge like shards while crops
/// of another window do not. `extra` goes to every run.
void checkCropWindow(const std::string& device, const std::string& extra = "")
{
    const auto dir = freshDir("oas_render_crop_" + device);
    const std::string scene =
        std::string(OAS_SCENES_DIR) + "/cornell7d.json --resolution 24x16 --spp 8 --device " + device + " " + extra + " ";
    const auto renderTo = [&](const std::string& name, const std::string& args) {
        const auto [status, err] = runRenderStderr(scene + args + " -o '" + (dir / name).string() + "'");
        EXPECT_EQ(status, 0) << args << "\n" << err;
        return render::readRenderFile((dir / name).string());
    };
    const auto whole = renderTo("whole.exr", "");
    ASSERT_EQ(whole.sums.width, 24u);
    ASSERT_EQ(whole.sums.height, 16u);
    EXPECT_EQ(whole.attributes.count("oas.cropWindow"), 0u);
    const std::string window = "--cropwindow 0.25 0.6 0.5 1";
    const auto crop = renderTo("crop.exr", window);
    ASSERT_EQ(crop.sums.width, 9u);
    ASSERT_EQ(crop.sums.height, 8u);
    EXPECT_EQ(crop.attributes.at("oas.cropWindow"), "[6, 15) x [8, 16) of 24x16");
    EXPECT_EQ(crop.attributes.at("oas.resolution"), "9x8");
    EXPECT_EQ(crop.attributes.at("oas.sceneHash"), whole.attributes.at("oas.sceneHash"));
    const auto expected = whole.sums.window(6, 8, 9, 8);
    EXPECT_TRUE(crop.sums.words == expected.words) << device << ": the crop's sums differ from the whole frame's";
    double total = 0;
    for (float v : crop.sums.image().rgba) total += v;
    EXPECT_GT(total, 9.0 * 8.0) << "the crop is black: the comparison would prove nothing";
    // Two shards of the crop add up to the crop; a crop of another window of that size is refused.
    const auto first = renderTo("first.exr", window + " --samples 0:3");
    const auto rest = renderTo("rest.exr", window + " --samples 3:8");
    EXPECT_TRUE(render::mergeRenders({first, rest}, {"first.exr", "rest.exr"}).sums.words == crop.sums.words);
    const auto other = renderTo("other.exr", "--cropwindow 0.5 0.85 0.5 1 --samples 3:8");
    EXPECT_THROW(render::mergeRenders({first, other}, {"first.exr", "other.exr"}), InvalidArgument);
    std::filesystem::remove_all(dir);
}

TEST(RenderCli, CropWindowHoldsTheWholeFramesPixelsBitForBitOnTheCpu)
{
    checkCropWindow("cpu");
}

TEST(RenderCli, AnyThreadCountGivesTheSameFile)
{
    const auto dir = freshDir("oas_render_threads");
    std::vector<std::uint32_t> first;
    for (const char* threads : {"1", "3", "0"}) {
        const std::string out = (dir / (std::string("t") + threads + ".exr")).string();
        const auto [status, err] = runRenderStderr(std::string(OAS_SCENES_DIR) +
                                                   "/cornell7d.json --device cpu "
                                                   "--resolution 20x13 --spp 9 --threads " +
                                                   threads + " -o '" + out + "'");
        ASSERT_EQ(status, 0) << err;
        const auto words = render::readRenderFile(out).sums.words;
        if (first.empty()) first = words;
        EXPECT_TRUE(words == first) << "--threads " << threads;
    }
    std::filesystem::remove_all(dir);
}

TEST(RenderCli, ImagesTooLargeForMemorySayHowLarge)
{
#if defined(__SANITIZE_ADDRESS__)
    GTEST_SKIP() << "SKIPPED under AddressSanitizer: it needs more address space than the limit this test sets";
#else
    // Regression (issue 8): an in-range resolution that cannot be allocated ended in an uncaught
    // std::bad_alloc. Under a 1 GiB address-space limit a 16384 x 16384 render (4 GiB of float RGBA)
    // must fail with a message naming the size, and write nothing.
    const auto dir = std::filesystem::temp_directory_path() / ("oas_render_oom_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    std::ifstream in(std::string(OAS_SCENES_DIR) + "/furnace.json");
    nlohmann::json j = nlohmann::json::parse(in);
    j["resolution"] = {16384, 16384};
    j["sampler"] = {{"name", "random"}, {"spp", 1}};
    std::ofstream(dir / "huge.json") << j.dump();
    const std::string err = (dir / "err.txt").string();
    const std::string command = "ulimit -v 1048576; exec " + std::string(OAS_RENDER_EXE) + " '" + (dir / "huge.json").string() +
                                "' --device cpu --spp 1 -o '" + (dir / "huge.exr").string() + "' 2>'" + err + "' >/dev/null";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 1);
    std::ifstream errIn(err);
    const std::string text((std::istreambuf_iterator<char>(errIn)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("oas-render: error: cannot allocate"), std::string::npos) << text;
    EXPECT_NE(text.find("16384x16384"), std::string::npos) << text;
    // The sums take 12 words of 4 bytes per pixel: 16384^2 * 48 B = 12288 MiB.
    EXPECT_NE(text.find("12288 MiB"), std::string::npos) << text;
    EXPECT_FALSE(std::filesystem::exists(dir / "huge.exr"));
    std::filesystem::remove_all(dir);
#endif
}

/// Where --checkpoints and oas-view stop. Faure over 8 dimensions has base 8, the smallest prime
/// power >= 8, so its nets are at 8 and 64 (and 512 past 100 spp); Bose at 16 spp has N = 16.
TEST(Checkpoints, FaureAtThePowersOfItsBaseOthersAtWholePasses)
{
    using V = std::vector<std::uint32_t>;
    const Pattern faure = test::faurePattern(100, 8), bose = makePattern({.sampler = "bose", .spp = 16});
    ASSERT_EQ(faure.s, 8u);
    EXPECT_EQ(apps::checkpointCounts(faure, 0, 100), (V{8, 64}));
    EXPECT_EQ(apps::checkpointCounts(faure, 8, 100), (V{64}));
    EXPECT_EQ(apps::checkpointCounts(faure, 0, 64), (V{8}));  // the end is not a stop
    EXPECT_EQ(apps::checkpointCounts(faure, 64, 100), V{});
    ASSERT_EQ(bose.N, 16u);
    EXPECT_EQ(apps::checkpointCounts(bose, 0, 50), (V{16, 32, 48}));
    EXPECT_EQ(apps::checkpointCounts(bose, 16, 48), (V{32}));
}

// The CLI on the Vulkan device (lavapipe unless chosen): the same crop property on the GPU. The
// fixture skips visibly without a device.
/// --checkpoints: one render writes the image after every q^m samples of a faure sequence (q = 11
/// here: 11 and 121 of 300), each the sums of the shard render --samples 0:q^m word for word,
/// and the final image is that of the render without checkpoints.
void checkCheckpoints(const char* device)
{
    const auto dir = freshDir(std::string("oas_render_checkpoints_") + device);
    const std::string common = std::string(OAS_SCENES_DIR) + "/blue_spheres9d.json --sampler faure --spp 300 --resolution 12x9 " +
                               "--device " + device + " -o '";
    auto words = [&](const std::string& name, const std::string& more) {
        const std::string out = (dir / name).string();
        const auto [status, err] = runRenderStderr(common + out + "' " + more);
        EXPECT_EQ(status, 0) << err;
        return render::readRenderFile(out).sums.words;
    };
    const auto full = words("full.exr", "--checkpoints");
    EXPECT_TRUE(full == words("plain.exr", "")) << "checkpoints changed the final image";
    for (std::uint32_t c : {11u, 121u}) {
        const auto checkpoint = render::readRenderFile((dir / ("full.spp" + std::to_string(c) + ".exr")).string());
        ASSERT_EQ(checkpoint.ranges.size(), 1u);
        EXPECT_EQ(checkpoint.ranges[0].end, c);
        EXPECT_TRUE(checkpoint.sums.words == words("shard" + std::to_string(c) + ".exr", "--samples 0:" + std::to_string(c)))
            << "checkpoint " << c;
    }
    EXPECT_FALSE(std::filesystem::exists(dir / "full.spp1331.exr")) << "no checkpoint past the render's samples";
    std::filesystem::remove_all(dir);
}

TEST(RenderCli, CheckpointsAreTheShardsOfTheirSamplesOnTheCpu)
{
    checkCheckpoints("cpu");
}

TEST_F(RenderGpu, CliCheckpointsAreTheShardsOfTheirSamples)
{
    checkCheckpoints("gpu");
}

TEST_F(RenderGpu, CliCropWindowHoldsTheWholeFramesPixelsBitForBit)
{
    checkCropWindow("gpu");
}

TEST_F(RenderGpu, CliWavefrontKernelWritesTheMegakernelsSumsAndExplainNamesTheKernels)
{
    // `--kernel wavefront` renders with pt_wavefront.comp: the file's sums are the default
    // megakernel's, word for word (tests/wavefront_test.cpp cuts renders every other way).
    // --explain names the kernels a render runs: the generation kernel where the samples are
    // prefetched (cornell7d's 7D plan with the OA), then the path tracer's.
    const auto dir = freshDir("oas_render_kernel");
    const std::string common = std::string(OAS_SCENES_DIR) + "/cornell7d.json --spp 16 --resolution 12x9 -o '";
    auto words = [&](const std::string& name, const std::string& more) {
        const std::string out = (dir / name).string();
        const auto [status, err] = runRenderStderr(common + out + "' " + more);
        EXPECT_EQ(status, 0) << err;
        return render::readRenderFile(out).sums.words;
    };
    EXPECT_TRUE(words("mega.exr", "") == words("wavefront.exr", "--kernel wavefront"));
    const auto explain = [&](const std::string& kernel) {
        const auto out = dir / ("explain_" + kernel);
        const std::string command = std::string(OAS_RENDER_EXE) + " " + std::string(OAS_SCENES_DIR) +
                                    "/cornell7d.json --explain --kernel " + kernel + " >'" + out.string() + "'";
        EXPECT_EQ(std::system(command.c_str()), 0) << command;
        std::ifstream in(out);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const std::string mega = explain("mega"), wavefront = explain("wavefront");
    EXPECT_NE(mega.find("GPU kernels: oas_generate ("), std::string::npos) << mega;
    EXPECT_NE(mega.find(", then pt_render (the megakernel"), std::string::npos) << mega;
    EXPECT_NE(wavefront.find(", then pt_wavefront: the camera kernel, up to "), std::string::npos) << wavefront;
    std::filesystem::remove_all(dir);
}

}  // namespace

// The progressive loop of oas-render and oas-view: forEachBatch's batches are passes of
// perBatch samples over kRenderTile tiles, row by row (written out here independently), and a
// BatchCursor with smaller tiles covers every pixel once per pass with the same samples, which is
// why oas-view's accumulation equals oas-render's.
TEST(BatchCursor, PassesCoverEveryPixelOnceWithTheSameSamplesForAnyTile)
{
    struct Case {
        std::uint32_t w, h, spp, perBatch;
    };
    for (const Case c : {Case{300, 200, 10, 4}, Case{64, 64, 16, 8}, Case{513, 3, 5, 5}, Case{1, 1, 3, 1}}) {
        std::vector<oas::render::SampleBatch> expected;
        for (std::uint32_t first = 0; first < c.spp; first += c.perBatch)
            for (std::uint32_t y = 0; y < c.h; y += 256)
                for (std::uint32_t x = 0; x < c.w; x += 256) {
                    oas::render::SampleBatch b;
                    b.x0 = x, b.y0 = y, b.width = std::min(256u, c.w - x), b.height = std::min(256u, c.h - y);
                    b.firstSample = first, b.count = std::min(c.perBatch, c.spp - first), b.seed = 9;
                    expected.push_back(b);
                }
        std::vector<oas::render::SampleBatch> got;
        const std::uint32_t done = oas::render::forEachBatch(c.w, c.h, c.spp, c.perBatch, 9,
                                                             [&](const oas::render::SampleBatch& b) { got.push_back(b); });
        EXPECT_EQ(done, c.spp);
        ASSERT_EQ(got.size(), expected.size());
        for (std::size_t i = 0; i < got.size(); ++i) {
            EXPECT_EQ(got[i].x0, expected[i].x0);
            EXPECT_EQ(got[i].y0, expected[i].y0);
            EXPECT_EQ(got[i].width, expected[i].width);
            EXPECT_EQ(got[i].height, expected[i].height);
            EXPECT_EQ(got[i].firstSample, expected[i].firstSample);
            EXPECT_EQ(got[i].count, expected[i].count);
            EXPECT_EQ(got[i].seed, expected[i].seed);
        }
        // Smaller tiles, changed between passes as oas-view does: per pixel the same list of
        // (firstSample, count) in the same order.
        for (std::uint32_t tile : {1u, 7u, 64u}) {
            std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> perPixel(std::size_t(c.w) * c.h);
            oas::render::BatchCursor cursor(c.w, c.h, c.spp, c.perBatch, 9, tile);
            std::uint32_t passes = 0;
            while (!cursor.done()) {
                const auto& b = cursor.batch();
                EXPECT_LE(b.width, cursor.tile());
                for (std::uint32_t y = b.y0; y < b.y0 + b.height; ++y)
                    for (std::uint32_t x = b.x0; x < b.x0 + b.width; ++x)
                        perPixel[std::size_t(y) * c.w + x].push_back({b.firstSample, b.count});
                if (cursor.advance()) cursor.setTile(tile + 1 + passes++);  // a new tile every pass
            }
            for (const auto& list : perPixel) {
                std::vector<std::pair<std::uint32_t, std::uint32_t>> want;
                for (std::uint32_t first = 0; first < c.spp; first += c.perBatch)
                    want.push_back({first, std::min(c.perBatch, c.spp - first)});
                ASSERT_EQ(list, want) << "tile " << tile;
            }
        }
    }
}

// oas-render and oas-view write the same header for the same render (plus their own extras): the
// frame fields a merge compares, and where the render came from.
TEST(RenderAttributes, EveryWriterRecordsTheFrameFields)
{
    auto s = loadTestScene("cornell7d.json");
    const auto plan = render::planDimensions(s);
    const auto data = render::flattenScene(s);
    const auto pattern = render::scenePattern(s, plan, false).pattern;
    const auto a = render::renderAttributes(s, data, plan, pattern, 37);
    for (const std::string& field : render::frameFields()) EXPECT_TRUE(a.count(field)) << field;
    EXPECT_EQ(a.at("oas.seed"), "37");
    EXPECT_EQ(a.at("oas.resolution"), std::to_string(s.width) + "x" + std::to_string(s.height));
    EXPECT_EQ(a.at("oas.sppRequested"), std::to_string(s.sampler.spp));
    EXPECT_EQ(a.at("oas.sampler"), oas::describe(pattern));
    EXPECT_EQ(a.at("oas.scene"), s.path.string());
    EXPECT_EQ(a.at("oas.pattern").size(), 16u * 9 - 1) << "16 words of 8 hex digits";
    // The plan's first line only (EXR string attributes stay one line).
    EXPECT_FALSE(a.at("oas.dimensionPlan").empty());
    EXPECT_EQ(a.at("oas.dimensionPlan").find('\n'), std::string::npos);
    EXPECT_EQ(plan.explain().rfind(a.at("oas.dimensionPlan"), 0), 0u);
    // The scene hash follows what is rendered, not what the file is called.
    auto renamed = s;
    renamed.name = "another name";
    EXPECT_EQ(render::renderAttributes(renamed, render::flattenScene(renamed), plan, pattern, 37).at("oas.sceneHash"),
              a.at("oas.sceneHash"));
    auto recoloured = data;
    recoloured.materials[0].albedo.x *= 0.5f;
    EXPECT_NE(render::renderAttributes(s, recoloured, plan, pattern, 37).at("oas.sceneHash"), a.at("oas.sceneHash"));
}
