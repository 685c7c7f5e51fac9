// oas-view: an interactive GLFW + Vulkan viewer on the same library and tracer as oas-render.
//
//   oas-view SCENE.json [--sampler S] [--spp N] [--offset O] [--reference REF.exr]
//       renders progressively: each frame runs the path tracer for ~40 ms (the passes of
//       oas-render, cut into smaller tiles while a dispatch takes longer than that), then shows
//       the accumulation tone-mapped exactly as oas-render's PNG (image::srgb8). The title shows
//       spp done, elapsed time, Mpaths/s and, with a reference, the running relMSE.
//   oas-view --points --sampler S --spp N --dims D
//       the 2D projection of two dimensions, from the GPU generation kernel (oas-samples'
//       numbers), with the strata the construction promises and the projection's power spectrum.
//
// Keys (render): s / S next / previous sampler, o next offset, + / - the sampler's next valid spp
// at least double / at most half the current one, r restart,
// e false-colour error against --reference, p save the image (EXR + PNG, as oas-render), z zoom
// 1x / 2x / 3x (resizes the window), q / Esc quit. Keys (points): ] / [ next / previous pair, . next block (both dimensions + blockDims),
// s / S, o, + / - as above, p save a screenshot, q / Esc quit.
//
// Tests drive it with --script "KEY@FRAME ..." (the same handler as the keyboard) and
// --screenshot FILE --frames K: after frame K, once the scripted keys are done and the render is
// complete, it writes what the window shows (read back from the swapchain image) and exits.
// Without a display it says so and exits with status 2.
#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>

#include "image/image.hpp"
#include "image/metrics.hpp"
#include "oas/atomic_file.hpp"
#include "oas/generate_gpu.hpp"
#include "oas/pattern.hpp"
#include "oas/periodogram.hpp"
#include "render/plan.hpp"
#include "render/render_file.hpp"
#include "render/scene_data.hpp"
#include "render/scene_pattern.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"
#include "view/points_view.hpp"
#include "view/presenter.hpp"

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Exit status 2 with a message: bad input or no display.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::string glfwMessage()
{
    const char* text = nullptr;
    const int code = glfwGetError(&text);
    return code == GLFW_NO_ERROR ? std::string("no GLFW error reported") : std::string(text ? text : "unknown");
}

/// A scripted key: pressed before frame `frame` is drawn.
struct ScriptedKey {
    int key;
    bool shift;
    std::uint32_t frame;
};

/// Key names for --script: one character (s, S, o, r, e, p, q, +, -, ], [, .) or esc.
std::vector<ScriptedKey> parseScript(const std::string& text)
{
    std::vector<ScriptedKey> keys;
    std::istringstream in(text);
    std::string token;
    std::uint32_t frame = 1;
    while (in >> token) {
        std::string name = token;
        const auto at = token.find('@');
        if (at != std::string::npos) {
            name = token.substr(0, at);
            const std::string number = token.substr(at + 1);
            if (number.empty() || number.size() > 6 || number.find_first_not_of("0123456789") != std::string::npos)
                throw UsageError("--script: '" + token + "': the frame after @ must be a number 0 .. 999999");
            frame = std::uint32_t(std::stoul(number));
        }
        ScriptedKey k{0, false, frame};
        if (name == "esc") {
            k.key = GLFW_KEY_ESCAPE;
        } else if (name.size() == 1) {
            const char c = name[0];
            if (c >= 'a' && c <= 'z') k.key = GLFW_KEY_A + (c - 'a');
            else if (c >= 'A' && c <= 'Z') k.key = GLFW_KEY_A + (c - 'A'), k.shift = true;
            else if (c == '+') k.key = GLFW_KEY_EQUAL, k.shift = true;
            else if (c == '-') k.key = GLFW_KEY_MINUS;
            else if (c == ']') k.key = GLFW_KEY_RIGHT_BRACKET;
            else if (c == '[') k.key = GLFW_KEY_LEFT_BRACKET;
            else if (c == '.') k.key = GLFW_KEY_PERIOD;
        }
        if (k.key == 0)
            throw UsageError("--script: unknown key '" + name + "' (valid: a letter, + - ] [ . or esc, e.g. \"s@3 r@5\")");
        keys.push_back(k);
    }
    return keys;
}

