// Path-tracing throughput on the GPU: Mpaths/s per scene, the cost of OA sampling against the
// independent sampler inside the same render, and the speed of each scene with and without its
// optional effects (absent effects are specialised away, so "without" is the compiled-out speed).
// Prints figures; asserts nothing.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>

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

Result measure(oas::vk::Context& context, const oas::scene::Scene& scene, const std::string& sampler, std::uint32_t spp)
{
    const auto plan = oas::render::planDimensions(scene);
    const auto data = oas::render::flattenScene(scene);
    oas::PatternRequest request;
    request.sampler = sampler;
    request.spp = spp;
    request.dims = plan.sampleDims;
    const auto pattern = oas::makePattern(request);
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

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-render-bench: Mpaths/s per scene, OA overhead, effect costs (GPU)"};
    std::string scenesDir = "scenes";
    std::uint32_t size = 128;
    app.add_option("--scenes", scenesDir, "scene directory");
    app.add_option("--size", size, "render width (height keeps the aspect)")->check(CLI::Range(8u, 4096u));
    CLI11_PARSE(app, argc, argv);
    oas::vk::selectLavapipeIfUnset();
    oas::vk::Context context;
    std::printf("oas-render-bench on %s, scenes at %u px wide\n", context.deviceName().c_str(), size);
    auto load = [&](const std::string& name) {
        auto s = oas::scene::loadScene(scenesDir + "/" + name);
        s.height = std::max(1u, s.height * size / s.width);
        s.width = size;
        return s;
    };
    std::printf("\n%-18s %5s %6s %12s %12s %10s %10s %10s\n", "scene", "dims", "spp", "OA Mpaths/s", "rnd Mpaths/s",
                "OA/random", "OA build", "rnd build");
    for (const auto& [name, spp] : {std::pair{"cornell7d.json", 121u}, {"blue_spheres9d.json", 121u},
                                    {"interior_deep.json", 64u}}) {
        const auto scene = load(name);
        const Result oa = measure(context, scene, "oa", spp);
        const Result rnd = measure(context, scene, "random", spp);
        std::printf("%-18s %5u %6u %12.3f %12.3f %10.3f %9.2fs %9.2fs\n", scene.name.c_str(), oa.dims, spp, oa.mpaths,
                    rnd.mpaths, oa.mpaths / rnd.mpaths, oa.buildSeconds, rnd.buildSeconds);
        std::fflush(stdout);
    }
    std::printf("\neffects of cornell7d (OA, 121 spp): speed relative to the full scene\n");
    const auto full = load("cornell7d.json");
    const double base = measure(context, full, "oa", 121).mpaths;
    auto noLens = full;
    noLens.camera.apertureRadius = 0;
    auto noMotion = full;
    for (auto& s : noMotion.shapes) s.velocity = glm::vec3(0);
    auto neither = noLens;
    for (auto& s : neither.shapes) s.velocity = glm::vec3(0);
    std::printf("%-28s %12.3f Mpaths/s  1.000\n", "full (lens + motion)", base);
    for (const auto& [label, scene] : {std::pair{"without depth of field", noLens}, {"without motion blur", noMotion},
                                       {"without either", neither}}) {
        const double m = measure(context, scene, "oa", 121).mpaths;
        std::printf("%-28s %12.3f Mpaths/s  %.3f\n", label, m, m / base);
        std::fflush(stdout);
    }
    return 0;
}
