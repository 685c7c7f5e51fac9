// Path-tracing throughput on the GPU and on the CPU reference tracer: Mpaths/s per scene, the
// cost of OA sampling against the independent sampler inside the same render, and the speed of
// each scene with and without its optional effects (absent effects are specialised away, so
// "without" is the compiled-out speed). OA and independent renders alternate, `--repeats` times,
// and the ratio is the median of the per-repeat ratios, so load from other processes on a shared
// machine cancels. GPU renders dispatch the samples in batches as oas-render does (samplesPerBatch).
// --profile breaks each scene's GPU frame down by elimination instead: the same kernel with its
// work per sample removed in steps (pt_render.comp's PT_STAGE, the plan cut to first hits), with
// and without the scene-feature specialisation, at 1 and 8 samples per dispatch.
// Prints figures; asserts nothing.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "apps/cli_main.hpp"
#include "oas/oa_columns.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"

namespace {

using Clock = std::chrono::steady_clock;

/// The scenes and sample counts every table uses (the paper's 121 = 11^2; the deep scene at 64).
const std::pair<const char*, std::uint32_t> kBenchScenes[] = {
    {"cornell7d.json", 121u}, {"blue_spheres9d.json", 121u}, {"interior_deep.json", 64u}};

struct Result {
    double mpaths;
    std::uint32_t dims;
    double buildSeconds;  ///< pipeline build (process start to first dispatch is about this)
};

/// What one render of `scene` with `sampler` at `spp` needs: its dimension plan, flattened data
/// and the sampler's pattern for the plan's dimensions.
struct Setup {
    oas::render::DimensionPlan plan;
    oas::render::SceneData data;
    oas::Pattern pattern;
    Setup(const oas::scene::Scene& scene, const std::string& sampler, std::uint32_t spp)
        : plan(oas::render::planDimensions(scene)), data(oas::render::flattenScene(scene))
    {
        oas::PatternRequest request;
        request.sampler = sampler;
        request.spp = spp;
        request.dims = plan.sampleDims;
        pattern = oas::makePattern(request);
    }
};

/// One GPU variant of a render: the kernel's stage, samples per dispatch, and a change to the
/// plan's effects (the profile's eliminations; the default is the plain render).
struct Variant {
    oas::render::KernelStage stage = oas::render::KernelStage::PathTrace;
    bool specialiseSceneFeatures = true;
    std::uint32_t perDispatch = 0;  ///< samples per pixel per dispatch; 0: as oas-render (samplesPerBatch)
    bool primaryHitOnly = false;    ///< maxDepth 1, no light sampling: camera rays to their first hit
};

Result measure(oas::vk::Context& context, const oas::scene::Scene& scene, const std::string& sampler, std::uint32_t spp,
               const Variant& variant = {})
{
    Setup setup(scene, sampler, spp);
    if (variant.primaryHitOnly) {
        setup.plan.maxDepth = 1;
        setup.plan.nee = setup.plan.mis = false;
    }
    const auto& [plan, data, pattern] = setup;
    oas::render::GpuTracer tracer(context, data, plan, pattern,
                                  {variant.stage, variant.specialiseSceneFeatures});  // pipeline compile: not timed
    oas::render::SampleBatch batch;
    batch.width = scene.width;
    batch.height = scene.height;
    batch.count = 1;
    tracer.trace(batch);  // warm-up
    const auto start = Clock::now();
    const std::uint32_t perDispatch = variant.perDispatch ? variant.perDispatch : tracer.samplesPerBatch();
    for (std::uint32_t i = 0; i < spp; i += batch.count) {
        batch.firstSample = i;
        batch.count = std::min(perDispatch, spp - i);
        tracer.trace(batch);
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return {double(scene.width) * scene.height * spp / seconds / 1e6, plan.usedDims, tracer.pipelineBuildSeconds()};
}

/// The CPU reference tracer on every core, the whole image at all spp in one batch.
Result measureCpu(const oas::scene::Scene& scene, const std::string& sampler, std::uint32_t spp)
{
    const Setup setup(scene, sampler, spp);
    const auto& [plan, data, pattern] = setup;
    oas::render::SampleBatch batch;
    batch.width = scene.width;
    batch.height = scene.height;
    batch.count = spp;
    oas::render::Accumulation accumulation(scene.width, scene.height);
    const auto start = Clock::now();
    oas::render::traceCpu(data, plan, pattern, batch, accumulation, 0);
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return {double(scene.width) * scene.height * spp / seconds / 1e6, plan.usedDims, 0.0};
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// OA and independent renders alternated `repeats` times: medians and the median ratio.
struct Pair {
    double oa, random, ratio, oaBuild = 0, randomBuild = 0;
    std::uint32_t dims = 0;
};

template <class Measure>
Pair alternate(int repeats, Measure&& measureOne)
{
    std::vector<double> oa, rnd, ratio;
    Pair p{};
    for (int i = 0; i < repeats; ++i) {
        const Result a = measureOne("oa"), b = measureOne("random");
        oa.push_back(a.mpaths);
        rnd.push_back(b.mpaths);
        ratio.push_back(a.mpaths / b.mpaths);
        p.oaBuild = a.buildSeconds;
        p.randomBuild = b.buildSeconds;
        p.dims = a.dims;
    }
    p.oa = median(oa);
    p.random = median(rnd);
    p.ratio = median(ratio);
    return p;
}

/// The frame's time by elimination, per scene: each variant alternated with the others `repeats`
/// times (medians), as milliseconds per frame of `spp` samples and as a share of the full render.
void profile(oas::vk::Context& context, const oas::scene::Scene& scene, std::uint32_t spp, int repeats)
{
    using oas::render::KernelStage;
    struct Row {
        const char* label;
        const char* sampler;
        Variant variant;
        std::vector<double> ms;
    };
    const std::uint32_t batched = 8;
    auto variant = [](KernelStage stage, std::uint32_t perDispatch = 1, bool primaryHitOnly = false, bool specialise = true) {
        return Variant{stage, specialise, perDispatch, primaryHitOnly};
    };
    std::vector<Row> rows = {
        {"path tracer, OA (1 spp per dispatch)", "oa", variant(KernelStage::PathTrace), {}},
        {"  with every shape/material/light type", "oa", variant(KernelStage::PathTrace, 1, false, false), {}},
        {"path tracer, independent", "random", variant(KernelStage::PathTrace), {}},
        {"path tracer, OA, 8 spp per dispatch", "oa", variant(KernelStage::PathTrace, batched), {}},
        {"camera rays to first hit only, OA", "oa", variant(KernelStage::PathTrace, 1, true), {}},
        {"sample fetches only, OA", "oa", variant(KernelStage::FetchesOnly), {}},
        {"sample fetches only, independent", "random", variant(KernelStage::FetchesOnly), {}},
        {"nothing (dispatch + accumulation)", "oa", variant(KernelStage::Nothing), {}},
        {"nothing, 8 spp per dispatch", "oa", variant(KernelStage::Nothing, batched), {}},
    };
    for (int r = 0; r < repeats; ++r)
        for (auto& row : rows) {
            const Result m = measure(context, scene, row.sampler, spp, row.variant);
            row.ms.push_back(double(scene.width) * scene.height * spp / (m.mpaths * 1e6) * 1e3);
        }
    const double full = median(rows[0].ms);
    std::printf("\nprofile of %s, %ux%u, %u spp (ms per frame, median of %d; share of the OA path tracer's frame)\n",
                scene.name.c_str(), scene.width, scene.height, spp, repeats);
    for (const auto& row : rows) {
        const double ms = median(row.ms);
        std::printf("  %-42s %10.1f ms  %6.3f\n", row.label, ms, ms / full);
    }
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-render-bench: Mpaths/s per scene, OA overhead, effect costs (GPU and CPU reference)"};
    std::string scenesDir = "scenes", only;
    std::uint32_t size = 128;
    int repeats = 1;
    bool cpu = false, noGpu = false, noEffects = false, profileFrames = false;
    app.add_option("--scenes", scenesDir, "scene directory");
    app.add_option("--size", size, "render width (height keeps the aspect)")->check(CLI::Range(8u, 4096u));
    app.add_option("--repeats", repeats, "OA/independent alternations per figure (medians)")->check(CLI::Range(1, 50));
    app.add_option("--only", only, "only scenes whose file name contains this text");
    app.add_flag("--cpu", cpu, "also measure the CPU reference tracer (all cores)");
    app.add_flag("--no-gpu", noGpu, "skip the GPU figures (with --cpu: CPU only)");
    app.add_flag("--no-effects", noEffects, "skip the effect-cost table");
    app.add_flag("--profile", profileFrames,
                 "GPU only: each scene's frame time by elimination (no tracing, fetches only, first hits only, "
                 "samples per dispatch) instead of the tables");
    return oas::runCli("oas-render-bench", app, argc, argv, [&] {
        std::unique_ptr<oas::vk::Context> context;
        if (!noGpu) {
            oas::vk::selectLavapipeIfUnset();
            context = std::make_unique<oas::vk::Context>();
        }
        std::printf("oas-render-bench on %s, scenes at %u px wide, %d alternation(s), CPU threads: %u (OA loops: %s)\n",
                    context ? context->deviceName().c_str() : "no GPU", size, repeats,
                    std::max(1u, std::thread::hardware_concurrency()),
                    oas::bestCpuIsa() == oas::CpuIsa::Avx2 ? "AVX2" : "baseline ISA");
        auto load = [&](const std::string& name) {
            auto s = oas::scene::loadScene(scenesDir + "/" + name);
            s.height = std::max(1u, s.height * size / s.width);
            s.width = size;
            return s;
        };
        if (profileFrames) {
            if (!context) throw std::invalid_argument("--profile needs the GPU (drop --no-gpu)");
            for (const auto& [name, spp] : kBenchScenes)
                if (only.empty() || std::string(name).find(only) != std::string::npos)
                    profile(*context, load(name), spp, repeats);
            return 0;
        }
        std::printf("\n%-18s %-4s %5s %6s %12s %12s %10s %10s %10s\n", "scene", "dev", "dims", "spp", "OA Mpaths/s",
                    "rnd Mpaths/s", "OA/random", "OA build", "rnd build");
        for (const auto& [name, spp] : kBenchScenes) {
            if (!only.empty() && std::string(name).find(only) == std::string::npos) continue;
            const auto scene = load(name);
            if (context) {
                const Pair p = alternate(repeats, [&](const char* sampler) { return measure(*context, scene, sampler, spp); });
                std::printf("%-18s %-4s %5u %6u %12.3f %12.3f %10.3f %9.2fs %9.2fs\n", scene.name.c_str(), "gpu", p.dims, spp,
                            p.oa, p.random, p.ratio, p.oaBuild, p.randomBuild);
                std::fflush(stdout);
            }
            if (cpu) {
                const Pair p = alternate(repeats, [&](const char* sampler) { return measureCpu(scene, sampler, spp); });
                std::printf("%-18s %-4s %5u %6u %12.3f %12.3f %10.3f %10s %10s\n", scene.name.c_str(), "cpu", p.dims, spp, p.oa,
                            p.random, p.ratio, "-", "-");
                std::fflush(stdout);
            }
        }
        if (noEffects || !context) return 0;
        std::printf("\neffects of cornell7d (OA, 121 spp): speed relative to the full scene\n");
        const auto full = load("cornell7d.json");
        const double base = measure(*context, full, "oa", 121).mpaths;
        auto noLens = full;
        noLens.camera.apertureRadius = 0;
        auto noMotion = full;
        for (auto& s : noMotion.shapes) s.velocity = glm::vec3(0);
        auto neither = noLens;
        for (auto& s : neither.shapes) s.velocity = glm::vec3(0);
        std::printf("%-28s %12.3f Mpaths/s  1.000\n", "full (lens + motion)", base);
        for (const auto& [label, scene] :
             {std::pair{"without depth of field", noLens}, {"without motion blur", noMotion}, {"without either", neither}}) {
            const double m = measure(*context, scene, "oa", 121).mpaths;
            std::printf("%-28s %12.3f Mpaths/s  %.3f\n", label, m, m / base);
            std::fflush(stdout);
        }
        return 0;
    });
}