/// The samplers the s key cycles through: the library's, then the chooser.
std::vector<std::string> samplerCycle()
{
    std::vector<std::string> names = oas::samplerNames();
    names.push_back("oa");
    return names;
}

const std::vector<std::string> kOffsets = {"cmj", "mj", "j", "centered"};

std::string cycled(const std::vector<std::string>& list, const std::string& current, int step)
{
    auto it = std::find(list.begin(), list.end(), current);
    const int n = int(list.size());
    const int i = it == list.end() ? 0 : int(it - list.begin());
    return list[std::size_t(((i + step) % n + n) % n)];
}

/// The + and - keys: the sampler's smallest valid count >= 2 x current, or its largest valid
/// count <= current / 2 (Bose only makes q^2, Bose-Bush 2 q^2, ...); the current one if none.
std::uint32_t nextCount(const std::string& sampler, std::uint32_t strength, std::uint32_t dims, std::uint32_t current,
                        bool up)
{
    try {
        if (up) {
            const std::uint32_t lo = std::min(current * 2, oas::kMaxSamples);
            const auto c = oas::validCounts(sampler, strength, dims, lo, std::min(lo * 2 + 16, oas::kMaxSamples));
            return c.empty() ? current : c.front();
        }
        if (current < 2) return current;
        const auto c = oas::validCounts(sampler, strength, dims, std::max(1u, current / 8), current / 2);
        return c.empty() ? current : c.back();
    } catch (const oas::InvalidArgument&) {
        return current;
    }
}

/// What both modes share: the window, the Vulkan context that computes and presents, the keys.
class Viewer {
public:
    Viewer(std::uint32_t width, std::uint32_t height, const std::string& title)
    {
        glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
        window_ = glfwCreateWindow(int(width), int(height), title.c_str(), nullptr, nullptr);
        if (!window_) throw std::runtime_error("cannot open a window: " + glfwMessage());
        glfwSetWindowUserPointer(window_, this);
        glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
            if (action == GLFW_PRESS || action == GLFW_REPEAT)
                static_cast<Viewer*>(glfwGetWindowUserPointer(w))->pending_.push_back({key, (mods & GLFW_MOD_SHIFT) != 0, 0});
        });
        oas::vk::ContextOptions options;
        std::uint32_t count = 0;
        const char** names = glfwGetRequiredInstanceExtensions(&count);
        if (!names) throw std::runtime_error("GLFW found no Vulkan surface support: " + glfwMessage());
        for (std::uint32_t i = 0; i < count; ++i) options.instanceExtensions.push_back(names[i]);
        options.deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
        options.canPresent = [](VkInstance instance, VkPhysicalDevice device, std::uint32_t family) {
            return glfwGetPhysicalDevicePresentationSupport(instance, device, family) == GLFW_TRUE;
        };
        context_ = std::make_unique<oas::vk::Context>(options);
        presenter_ = std::make_unique<oas::view::Presenter>(*context_, window_);
    }
    ~Viewer()
    {
        presenter_.reset();
        if (window_) glfwDestroyWindow(window_);
    }
    oas::vk::Context& context() { return *context_; }
    GLFWwindow* window() { return window_; }
    oas::view::Presenter& presenter() { return *presenter_; }
    bool shouldClose() const { return glfwWindowShouldClose(window_); }
    void close() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
    void setTitle(const std::string& t) { glfwSetWindowTitle(window_, t.c_str()); }
    /// Polls the window system and returns the keys pressed since the last call, scripted ones
    /// for `frame` first.
    std::vector<ScriptedKey> keys(std::vector<ScriptedKey>& script, std::uint32_t frame)
    {
        glfwPollEvents();
        std::vector<ScriptedKey> out;
        for (auto it = script.begin(); it != script.end();)
            if (it->frame <= frame) {
                out.push_back(*it);
                it = script.erase(it);
            } else {
                ++it;
            }
        out.insert(out.end(), pending_.begin(), pending_.end());
        pending_.clear();
        return out;
    }
    /// Validation findings so far (the layer is on with OAS_VK_VALIDATION=1).
    std::size_t validationFindings() const { return context_->validationMessages().size(); }

