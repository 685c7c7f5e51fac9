#pragma once
// What oas-view's two modes (render_mode.hpp, points_mode.hpp) share: the window and the Vulkan
// context that computes and presents, scripted and typed keys, the sampler / offset / spp cycles
// of the s, o, + and - keys, and the frame loop that shows a mode's frames and takes screenshots.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "view/presenter.hpp"
#include "vk/context.hpp"

namespace oas::view {

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point t)
{
    return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Exit status 2 with a message: bad input or no display (oas::runCli maps std::invalid_argument to 2).
struct UsageError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

/// GLFW's last error as text (its error callback is silenced; errors are read where they matter).
std::string glfwMessage();

/// A key press, typed or scripted: a scripted one is pressed before frame `frame` is drawn.
struct ScriptedKey {
    int key;
    bool shift;
    std::uint32_t frame;
};

/// --script "KEY@FRAME ...": one character (s, S, o, r, e, p, q, +, -, ], [, .) or esc; a key
/// without @ goes with the previous key's frame (1 at first). Throws UsageError on a bad token.
std::vector<ScriptedKey> parseScript(const std::string& text);

/// The samplers the s key cycles through: the library's, then the chooser ("oa").
std::vector<std::string> samplerCycle();

/// The offsets the o key cycles through.
extern const std::vector<std::string> kOffsets;

/// The entry `step` places after `current` in `list`, wrapping (the first one if absent).
std::string cycled(const std::vector<std::string>& list, const std::string& current, int step);

/// The + and - keys: the sampler's smallest valid count >= 2 x current, or its largest valid
/// count <= current / 2 (Bose only makes q^2, Bose-Bush 2 q^2, ...); the current one if none.
std::uint32_t nextCount(const std::string& sampler, std::uint32_t strength, std::uint32_t dims, std::uint32_t current, bool up);

/// The options both modes take from the command line.
struct CommonOptions {
    std::string sampler, offset = "cmj", screenshot, script, save;
    std::uint32_t spp = 0, seed = 0, frames = 1, zoom = 0, strength = 0;
};

/// The window, the Vulkan context that computes and presents in it, and its keys.
class Viewer {
public:
    Viewer(std::uint32_t width, std::uint32_t height, const std::string& title);
    ~Viewer();
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    vk::Context& context() { return *context_; }
    GLFWwindow* window() { return window_; }
    Presenter& presenter() { return *presenter_; }
    bool shouldClose() const { return glfwWindowShouldClose(window_); }
    void close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
    void setTitle(const std::string& t) { glfwSetWindowTitle(window_, t.c_str()); }
    /// Polls the window system and returns the keys pressed since the last call, scripted ones
    /// for `frame` first.
    std::vector<ScriptedKey> keys(std::vector<ScriptedKey>& script, std::uint32_t frame);
    /// Validation findings so far (the layer is on with OAS_VK_VALIDATION=1).
    std::size_t validationFindings() const { return context_->validationMessages().size(); }

private:
    GLFWwindow* window_ = nullptr;
    std::unique_ptr<vk::Context> context_;
    std::unique_ptr<Presenter> presenter_;
    std::vector<ScriptedKey> pending_;
};

/// Writes `frame` as a PNG (atomically, creating the folder) and says so on stdout.
void writeScreenshot(const std::string& path, const Frame& frame);

/// The frame loop both modes share; q and Esc close the window. A Mode has key(k, viewer), frame(viewer) -> const Frame&,
/// complete(), busy() (another thread uses the queue: do not present), title() and release()
/// (frees its Vulkan objects before the context goes); one that also has takeSaveRequest() and
/// stem() saves the window's picture as STEM.png when its p key asks.
template <class Mode>
int runFrames(Mode& mode, Viewer& viewer, const CommonOptions& o)
{
    constexpr bool savesScreens = requires(Mode & m)
    {
        m.takeSaveRequest();
        m.stem();
    };
    // Frames count the frames shown: scripted keys and --frames refer to what the window showed,
    // whatever time a pipeline build took before the first one.
    std::vector<ScriptedKey> script = parseScript(o.script);
    std::uint32_t frame = 0, loops = 0;
    double slowestFrame = 0;
    while (!viewer.shouldClose()) {
        ++loops;
        for (const auto& k : viewer.keys(script, frame + 1)) {
            // q and Esc quit in every mode; the mode sees the other keys.
            if (k.key == GLFW_KEY_Q || k.key == GLFW_KEY_ESCAPE)
                viewer.close();
            else
                mode.key(k, viewer);
        }
        if (viewer.shouldClose()) break;
        const auto t = Clock::now();
        const Frame& f = mode.frame(viewer);
        const bool finished = !o.screenshot.empty() && frame + 1 >= o.frames && script.empty() && mode.complete();
        bool wantPicture = finished;
        if constexpr (savesScreens) wantPicture = wantPicture || mode.takeSaveRequest();
        const bool shown = f.width > 0 && !mode.busy() && viewer.presenter().present(f, wantPicture);
        frame += shown;
        slowestFrame = std::max(slowestFrame, secondsSince(t));
        viewer.setTitle(mode.title());
        if (shown && wantPicture) {
            std::string path = o.screenshot;
            if constexpr (savesScreens)
                if (!finished) path = mode.stem() + ".png";
            writeScreenshot(path, viewer.presenter().lastShown());
            if (finished) break;
        }
        if (!shown) glfwWaitEventsTimeout(0.01);  // nothing shown (pipeline build, minimised)
    }
    mode.release();
    std::fprintf(stderr, "oas-view: %u frames shown (%u loops), slowest loop %.0f ms, swapchain recreated %u time(s)\n", frame,
                 loops, slowestFrame * 1000, viewer.presenter().recreations());
    if (const std::size_t n = viewer.validationFindings()) {
        std::fprintf(stderr, "oas-view: error: %zu Vulkan validation message(s) (above)\n", n);
        return 3;
    }
    return 0;
}

}  // namespace oas::view
