#pragma once
// Rendering a flattened scene with the path tracer of shaders/pt/pt_trace.glsl, on the GPU
// (pt_render.comp) or on the CPU (the same GLSL compiled as C++: the reference tracer).
// Both add into the same exact per-pixel sums (render/accumulation.hpp), so the two sides and any
// split of the samples give sums that can be added in any order.
#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "oas/generate_gpu.hpp"
#include "oas/pattern.hpp"
#include "render/accumulation.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "vk/context.hpp"

namespace oas::render {

class GpuWavefront;  // render/wavefront_gpu.hpp

/// Samples [firstSample, firstSample + count) of every pixel in the rectangle, added to an
/// accumulation of the whole image.
struct SampleBatch {
    std::uint32_t x0 = 0, y0 = 0, width = 0, height = 0;
    std::uint32_t firstSample = 0, count = 1;
    std::uint32_t seed = 0;
};

/// Samples per dispatch for a scene: as many as lavapipe's per-invocation loop cap allows in the
/// worst case, at most kMaxSamplesPerBatch. Lavapipe silently ends an invocation's loops after
/// 65535 iterations in all, so a batch takes floor(65535 / w) samples, where w bounds one sample's
/// loop iterations: its own, the vertex loop's, and per ray one per BVH node and one per shape (the
/// walk visits a node at most once; each shape lies in one leaf). At least 1: a scene whose single
/// sample could pass the cap (w > 65535) gets one per dispatch, as small as a batch goes.
std::uint32_t samplesPerBatch(const DimensionPlan& plan, const SceneData& data);
/// The largest batch: bounds a dispatch's length on real GPUs (a watchdog ends long ones). 16
/// rather than 8 made lavapipe's 96-px cornell7d and blue_spheres9d renders 1.05-1.07x faster
/// (fewer dispatches, and the OA generation shares each pixel's state over twice the samples);
/// 32 gained nothing more (oas-render-bench, 3 rounds, 2026-12-05).
constexpr std::uint32_t kMaxSamplesPerBatch = 16;
/// Samples per batch for the CPU tracer, which has no loop cap: it makes each OA dimension for a
/// run of a pixel's consecutive samples at once (OaColumns, vectorized across the run), and a run
/// ends with its batch, so a GPU-sized batch of 8 would leave one vector step per run and the
/// run's setup (block and column state) unshared. 64 shares it; a pass over the image stays short
/// enough that stop signals, honoured between passes, are answered in seconds.
constexpr std::uint32_t kCpuSamplesPerBatch = 64;

/// Visits samples [firstSample, spp) of a width x height image as passes of sample batches, each
/// pass over tiles of at most kRenderTile^2 pixels (bounded dispatches). `trace` gets every batch;
/// `afterPass(samplesDone)` runs after each pass and returns false to stop early (Ctrl-C).
/// Returns the samples per pixel done (counted from firstSample).
constexpr std::uint32_t kRenderTile = 256;
std::uint32_t forEachBatch(std::uint32_t width, std::uint32_t height, std::uint32_t spp, std::uint32_t perBatch,
                           std::uint32_t seed, const std::function<void(const SampleBatch&)>& trace,
                           const std::function<bool(std::uint32_t)>& afterPass = {}, std::uint32_t firstSample = 0);

/// The batches of forEachBatch one at a time, for callers that interleave other work between
/// dispatches (oas-view presents a frame every ~50 ms). With the default tile these are
/// forEachBatch's batches in its order. A smaller tile (setTile, applied from the next pass) splits
/// each pass into more, shorter dispatches over the same samples: every pixel still receives the
/// same passes in the same order, so the accumulation stays bit-identical.
class BatchCursor {
public:
    /// Samples [firstSample, spp) of every pixel.
    BatchCursor(std::uint32_t width, std::uint32_t height, std::uint32_t spp, std::uint32_t perBatch, std::uint32_t seed,
                std::uint32_t tile = kRenderTile, std::uint32_t firstSample = 0);
    /// Tile edge in pixels (1 .. kRenderTile) for the passes that start after this call.
    void setTile(std::uint32_t tile) { nextTile_ = std::clamp<std::uint32_t>(tile, 1, kRenderTile); }
    std::uint32_t tile() const { return tile_; }
    bool done() const { return done_ >= spp_; }
    /// The current batch (valid while !done()).
    const SampleBatch& batch() const { return batch_; }
    /// Moves to the next batch; returns true when that completed a pass over the image.
    bool advance();
    /// Samples per pixel of the completed passes (counted from firstSample).
    std::uint32_t samplesDone() const { return done_; }

private:
    void startPass();
    std::uint32_t width_, height_, spp_, perBatch_, first_, done_ = 0;
    std::uint32_t tile_ = kRenderTile, nextTile_ = kRenderTile;
    SampleBatch batch_;
};

/// The CPU reference: `threads` workers (0: all). Returns the number of samples rejected (NaN,
/// infinite, negative or >= 2^64 radiance): left out of the sums, counted as samples, as on the GPU.
std::uint64_t traceCpu(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern, const SampleBatch& batch,
                       Accumulation& accumulation, unsigned threads = 0);

/// One sample's radiance on the CPU (tests: compare single samples).
glm::vec3 radianceCpu(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern, std::uint32_t px,
                      std::uint32_t py, std::uint32_t seed, std::uint32_t sampleIndex);

/// One next-event estimate (a light sample, MIS-weighted when the plan has MIS) at the surface
/// point x with shading normal n (facing wo) and material `material`, at path vertex `vertex`:
/// what pt_radiance adds there. For tests of the estimator's edge cases.
glm::vec3 nextEventCpu(const SceneData& data, const DimensionPlan& plan, const Pattern& pattern, std::uint32_t seed,
                       std::uint32_t sampleIndex, std::uint32_t vertex, std::uint32_t material, glm::vec3 x, glm::vec3 n,
                       glm::vec3 wo, float time = 0.0f);

/// The BVH walk's box tests on the CPU, for tests: the entry distances of the children
/// nodes[first] and nodes[first + 1] as the CPU tracer's walk computes them (four lanes per box),
/// and as the shared GLSL's scalar pt_box computes them (the GPU kernel's).
glm::vec2 childrenBoxCpu(const SceneData& data, std::uint32_t first, glm::vec3 origin, glm::vec3 inverseDirection, float tMax);
glm::vec2 childrenBoxScalar(const SceneData& data, std::uint32_t first, glm::vec3 origin, glm::vec3 inverseDirection, float tMax);

/// One past the last sample dimension pt_radiance fetches for this plan: its camera group and the
/// groups of vertices 1 .. maxDepth (the last vertex's group may reach past plan.sampleDims: every
/// vertex group is fetched at the same width). Evaluated with the shared GLSL's own functions
/// (pt_sample_dims.glsl) on the CPU, so the GPU's prefetch covers exactly what the kernel reads.
std::uint32_t fetchedDimsEnd(const DimensionPlan& plan, const Pattern& pattern);

/// The dimensions below 32 that no path uses, as bits (d: 1 << d): those in none of the plan's
/// entries (the alignment gaps, what the last vertex's group holds but the path stops before
/// using, the padding to whole texels). pt_radiance may fetch them with its groups but reads no
/// value of theirs, so the generation kernel's baselines leave them unmade
/// (SampleRequest::unreadDims; RenderGpu.PrefetchedBaselinesGiveTheSumsOfTheInlineFetch checks
/// the sums on every shipped scene).
std::uint32_t unusedDims(const DimensionPlan& plan);

/// Dimensions per (pixel, sample) the GPU kernel reads from prefetched samples
/// (pt_constants.glsl's PT_PREFETCH_DIMS): fetchedDimsEnd rounded up to whole uvec4 texels for
/// the OAs, the padded 2D baselines (their pairs' permutation keys), the table-driven Sobol
/// samplers (their direction numbers, OasSobolColumn) and Halton (its digit permutations,
/// OasHaltonColumn), whose state the generation kernel makes once per pass; 0 (each sample's own
/// oas_draw in the kernel) for random and sobol-burley, which have no per-pass state to share.
std::uint32_t prefetchDims(const DimensionPlan& plan, const Pattern& pattern);

/// The most prefetched dimensions per sample where GpuTracerOptions::Prefetch::WherePays decides.
/// The generation kernel makes every dimension of every sample, and a deep plan's paths mostly
/// end (escape, roulette) long before its last vertex, where oas_draw in the tracer makes only
/// what a path reaches. Measured on lavapipe (96 px, 3 rounds, docs/BENCHMARKS.md): prefetching
/// made cornell7d (8 dims) and blue_spheres9d (12) faster, interior_deep (44) 0.95-0.98x as fast.
constexpr std::uint32_t kPrefetchPaysUpToDims = 16;

/// What the GPU kernel does per sample (pt_render.comp's PT_STAGE): the path tracer, or for
/// oas-render-bench --profile's breakdown by elimination, nothing (dispatch and accumulation alone)
/// or the sample fetches alone.
enum class KernelStage : std::uint32_t { PathTrace = 0, Nothing = 1, FetchesOnly = 2 };

/// The wavefront's default queue capacity in paths: a whole tile (kRenderTile^2 pixels) of the
/// largest batch (kMaxSamplesPerBatch), so that oas-render's batches are never split. Two queues
/// of 80-byte records and 16 bytes of radiance a path: 176 MiB at this capacity, allocated only
/// as large as the largest batch traced.
constexpr std::uint64_t kWavefrontMaxPaths = std::uint64_t(kRenderTile) * kRenderTile * kMaxSamplesPerBatch;

/// What the wavefront kernel did since the last clear(): paths started (camera rays), paths
/// ended, and how many paths took each step (stepped[v]: the paths that found vertex v, v >= 1;
/// stepped[0] is unused). Every path started ends once (the tracer throws otherwise).
struct WavefrontStats {
    std::uint64_t started = 0, finished = 0;
    std::vector<std::uint64_t> stepped;
};

/// The megakernel's lanes per vertex since the last clear(), where GpuTracerOptions::countLanes:
/// liveLanes[v] lanes ran the vertex loop at v (v = 0 the camera ray, v >= 1 the step that finds
/// vertex v; the same paths as WavefrontStats::stepped[v]) in subgroupSteps[v] steps of a
/// subgroup of subgroupSize lanes in lock step. liveLanes[v] / (subgroupSteps[v] * subgroupSize)
/// is the share of the lanes that did work there: the rest waited for a longer path of their
/// subgroup, which is what a wavefront's compaction can win back.
struct LaneCounts {
    std::uint32_t subgroupSize = 0;
    std::vector<std::uint64_t> liveLanes, subgroupSteps;
};

/// How the GPU kernel is specialised; renders use the defaults, oas-render-bench varies them.
struct GpuTracerOptions {
    KernelStage stage = KernelStage::PathTrace;
    /// Compile away the code of shape types, materials and lights the scene lacks (same images);
    /// false keeps all of it, the kernel before this specialisation (the benchmark's baseline).
    bool specialiseSceneFeatures = true;
    /// Whether each batch's OA sample values are generated by a kernel of their own first
    /// (oas_generate.comp, which makes a pixel's block and column state once per pass for the
    /// batch's samples) and read by the path tracer, or made with oas_draw inside the path tracer,
    /// every sample its own. The same values either way. WherePays prefetches plans of at most
    /// kPrefetchPaysUpToDims dimensions; baselines without per-pass state always draw inline
    /// (prefetchDims).
    enum class Prefetch { WherePays, Always, Never };
    Prefetch prefetch = Prefetch::WherePays;
    /// Caps the points (pixels x samples) one generation dispatch makes; 0: the device's limits.
    /// A batch with more is traced in strips of rows (tests cover the seams with a small cap).
    std::uint64_t maxPrefetchPoints = 0;
    /// The megakernel (pt_render.comp: one invocation traces a pixel's samples, whole paths) or
    /// the wavefront (pt_wavefront.comp: paths as records in queues, one dispatch per vertex, for
    /// PathTrace only). The same sums, word for word.
    enum class Kernel { Mega, Wavefront };
    Kernel kernel = Kernel::Mega;
    /// The wavefront's queue capacity in paths; 0: kWavefrontMaxPaths. A batch with more is traced
    /// in strips of rows; where one row's paths exceed it, trace() refuses the batch, naming it.
    std::uint64_t maxWavefrontPaths = 0;
    /// The megakernel built with subgroup ballots that count its live lanes per vertex
    /// (laneCounts()): the same sums, slower; a benchmark's probe. Throws std::invalid_argument
    /// with the wavefront, or on a device without subgroup ballots in compute shaders.
    bool countLanes = false;
};

/// "Kernel" names for --kernel and --explain: "mega" and "wavefront".
const char* kernelName(GpuTracerOptions::Kernel kernel);
/// Parses a --kernel value; throws oas::InvalidArgument naming `option`, the value and the valid ones.
GpuTracerOptions::Kernel parseKernel(const std::string& value, const char* option);
/// The GPU kernels a render of this plan and pattern runs, in order, for --explain: the generation
/// kernel where samples are prefetched, then the megakernel or the wavefront's three.
std::string describeKernels(const DimensionPlan& plan, const Pattern& pattern, GpuTracerOptions::Kernel kernel);

/// The kernel's specialization constants for a plan and pattern: each field of the table
/// (shaders/pt/pt_constants.glsl) from its HOST expression, the scene-feature entries from
/// `features`, or left at their defaults (every path kept) when it is null. The GPU tracer passes
/// them to pt_render.comp; the CPU tracer reads the plan's.
pt::PtSpecialization specialization(const DimensionPlan& plan, const Pattern& pattern, KernelStage stage,
                                    const SceneFeatures* features);

class GpuTracer {
public:
    GpuTracer(vk::Context& context, const SceneData& data, const DimensionPlan& plan, const Pattern& pattern,
              const GpuTracerOptions& options = {});
    ~GpuTracer();
    /// Dispatches the batch (the whole rectangle in one dispatch) and waits.
    void trace(const SampleBatch& batch);
    /// The exact sums of every pixel since the last clear().
    Accumulation accumulation() const;
    /// Samples rejected since the last clear() (NaN, infinite, negative or >= 2^64 radiance): left
    /// out of the sums, counted so that a render can report them (our scenes have none).
    std::uint64_t rejectedSamples() const;
    void clear();
    /// Whether `pattern` runs on this tracer's pipeline (the same oas::specializationKey: the
    /// specialization constants); other pattern fields are push constants.
    bool accepts(const Pattern& pattern) const;
    /// Switches to another pattern of the same specialization without recompiling (the study
    /// renders many sample counts per sampler). Throws std::invalid_argument otherwise.
    void setPattern(const Pattern& pattern);
    /// Wall-clock seconds the constructor spent building the compute pipeline (shader compile and
    /// specialization: on lavapipe most of a short render's time).
    double pipelineBuildSeconds() const { return pipelineBuildSeconds_; }
    /// samplesPerBatch for this tracer's scene and plan.
    std::uint32_t samplesPerBatch() const { return samplesPerBatch_; }
    /// The wavefront's counts since the last clear() (all zero with the megakernel).
    WavefrontStats wavefrontStats() const;
    /// The megakernel's live lanes per vertex since the last clear(), where options.countLanes
    /// (empty otherwise).
    LaneCounts laneCounts() const { return laneCounts_; }

private:
    void addLaneWords();  ///< the counting variant's words of the last dispatch into laneCounts_
    vk::Context& context_;
    Pattern pattern_;
    std::uint32_t width_, height_;
    std::unique_ptr<vk::ComputePipeline> pipeline_;
    std::vector<std::unique_ptr<vk::Buffer>> buffers_;
    std::uint32_t prefetchDims_ = 0;           ///< PT_PREFETCH_DIMS
    std::uint32_t unreadDims_ = 0;             ///< dimensions no path uses (unusedDims)
    std::unique_ptr<GpuGenerator> generator_;  ///< the batches' samples, where prefetchDims_ != 0
    std::unique_ptr<GpuWavefront> wavefront_;  ///< the wavefront kernels, where options say so
    double pipelineBuildSeconds_ = 0;
    std::uint32_t samplesPerBatch_ = 1;
    std::unique_ptr<vk::Buffer> laneWords_;  ///< the counting variant's PT_BINDING_OCCUPANCY, where countLanes
    LaneCounts laneCounts_;
};

}  // namespace oas::render