private:
    GLFWwindow* window_ = nullptr;
    std::unique_ptr<oas::vk::Context> context_;
    std::unique_ptr<oas::view::Presenter> presenter_;
    std::vector<ScriptedKey> pending_;
};

void writeScreenshot(const std::string& path, const oas::view::Frame& frame)
{
    if (const auto parent = std::filesystem::path(path).parent_path(); !parent.empty())
        std::filesystem::create_directories(parent);
    oas::writeFileAtomically(path, oas::image::encodePngRgb8(frame.width, frame.height, frame.rgb));
    std::printf("wrote %s (%ux%u, the window's content)\n", path.c_str(), frame.width, frame.height);
}

struct CommonOptions {
    std::string sampler, offset = "cmj", screenshot, script, save;
    std::uint32_t spp = 0, seed = 0, frames = 1, zoom = 0, strength = 0;
};

// ------------------------------------------------------------------------------ render mode

class RenderMode {
public:
    RenderMode(const std::string& scenePath, const CommonOptions& o, const std::string& referencePath)
        : o_(o), scene_(oas::scene::loadScene(scenePath))
    {
        if (!o.sampler.empty()) scene_.sampler.name = o.sampler;
        if (o.spp) scene_.sampler.spp = o.spp;
        if (!o.offset.empty()) scene_.sampler.offset = o.offset;
        if (o.strength) scene_.sampler.strength = o.strength;
        plan_ = oas::render::planDimensions(scene_);
        data_ = oas::render::flattenScene(scene_);
        if (!referencePath.empty()) {
            try {
                reference_ = oas::image::readExr(referencePath);
            } catch (const std::exception& e) {
                throw UsageError("--reference: " + std::string(e.what()) + " (valid: an OpenEXR image, e.g. from oas-render)");
            }
            if (reference_->width != scene_.width || reference_->height != scene_.height)
                throw UsageError("--reference " + referencePath + " is " + std::to_string(reference_->width) + "x" +
                                 std::to_string(reference_->height) + ", the scene renders " +
                                 std::to_string(scene_.width) + "x" + std::to_string(scene_.height) +
                                 ": valid a reference of the scene's size");
        }
        choose(scene_.sampler.name, /*fromOptions=*/!o.sampler.empty() || o.spp || o.strength);
        zoom_ = o.zoom ? o.zoom : std::max(1u, std::min(768u / std::max(1u, scene_.width), 768u / std::max(1u, scene_.height)));
        stem_ = o.save.empty() ? "out/view_" + scene_.name : o.save;
    }
    std::uint32_t windowWidth() const { return scene_.width * zoom_; }
    std::uint32_t windowHeight() const { return scene_.height * zoom_; }
    std::string name() const { return scene_.name; }

    /// Picks the pattern for `sampler` at the current spp; false (and a message) if it has none.
    bool choose(const std::string& sampler, bool fromOptions)
    {
        oas::scene::Scene s = scene_;
        s.sampler.name = sampler;
        try {
            auto chosen = oas::render::scenePattern(s, plan_, fromOptions);
            pattern_ = chosen.pattern;
            choice_ = chosen.choice;
            scene_.sampler.name = sampler;
            return true;
        } catch (const oas::InvalidArgument& e) {
            if (!started_) throw;  // the command line's own request: a usage error
            std::fprintf(stderr, "oas-view: %s: %s (kept %s)\n", sampler.c_str(), e.what(), choice_.c_str());
            return false;
        }
    }

