#pragma once
// The scene part's time axis, measured apart from its accuracy. A render's error does not depend
// on the machine (its images are bit-identical anywhere), so accuracy renders may be pooled over
// runs, days and machines; its time does, and drifts even within a run (cornell7d's renders of the
// same points ran 1.4-2.1x faster in a top-up run a day later than in the first run). So every
// equal-time figure comes from one cost run per scene: every (sampler, spp) point of the scene
// rendered in rounds, each round visiting all points in the same order (A B C ... A B C ...), so
// that slow phases of a shared machine fall on every point alike, with pipeline builds done
// before the first round and reported apart.
#include <cstdint>
#include <string>
#include <vector>

#include "experiment.hpp"
#include "scene_study.hpp"
#include "vk/context.hpp"

namespace oas::study {

// SceneCost (one point of a cost run) is declared in scene_study.hpp, whose section reads it.

/// scene_costs.csv's columns: scene,sampler,spp,seconds,se,rounds,run_id,machine,device,date,
/// commit,sources (the last two may be missing: files from before cost runs were stamped).
const std::vector<std::string>& sceneCostColumns();
void writeSceneCosts(const std::string& path, const std::vector<SceneCost>& costs);
/// Throws std::runtime_error naming the file, row and column for a missing column or a bad number.
std::vector<SceneCost> readSceneCosts(const std::string& path);
/// The two devices a scene is timed on: the GPU tracer (in CI and on this machine, lavapipe) and
/// the C++ twin (`oas-render --device cpu`, what a user without a GPU runs). The samplers' relative
/// costs differ between them (the twin fetches OA values in vectorized runs, lavapipe loads storage
/// buffers one lane at a time), so each has its own cost run and its own equal-time verdicts.
enum class CostDevice { Gpu, CpuTwin };
/// The `device` column of the CPU twin's rows (a GPU row holds the Vulkan device's name).
inline constexpr const char* kCpuTwinDeviceName = "CPU twin";
CostDevice costDeviceOf(const SceneCost& row);
/// "GPU" or "CPU twin": how progress messages name a device kind.
const char* costDeviceLabel(CostDevice device);

/// `kept` without the (scene, device kind) runs that `fresh` has, then `fresh`.
std::vector<SceneCost> mergeSceneCosts(const std::vector<SceneCost>& kept, const std::vector<SceneCost>& fresh);
/// The scene's rows timed on `device`, all of one run. Throws std::runtime_error when they come
/// from several runs (times from different runs are not comparable); empty when there are none.
std::vector<SceneCost> costsOfScene(const std::vector<SceneCost>& costs, const std::string& scene,
                                    CostDevice device = CostDevice::Gpu);

/// The seconds one render of (sampler, spp) costs by a scene's cost run (`sceneRows`, costsOfScene):
/// the point's mean; for a count the run did not time, the sampler's seconds per spp at its timed
/// count nearest in log × spp. Throws std::runtime_error when the run has no row of the sampler.
double costRunSeconds(const std::vector<SceneCost>& sceneRows, const std::string& sampler, std::uint32_t spp);

/// The hash of the sources that decide render time (cmake/oas_sources_hash.cmake), as this build
/// was compiled from: a cost run stamped with another hash timed other code.
std::string renderSourcesHash();
/// The scenes whose rows in `costs` are not stamped with renderSourcesHash(), in first-seen order.
std::vector<std::string> staleCostScenes(const std::vector<SceneCost>& costs);

/// Mean and standard error (sd / √n) of the times; s.e. 0 for one time.
SceneCost summarizeTimes(const std::vector<double>& seconds);

struct SceneCostOptions {
    std::string scenesDir = "scenes";
    std::uint32_t rounds = 3;  ///< at least 3
    std::string runId, machine, date, commit;
    CostDevice device = CostDevice::Gpu;
    unsigned cpuThreads = 0;  ///< CPU twin workers (0: all cores, as `oas-render --device cpu`)
};

/// Times every (sampler, spp) point that `measurements` hold for `record`'s scene, at the
/// record's resolution, in options.rounds rounds, on options.device: the GPU tracer on `context`
/// (required then), or the CPU twin (`context` unused, may be null). `pipelineSeconds` receives
/// the build time of the scene's pipelines (excluded from the times; 0 on the CPU twin). Progress
/// goes to stderr.
std::vector<SceneCost> measureSceneCosts(const SceneRecord& record, const std::vector<SceneMeasurement>& measurements,
                                         const std::vector<SamplerSpec>& samplers, const SceneCostOptions& options,
                                         oas::vk::Context* context, double* pipelineSeconds = nullptr);

}  // namespace oas::study
