#include "view/render_mode.hpp"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "apps/checkpoints.hpp"
#include "image/metrics.hpp"
#include "render/render_file.hpp"
#include "render/scene_pattern.hpp"
#include "view/points_view.hpp"

namespace oas::view {

RenderMode::RenderMode(const std::string& scenePath, const CommonOptions& o, const std::string& referencePath)
    : o_(o), scene_(scene::loadScene(scenePath))
{
    if (!o.sampler.empty()) scene_.sampler.name = o.sampler;
    if (o.spp) scene_.sampler.spp = o.spp;
    if (!o.offset.empty()) scene_.sampler.offset = o.offset;
    if (o.strength) scene_.sampler.strength = o.strength;
    plan_ = render::planDimensions(scene_);
    data_ = render::flattenScene(scene_);
    if (!referencePath.empty()) {
        try {
            reference_ = image::readExr(referencePath);
        } catch (const std::exception& e) {
            throw UsageError("--reference: " + std::string(e.what()) + " (valid: an OpenEXR image, e.g. from oas-render)");
        }
        if (reference_->width != scene_.width || reference_->height != scene_.height)
            throw UsageError("--reference " + referencePath + " is " + std::to_string(reference_->width) + "x" +
                             std::to_string(reference_->height) + ", the scene renders " + std::to_string(scene_.width) + "x" +
                             std::to_string(scene_.height) + ": valid a reference of the scene's size");
    }
    choose(scene_.sampler.name, /*fromOptions=*/!o.sampler.empty() || o.spp || o.strength);
    zoom_ = o.zoom ? o.zoom : std::max(1u, std::min(768u / std::max(1u, scene_.width), 768u / std::max(1u, scene_.height)));
    stem_ = o.save.empty() ? "out/view_" + scene_.name : o.save;
}

bool RenderMode::choose(const std::string& sampler, bool fromOptions)
{
    scene::Scene s = scene_;
    s.sampler.name = sampler;
    try {
        auto chosen = render::scenePattern(s, plan_, fromOptions);
        pattern_ = chosen.pattern;
        choice_ = chosen.choice;
        scene_.sampler.name = sampler;
        return true;
    } catch (const InvalidArgument& e) {
        if (!started_) throw;  // the command line's own request: a usage error
        std::fprintf(stderr, "oas-view: %s: %s (kept %s)\n", sampler.c_str(), e.what(), choice_.c_str());
        return false;
    }
}

void RenderMode::key(const ScriptedKey& k, Viewer& v)
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
    case GLFW_KEY_R:
        restart();
        break;
    case GLFW_KEY_E:
        if (reference_)
            falseColour_ = !falseColour_;
        else
            std::fprintf(stderr, "oas-view: e: no --reference to compare with\n");
        break;
    case GLFW_KEY_P:
        save();
        break;
    case GLFW_KEY_Z:
        // Zoom 1x, 2x, 3x: resizes the window (the swapchain follows).
        zoom_ = zoom_ % 3 + 1;
        glfwSetWindowSize(v.window(), int(windowWidth()), int(windowHeight()));
        shown_.width = 0;  // redraw at the new zoom
        break;
    default:
        break;
    }
}

void RenderMode::restart()
{
    cursor_.reset();
    if (tracer_ && tracer_->accepts(pattern_)) {
        tracer_->setPattern(pattern_);
        tracer_->clear();
    }
    samplesShown_ = 0;
    started_ = true;
}