    void key(const ScriptedKey& k, Viewer& v)
    {
        switch (k.key) {
            case GLFW_KEY_S: {
                // The next sampler that has a pattern for this scene's dimensions and spp.
                std::string next = scene_.sampler.name;
                for (std::size_t tries = 0; tries < samplerCycle().size(); ++tries) {
                    next = cycled(samplerCycle(), next, k.shift ? -1 : 1);
                    if (choose(next, true)) break;
                }
                restart();
                break;
            }
            case GLFW_KEY_O: {
                const std::string old = scene_.sampler.offset;
                scene_.sampler.offset = cycled(kOffsets, old, 1);
                if (!choose(scene_.sampler.name, true)) scene_.sampler.offset = old;
                restart();
                break;
            }
            case GLFW_KEY_EQUAL:
            case GLFW_KEY_KP_ADD:
            case GLFW_KEY_MINUS:
            case GLFW_KEY_KP_SUBTRACT: {
                const std::uint32_t old = scene_.sampler.spp;
                const bool up = k.key == GLFW_KEY_EQUAL || k.key == GLFW_KEY_KP_ADD;
                scene_.sampler.spp = nextCount(scene_.sampler.name, pattern_.strength, plan_.sampleDims, old, up);
                if (!choose(scene_.sampler.name, true)) scene_.sampler.spp = old;
                restart();
                break;
            }
            case GLFW_KEY_R: restart(); break;
            case GLFW_KEY_E:
                if (reference_) falseColour_ = !falseColour_;
                else std::fprintf(stderr, "oas-view: e: no --reference to compare with\n");
                break;
            case GLFW_KEY_P: save(); break;
            case GLFW_KEY_Z:
                // Zoom 1x, 2x, 3x: resizes the window (the swapchain follows).
                zoom_ = zoom_ % 3 + 1;
                glfwSetWindowSize(v.window(), int(windowWidth()), int(windowHeight()));
                shown_.width = 0;  // redraw at the new zoom
                break;
            case GLFW_KEY_Q:
            case GLFW_KEY_ESCAPE: v.close(); break;
            default: break;
        }
    }

    void restart()
    {
        cursor_.reset();
        if (tracer_ && tracer_->accepts(pattern_)) {
            tracer_->setPattern(pattern_);
            tracer_->clear();
        }
        samplesShown_ = 0;
        started_ = true;
    }

