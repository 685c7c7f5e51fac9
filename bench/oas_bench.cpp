// Sample-generation throughput: sample-dims/s of every construction on the CPU (one thread, all
// threads) and the GPU, with the same-shape hash-only kernel as the practical ceiling. The
// hash-only kernel runs interleaved with every row (hash, sampler, hash, sampler, ...) and the
// ratio is the median of the per-repeat ratios, so load from other processes on a shared machine
// cancels. Prints figures; asserts nothing (machines are shared and noisy).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "apps/cli_main.hpp"
#include "faure_bench_spv.h"
#include "faure_bench_static_spv.h"
#include "oas/generate_gpu.hpp"
#include "oas/glsl_compat.hpp"
#include "oas/oa_columns.hpp"
#include "oas/pattern.hpp"

namespace {

using Clock = std::chrono::steady_clock;

template <class F>
double medianSeconds(int repeats, F&& f)
{
    std::vector<double> t;
    for (int i = 0; i < repeats; ++i) {
        const auto start = Clock::now();
        f();
        t.push_back(std::chrono::duration<double>(Clock::now() - start).count());
    }
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

struct Row {
    const char* sampler;
    std::uint32_t spp, strength;
    const char* offset;
};

/// One pass of the pattern (N samples) for `pixels` pixels in a row, `dims` dimensions each.
oas::SampleRequest onePass(const oas::Pattern& pattern, std::uint32_t pixels, std::uint32_t dims)
{
    oas::SampleRequest r;
    r.width = pixels;
    r.height = 1;
    r.spp = pattern.N;
    r.dims = dims;
    return r;
}

/// What specialising the kernel on the pattern kind buys: the same generation kernel built without
/// OAS_STATIC_* (every construction, offset and field kind decided at run time), against the
/// specialised one, alternated per repeat; and the pipeline build time of each. Correctness does
/// not depend on specialisation (tests/loop_free_test.cpp); speed and build time do.
void printSpecialisationCost(oas::vk::Context& context, std::uint32_t pixels, std::uint32_t dims, int repeats)
{
    // Both generators start empty, so each row's first run builds its specialised pipeline; the
    // unspecialised one is built by the first row only and serves every pattern.
    oas::GpuGenerator specialised(context), unspecialised(context, oas::GpuGenerator::Kernel::Unspecialised);
    const std::vector<Row> rows = {
        {"bose", 121, 0, "cmj"}, {"bose", 64, 0, "cmj"}, {"addelman-kempthorne", 162, 0, "cmj"}, {"halton", 121, 0, "cmj"}};
    std::printf("\nspecialisation (GPU M/s; the unspecialised kernel builds once for every pattern)\n");
    std::printf("%-34s %14s %14s %8s %12s %12s\n", "sampler", "specialised", "unspecialised", "ratio", "build spec s",
                "build unsp s");
    for (const Row& row : rows) {
        const oas::Pattern pattern = oas::makePattern({row.sampler, row.spp, dims, row.strength, row.offset});
        const oas::SampleRequest r = onePass(pattern, pixels, dims);
        const double sampleDims = double(pixels) * r.spp * dims;
        double builds[2];
        oas::GpuGenerator* kernels[2] = {&specialised, &unspecialised};
        for (int k = 0; k < 2; ++k) {  // warm-up, timing the pipeline builds
            const double before = kernels[k]->pipelineBuildSeconds();
            kernels[k]->run(pattern, r);
            builds[k] = kernels[k]->pipelineBuildSeconds() - before;
        }
        std::vector<double> seconds[2];
        for (int i = 0; i < repeats; ++i)
            for (int k = 0; k < 2; ++k) seconds[k].push_back(medianSeconds(1, [&] { kernels[k]->run(pattern, r); }));
        double rates[2];
        for (int k = 0; k < 2; ++k) {
            std::sort(seconds[k].begin(), seconds[k].end());
            rates[k] = sampleDims / seconds[k][seconds[k].size() / 2] / 1e6;
        }
        const std::string label = oas::describe(pattern).substr(0, 34);
        std::printf("%-34s %14.1f %14.1f %8.2f %12.2f %12.2f\n", label.c_str(), rates[0], rates[1], rates[1] / rates[0],
                    builds[0], builds[1]);
        std::fflush(stdout);
    }
}

}  // namespace

/// The progressive sampler (shaders/oas/oas_faure.glsl; not yet a pattern): every dimension of
/// every sample of a row of pixels, base q with K digits (q^K samples), against Bose CMJ (N = 121)
/// in the same run, alternated per repeat: on the CPU twin (one thread; Faure as scalar calls,
/// Bose through generateCpu's vectorized OaColumns) and on the GPU (a kernel of the same layout,
/// bench/faure_bench.comp, against the specialised generation kernel; once with K a run-time
/// value, once with K a specialization constant, OAS_STATIC_FAURE_DIGITS). Issue goal: >= 0.5x
/// Bose CMJ per value on both.
void printProgressiveCost(oas::vk::Context* context, oas::GpuGenerator* gpu, std::uint32_t dims, int repeats)
{
    std::printf("\nProgressive Faure (oas_faure_value, standalone) vs Bose CMJ 121, M values/s, median of %d:\n", repeats);
    std::printf("%-22s %8s %12s %12s %8s %12s %12s %12s %8s %8s\n", "base, digits", "spp", "CPU faure", "CPU bose", "ratio",
                "GPU faure", "GPU K-spec", "GPU bose", "ratio", "K-spec");
    oas::PatternRequest req;
    req.sampler = "bose";
    req.spp = 121;
    req.dims = dims;
    const oas::Pattern bose = oas::makePattern(req);
    struct Push {
        oas::glsl::OasFaure faure;
        std::uint32_t pixels, spp, dims, frameSeed;
    };
    std::unique_ptr<oas::vk::ComputePipeline> pipeline;
    if (context)
        pipeline = std::make_unique<oas::vk::ComputePipeline>(*context, faure_bench_spv, sizeof(faure_bench_spv), 1,
                                                              sizeof(Push), oas::vk::ComputePipeline::SpecConstants{},
                                                              std::vector{oas::vk::BindingKind::UintStorageTexelBuffer});
    for (const auto& [q, digits] : std::vector<std::pair<std::uint32_t, std::uint32_t>>{{11, 2}, {11, 3}, {11, 4}, {7, 4}}) {
        oas::glsl::OasField f;
        f.p = q;
        f.k = 1;
        f.q = q;
        f.poly = 0;
        const oas::Divisor byP = oas::makeDivisor(q);
        f.recipP = byP.recip;
        f.shiftP = byP.shift;
        const oas::glsl::OasFaure fa = oas::glsl::oas_faure_make(f, digits);
        const std::uint32_t spp = fa.strata;
        std::unique_ptr<oas::vk::ComputePipeline> specialised;
        if (context)
            specialised = std::make_unique<oas::vk::ComputePipeline>(*context, faure_bench_static_spv,
                                                                     sizeof(faure_bench_static_spv), 1, sizeof(Push),
                                                                     oas::vk::ComputePipeline::SpecConstants{{0, digits}},
                                                                     std::vector{oas::vk::BindingKind::UintStorageTexelBuffer});
        // About 2^21 values per CPU run and 2^23 per GPU run, whatever the count.
        const std::uint32_t cpuPixels = std::max<std::uint32_t>(1, (1u << 21) / (spp * dims));
        const std::uint32_t gpuPixels = std::max<std::uint32_t>(1, (1u << 23) / (spp * dims));
        const std::uint32_t bosePixels = std::max<std::uint32_t>(1, (1u << 21) / (121 * dims));
        // The CPU runs' values (the GPU's stay in their buffer).
        std::vector<float> out(std::max(std::size_t(cpuPixels) * spp, std::size_t(bosePixels) * 121) * dims);
        auto faureCpu = [&] {
            for (std::uint32_t px = 0; px < cpuPixels; ++px) {
                const std::uint32_t seed = oas::pixelSeed(px, 0, 1);
                for (std::uint32_t i = 0; i < spp; ++i)
                    for (std::uint32_t d = 0; d < dims; ++d)
                        out[(std::size_t(px) * spp + i) * dims + d] =
                            oas::glsl::oas_faure_value(fa, d % q, i, oas::glsl::oas_faure_key(seed, d / q, d % q));
            }
        };
        const oas::SampleRequest boseCpu = onePass(bose, bosePixels, dims);
        std::vector<double> cpuRatio, cpuFaure, cpuBose;
        for (int i = 0; i < repeats; ++i) {
            const double a = double(cpuPixels) * spp * dims / medianSeconds(1, faureCpu) / 1e6;
            const double b = double(bosePixels) * 121 * dims /
                             medianSeconds(1, [&] { oas::generateCpu(bose, boseCpu, out.data(), 1); }) / 1e6;
            cpuFaure.push_back(a), cpuBose.push_back(b), cpuRatio.push_back(a / b);
        }
        auto median = [](std::vector<double> v) {
            std::sort(v.begin(), v.end());
            return v[v.size() / 2];
        };
        std::vector<double> gpuRatio, gpuFaure, gpuBose, gpuSpecialised, gpuSpecialisedRatio;
        if (context && gpu) {
            oas::vk::Buffer values(*context, std::size_t(gpuPixels) * spp * dims * sizeof(float));
            const Push push{fa, gpuPixels, spp, dims, 1};
            oas::vk::Buffer* buffers[] = {&values};
            auto faureOn = [&](oas::vk::ComputePipeline& p) {
                return [&] { context->dispatch(p, buffers, &push, sizeof(push), (gpuPixels * spp + 63) / 64); };
            };
            const auto faureGpu = faureOn(*pipeline), faureGpuSpecialised = faureOn(*specialised);
            const oas::SampleRequest boseGpu = onePass(bose, std::max<std::uint32_t>(1, (1u << 23) / (121 * dims)), dims);
            faureGpu();
            faureGpuSpecialised();
            gpu->run(bose, boseGpu);  // warm-up
            for (int i = 0; i < repeats; ++i) {
                const double a = double(gpuPixels) * spp * dims / medianSeconds(1, faureGpu) / 1e6;
                const double c = double(gpuPixels) * spp * dims / medianSeconds(1, faureGpuSpecialised) / 1e6;
                const double b = double(boseGpu.width) * 121 * dims / medianSeconds(1, [&] { gpu->run(bose, boseGpu); }) / 1e6;
                gpuFaure.push_back(a), gpuBose.push_back(b), gpuRatio.push_back(a / b);
                gpuSpecialised.push_back(c), gpuSpecialisedRatio.push_back(c / b);
            }
        }
        const std::string label = "q = " + std::to_string(q) + ", K = " + std::to_string(digits);
        std::printf("%-22s %8u %12.1f %12.1f %8.2f", label.c_str(), spp, median(cpuFaure), median(cpuBose), median(cpuRatio));
        if (!gpuRatio.empty())
            std::printf(" %12.1f %12.1f %12.1f %8.2f %8.2f\n", median(gpuFaure), median(gpuSpecialised), median(gpuBose),
                        median(gpuRatio), median(gpuSpecialisedRatio));
        else
            std::printf(" %12s %12s %12s %8s %8s\n", "-", "-", "-", "-", "-");
        std::fflush(stdout);
    }
}

int main(int argc, char** argv)
{
    CLI::App app{"oas-bench: sample-dims/s per construction on CPU and GPU"};
    std::uint32_t pixels = 16384, dims = 8;
    int repeats = 3;
    bool quick = false, noGpu = false;
    std::string only;
    app.add_option("--pixels", pixels, "pixels per run")->check(CLI::Range(1u, 1u << 24));
    app.add_option("--dims", dims, "dimensions per sample")->check(CLI::Range(1u, 4096u));
    app.add_option("--repeats", repeats, "runs per figure (median reported)")->check(CLI::Range(1, 100));
    app.add_flag("--quick", quick, "1024 pixels, one repeat: a smoke run");
    app.add_flag("--no-gpu", noGpu, "CPU figures only");
    app.add_option("--only", only, "run only rows whose sampler name or label contains this text");
    return oas::runCli("oas-bench", app, argc, argv, [&] {
        if (quick) {
            pixels = 1024;
            repeats = 1;
        }
        const std::vector<Row> rows = {
            {"bose", 121, 0, "cmj"},
            {"bose", 121, 0, "mj"},
            {"bose", 121, 0, "j"},
            {"bose", 64, 0, "cmj"},
            {"bose", 49, 0, "cmj"},  // the field sizes of the Addelman-Kempthorne rows: q = 7 ...
            {"bose", 81, 0, "cmj"},  // ... and q = 9, GF(3^2)
            {"bush", 125, 3, "mj"},
            {"bose-bush", 128, 0, "cmj"},
            {"addelman-kempthorne", 98, 0, "cmj"},
            {"addelman-kempthorne", 162, 0, "cmj"},
            {"cmjnd", 256, 8, "cmj"},
            {"random", 121, 0, "cmj"},
            {"jittered2d", 121, 0, "cmj"},
            {"cmj2d", 121, 0, "cmj"},
            {"zerotwo", 128, 0, "cmj"},
            {"halton", 121, 0, "cmj"},
            {"sobol", 128, 0, "cmj"},
            {"sobol-owen", 128, 0, "cmj"},
            {"sobol-burley", 128, 0, "cmj"},
            {"faure", 121, 11, "cmj"},   // base 11, K = 2 (its 11 dims a block: 8 used here)
            {"faure", 1331, 11, "cmj"},  // base 11, K = 3
        };
        std::unique_ptr<oas::vk::Context> context;
        std::unique_ptr<oas::GpuGenerator> gpu, hashOnly;
        if (!noGpu) {
            oas::vk::selectLavapipeIfUnset();
            try {
                context = std::make_unique<oas::vk::Context>();
                gpu = std::make_unique<oas::GpuGenerator>(*context);
                hashOnly = std::make_unique<oas::GpuGenerator>(*context, oas::GpuGenerator::Kernel::HashOnly);
            } catch (const oas::vk::NoDeviceError& e) {
                std::printf("GPU: SKIPPED (no Vulkan device: %s)\n", e.what());
            }
        }
        const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
        std::printf("oas-bench: %u pixels x spp x %u dims, median of %d; CPU threads: %u (OA loops: %s); GPU: %s\n", pixels, dims,
                    repeats, threads, oas::bestCpuIsa() == oas::CpuIsa::Avx2 ? "AVX2" : "baseline ISA",
                    context ? context->deviceName().c_str() : "none");
        std::printf("%-34s %6s %14s %14s %14s %12s %10s\n", "sampler", "spp", "CPU 1 thr M/s", "CPU all M/s", "GPU M/s",
                    "GPU/hash", "build s");
        // Whole-image CPU buffers get large; the CPU runs cover a slice of the pixels and scale.
        const std::uint32_t cpuPixels = std::min<std::uint32_t>(pixels, 4096);
        double hashRate = 0;
        for (int pass = 0; pass < 2; ++pass) {
            for (const Row& row : rows) {
                if (pass == 0 && row.sampler != std::string("bose")) continue;  // ceiling first
                if (pass == 1 && !only.empty() && std::string(row.sampler).find(only) == std::string::npos &&
                    oas::describe(oas::makePattern({row.sampler, row.spp, dims, row.strength, row.offset})).find(only) ==
                        std::string::npos)
                    continue;
                oas::PatternRequest req;
                req.sampler = row.sampler;
                req.spp = row.spp;
                req.strength = row.strength;
                req.dims = dims;
                req.offset = row.offset;
                const oas::Pattern pattern = oas::makePattern(req);
                const oas::SampleRequest r = onePass(pattern, pixels, dims);
                const double sampleDims = double(pixels) * r.spp * dims;
                if (pass == 0) {
                    if (hashOnly) {
                        hashOnly->run(pattern, r);  // warm-up: pipeline and buffer creation
                        hashRate = sampleDims / medianSeconds(repeats, [&] { hashOnly->run(pattern, r); }) / 1e6;
                        std::printf("%-34s %6u %14s %14s %14.1f %12s\n", "hash-only kernel (ceiling)", r.spp, "-", "-", hashRate,
                                    "1.00");
                    }
                    break;
                }
                oas::SampleRequest cr = r;
                cr.width = cpuPixels;
                std::vector<float> out(std::size_t(cpuPixels) * r.spp * dims);
                const double cpuDims = double(cpuPixels) * r.spp * dims;
                const std::uint32_t onePixels = std::max<std::uint32_t>(1, cpuPixels / 8);
                oas::SampleRequest one = r;
                one.width = onePixels;
                const double cpu1 = double(onePixels) * r.spp * dims /
                                    medianSeconds(repeats, [&] { oas::generateCpu(pattern, one, out.data(), 1); }) / 1e6;
                const double cpuN =
                    cpuDims / medianSeconds(repeats, [&] { oas::generateCpu(pattern, cr, out.data(), threads); }) / 1e6;
                double gpuRate = 0, ratio = 0, buildSeconds = 0;
                if (gpu) {
                    const double builtBefore = gpu->pipelineBuildSeconds();
                    gpu->run(pattern, r);
                    buildSeconds = gpu->pipelineBuildSeconds() - builtBefore;
                    if (hashOnly) hashOnly->run(pattern, r);  // warm-up: this layout's pipeline
                    std::vector<double> seconds, ratios;
                    for (int i = 0; i < repeats; ++i) {
                        const double sampler = medianSeconds(1, [&] { gpu->run(pattern, r); });
                        seconds.push_back(sampler);
                        if (hashOnly) ratios.push_back(medianSeconds(1, [&] { hashOnly->run(pattern, r); }) / sampler);
                    }
                    std::sort(seconds.begin(), seconds.end());
                    std::sort(ratios.begin(), ratios.end());
                    gpuRate = sampleDims / seconds[seconds.size() / 2] / 1e6;
                    if (!ratios.empty()) ratio = ratios[ratios.size() / 2];
                }
                const std::string label = oas::describe(pattern).substr(0, 34);
                if (gpu)
                    std::printf("%-34s %6u %14.1f %14.1f %14.1f %12.2f %10.2f\n", label.c_str(), r.spp, cpu1, cpuN, gpuRate,
                                ratio, buildSeconds);
                else
                    std::printf("%-34s %6u %14.1f %14.1f %14s %12s\n", label.c_str(), r.spp, cpu1, cpuN, "-", "-");
                std::fflush(stdout);
            }
        }
        if (gpu && only.empty()) printSpecialisationCost(*context, pixels, dims, repeats);
        if (only.empty() || std::string("faure").find(only) != std::string::npos)
            printProgressiveCost(context.get(), gpu.get(), dims, repeats);
        return 0;
    });
}
