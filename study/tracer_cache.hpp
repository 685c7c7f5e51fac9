#pragma once
// GPU tracers for the study: one per pipeline specialization, built up front and warmed up, so
// that pipeline builds and first-use costs stay out of every timing.
#include <algorithm>
#include <atomic>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "oas/pattern.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "vk/context.hpp"

namespace oas::study {

/// One GPU tracer per pipeline specialization, reused across sample counts (the pattern is a push
/// constant). Lavapipe took ~17 s to build one path-tracing pipeline on this machine (1.5 s since
/// the tracer calls the sampler at one site), so all of a scene's pipelines are built up front on
/// every core (pipeline creation is thread-safe in Vulkan) and warmed up with one untimed dispatch:
/// builds and first-use costs stay out of the timings.
class TracerCache {
public:
    TracerCache(oas::vk::Context& context, const oas::render::SceneData& data, const oas::render::DimensionPlan& plan)
        : context_(context), data_(data), plan_(plan)
    {
    }
    void prepare(const std::vector<oas::Pattern>& patterns)
    {
        std::vector<oas::Pattern> todo;
        for (const auto& p : patterns)
            if (!find(p) && std::none_of(todo.begin(), todo.end(), [&](const oas::Pattern& q) {
                    return oas::specializationKey(q) == oas::specializationKey(p);
                }))
                todo.push_back(p);
        std::vector<std::unique_ptr<oas::render::GpuTracer>> made(todo.size());
        std::atomic<size_t> next{0};
        std::vector<std::thread> pool;
        std::exception_ptr failure;
        std::mutex failureMutex;
        for (unsigned t = 0; t < std::max(1u, std::thread::hardware_concurrency()); ++t)
            pool.emplace_back([&] {
                for (size_t i; (i = next++) < todo.size();) {
                    try {
                        made[i] = std::make_unique<oas::render::GpuTracer>(context_, data_, plan_, todo[i]);
                    } catch (...) {
                        std::lock_guard<std::mutex> lock(failureMutex);
                        failure = std::current_exception();
                    }
                }
            });
        for (auto& th : pool) th.join();
        if (failure) std::rethrow_exception(failure);
        for (auto& t : made) {
            oas::render::SampleBatch warm;
            warm.width = std::min<std::uint32_t>(8, std::uint32_t(data_.globals.image.x));
            warm.height = std::min<std::uint32_t>(8, std::uint32_t(data_.globals.image.y));
            t->trace(warm);
            tracers_.push_back(std::move(t));
        }
    }
    oas::render::GpuTracer& get(const oas::Pattern& pattern)
    {
        if (!find(pattern)) prepare({pattern});
        auto* t = find(pattern);
        t->setPattern(pattern);
        return *t;
    }

    /// Pipelines built so far, and their build seconds summed (each measured on its own thread,
    /// so with several built at once the sum exceeds the wall time).
    std::size_t size() const { return tracers_.size(); }
    double buildSeconds() const
    {
        double sum = 0;
        for (const auto& t : tracers_) sum += t->pipelineBuildSeconds();
        return sum;
    }

private:
    oas::render::GpuTracer* find(const oas::Pattern& pattern)
    {
        for (auto& t : tracers_)
            if (t->accepts(pattern)) return t.get();
        return nullptr;
    }
    oas::vk::Context& context_;
    const oas::render::SceneData& data_;
    const oas::render::DimensionPlan& plan_;
    std::vector<std::unique_ptr<oas::render::GpuTracer>> tracers_;
};

}  // namespace oas::study