    /// One frame's work: builds the pipeline off-thread when the specialization changed, traces
    /// for about 40 ms, then returns the frame to show.
    const oas::view::Frame& frame(Viewer& v)
    {
        started_ = true;
        if (!tracer_ || !tracer_->accepts(pattern_)) {
            if (!building_.valid()) {
                const oas::Pattern p = pattern_;
                // Built and warmed up (lavapipe compiles at the first dispatch) off the main
                // thread, which meanwhile only polls events: busy() keeps it from presenting, so
                // the queue has one user at a time.
                building_ = std::async(std::launch::async, [this, &v, p] {
                    auto t = std::make_unique<oas::render::GpuTracer>(v.context(), data_, plan_, p);
                    oas::render::SampleBatch warm;
                    warm.width = std::min(8u, scene_.width);
                    warm.height = std::min(8u, scene_.height);
                    t->trace(warm);
                    t->clear();
                    return t;
                });
                buildStart_ = Clock::now();
            }
            if (building_.wait_for(std::chrono::milliseconds(30)) != std::future_status::ready) {
                status_ = "building the pipeline (" + std::to_string(int(secondsSince(buildStart_))) + " s)";
                return shown_;
            }
            tracer_ = building_.get();
            deviceName_ = v.context().deviceName();
            if (!tracer_->accepts(pattern_)) return shown_;  // switched again meanwhile: build that one next frame
            tracer_->setPattern(pattern_);
            tracer_->clear();
            cursor_.reset();
        }
        if (!cursor_) {
            cursor_.emplace(scene_.width, scene_.height, scene_.sampler.spp, oas::render::samplesPerBatch(plan_), o_.seed,
                            tile_);
            renderStart_ = Clock::now();
            traceSeconds_ = 0;
        }
        const auto frameStart = Clock::now();
        while (!cursor_->done() && (secondsSince(frameStart) < 0.04)) {
            const auto t = Clock::now();
            tracer_->trace(cursor_->batch());
            const double dt = secondsSince(t);
            traceSeconds_ += dt;
            passSlowest_ = std::max(passSlowest_, dt);
            if (cursor_->advance()) {
                // Keep the slowest dispatch of a pass near 10-40 ms, so that a frame never waits long
                // for one (tiles of one image differ in cost many times over: the slowest decides).
                // The tile only changes between passes, which leaves the accumulation oas-render's.
                if (passSlowest_ > 0.04 && tile_ > 8) tile_ /= 2;
                else if (passSlowest_ < 0.01 && tile_ < oas::render::kRenderTile) tile_ *= 2;
                cursor_->setTile(tile_);
                passSlowest_ = 0;
            }
        }
        const std::uint32_t done = cursor_->samplesDone();
        if (done != samplesShown_ || shown_.width == 0 || falseColour_ != shownFalseColour_) {
            // Completed passes only, so every pixel of the shown image has the same spp.
            shownSums_ = tracer_->accumulation();
            image_ = shownSums_.image();
            const oas::image::Image shownImage =
                falseColour_ && reference_ ? oas::image::falseColourError(image_, *reference_) : image_;
            oas::view::Frame f;
            f.width = scene_.width;
            f.height = scene_.height;
            f.rgb = oas::image::srgb8(shownImage);
            shown_ = oas::view::zoomed(f, zoom_);
            samplesShown_ = done;
            shownFalseColour_ = falseColour_;
            if (reference_ && done) relMse_ = oas::image::compare(image_, *reference_).relMse;
        }
        const double elapsed = secondsSince(renderStart_);
        std::ostringstream t;
        t << done << "/" << scene_.sampler.spp << " spp, " << std::fixed;
        t.precision(1);
        t << elapsed << " s, ";
        t.precision(2);
        t << (traceSeconds_ > 0 ? double(scene_.width) * scene_.height * done / traceSeconds_ / 1e6 : 0.0)
          << " Mpaths/s";
        if (reference_ && done) {
            t.precision(3);
            t << std::scientific << ", relMSE " << relMse_;
        }
        if (falseColour_) t << ", false-colour error";
        status_ = t.str();
        return shown_;
    }
    bool complete() const { return cursor_ && cursor_->done() && samplesShown_ == scene_.sampler.spp; }
    /// A pipeline is being built on another thread: do not present (one queue user at a time).
    bool busy() const { return building_.valid(); }
    /// Frees every Vulkan object before the viewer's context goes (a pipeline still building is
    /// waited for).
    void release()
    {
        if (building_.valid()) building_.wait();
        building_ = {};
        tracer_.reset();
    }
    std::string title() const { return "oas-view: " + scene_.name + " | " + choice_ + " | " + status_; }

    void save()
    {
        if (samplesShown_ == 0) {
            std::fprintf(stderr, "oas-view: p: nothing rendered yet\n");
            return;
        }
        const std::string exr = stem_ + ".exr", png = stem_ + ".png";
        if (const auto parent = std::filesystem::path(exr).parent_path(); !parent.empty())
            std::filesystem::create_directories(parent);
        // A render file like oas-render's (mergeable with shards of the same frame): the sums of
        // the completed passes, samples [0, samplesShown_).
        auto attributes = oas::render::renderAttributes(scene_, data_, plan_, pattern_, o_.seed);
        attributes["oas.writer"] = "oas-view";
        attributes["oas.device"] = deviceName_;
        oas::render::writeRenderFile(exr, shownSums_, {{0, samplesShown_}}, attributes);
        oas::image::writePngPreview(png, image_);
        std::printf("wrote %s and %s (%u spp, %s)\n", exr.c_str(), png.c_str(), samplesShown_, choice_.c_str());
    }

private:
    CommonOptions o_;
    oas::scene::Scene scene_;
    oas::render::DimensionPlan plan_;
    oas::render::SceneData data_;
    std::optional<oas::image::Image> reference_;
    oas::Pattern pattern_;
    std::string choice_, status_, stem_, deviceName_;
    std::unique_ptr<oas::render::GpuTracer> tracer_;
    std::future<std::unique_ptr<oas::render::GpuTracer>> building_;
    std::optional<oas::render::BatchCursor> cursor_;
    std::uint32_t tile_ = 32, zoom_ = 1, samplesShown_ = 0;
    bool falseColour_ = false, shownFalseColour_ = false, started_ = false;
    double traceSeconds_ = 0, relMse_ = 0, passSlowest_ = 0;
    Clock::time_point renderStart_ = Clock::now(), buildStart_ = Clock::now();
    oas::image::Image image_;
    oas::render::Accumulation shownSums_;  ///< the sums image_ shows (completed passes only)
    oas::view::Frame shown_;
};

