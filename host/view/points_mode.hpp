#pragma once
// oas-view's points mode: the 2D projection of two dimensions of a sampler's points, from the GPU
// generation kernel (oas-samples' numbers), with the strata the construction promises, the
// projection's power spectrum, and labels naming what is shown (points_view.hpp draws it).
//
// Keys: ] / [ next / previous pair, . the same pair in the next block (both dimensions +
// blockDims), s / S next / previous sampler, o next offset, + / - the sampler's next valid count
// up / down, p save a screenshot (STEM.png), q / Esc quit.
#include <cstdint>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "oas/generate_gpu.hpp"
#include "oas/pattern.hpp"
#include "view/points_view.hpp"
#include "view/viewer.hpp"

namespace oas::view {

class PointsMode {
public:
    /// Checks the pair and makes the pattern before any window opens: bad input throws
    /// (UsageError, InvalidArgument) even without a display.
    PointsMode(const CommonOptions& o, std::uint32_t dims, std::uint32_t a, std::uint32_t b);
    std::uint32_t windowWidth() const { return pointsLayout(1, kRadius).width; }
    std::uint32_t windowHeight() const { return pointsLayout(1, kRadius).height; }

    void key(const ScriptedKey& k, Viewer& v);
    /// Points and spectrum are made on a worker thread (the generation kernel's pipeline build
    /// takes seconds on lavapipe); meanwhile busy() keeps the main thread from presenting, so the
    /// queue has one user at a time, and keys pressed meanwhile start the next job.
    const Frame& frame(Viewer& v);
    bool complete() const { return !dirty_ && !job_.valid() && shown_.width > 0; }
    /// A job is using the queue on another thread: do not present.
    bool busy() const { return job_.valid(); }
    void release();
    bool takeSaveRequest() { return std::exchange(saveRequested_, false); }
    std::string stem() const { return stem_; }
    std::string title() const;

private:
    static constexpr std::uint32_t kSets = 16;
    static constexpr int kRadius = kSpectrumRadius;

    /// The projection of pixel (0, 0)'s points and the spectrum averaged over kSets pixels, from
    /// the GPU kernel (one randomization's periodogram is mostly noise), drawn with `labels`.
    Frame draw(Viewer& v, const Pattern& pattern, std::uint32_t a, std::uint32_t b, std::uint32_t dims,
               const PointsLabels& labels);
    /// What the picture says about the current request.
    PointsLabels labels() const;
    /// Next/previous pair (a, b), a < b, in the order (0,1) (0,2) ... (0,D-1) (1,2) ...
    void step(int dir);
    bool makePattern(bool first);

    CommonOptions o_;
    std::string sampler_, offset_, stem_;
    std::uint32_t spp_, dims_, a_, b_;
    Pattern pattern_;
    StrataPromise promise_;
    std::unique_ptr<GpuGenerator> generator_;
    Frame shown_;
    std::future<Frame> job_;
    bool dirty_ = true, saveRequested_ = false;
};

}  // namespace oas::view
