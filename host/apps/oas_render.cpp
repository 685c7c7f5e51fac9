// oas-render: renders a scene (scenes/README.md) with the OA path tracer on the GPU (lavapipe
// unless you chose a driver) or with the CPU reference tracer, progressively, and writes a float
// OpenEXR (spp, sampler, time and dimension plan in its header) plus a tone-mapped sRGB PNG.
// Ctrl-C stops after the current batch and writes the image accumulated so far (its real spp
// recorded). Outputs are written to temporary files and renamed.
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <unistd.h>

#include "image/image.hpp"
#include "oas/pattern.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"

namespace {

std::atomic<bool> gInterrupted{false};
extern "C" void onInterrupt(int) { gInterrupted = true; }

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
    std::string scenePath, sampler, output, device = "gpu", offset;
    std::uint32_t spp = 0, seed = 0, strength = 0;
    bool explain = false;
    app.add_option("scene", scenePath, "scene file (JSON, see scenes/README.md)")->required();
    app.add_option("--sampler", sampler, "override the scene's sampler (oa, bose, ..., random, halton)");
    app.add_option("--spp", spp, "override the scene's samples per pixel")->check(CLI::Range(1u, 1u << 24));
    app.add_option("--offset", offset, "override the OA offset")->check(CLI::IsMember({"centered", "j", "mj", "cmj"}));
    app.add_option("--strength", strength, "override the OA strength");
    app.add_option("--seed", seed, "user seed (decorrelates renders)");
    app.add_option("-o,--output", output, "output EXR (default out/<scene>.exr); a PNG preview is written beside it");
    app.add_option("--device", device, "gpu (Vulkan) or cpu (the reference tracer)")->check(CLI::IsMember({"gpu", "cpu"}));
    app.add_flag("--explain", explain, "print the dimension plan and the sampler choice, then exit");
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "oas-render: error: " << e.what() << "\nrun with --help for the options\n";
        return 2;
    }
    try {
        oas::scene::Scene scene = oas::scene::loadScene(scenePath);
        if (!sampler.empty()) scene.sampler.name = sampler;
        if (spp) scene.sampler.spp = spp;
        if (!offset.empty()) scene.sampler.offset = offset;
        if (strength) scene.sampler.strength = strength;
        const oas::render::DimensionPlan plan = oas::render::planDimensions(scene);

        oas::PatternRequest request;
        request.sampler = scene.sampler.name;
        request.spp = scene.sampler.spp;
        request.dims = plan.sampleDims;
        request.strength = scene.sampler.strength;
        request.offset = scene.sampler.offset;
        oas::Pattern pattern;
        std::string choice;
        if (request.sampler == "oa") {
            const auto c = oas::chooseOrthogonalArray(request);
            pattern = c.pattern;
            choice = c.explanation;
        } else {
            pattern = oas::makePattern(request);
            choice = oas::describe(pattern);
        }
        if (explain) {
            std::cout << "scene " << scene.name << ": " << scene.width << "x" << scene.height << ", "
                      << scene.shapes.size() << " shapes, " << scene.lights.size() + scene.areaLightCount()
                      << " lights\n"
                      << "dimension plan: " << plan.explain() << "sampler: " << choice << "\n";
            return 0;
        }
        if (output.empty()) output = "out/" + scene.name + ".exr";
        if (const auto parent = std::filesystem::path(output).parent_path(); !parent.empty())
            std::filesystem::create_directories(parent);
        const std::string png = std::filesystem::path(output).replace_extension(".png").string();

        const oas::render::SceneData data = oas::render::flattenScene(scene);
        std::unique_ptr<oas::vk::Context> context;
        std::unique_ptr<oas::render::GpuTracer> gpu;
        std::string where = "CPU reference tracer";
        if (device == "gpu") {
            oas::vk::selectLavapipeIfUnset();
            context = std::make_unique<oas::vk::Context>();
            gpu = std::make_unique<oas::render::GpuTracer>(*context, data, plan, pattern);
            where = context->deviceName();
        }
        std::cerr << "rendering " << scene.name << " (" << scene.width << "x" << scene.height << ", "
                  << scene.sampler.spp << " spp, " << plan.usedDims << "D) on " << where << "\n"
                  << "sampler: " << choice << "\n";
        std::signal(SIGINT, onInterrupt);
        std::vector<float> cpuAccumulation(std::size_t(scene.width) * scene.height * 4, 0.0f);
        Progress progress(scene.sampler.spp);
        const auto start = std::chrono::steady_clock::now();
        const std::uint32_t done = oas::render::forEachBatch(
            scene.width, scene.height, scene.sampler.spp, oas::render::samplesPerBatch(plan), seed,
            [&](const oas::render::SampleBatch& batch) {
                if (gpu)
                    gpu->trace(batch);
                else
                    oas::render::traceCpu(data, plan, pattern, batch, cpuAccumulation);
            },
            [&](std::uint32_t samplesDone) {  // Ctrl-C is honoured between passes
                progress.update(samplesDone,
                                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
                return !gInterrupted;
            });
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (gInterrupted) std::cerr << "\ninterrupted: writing the " << done << " spp accumulated so far\n";
        const std::vector<float> accumulation = gpu ? gpu->accumulation() : cpuAccumulation;
        oas::image::Image image;
        image.width = scene.width;
        image.height = scene.height;
        image.rgba.resize(accumulation.size());
        for (std::size_t i = 0; i < accumulation.size(); i += 4) {
            const float n = std::max(accumulation[i + 3], 1.0f);
            image.rgba[i] = accumulation[i] / n;
            image.rgba[i + 1] = accumulation[i + 1] / n;
            image.rgba[i + 2] = accumulation[i + 2] / n;
            image.rgba[i + 3] = 1.0f;
        }
        std::string planLine = plan.explain();
        planLine = planLine.substr(0, planLine.find('\n'));
        oas::image::writeExr(output, image,
                             {{"oas.spp", std::to_string(done)},
                              {"oas.sppRequested", std::to_string(scene.sampler.spp)},
                              {"oas.sampler", oas::describe(pattern)},
                              {"oas.renderTimeSeconds", std::to_string(seconds)},
                              {"oas.dimensionPlan", planLine},
                              {"oas.device", where},
                              {"oas.scene", scene.path.string()}});
        oas::image::writePngPreview(png, image);
        const double paths = double(scene.width) * scene.height * done;
        std::printf("%s: %u spp in %.2f s, %.3f Mpaths/s on %s\nwrote %s and %s\n", scene.name.c_str(), done, seconds,
                    paths / seconds / 1e6, where.c_str(), output.c_str(), png.c_str());
        return gInterrupted ? 130 : 0;
    } catch (const oas::scene::SceneError& e) {
        std::cerr << "oas-render: error: " << e.what() << "\n";
        return 2;
    } catch (const oas::InvalidArgument& e) {
        std::cerr << "oas-render: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "oas-render: error: " << e.what() << "\n";
        return 1;
    }
}