// ------------------------------------------------------------------------------ points mode

class PointsMode {
public:
    PointsMode(const CommonOptions& o, std::uint32_t dims, std::uint32_t a, std::uint32_t b)
        : o_(o), sampler_(o.sampler.empty() ? "bose" : o.sampler), offset_(o.offset.empty() ? "cmj" : o.offset),
          spp_(o.spp ? o.spp : 121), dims_(dims), a_(a), b_(b)
    {
        if (a >= dims || b >= dims)
            throw UsageError("--pair " + std::to_string(a) + "," + std::to_string(b) + ": valid dimensions 0 .. " +
                             std::to_string(dims - 1) + " (--dims " + std::to_string(dims) + ")");
        makePattern(true);
        stem_ = o.save.empty() ? "out/view_points" : o.save;
    }
    std::uint32_t windowWidth() const { return 2 * 768 + kGap; }
    std::uint32_t windowHeight() const { return 768; }

    void key(const ScriptedKey& k, Viewer& v)
    {
        switch (k.key) {
            case GLFW_KEY_RIGHT_BRACKET: step(+1); break;
            case GLFW_KEY_LEFT_BRACKET: step(-1); break;
            case GLFW_KEY_PERIOD: {
                // The same pair in the next block (wrapping), to see blocks' independence.
                const std::uint32_t bd = std::max(1u, pattern_.blockDims);
                a_ = (a_ + bd) % dims_;
                b_ = (b_ + bd) % dims_;
                dirty_ = true;
                break;
            }
            case GLFW_KEY_S: {
                const std::string old = sampler_;
                for (std::size_t tries = 0; tries < samplerCycle().size(); ++tries) {
                    sampler_ = cycled(samplerCycle(), sampler_, k.shift ? -1 : 1);
                    if (makePattern(false)) return;
                }
                sampler_ = old;
                break;
            }
            case GLFW_KEY_O: {
                const std::string old = offset_;
                offset_ = cycled(kOffsets, offset_, 1);
                if (!makePattern(false)) offset_ = old;
                break;
            }
            case GLFW_KEY_EQUAL:
            case GLFW_KEY_KP_ADD:
            case GLFW_KEY_MINUS:
            case GLFW_KEY_KP_SUBTRACT: {
                // The sampler's next valid count up or down (Bose: q^2 only, ...).
                const std::uint32_t old = spp_;
                const bool up = k.key == GLFW_KEY_EQUAL || k.key == GLFW_KEY_KP_ADD;
                spp_ = std::min(nextCount(sampler_, pattern_.strength, dims_, old, up), 1u << 16);
                if (!makePattern(false)) spp_ = old;
                break;
            }
            case GLFW_KEY_P: saveRequested_ = true; break;
            case GLFW_KEY_Q:
            case GLFW_KEY_ESCAPE: v.close(); break;
            default: break;
        }
    }

    /// Points and spectrum are made on a worker thread (the generation kernel's pipeline build
    /// takes seconds on lavapipe); meanwhile busy() keeps the main thread from presenting, so the
    /// queue has one user at a time, and keys pressed meanwhile start the next job.
    const oas::view::Frame& frame(Viewer& v)
    {
        if (job_.valid()) {
            if (job_.wait_for(std::chrono::milliseconds(30)) != std::future_status::ready) return shown_;
            shown_ = job_.get();
        }
        if (dirty_) {
            dirty_ = false;
            job_ = std::async(std::launch::async, [this, &v, pattern = pattern_, a = a_, b = b_, dims = dims_] {
                return draw(v, pattern, a, b, dims);
            });
            promise_ = oas::view::strataPromise(pattern_, a_, b_);
        }
        return shown_;
    }
    bool complete() const { return !dirty_ && !job_.valid() && shown_.width > 0; }
    /// A job is using the queue on another thread: do not present.
    bool busy() const { return job_.valid(); }
    void release()
    {
        if (job_.valid()) job_.wait();
        job_ = {};
        generator_.reset();
    }
    bool takeSaveRequest() { return std::exchange(saveRequested_, false); }
    std::string stem() const { return stem_; }
    std::string title() const
    {
        return "oas-view points: " + oas::describe(pattern_) + " | dims (" + std::to_string(a_) + ", " +
               std::to_string(b_) + ") of " + std::to_string(dims_) + " | " + promise_.what + " | spectrum of " +
               std::to_string(kSets) + " randomizations, |k| <= " + std::to_string(kRadius);
    }

private:
    static constexpr std::uint32_t kSets = 16, kGap = 8;
    static constexpr int kRadius = 32;

