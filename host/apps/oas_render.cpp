// oas-render: renders a scene (scenes/README.md) with the OA path tracer on the GPU (lavapipe
// unless you chose a driver) or with the CPU reference tracer, progressively, and writes a render
// file (render/render_file.hpp: an OpenEXR with the mean image, the exact per-pixel sums, and the
// samples, sampler, plan, seed and time in its header) plus a tone-mapped sRGB PNG.
// --samples A:B renders only sample indices [A, B) of every pixel: a shard that oas-merge adds to
// the other shards of the frame, bit for bit the render of their union.
// --resolution WxH overrides the scene's image size. --cropwindow x0 x1 y0 y1 (pbrt's, fractions
// of the image) renders only that window's pixels, each bit for bit as in the whole frame, and
// writes an image of the window alone: a render file must hold the same samples in every pixel
// (oas-merge and oas-diff rely on it), so the file's oas.resolution is the window's size and
// oas.cropWindow says where it lies in the frame; crops of one window merge like shards.
// --threads N sets the CPU tracer's workers (0: all cores); any N gives the same bits.
// A scene with no light renders black: a warning says so, and the render goes on.
// Ctrl-C, SIGTERM and SIGHUP stop after the current pass and write the passes finished (a valid
// shard: the rest can be rendered later with --samples and merged); a second signal ends the
// process at once. Outputs are written to temporary files and renamed; temporaries left by a
// killed run are removed by the next write.
#include <CLI/CLI.hpp>
#include <atomic>
#include <cctype>
#include <chrono>
#include <csignal>
#include <new>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <tuple>
#include <unistd.h>
#include <vector>

#include "apps/checkpoints.hpp"
#include "apps/cli_main.hpp"
#include "image/image.hpp"
#include "oas/pattern.hpp"
#include "render/plan.hpp"
#include "render/render_file.hpp"
#include "render/scene_data.hpp"
#include "render/scene_pattern.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"

namespace {

/// The signal that asked us to stop (0: none). The first of SIGINT, SIGTERM, SIGHUP stops the
/// render after the current pass; SA_RESETHAND restores the default action on delivery, so a
/// second one ends the process at once (the user asked twice).
volatile std::sig_atomic_t gStopSignal = 0;
extern "C" void onStopSignal(int sig)
{
    gStopSignal = sig;
}

void installStopHandlers()
{
    for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
        struct sigaction action {};
        action.sa_handler = onStopSignal;
        sigemptyset(&action.sa_mask);
        action.sa_flags = SA_RESTART | SA_RESETHAND;
        ::sigaction(sig, &action, nullptr);
    }
}

const char* signalName(int sig)
{
    return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : sig == SIGHUP ? "SIGHUP" : "a signal";
}

/// A file name from a scene's name for the default output out/<name>.exr: characters other than
/// letters, digits, '-', '_' and '.' become '_' and leading dots are dropped, so the name can
/// neither leave out/ ("../x", "/abs"), nor hide, nor be cut short by a NUL. Empty: the scene
/// file's own stem, then "render".
std::string outputStem(const std::string& sceneName, const std::filesystem::path& sceneFile)
{
    auto clean = [](const std::string& text) {
        std::string out;
        for (unsigned char c : text) out += (std::isalnum(c) || c == '-' || c == '_' || c == '.') ? char(c) : '_';
        out.erase(0, out.find_first_not_of('.'));
        if (out.size() > 200) out.resize(200);
        return out;
    };
    for (const std::string& candidate : {clean(sceneName), clean(sceneFile.stem().string())})
        if (!candidate.empty()) return candidate;
    return "render";
}

