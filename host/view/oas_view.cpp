// oas-view: an interactive GLFW + Vulkan viewer on the same library and tracer as oas-render.
//
//   oas-view SCENE.json [--sampler S] [--spp N] [--offset O] [--reference REF.exr]
//       renders progressively (render_mode.hpp: the keys and what the title shows).
//   oas-view --points --sampler S --spp N --dims D [--pair A,B]
//       the 2D projection of two dimensions, from the GPU generation kernel (oas-samples'
//       numbers), with the strata the construction promises and the projection's power spectrum
//       (points_mode.hpp: the keys; points_view.hpp: the picture).
//
// Tests drive it with --script "KEY@FRAME ..." (the same handler as the keyboard) and
// --screenshot FILE --frames K: after frame K, once the scripted keys are done and the render is
// complete, it writes what the window shows (read back from the swapchain image) and exits.
// Without a display it says so and exits with status 2.
#include <CLI/CLI.hpp>

#include <iostream>
#include <memory>
#include <sstream>

#include "apps/cli_main.hpp"
#include "oas/pattern.hpp"
#include "scene/scene.hpp"
#include "view/points_mode.hpp"
#include "view/render_mode.hpp"
#include "view/viewer.hpp"

using oas::view::UsageError;

int main(int argc, char** argv)
{
    CLI::App app{"oas-view: watch a render converge, or look at a sampler's projections and spectrum"};
    std::string scenePath, reference, pair = "0,1";
    oas::view::CommonOptions o;
    o.offset.clear();
    bool points = false;
    std::uint32_t dims = 4;
    app.add_option("scene", scenePath, "scene file (render mode)");
    app.add_flag("--points", points, "points mode: a sampler's 2D projections and their spectrum");
    app.add_option("--sampler", o.sampler, "sampler (oa, bose, ..., random, halton, sobol)");
    app.add_option("--spp", o.spp, "samples per pixel (points: per point set)")->check(CLI::Range(1u, 1u << 24));
    app.add_option("--offset", o.offset, "OA offset")->check(CLI::IsMember({"centered", "j", "mj", "cmj"}));
    app.add_option("--strength", o.strength, "OA strength");
    app.add_option("--seed", o.seed, "user seed (the same seed renders what oas-render --seed renders)");
    app.add_option("--reference", reference, "reference EXR of the scene's size: running relMSE and the e key");
    app.add_option("--dims", dims, "points mode: dimensions per point (4)")->check(CLI::Range(2u, 4096u));
    app.add_option("--pair", pair, "points mode: the first pair of dimensions shown (0,1)");
    app.add_option("--screenshot", o.screenshot, "write the window's image (PNG) after --frames frames and exit");
    app.add_option("--frames", o.frames, "frames before the screenshot (1); it also waits for the render and --script")
        ->check(CLI::Range(1u, 1000000u));
    app.add_option("--script", o.script, "keys to press, e.g. \"s@3 r@5\" (key@frame; see the source's header)");
    app.add_option("--save", o.save, "file stem for the p key (default out/view_<scene>)");
    app.add_option("--zoom", o.zoom, "integer zoom of the render (0: fit about 768 px)")->check(CLI::Range(0u, 64u));
    return oas::runCli("oas-view", app, argc, argv, [&] {
        oas::view::parseScript(o.script);  // bad scripts fail before any window opens
        if (points == !scenePath.empty())
            throw UsageError(points ? "--points takes no scene file" : "give a scene file, or --points");
        std::uint32_t a = 0, b = 1;
        if (points) {
            char comma = 0;
            std::istringstream in(pair);
            if (!(in >> a >> comma >> b) || comma != ',' || !in.eof())
                throw UsageError("--pair '" + pair + "': valid two dimension numbers, e.g. 0,1");
        }
        // Scenes and patterns are checked before a window opens, so that bad input says so (exit
        // 2) even without a display.
        std::unique_ptr<oas::view::RenderMode> render;
        std::unique_ptr<oas::view::PointsMode> pointsMode;
        if (points)
            pointsMode = std::make_unique<oas::view::PointsMode>(o, dims, a, b);
        else
            render = std::make_unique<oas::view::RenderMode>(scenePath, o, reference);

        glfwSetErrorCallback([](int, const char*) {});  // reported through glfwGetError instead
        if (!glfwInit())
            throw UsageError("no display: " + oas::view::glfwMessage() +
                             ". oas-view needs a desktop session or a virtual one, e.g. xvfb-run -a oas-view ...");
        struct Terminate {
            ~Terminate() { glfwTerminate(); }
        } terminate;
        if (!glfwVulkanSupported()) throw std::runtime_error("GLFW found no Vulkan loader: " + oas::view::glfwMessage());
        oas::vk::selectLavapipeIfUnset();
        const std::uint32_t w = points ? pointsMode->windowWidth() : render->windowWidth();
        const std::uint32_t h = points ? pointsMode->windowHeight() : render->windowHeight();
        oas::view::Viewer viewer(w, h, points ? "oas-view points" : "oas-view: " + render->name());
        return points ? oas::view::runFrames(*pointsMode, viewer, o) : oas::view::runFrames(*render, viewer, o);
    });
}