    /// The projection of pixel (0, 0)'s points and the spectrum averaged over kSets pixels, from
    /// the GPU kernel (one randomization's periodogram is mostly noise).
    oas::view::Frame draw(Viewer& v, const oas::Pattern& pattern, std::uint32_t a, std::uint32_t b, std::uint32_t dims)
    {
        if (!generator_) generator_ = std::make_unique<oas::GpuGenerator>(v.context());
        oas::SampleRequest req;
        req.width = kSets;
        req.height = 1;
        req.spp = pattern.N;
        req.dims = dims;
        req.seed = o_.seed;
        std::vector<float> pts(std::size_t(kSets) * pattern.N * dims);
        generator_->generate(pattern, req, pts.data());
        auto column = [&](std::uint32_t set, std::uint32_t dim) {
            std::vector<float> c(pattern.N);
            for (std::uint32_t i = 0; i < pattern.N; ++i) c[i] = pts[(std::size_t(set) * pattern.N + i) * dims + dim];
            return c;
        };
        const std::uint32_t size = oas::view::panelSize(pattern.N);
        const auto promise = oas::view::strataPromise(pattern, a, b);
        const oas::view::Frame left = oas::view::drawProjection(column(0, a), column(0, b), size, promise, pattern.N);
        std::vector<double> power(std::size_t(2 * kRadius + 1) * (2 * kRadius + 1), 0.0);
        for (std::uint32_t set = 0; set < kSets; ++set) {
            const auto xs = column(set, a), ys = column(set, b);
            oas::addPeriodogram(xs.data(), ys.data(), pattern.N, kRadius, power);
        }
        for (auto& p : power) p /= kSets;
        return oas::view::sideBySide(left, oas::view::drawSpectrum(power, kRadius, size), kGap);
    }

    /// Next/previous pair (a, b), a < b, in the order (0,1) (0,2) ... (0,D-1) (1,2) ...
    void step(int dir)
    {
        std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
        for (std::uint32_t i = 0; i < dims_; ++i)
            for (std::uint32_t j = i + 1; j < dims_; ++j) pairs.push_back({i, j});
        if (pairs.empty()) return;
        auto it = std::find(pairs.begin(), pairs.end(), std::make_pair(std::min(a_, b_), std::max(a_, b_)));
        const int n = int(pairs.size());
        const int i = it == pairs.end() ? 0 : int(it - pairs.begin());
        std::tie(a_, b_) = pairs[std::size_t(((i + dir) % n + n) % n)];
        dirty_ = true;
    }
    bool makePattern(bool first)
    {
        oas::PatternRequest r;
        r.sampler = sampler_;
        r.spp = spp_;
        r.dims = dims_;
        r.offset = offset_;
        r.strength = o_.strength;
        try {
            pattern_ = sampler_ == "oa" ? oas::chooseOrthogonalArray(r).pattern : oas::makePattern(r);
            dirty_ = true;
            return true;
        } catch (const oas::InvalidArgument& e) {
            if (first) throw;
            std::fprintf(stderr, "oas-view: %s at %u spp: %s\n", sampler_.c_str(), spp_, e.what());
            return false;
        }
    }
    CommonOptions o_;
    std::string sampler_, offset_, stem_;
    std::uint32_t spp_, dims_, a_, b_;
    oas::Pattern pattern_;
    oas::view::StrataPromise promise_;
    std::unique_ptr<oas::GpuGenerator> generator_;
    oas::view::Frame shown_;
    std::future<oas::view::Frame> job_;
    bool dirty_ = true, saveRequested_ = false;
};

