#pragma once
// oas-view's render mode: a scene rendered progressively by the GPU path tracer (oas-render's
// passes, cut into smaller tiles while a dispatch takes longer than ~40 ms), shown tone-mapped
// exactly as oas-render's PNG (image::srgb8). The title shows spp done, elapsed time, Mpaths/s
// and, with a reference, the running relMSE.
//
// Keys: s / S next / previous sampler, o next offset, + / - the sampler's next valid spp at least
// double / at most half the current one, r restart, e false-colour error against --reference,
// p save the image (EXR + PNG, as oas-render), z zoom 1x / 2x / 3x (resizes the window),
// q / Esc quit.
#include <cstdint>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "image/image.hpp"
#include "oas/pattern.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"
#include "view/viewer.hpp"

namespace oas::view {

class RenderMode {
public:
    /// Loads the scene and the reference and picks the pattern, before any window opens: bad input
    /// throws (scene::SceneError, InvalidArgument, UsageError) even without a display.
    RenderMode(const std::string& scenePath, const CommonOptions& o, const std::string& referencePath);
    std::uint32_t windowWidth() const { return scene_.width * zoom_; }
    std::uint32_t windowHeight() const { return scene_.height * zoom_; }
    std::string name() const { return scene_.name; }

    /// Picks the pattern for `sampler` at the current spp; false (and a message) if it has none.
    bool choose(const std::string& sampler, bool fromOptions);
    void key(const ScriptedKey& k, Viewer& v);
    void restart();
    /// One frame's work: builds the pipeline off-thread when the specialization changed, traces
    /// for about 40 ms, then returns the frame to show.
    const Frame& frame(Viewer& v);
    bool complete() const { return cursor_ && samplesDone() == scene_.sampler.spp && samplesShown_ == scene_.sampler.spp; }
    /// A pipeline is being built on another thread: do not present (one queue user at a time).
    bool busy() const { return building_.valid(); }
    /// Frees every Vulkan object before the viewer's context goes (a pipeline still building is
    /// waited for).
    void release();
    std::string title() const { return "oas-view: " + scene_.name + " | " + choice_ + " | " + status_; }
    /// The p key: the completed passes as a render file like oas-render's, and its PNG.
    void save();

private:
    CommonOptions o_;
    scene::Scene scene_;
    render::DimensionPlan plan_;
    render::SceneData data_;
    std::optional<image::Image> reference_;
    Pattern pattern_;
    std::string choice_, status_, stem_, deviceName_;
    std::unique_ptr<render::GpuTracer> tracer_;
    std::future<std::unique_ptr<render::GpuTracer>> building_;
    /// With `faure`, the render runs in segments that end at its checkpoints (apps/checkpoints.hpp:
    /// every q^m spp), and a frame that completes one shows it: each (0,m,d)-net prefix is seen.
    /// Other samplers run one segment, [0, spp).
    std::optional<render::BatchCursor> cursor_;
    std::vector<std::uint32_t> checkpoints_;
    std::uint32_t segmentFirst_ = 0, segmentEnd_ = 0, checkpointShown_ = 0;
    void startSegment(std::uint32_t first);
    std::uint32_t samplesDone() const { return cursor_ ? segmentFirst_ + cursor_->samplesDone() : 0; }
    std::uint32_t tile_ = 32, zoom_ = 1, samplesShown_ = 0;
    bool falseColour_ = false, shownFalseColour_ = false, started_ = false;
    double traceSeconds_ = 0, relMse_ = 0, passSlowest_ = 0;
    Clock::time_point renderStart_ = Clock::now(), buildStart_ = Clock::now();
    image::Image image_;
    render::Accumulation shownSums_;  ///< the sums image_ shows (completed passes only)
    Frame shown_;
};

}  // namespace oas::view
