// Path-tracing throughput on the GPU and on the CPU reference tracer: Mpaths/s per scene, the
// cost of OA sampling against the independent sampler inside the same render, and the speed of
// each scene with and without its optional effects (absent effects are specialised away, so
// "without" is the compiled-out speed). OA and independent renders alternate, `--repeats` times,
// and the ratio is the median of the per-repeat ratios, so load from other processes on a shared
// machine cancels. Prints figures; asserts nothing.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"

namespace {

using Clock = std::chrono::steady_clock;

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

Result measure(oas::vk::Context& context, const oas::scene::Scene& scene, const std::string& sampler, std::uint32_t spp)
{
    const Setup setup(scene, sampler, spp);
    const auto& [plan, data, pattern] = setup;
    oas::render::GpuTracer tracer(context, data, plan, pattern);  // pipeline compile: not timed
    oas::render::SampleBatch batch;
    batch.width = scene.width;
    batch.height = scene.height;
    batch.count = 1;
    tracer.trace(batch);  // warm-up
    const auto start = Clock::now();
    for (std::uint32_t i = 0; i < spp; ++i) {
        batch.firstSample = i;
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

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-render-bench: Mpaths/s per scene, OA overhead, effect costs (GPU and CPU reference)"};
    std::string scenesDir = "scenes", only;
    std::uint32_t size = 128;
    int repeats = 1;
    bool cpu = false, noGpu = false, noEffects = false;
    app.add_option("--scenes", scenesDir, "scene directory");
    app.add_option("--size", size, "render width (height keeps the aspect)")->check(CLI::Range(8u, 4096u));
    app.add_option("--repeats", repeats, "OA/independent alternations per figure (medians)")->check(CLI::Range(1, 50));
    app.add_option("--only", only, "only scenes whose file name contains this text");
    app.add_flag("--cpu", cpu, "also measure the CPU reference tracer (all cores)");
    app.add_flag("--no-gpu", noGpu, "skip the GPU figures (with --cpu: CPU only)");
    app.add_flag("--no-effects", noEffects, "skip the effect-cost table");
    CLI11_PARSE(app, argc, argv);
    std::unique_ptr<oas::vk::Context> context;
    if (!noGpu) {
        oas::vk::selectLavapipeIfUnset();
        context = std::make_unique<oas::vk::Context>();
    }
    std::printf("oas-render-bench on %s, scenes at %u px wide, %d alternation(s), CPU threads: %u\n",
                context ? context->deviceName().c_str() : "no GPU", size, repeats,
                std::max(1u, std::thread::hardware_concurrency()));
    auto load = [&](const std::string& name) {
        auto s = oas::scene::loadScene(scenesDir + "/" + name);
        s.height = std::max(1u, s.height * size / s.width);
        s.width = size;
        return s;
    };
    std::printf("\n%-18s %-4s %5s %6s %12s %12s %10s %10s %10s\n", "scene", "dev", "dims", "spp", "OA Mpaths/s",
                "rnd Mpaths/s", "OA/random", "OA build", "rnd build");
    for (const auto& [name, spp] : {std::pair{"cornell7d.json", 121u}, {"blue_spheres9d.json", 121u},
                                    {"interior_deep.json", 64u}}) {
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
            std::printf("%-18s %-4s %5u %6u %12.3f %12.3f %10.3f %10s %10s\n", scene.name.c_str(), "cpu", p.dims, spp,
                        p.oa, p.random, p.ratio, "-", "-");
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
    for (const auto& [label, scene] : {std::pair{"without depth of field", noLens}, {"without motion blur", noMotion},
                                       {"without either", neither}}) {
        const double m = measure(*context, scene, "oa", 121).mpaths;
        std::printf("%-28s %12.3f Mpaths/s  %.3f\n", label, m, m / base);
        std::fflush(stdout);
    }
    return 0;
}