/// The frame loop both modes share.
template <class Mode>
int run(Mode& mode, Viewer& viewer, const CommonOptions& o)
{
    // Frames count the frames shown: scripted keys and --frames refer to what the window showed,
    // whatever time a pipeline build took before the first one.
    std::vector<ScriptedKey> script = parseScript(o.script);
    std::uint32_t frame = 0, loops = 0;
    double slowestFrame = 0;
    while (!viewer.shouldClose()) {
        ++loops;
        for (const auto& k : viewer.keys(script, frame + 1)) mode.key(k, viewer);
        if (viewer.shouldClose()) break;
        const auto t = Clock::now();
        const oas::view::Frame& f = mode.frame(viewer);
        const bool finished = !o.screenshot.empty() && frame + 1 >= o.frames && script.empty() && mode.complete();
        bool wantPicture = finished;
        if constexpr (std::is_same_v<Mode, PointsMode>) wantPicture = wantPicture || mode.takeSaveRequest();
        const bool shown = f.width > 0 && !mode.busy() && viewer.presenter().present(f, wantPicture);
        frame += shown;
        slowestFrame = std::max(slowestFrame, secondsSince(t));
        viewer.setTitle(mode.title());
        if (shown && wantPicture) {
            std::string path = o.screenshot;
            if constexpr (std::is_same_v<Mode, PointsMode>)
                if (!finished) path = mode.stem() + ".png";
            writeScreenshot(path, viewer.presenter().lastShown());
            if (finished) break;
        }
        if (!shown) glfwWaitEventsTimeout(0.01);  // nothing shown (pipeline build, minimised)
    }
    mode.release();
    std::fprintf(stderr, "oas-view: %u frames shown (%u loops), slowest loop %.0f ms, swapchain recreated %u time(s)\n",
                 frame, loops, slowestFrame * 1000, viewer.presenter().recreations());
    if (const std::size_t n = viewer.validationFindings()) {
        std::fprintf(stderr, "oas-view: error: %zu Vulkan validation message(s) (above)\n", n);
        return 3;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-view: watch a render converge, or look at a sampler's projections and spectrum"};
    std::string scenePath, reference, pair = "0,1";
    CommonOptions o;
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
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::cerr << "oas-view: error: " << e.what() << "\nrun with --help for the options\n";
        return 2;
    }
    try {
        parseScript(o.script);  // bad scripts fail before any window opens
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
        std::unique_ptr<RenderMode> render;
        std::unique_ptr<PointsMode> pointsMode;
        if (points) pointsMode = std::make_unique<PointsMode>(o, dims, a, b);
        else render = std::make_unique<RenderMode>(scenePath, o, reference);

        glfwSetErrorCallback([](int, const char*) {});  // reported through glfwGetError instead
        if (!glfwInit())
            throw UsageError("no display: " + glfwMessage() +
                             ". oas-view needs a desktop session or a virtual one, e.g. xvfb-run -a oas-view ...");
        struct Terminate {
            ~Terminate() { glfwTerminate(); }
        } terminate;
        if (!glfwVulkanSupported()) throw std::runtime_error("GLFW found no Vulkan loader: " + glfwMessage());
        oas::vk::selectLavapipeIfUnset();
        const std::uint32_t w = points ? pointsMode->windowWidth() : render->windowWidth();
        const std::uint32_t h = points ? pointsMode->windowHeight() : render->windowHeight();
        Viewer viewer(w, h, points ? "oas-view points" : "oas-view: " + render->name());
        return points ? run(*pointsMode, viewer, o) : run(*render, viewer, o);
    } catch (const UsageError& e) {
        std::cerr << "oas-view: error: " << e.what() << "\n";
        return 2;
    } catch (const oas::scene::SceneError& e) {
        std::cerr << "oas-view: error: " << e.what() << "\n";
        return 2;
    } catch (const oas::InvalidArgument& e) {
        std::cerr << "oas-view: error: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "oas-view: error: " << e.what() << "\n";
        return 1;
    }
}