const Frame& RenderMode::frame(Viewer& v)
{
    started_ = true;
    if (!tracer_ || !tracer_->accepts(pattern_)) {
        if (!building_.valid()) {
            const Pattern p = pattern_;
            // Built and warmed up (lavapipe compiles at the first dispatch) off the main
            // thread, which meanwhile only polls events: busy() keeps it from presenting, so
            // the queue has one user at a time.
            building_ = std::async(std::launch::async, [this, &v, p] {
                auto t = std::make_unique<render::GpuTracer>(v.context(), data_, plan_, p);
                render::SampleBatch warm;
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
        checkpoints_ = pattern_.construction == OAS_FAURE ? apps::checkpointCounts(pattern_, 0, scene_.sampler.spp)
                                                          : std::vector<std::uint32_t>{};
        checkpointShown_ = 0;
        startSegment(0);
        renderStart_ = Clock::now();
        traceSeconds_ = 0;
    } else if (cursor_->done() && segmentEnd_ < scene_.sampler.spp) {
        startSegment(segmentEnd_);  // the last frame showed the checkpoint at segmentEnd_
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
            if (passSlowest_ > 0.04 && tile_ > 8)
                tile_ /= 2;
            else if (passSlowest_ < 0.01 && tile_ < render::kRenderTile)
                tile_ *= 2;
            cursor_->setTile(tile_);
            passSlowest_ = 0;
        }
    }
    const std::uint32_t done = samplesDone();
    if (done != samplesShown_ || shown_.width == 0 || falseColour_ != shownFalseColour_) {
        // Completed passes only, so every pixel of the shown image has the same spp.
        shownSums_ = tracer_->accumulation();
        image_ = shownSums_.image();
        const image::Image shownImage = falseColour_ && reference_ ? image::falseColourError(image_, *reference_) : image_;
        Frame f;
        f.width = scene_.width;
        f.height = scene_.height;
        f.rgb = image::srgb8(shownImage);
        shown_ = zoomed(f, zoom_);
        samplesShown_ = done;
        shownFalseColour_ = falseColour_;
        if (reference_ && done) relMse_ = image::compare(image_, *reference_).relMse;
        if (done != checkpointShown_ && std::find(checkpoints_.begin(), checkpoints_.end(), done) != checkpoints_.end()) {
            checkpointShown_ = done;  // what the prefix guarantees, as oas-render --explain says it
            std::printf("oas-view: checkpoint %u spp: %s\n", done, prefixGuarantee(pattern_, done).c_str());
            std::fflush(stdout);
        }
    }
    const double elapsed = secondsSince(renderStart_);
    std::ostringstream t;
    t << done << "/" << scene_.sampler.spp << " spp, " << std::fixed;
    t.precision(1);
    t << elapsed << " s, ";
    t.precision(2);
    t << (traceSeconds_ > 0 ? double(scene_.width) * scene_.height * done / traceSeconds_ / 1e6 : 0.0) << " Mpaths/s";
    if (reference_ && done) {
        t.precision(3);
        t << std::scientific << ", relMSE " << relMse_;
    }
    if (checkpointShown_) t << ", checkpoint " << checkpointShown_ << " (a net)";
    if (falseColour_) t << ", false-colour error";
    status_ = t.str();
    return shown_;
}

void RenderMode::startSegment(std::uint32_t first)
{
    segmentFirst_ = first;
    segmentEnd_ = scene_.sampler.spp;
    for (const std::uint32_t c : checkpoints_)
        if (c > first) {
            segmentEnd_ = c;
            break;
        }
    // The next segment's passes are oas-render's passes over [first, segmentEnd_): the sums of
    // any split of the samples are the same (render/accumulation.hpp), so the image at spp is too.
    cursor_.emplace(scene_.width, scene_.height, segmentEnd_, render::samplesPerBatch(plan_, data_), o_.seed, tile_, first);
}

void RenderMode::release()
{
    if (building_.valid()) building_.wait();
    building_ = {};
    tracer_.reset();
}

void RenderMode::save()
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
    auto attributes = render::renderAttributes(scene_, data_, plan_, pattern_, o_.seed);
    attributes["oas.writer"] = "oas-view";
    attributes["oas.device"] = deviceName_;
    render::writeRenderFile(exr, shownSums_, {{0, samplesShown_}}, attributes);
    image::writePngPreview(png, image_);
    std::printf("wrote %s and %s (%u spp, %s)\n", exr.c_str(), png.c_str(), samplesShown_, choice_.c_str());
}

}  // namespace oas::view
