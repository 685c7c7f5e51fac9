// oas-smallpt: the example tracer (smallpt.hpp) from the command line.
//   oas-smallpt                 one frame per sampler, each timed, with its image mean
//   oas-smallpt --bench         the embedder's question: what does oas cost per frame, and what
//                               does it buy at equal samples and at equal time? Rounds alternate
//                               the samplers; MSE against a reference rendered with the own hash.
// Besides oas throughout, each oas sampler also runs with oas for a path's first vertices only
// (--oas-vertices; the camera is vertex 0) and the own hash beyond.
// Exit 0; 1 on an error (message on stderr); 77 when there is no Vulkan device.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <numeric>
#include <string>
#include <vector>

#include "smallpt.hpp"
#include "vk/check.hpp"

namespace {

double seconds(const auto& f)
{
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double meanSquaredError(const std::vector<float>& a, const std::vector<float>& b)
{
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i) sum += (double(a[i]) - b[i]) * (double(a[i]) - b[i]);
    return sum / double(a.size());
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-smallpt: a small Vulkan path tracer that embeds oas, against its own hash"};
    std::uint32_t size = 96, spp = 49, rounds = 3, seeds = 4, refSpp = 4096, perDispatch = 0;
    std::vector<std::uint32_t> partVertices = {2, 3};
    bool bench = false;
    app.add_option("--size", size, "image width and height")->check(CLI::Range(8u, 1024u));
    app.add_option("--spp", spp, "samples per pixel (oas: Bose CMJ, so a prime power squared; 49 is over a prime field, the cheapest)")->check(CLI::Range(4u, 65536u));
    app.add_option("--per-dispatch", perDispatch, "samples per tracer dispatch (default: one pass, the pattern's N, at most 256)")
        ->check(CLI::Range(1u, 256u));
    app.add_flag("--bench", bench, "frame cost and MSE at equal spp and equal time, samplers alternated");
    app.add_option("--rounds", rounds, "--bench: timed rounds (medians)")->check(CLI::Range(1u, 50u));
    app.add_option("--seeds", seeds, "--bench: frames (seeds) per sampler for the MSE")->check(CLI::Range(1u, 64u));
    app.add_option("--oas-vertices", partVertices,
                   "also run each oas sampler with oas for a path's first V vertices only (the camera is vertex 0)")
        ->check(CLI::Range(0u, smallpt::kPathVertices));
    app.add_option("--ref-spp", refSpp, "--bench: the reference's samples per pixel (own hash)")->check(CLI::Range(16u, 1u << 20));
    CLI11_PARSE(app, argc, argv);

    try {
        OasPattern pattern;
        char why[256];
        if (oas_make_pattern(OAS_BOSE, spp, 0, OAS_OFFSET_CMJ, &pattern, why, sizeof why) != 0) {
            std::fprintf(stderr, "oas-smallpt: --spp %u: %s\n", spp, why);
            return 1;
        }
        // One pass a dispatch by default: the prefetch kernel makes a column's state once per
        // dispatch, and each dispatch waits for the device (measured: 16 a dispatch cost 3.5x the
        // own hash's frame with oas throughout, 49 a dispatch 3.0x, Bose 49 on lavapipe).
        if (perDispatch == 0) perDispatch = std::min(pattern.N, 256u);
        oas::vk::selectLavapipeIfUnset();
        oas::vk::Context ctx;
        // The configurations: the own hash, and each oas sampler with oas throughout and for a
        // path's first vertices only.
        struct Config {
            smallpt::Sampler sampler;
            std::uint32_t oasVertices;
            std::string name;
        };
        std::vector<Config> configs = {{smallpt::Sampler::OwnHash, 0, smallpt::samplerName(smallpt::Sampler::OwnHash)}};
        for (auto s : {smallpt::Sampler::OasInline, smallpt::Sampler::OasPrefetch}) {
            configs.push_back({s, smallpt::kPathVertices, smallpt::samplerName(s)});
            for (std::uint32_t v : partVertices)
                if (v < smallpt::kPathVertices)
                    configs.push_back({s, v, fmt::format("{}, {} vert.", smallpt::samplerName(s), v)});
        }
        std::vector<smallpt::Renderer> renderers;
        std::vector<double> buildSeconds;
        renderers.reserve(configs.size());  // a renderer's pipelines and buffers stay where they were made
        for (const Config& c : configs)  // the first render builds the pipelines: timed apart from the frames
            buildSeconds.push_back(seconds([&] {
                renderers.emplace_back(ctx, pattern, c.sampler, size, size, perDispatch, c.oasVertices).render(1, 1);
            }));
        fmt::print("oas-smallpt on {}: {}x{} px, {} spp (Bose CMJ, N = {}), {} dims a path, {} samples a dispatch\n",
                   ctx.deviceName(), size, size, spp, pattern.N, smallpt::pathDimensions(pattern), perDispatch);
        const std::size_t n = configs.size(), hash = 0;
        if (!bench) {
            for (std::size_t c = 0; c < n; ++c) {
                std::vector<float> image;
                const double t = seconds([&] { image = renderers[c].render(1, spp); });
                fmt::print("{:<24} {:8.3f} s  mean {:.4f}  (pipeline build and a 1-spp frame {:.2f} s)\n", configs[c].name, t,
                           std::accumulate(image.begin(), image.end(), 0.0) / double(image.size()), buildSeconds[c]);
            }
            return 0;
        }
        // Frame cost: rounds alternate the samplers, so drift on a shared machine hits all alike.
        std::vector<std::vector<double>> times(n), ratios(n);
        for (std::uint32_t r = 0; r < rounds; ++r) {
            for (std::size_t c = 0; c < n; ++c) times[c].push_back(seconds([&] { renderers[c].render(100 + r, spp); }));
            for (std::size_t c = 0; c < n; ++c) ratios[c].push_back(times[c].back() / times[hash].back());
        }
        std::vector<float> reference;
        const double refSeconds = seconds([&] { reference = renderers[hash].render(0xfeedu, refSpp); });
        std::vector<double> mse(n);
        for (std::size_t c = 0; c < n; ++c) {
            std::vector<double> each;
            for (std::uint32_t k = 0; k < seeds; ++k)
                each.push_back(meanSquaredError(renderers[c].render(1000 + k, spp), reference));
            mse[c] = std::accumulate(each.begin(), each.end(), 0.0) / seeds;
        }
        fmt::print("reference: own hash, {} spp ({:.1f} s); MSE: mean of {} frames; frame time: median of {} rounds\n", refSpp,
                   refSeconds, seeds, rounds);
        fmt::print("{:<24} {:>5} {:>10} {:>12} {:>12} {:>14} {:>16}\n", "sampler", "dims", "frame s", "x own hash", "MSE",
                   "MSE x hash", "equal-time MSE x");
        for (std::size_t c = 0; c < n; ++c) {
            const double cost = median(ratios[c]), mseRatio = mse[c] / mse[hash];
            // At equal time a frame gets 1/cost of the samples, and MSE scales as 1/spp for the
            // hash (independent samples); for oas this is the ratio a user would see if the
            // extra time were spent on more hash samples instead.
            fmt::print("{:<24} {:>5} {:>10.3f} {:>12.3f} {:>12.4g} {:>14.3f} {:>16.3f}\n", configs[c].name,
                       c == hash ? 0u : renderers[c].dimensions(), median(times[c]), cost, mse[c], mseRatio, mseRatio * cost);
        }
        return 0;
    } catch (const oas::vk::NoDeviceError& e) {
        std::fprintf(stderr, "oas-smallpt: SKIPPED: no Vulkan device: %s\n", e.what());
        return 77;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "oas-smallpt: %s\n", e.what());
        return 1;
    }
}