/// Progress on a terminal as one rewritten line; otherwise plain lines at every 10%.
class Progress {
public:
    explicit Progress(std::uint32_t total) : total_(total), tty_(::isatty(STDERR_FILENO) != 0) {}
    void update(std::uint32_t done, double seconds)
    {
        const int percent = int(100.0 * done / total_);
        if (tty_) {
            const int width = 40, filled = width * int(done) / int(total_);
            std::fprintf(stderr, "\r[%s%s] %3d%%  %u/%u spp  %.1f s", std::string(filled, '#').c_str(),
                         std::string(width - filled, '.').c_str(), percent, done, total_, seconds);
            if (done == total_) std::fputc('\n', stderr);
        } else if (percent / 10 != lastDecile_ || done == total_) {
            lastDecile_ = percent / 10;
            std::fprintf(stderr, "progress: %u/%u spp (%d%%), %.1f s\n", done, total_, percent, seconds);
        }
        std::fflush(stderr);
    }

private:
    std::uint32_t total_;
    bool tty_;
    int lastDecile_ = -1;
};

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-render: path-trace a scene with orthogonal-array sampling"};
    std::string scenePath, sampler, output, device = "gpu", offset, samples, kernel = "mega";
    std::uint32_t spp = 0, seed = 0, strength = 0;
    bool explain = false, checkpoints = false;
    std::string resolution;
    std::vector<std::string> crop;
    unsigned threads = 0;
    constexpr unsigned kMaxThreads = 1024;
    app.add_option("scene", scenePath, "scene file (JSON, see scenes/README.md)")->required();
    app.add_option("--sampler", sampler, "override the scene's sampler (oa, bose, ..., random, halton)");
    app.add_option("--spp", spp, "override the scene's samples per pixel")->check(CLI::Range(1u, 1u << 24));
    app.add_option("--offset", offset, "override the OA offset")->check(CLI::IsMember({"centered", "j", "mj", "cmj"}));
    app.add_option("--strength", strength, "override the OA strength");
    app.add_option("--seed", seed, "user seed (decorrelates renders)");
    app.add_option("--samples", samples,
                   "render only sample indices [A, B) of every pixel, written as A:B (0 <= A < B <= spp): a shard "
                   "for oas-merge");
    app.add_option("-o,--output", output, "output EXR (default out/<scene>.exr); a PNG preview is written beside it");
    app.add_option("--device", device, "gpu (Vulkan) or cpu (the reference tracer)")->check(CLI::IsMember({"gpu", "cpu"}));
    CLI::Option* kernelOption = app.add_option(
        "--kernel", kernel,
        "the GPU path tracer: mega (one invocation traces whole paths, the default) or wavefront (paths kept as records, one "
        "dispatch per vertex); the same image, word for word");
    app.add_option("--resolution", resolution, "override the scene's image size, written as WxH (e.g. 640x480)");
    app.add_option("--cropwindow", crop,
                   "render only the window x0 x1 y0 y1 (fractions of the image, as pbrt's) and write that window "
                   "alone")
        ->expected(4);
    CLI::Option* threadsOption =
        app.add_option("--threads", threads, "CPU tracer workers (--device cpu), 0 .. 1024; 0: all cores")
            ->check(CLI::Range(0u, kMaxThreads));
    app.add_flag("--explain", explain, "print the dimension plan and the sampler choice, then exit");
    app.add_flag("--checkpoints", checkpoints,
                 "also write the image at every count of samples that completes a net or array, as OUTPUT.spp<count>.exr "
                 "(faure: q, q^2, q^3 ...; the other samplers: every pass of N): one render gives an error-vs-samples "
                 "curve");
    return oas::runCli(
        "oas-render", app, argc, argv,
        [&] {
            if (threadsOption->count() && device != "cpu")
                throw oas::InvalidArgument("--threads " + std::to_string(threads) +
                                           ": the CPU tracer's workers: valid with --device cpu only");
            const auto gpuKernel = oas::render::parseKernel(kernel, "--kernel");
            if (kernelOption->count() && device != "gpu")
                throw oas::InvalidArgument("--kernel " + kernel + ": the GPU path tracer's kernel: valid with --device gpu only");
            oas::scene::Scene scene = oas::scene::loadScene(scenePath);
            if (!resolution.empty())
                std::tie(scene.width, scene.height) = oas::render::parseResolution(resolution, "--resolution");
            const oas::render::PixelWindow window =
                crop.empty() ? oas::render::PixelWindow{0, scene.width, 0, scene.height}
                             : oas::render::parseCropWindow(crop, scene.width, scene.height, "--cropwindow");
            if (!sampler.empty()) scene.sampler.name = sampler;
            if (spp) scene.sampler.spp = spp;
            if (!offset.empty()) scene.sampler.offset = offset;
            if (strength) scene.sampler.strength = strength;
            const oas::render::DimensionPlan plan = oas::render::planDimensions(scene);

            const bool fromOptions = !sampler.empty() || spp || !offset.empty() || strength;
            const oas::render::ScenePattern chosen = oas::render::scenePattern(scene, plan, fromOptions);
            const oas::Pattern pattern = chosen.pattern;
            const std::string& choice = chosen.choice;
            if (explain) {
                std::cout << "scene " << scene.name << ": " << scene.width << "x" << scene.height << ", " << scene.shapes.size()
                          << " shapes, " << scene.lights.size() + scene.areaLightCount() << " lights\n"
                          << "dimension plan: " << plan.explain() << "sampler: " << choice << "\n"
                          << "samples per pixel: " << scene.sampler.spp << "\n";
                if (device == "gpu")
                    std::cout << "GPU kernels: " << oas::render::describeKernels(plan, pattern, gpuKernel) << "\n";
                const std::string prefix = oas::prefixGuarantee(pattern, scene.sampler.spp);
                if (!prefix.empty()) std::cout << "progressive: " << prefix << "\n";
                return 0;
            }
            if (scene.lights.empty() && scene.areaLightCount() == 0 && !scene.hasEnvironment())
                std::cerr << "oas-render: warning: " << scenePath
                          << ": the scene has no light (no emitting material on a shape, no point or spot light, no "
                             "environment): it renders black\n";
            const oas::render::SampleRange range = samples.empty()
                                                       ? oas::render::SampleRange{0, scene.sampler.spp}
                                                       : oas::render::parseSampleRange(samples, scene.sampler.spp, "--samples");
            if (output.empty()) output = "out/" + outputStem(scene.name, scene.path) + ".exr";
            const std::string png = oas::render::prepareRenderOutput(output, "--output");

            const std::uint64_t imageBytes = std::uint64_t(scene.width) * scene.height * oas::render::kSumWords * 4;
            const auto outOfMemory = [&](const char* what) {
                return std::runtime_error("cannot allocate " + std::string(what) + " for a " + std::to_string(scene.width) + "x" +
                                          std::to_string(scene.height) + " image (" + std::to_string(imageBytes >> 20) +
                                          " MiB per copy of the sums): valid a resolution this machine can hold");
            };
            const oas::render::SceneData data = oas::render::flattenScene(scene);
            std::unique_ptr<oas::vk::Context> context;
            std::unique_ptr<oas::render::GpuTracer> gpu;
            std::string where = "CPU reference tracer";
            if (device == "gpu") {
                oas::vk::selectLavapipeIfUnset();
                context = std::make_unique<oas::vk::Context>();
                where = context->deviceName();
                std::cerr << "building the path-tracing pipeline for this plan on " << where
                          << (context->isLavapipe() ? " (lavapipe compiles it with LLVM: about 2 s)" : "") << "...\n";
                oas::render::GpuTracerOptions options;
                options.kernel = gpuKernel;
                gpu = std::make_unique<oas::render::GpuTracer>(*context, data, plan, pattern, options);
                std::fprintf(stderr, "pipeline built in %.2f s\n", gpu->pipelineBuildSeconds());
            }
            const std::string part = samples.empty() ? "" : ", samples " + oas::render::formatRanges({range});
            const std::string cropped =
                crop.empty() ? "" : ", crop " + oas::render::formatCropWindow(window, scene.width, scene.height);
            std::cerr << "rendering " << scene.name << " (" << scene.width << "x" << scene.height << cropped << ", "
                      << scene.sampler.spp << " spp" << part << ", " << plan.usedDims << "D) on " << where << "\n"
                      << "sampler: " << choice << "\n";
            installStopHandlers();
            oas::render::Accumulation cpuSums;
            try {
                if (!gpu) cpuSums = oas::render::Accumulation(scene.width, scene.height);
            } catch (const std::bad_alloc&) {
                throw outOfMemory("the accumulation buffer");
            }
            auto attributes = oas::render::renderAttributes(scene, data, plan, pattern, seed);
            attributes["oas.device"] = where;
            attributes["oas.pipelineBuildSeconds"] = gpu ? std::to_string(gpu->pipelineBuildSeconds()) : "0";
            attributes["oas.writer"] = "oas-render";
            if (!crop.empty()) {
                attributes["oas.resolution"] = std::to_string(window.width()) + "x" + std::to_string(window.height());
                attributes["oas.cropWindow"] = oas::render::formatCropWindow(window, scene.width, scene.height);
            }
            // The image so far (the exact sums make any moment's readable); `last` hands the CPU's over.
            const auto currentSums = [&](bool last) {
                try {
                    oas::render::Accumulation sums = gpu ? gpu->accumulation() : last ? std::move(cpuSums) : cpuSums;
                    if (!crop.empty()) sums = sums.window(window.x0, window.y0, window.width(), window.height());
                    return sums;
                } catch (const std::bad_alloc&) {
                    throw outOfMemory("the sums read back from the device");
                }
            };
            // Where the render stops to write a checkpoint, then its end: the segments are passes
            // over the same sample indices as one run, and the sums are exact, so the final image
            // is the same with checkpoints or without.
            std::vector<std::uint32_t> stops;
            if (checkpoints) stops = oas::apps::checkpointCounts(pattern, range.first, range.end);
            stops.push_back(range.end);
            Progress progress(range.size());
            const auto start = std::chrono::steady_clock::now();
            const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
            std::uint32_t done = 0;
            for (const std::uint32_t stop : stops) {
                const std::uint32_t from = range.first + done;
                done += oas::render::forEachBatch(
                    window.width(), window.height(), stop,
                    gpu ? oas::render::samplesPerBatch(plan, data) : oas::render::kCpuSamplesPerBatch, seed,
                    [&](oas::render::SampleBatch batch) {  // the window's tiles, placed in the frame
                        batch.x0 += window.x0;
                        batch.y0 += window.y0;
                        if (gpu)
                            gpu->trace(batch);
                        else
                            oas::render::traceCpu(data, plan, pattern, batch, cpuSums, threads);
                    },
                    [&](std::uint32_t samplesDone) {  // stop signals are honoured between passes
                        progress.update(from - range.first + samplesDone, elapsed());
                        return gStopSignal == 0;
                    },
                    from);
                if (gStopSignal != 0 || stop == range.end) break;
                const std::string path = output.substr(0, output.size() - 4) + ".spp" + std::to_string(stop) + ".exr";
                attributes["oas.renderTimeSeconds"] = std::to_string(elapsed());
                oas::render::writeRenderFile(path, currentSums(false), {{range.first, stop}}, attributes);
                std::cerr << "checkpoint: wrote " << path << " (samples " << range.first << ":" << stop << ")\n";
            }
            const int stopSignal = gStopSignal;
            const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            const oas::render::SampleRange finished{range.first, range.first + done};
            if (stopSignal) {
                std::cerr << "\ninterrupted by " << signalName(stopSignal) << "\n";
                if (done == 0) {
                    std::cerr << "no pass finished: nothing written\n";
                    return 128 + stopSignal;
                }
            }
            const oas::render::Accumulation sums = currentSums(true);
            attributes["oas.renderTimeSeconds"] = std::to_string(seconds);
            oas::image::Image image;
            try {
                image = oas::render::writeRenderFile(output, sums, {finished}, attributes);
            } catch (const std::bad_alloc&) {
                throw outOfMemory("the output image");
            }
            oas::image::writePngPreview(png, image);
            const double paths = double(window.width()) * window.height() * done;
            std::printf("%s: %u spp in %.2f s, %.3f Mpaths/s on %s", scene.name.c_str(), done, seconds, paths / seconds / 1e6,
                        where.c_str());
            if (gpu) std::printf(" (pipeline build before it: %.2f s)", gpu->pipelineBuildSeconds());
            std::printf("\n");
            if (const std::uint64_t rejected = sums.rejectedSamples())
                std::printf("warning: %llu of %.0f samples had a NaN, infinite, negative or huge (>= 2^64) radiance and "
                            "were left out of the pixel sums (oas.rejectedSamples in the EXR header)\n",
                            static_cast<unsigned long long>(rejected), paths);
            else
                std::printf("rejected samples: 0\n");
            std::printf("wrote %s (samples %s of %u) and %s\n", output.c_str(), oas::render::formatRanges({finished}).c_str(),
                        scene.sampler.spp, png.c_str());
            if (finished.end < range.end)
                std::printf("to finish the frame: oas-render %s --samples %u:%u -o REST.exr (with the same options), "
                            "then oas-merge %s REST.exr -o FULL.exr\n",
                            scenePath.c_str(), finished.end, range.end, output.c_str());
            return stopSignal ? 128 + stopSignal : 0;
        },
        [] { return std::string("out of memory (a smaller resolution or scene needs less)"); });
}
