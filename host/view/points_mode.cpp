#include "view/points_mode.hpp"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "oas/oas_pattern.h"
#include "oas/periodogram.hpp"

namespace oas::view {

PointsMode::PointsMode(const CommonOptions& o, std::uint32_t dims, std::uint32_t a, std::uint32_t b)
    : o_(o), sampler_(o.sampler.empty() ? "bose" : o.sampler), offset_(o.offset.empty() ? "cmj" : o.offset),
      spp_(o.spp ? o.spp : 121), dims_(dims), a_(a), b_(b)
{
    if (a >= dims || b >= dims)
        throw UsageError("--pair " + std::to_string(a) + "," + std::to_string(b) + ": valid dimensions 0 .. " +
                         std::to_string(dims - 1) + " (--dims " + std::to_string(dims) + ")");
    makePattern(true);
    stem_ = o.save.empty() ? "out/view_points" : o.save;
}

void PointsMode::key(const ScriptedKey& k, Viewer&)
{
    switch (k.key) {
    case GLFW_KEY_RIGHT_BRACKET:
        step(+1);
        break;
    case GLFW_KEY_LEFT_BRACKET:
        step(-1);
        break;
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
    case GLFW_KEY_P:
        saveRequested_ = true;
        break;
    default:
        break;
    }
}

const Frame& PointsMode::frame(Viewer& v)
{
    if (job_.valid()) {
        if (job_.wait_for(std::chrono::milliseconds(30)) != std::future_status::ready) return shown_;
        shown_ = job_.get();
    }
    if (dirty_) {
        dirty_ = false;
        promise_ = strataPromise(pattern_, a_, b_);
        job_ = std::async(std::launch::async, [this, &v, pattern = pattern_, a = a_, b = b_, dims = dims_, labels = labels()] {
            return draw(v, pattern, a, b, dims, labels);
        });
    }
    return shown_;
}

void PointsMode::release()
{
    if (job_.valid()) job_.wait();
    job_ = {};
    generator_.reset();
}

std::string PointsMode::title() const
{
    return "oas-view points: " + describe(pattern_) + " | dims (" + std::to_string(a_) + ", " + std::to_string(b_) + ") of " +
           std::to_string(dims_) + " | " + promise_.what + " | spectrum of " + std::to_string(kSets) +
           " randomizations, |k| <= " + std::to_string(kRadius);
}

PointsLabels PointsMode::labels() const
{
    // The offset only shapes orthogonal arrays; other samplers ignore it, and the label says so.
    const bool oa = pattern_.construction != 0 && pattern_.construction < OAS_RANDOM;
    // Fields apart by spaces, not '|': stb_easy_font draws '|' much like 'l'.
    PointsLabels l;
    l.header = "sampler " + sampler_ + "     " + std::to_string(pattern_.N) + " spp     " +
               (oa ? "offset " + offset_ : "no offset (not an OA)") + "     dimensions " + std::to_string(a_) + " (x) and " +
               std::to_string(b_) + " (y) of " + std::to_string(dims_) + "     seed " + std::to_string(o_.seed);
    l.detail = describe(pattern_) + ";   " + strataPromise(pattern_, a_, b_).what;
    l.xAxis = "dim " + std::to_string(a_);
    l.yAxis = "dim " + std::to_string(b_);
    l.spectrum = "power spectrum: mean of " + std::to_string(kSets) + " sets, k in -" + std::to_string(kRadius) + " .. " +
                 std::to_string(kRadius);
    l.spectrumScale = "log: black 0.01 .. white 10 (random: 1)";
    return l;
}

Frame PointsMode::draw(Viewer& v, const Pattern& pattern, std::uint32_t a, std::uint32_t b, std::uint32_t dims,
                       const PointsLabels& labels)
{
    if (!generator_) generator_ = std::make_unique<GpuGenerator>(v.context());
    SampleRequest req;
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
    std::vector<double> power(std::size_t(2 * kRadius + 1) * (2 * kRadius + 1), 0.0);
    for (std::uint32_t set = 0; set < kSets; ++set) {
        const auto xs = column(set, a), ys = column(set, b);
        addPeriodogram(xs.data(), ys.data(), pattern.N, kRadius, power);
    }
    for (auto& p : power) p /= kSets;
    return drawPointsView(column(0, a), column(0, b), strataPromise(pattern, a, b), pattern.N, power, kRadius, labels);
}

void PointsMode::step(int dir)
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

bool PointsMode::makePattern(bool first)
{
    PatternRequest r;
    r.sampler = sampler_;
    r.spp = spp_;
    r.dims = dims_;
    r.offset = offset_;
    r.strength = o_.strength;
    try {
        pattern_ = sampler_ == "oa" ? oas::chooseOrthogonalArray(r).pattern : oas::makePattern(r);
        dirty_ = true;
        return true;
    } catch (const InvalidArgument& e) {
        if (first) throw;
        std::fprintf(stderr, "oas-view: %s at %u spp: %s\n", sampler_.c_str(), spp_, e.what());
        return false;
    }
}

}  // namespace oas::view
