#pragma once
// The scene part of the study: relative MSE of path-traced images (full image and a crop) against
// a high-spp reference, versus samples per pixel and versus wall-clock time on the Vulkan device
// (lavapipe in CI), for every sampler of the study; equal-time and time-to-target tables; false
// colour error images at equal time; and each sampler's extra share of a frame's time.
// Jarosz et al. 2019 report relative MSE for the same kinds of scenes at 121/128 spp.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "experiment.hpp"
#include "stats.hpp"
#include "vk/context.hpp"
#include "image/metrics.hpp"
#include "oas/pattern.hpp"
#include "render/accumulation.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"

namespace oas::study {

/// A study scene and the crop that holds its effect of interest (fractions of the image).
struct SceneCase {
    std::string file;  ///< under the scenes folder
    double cropX, cropY, cropW, cropH;
    std::string cropWhat;
    bool paperHighCount = false;  ///< also rendered at the paper's 3969/4096 spp (the 7D and 9D scenes)
    /// Rare pixels estimated apart (SceneStudyOptions::rarePixels) unless the run sets another
    /// number: cornell7d 4 (0.1% of its 64 × 64 pixels; its light's corners), the others 0.
    std::uint32_t rarePixels = 0;
};

/// cornell7d, blue_spheres9d and interior_deep, with their crops.
std::vector<SceneCase> studyScenes();

/// The crop of `c` in pixels of a width x height image (at least 1 x 1, inside the image).
oas::image::Crop cropPixels(const SceneCase& c, std::uint32_t width, std::uint32_t height);

struct SceneStudyOptions {
    std::string scenesDir = "scenes";
    std::vector<std::string> scenes;  ///< scene names (file stems); empty: all of studyScenes()
    std::uint32_t width = 64;         ///< render width; the height keeps the scene's aspect
    std::uint32_t minSpp = 16, maxSpp = 1024;
    /// The paper's high count (3969/4096 spp): the 7D and 9D scenes (SceneCase::paperHighCount)
    /// also render every sampler at its valid count nearest this (0: none).
    std::uint32_t paperHighSpp = 0;
    /// Sobol reference, rendered as two independent halves; 0: 16 × the scene's largest count.
    std::uint32_t referenceSpp = 0;
    /// Every sampler the scene part of this mode renders, in whatever shards (empty: the run's
    /// own): the scene's largest count, and so the default reference, is taken over these, so
    /// that a first shard (the Dask driver's Sobol task) picks the reference the whole run would.
    std::vector<SamplerSpec> modeSamplers;
    /// Independent renders (new user seeds) per (sampler, spp): at least minTrials each, then
    /// more from a render-time budget that all of a scene's points share (budgetedMeans: the next
    /// render goes to the point whose relative s.e. it shrinks most per second, among points whose
    /// full-image or crop s.e. is above relSeTarget × mean), at most maxTrials per point.
    /// Estimates still above the target are marked (capped) in the tables.
    std::uint32_t minTrials = 8, maxTrials = 64;
    double relSeTarget = 0.1;
    double extraSecondsPerScene = 0;  ///< the shared budget, render seconds per scene
    std::string outDir = "docs/study";
    std::string command;  ///< how the study was invoked (for the markdown)
    bool quick = false;
    /// How the section names its settings: "quick mode", "full mode", or "reduced settings" when
    /// the command changed the full mode's scene options (the command line is printed too).
    std::string modeLabel = "full mode";
    std::string date, machine;  ///< when and on which CPU the run happened (for the section's table)
    /// A sampler shard (`--scene X --only A B`, for a scene whose full mode does not fit one run):
    /// when the scene's earlier record has the same settings (sameSceneSettings) and its reference
    /// image (outDir/scenes/NAME_reference.exr) is there, the shard reuses that reference, so that
    /// every shard's relMSE is against the same image, replaces only its own samplers' rows and
    /// joins the record (joinShardRecord). Otherwise the scene starts over: a new reference, and the
    /// scene's earlier rows are dropped (a note says why).
    bool samplerShard = false;
    /// Rare pixels: with k > 0 (per scene: SceneCase::rarePixels), the scene's k pixels whose two reference halves disagree most
    /// (relative to the value: rarePixelsOf) are estimated apart, for scenes like cornell7d whose
    /// error is mostly a few pixels that see a light in ~0.1% of their samples. Each point's
    /// full-image relMSE is then the mean over its renders of the relMSE without those pixels, plus
    /// the mean of those pixels' share over many further renders of just those pixels, traced on the
    /// CPU (traceCpu: the same samples, seeds and estimator as the GPU's), in batches of
    /// kRareBatch, while they can still bring the sum's s.e. (curvesOf) below relSeTarget
    /// (moreRareRendersHelp), at most maxRareRenders.
    std::int64_t rarePixels = -1;          ///< -1: each scene's SceneCase::rarePixels
    std::uint32_t maxRareRenders = 16384;  ///< per point
    /// A top-up (`--scene-top-up`): each chosen scene keeps its earlier rows and reference and adds
    /// renders where a point's s.e. is still above the target, with this run's budget and caps (at
    /// least the earlier ones). The earlier renders count as drawn (budgetedMeans' keptDraws), new
    /// renders continue their trial numbers, so their seeds are those a single run with the larger
    /// budget would have used, and the record joins the earlier one (joinShardRecord). The scene
    /// must have an earlier record with the same settings apart from the renders-per-point cap, and
    /// its reference image; otherwise the run stops with an error instead of starting over.
    bool topUp = false;
    /// What one render costs the shared budget: its own measured seconds (false), or its point's
    /// mean seconds in the scene's cost run (outDir/scene_costs.csv; true). Measured seconds vary
    /// from run to run, so which point gets the next extra render does too; the cost run's seconds
    /// are fixed data, so the renders a run makes (and every error figure) depend only on the
    /// settings: a run split over Dask workers (scripts/study_cluster.py) gives the same figures,
    /// byte for byte, as one worker. A point the cost run lacks costs its sampler's seconds per
    /// spp at its nearest timed count × its spp. Needs the scene's cost run only when
    /// extraSecondsPerScene > 0.
    bool costRunCosts = false;
    /// A sampler shard that must join the scene's kept record and reference (a Dask task): when it
    /// cannot, the run stops with an error instead of starting the scene over.
    bool mustJoin = false;
    /// A sampler shard run with the full mode's defaults (no scene option given): it takes the
    /// kept record's reference count and renders-per-point range, so that it can join it. Without
    /// this its reference count would follow the shard's own largest count (16x it, a power of
    /// two): a shard of baselines, whose largest count is 4096, computed 65536 where the record's
    /// reference, set by the Addelman-Kempthorne count 4418, has 131072, and started the scene over.
    bool shardTakesKeptSettings = false;
    /// A sampler shard whose scene's kept reference image is missing renders it again with this
    /// sampler (the record's count and seeds) and joins only if the image's own error estimate
    /// equals the record's to 9 digits, i.e. it is the same image; empty: such a shard cannot join.
    /// For records made before the images were kept, with a sampler whose values have not changed
    /// since (e.g. sobol-owen, the per-bit Owen scramble "sobol" was until 2026-12-06).
    std::string rebuildReferenceWith;
};

/// One scene's run, a row of scene_references.csv: its size, crop and reference, and the settings,
/// device and date it was measured with. The section is assembled from these rows and scenes.csv
/// alone, so scenes measured in separate runs (shards: `--scene X`, other machines, other days)
/// merge into one section, each saying how it was made.
struct SceneRecord {
    std::string name;
    std::uint32_t width = 0, height = 0, dims = 0;
    oas::image::Crop crop;
    std::string referenceSampler = "sobol";
    std::uint32_t referenceSpp = 0, largestSpp = 0;
    double refErr = 0, refErrCrop = 0, refSeconds = 0;
    /// Standard errors of refErr and refErrCrop (referenceErrorSe); NaN for runs that did not
    /// record them, whose curves then take refErr itself as the s.e. (a bound: curvesOfRecords).
    double refErrSe = NAN, refErrCropSe = NAN;
    // How it was measured.
    std::string device, machine, date, command, modeLabel;
    std::uint32_t minSpp = 0, maxSpp = 0, paperHighSpp = 0, minTrials = 0, maxTrials = 0;
    double relSeTarget = 0.1, extraSeconds = 0, runSeconds = 0;  ///< runSeconds: the scene's share of its run
    std::uint32_t rareCount = 0;                                 ///< SceneStudyOptions::rarePixels (0: no rare-pixel split)
    std::string rarePixels;                                      ///< the chosen pixels, "x:y x:y ..." (formatPixels)
};

/// One render's measurement.
struct SceneMeasurement {
    std::string scene, sampler, pattern;
    std::uint32_t spp = 0, trial = 0;
    double seconds = 0;                       ///< wall-clock time of the render's dispatches (pipeline build excluded)
    double relMse = 0, relMseCrop = 0;        ///< against the reference, minus the reference's own error
    double relMseRaw = 0, relMseCropRaw = 0;  ///< uncorrected
    /// The part of relMseRaw that comes from the render's worst pixels (the top 0.1% by their
    /// relative squared error, at least one pixel): relMse − relMseWorst is the rest of the image.
    double relMseWorst = 0;
    /// Rare-pixel split (SceneStudyOptions::rarePixels): the part of relMseRaw from the scene's
    /// rare pixels. A row with rareOnly set is not a render of the image but the mean of
    /// kRareBatch renders of the rare pixels alone (CPU, seconds = the batch's time): only its
    /// relMseRare counts, and curvesOf adds those rows' mean to the other rows' relMse − relMseRare.
    double relMseRare = 0;
    bool rareOnly = false;
};

/// Renders of the rare pixels per rareOnly row.
inline constexpr std::uint32_t kRareBatch = 16;

/// The k pixel indices (y · width + x) with the largest mean over R, G, B of (A − B)² / (R² + eps)
/// between two independent halves A and B of a reference R: the pixels whose estimate varies most
/// relative to their value, largest first.
std::vector<std::uint32_t> rarePixelsOf(const oas::image::Image& a, const oas::image::Image& b,
                                        const oas::image::Image& reference, std::uint32_t k, double relEpsilon = 1e-2);
/// The rare pixels' share of one render's relMSE, (1/P) Σ over `pixels` of the per-pixel error
/// against `reference` (as pixelRelErrors), for the render of `spp` samples of `pattern` with
/// render seed `seed`, traced on the CPU for just those pixels (traceCpu, one thread): the same
/// number a full GPU render with that seed gives, up to float rounding. `scratch` is reused.
double rarePixelsShareCpu(const oas::render::SceneData& data, const oas::render::DimensionPlan& plan, const oas::Pattern& pattern,
                          const std::vector<std::uint32_t>& pixels, std::uint32_t spp, std::uint32_t seed,
                          const oas::image::Image& reference, oas::render::Accumulation& scratch, double relEpsilon = 1e-2);
/// Whether one more batch of rare-pixel renders can still help a point reach relSeTarget: not once
/// the stratified sum rest + rare is there, and not while the image renders' part alone has an s.e.
/// above the target × the sum (only more image renders help then) and the rare part's s.e. is
/// already at most a third of the rest's (adding under 6% to the sum's s.e.). cornell7d's full run
/// of 2026-12-02 spent its rare-pixel stage's cap of 16384 renders on 19 such points.
bool moreRareRendersHelp(const Estimate& rest, const Estimate& rare, double relSeTarget);

/// "x:y x:y ..." of pixel indices in a width-wide image, and back (throws std::invalid_argument
/// naming the bad item and the image size for a malformed list or a pixel outside it).
std::string formatPixels(const std::vector<std::uint32_t>& pixels, std::uint32_t width);
std::vector<std::uint32_t> parsePixels(const std::string& text, std::uint32_t width, std::uint32_t height);

/// Share of the worst pixels: fraction of the image (0.1%), at least one pixel.
inline constexpr double kWorstPixelFraction = 0.001;

/// Per-pixel relative squared error, the mean over R, G, B of (I − R)² / (R² + eps), as
/// oas::image::compare sums it (its mean over pixels is compare's relMse).
std::vector<double> pixelRelErrors(const oas::image::Image& image, const oas::image::Image& reference, double relEpsilon = 1e-2);
/// The standard error of a reference's own relMSE estimate relMSE(A, B) / 4 from the per-pixel
/// terms e_p (pixelRelErrors(A, B) over the pixels it averages): E relMSE(A, B) = (1/P) Σ E e_p,
/// and for Gaussian pixel noise with R, G, B moving together e_p is its mean times a χ²₁ variable,
/// of variance 2 (E e_p)², which (2/3) e_p² estimates without bias (E χ⁴ = 3); less correlated
/// channels have a smaller variance, so this errs large. s.e. = √((2/3) Σ e_p²) / (4 P).
double referenceErrorSe(const std::vector<double>& pixelErrors);

/// The contribution to the image's relMSE (mean over all pixels) of its max(1, ceil(fraction × P))
/// largest per-pixel errors.
double worstPixelsContribution(std::vector<double> pixelErrors, double fraction = kWorstPixelFraction);

/// A sampler's curve on one scene: per spp, the median time and the mean relMSE over trials, with
/// the estimates (mean, s.e., n) behind them.
struct SceneCurve {
    std::string scene, sampler;
    std::vector<double> spp, seconds, relMse, relMseCrop;
    std::vector<Estimate> relMseE, relMseCropE;
    std::vector<Estimate> relMseRestE;       ///< relMSE without each render's worst 0.1% of pixels
    std::vector<Estimate> worstE;            ///< the worst pixels' contribution
    std::vector<std::uint32_t> rareRenders;  ///< renders of the rare pixels alone behind relMseE (0: no split)
};

/// Mean over trials (with s.e.) / median time per (scene, sampler, spp), in ladder order; `capped`
/// marks each estimate whose s.e. is above relSeTarget × mean (the adaptive loop hit its cap).
/// Time, crop, worst pixels and n come from the image renders only. Where a point has rareOnly
/// rows, its full-image estimate is the stratified sum: mean(relMse − relMseRare) over the image
/// renders plus mean(relMseRare) over the rareOnly rows, s.e. = √(s.e.₁² + s.e.₂²) (independent
/// renders); without them, the mean of relMse.
std::vector<SceneCurve> curvesOf(const std::vector<SceneMeasurement>& measurements, double relSeTarget = 0.1);

/// scene_references.csv and scenes.csv: write, and read back (by column name; a file without one of
/// the columns, or with a bad number, throws std::runtime_error naming the file, row and column).
void writeSceneRecords(const std::string& path, const std::vector<SceneRecord>& records);
std::vector<SceneRecord> readSceneRecords(const std::string& path);
void writeSceneMeasurements(const std::string& path, const std::vector<SceneMeasurement>& measurements);
std::vector<SceneMeasurement> readSceneMeasurements(const std::string& path);

/// Shards: `kept` without the rows of the scenes in `fresh`, then `fresh`; the result is in
/// studyScenes() order (other names last, in order of appearance), each scene's rows in their order.
std::vector<SceneRecord> mergeSceneRecords(const std::vector<SceneRecord>& kept, const std::vector<SceneRecord>& fresh);
std::vector<SceneMeasurement> mergeSceneMeasurements(const std::vector<SceneMeasurement>& kept,
                                                     const std::vector<SceneMeasurement>& fresh);

/// Sampler shards. Whether two records of a scene were measured with the same settings (size,
/// crop, dims, reference, spp ladder, renders per point, s.e. target, mode, device): shards of a
/// scene are merged only then. `why` (when not null) gets the first difference.
bool sameSceneSettings(const SceneRecord& a, const SceneRecord& b, std::string* why = nullptr);
/// The scene's record after a shard: `kept`'s reference (spp, error, seconds), the largest count
/// of either, extra and run seconds summed (the scene's total over its shards), and the shards'
/// dates, machines and commands listed (" + " between dates and machines, " ; " between commands),
/// each once.
SceneRecord joinShardRecord(const SceneRecord& kept, const SceneRecord& fresh);
/// Sampler shards: `kept` without the rows of the (scene, sampler) pairs in `fresh`, then `fresh`,
/// in studyScenes() order, each scene's rows in their order.
std::vector<SceneMeasurement> mergeSamplerShard(const std::vector<SceneMeasurement>& kept,
                                                const std::vector<SceneMeasurement>& fresh);

/// One point of a scene's cost run (scene_costs.hpp): the mean seconds of `rounds` renders of (scene, sampler, spp), ± s.e.
struct SceneCost {
    std::string scene, sampler;
    std::uint32_t spp = 0;
    double seconds = 0, se = 0;
    std::uint32_t rounds = 0;
    std::string runId, machine, device, date;
    /// What was timed: the commit (git rev-parse, "-dirty" with uncommitted changes to the render
    /// sources; empty where unknown) and renderSourcesHash() of the build that timed it (empty in
    /// rows from before cost runs were stamped).
    std::string commit, sources;
};

/// The markdown section (STUDY.md's scene part) from the data alone: every table, goal and verdict
/// from `measurements` of the scenes in `records` (other scenes' rows are ignored), for `samplers`;
/// the equal-time, time-to-target and cost tables take their times from `costs` (each scene's one
/// cost run) and say so where a scene has none.
std::string sceneSection(const std::vector<SceneRecord>& records, const std::vector<SceneMeasurement>& measurements,
                         const std::vector<SamplerSpec>& samplers, const std::vector<SceneCost>& costs = {});

/// The section from outDir's scene_references.csv, scenes.csv and (when present) scene_costs.csv
/// (`oas-study --parts none`); empty when outDir has no scene data.
std::string sceneSectionFromFiles(const std::string& outDir, const std::vector<SamplerSpec>& samplers);

/// Merges sampler shards run against one base (scripts/study_cluster.py): `baseDir` holds the
/// scenes' records, reference images and the reference shard's rows; each of `shardDirs` is a
/// copy of it after one `--only S --scene-join` run. The result in outDir is the base's records
/// joined with each shard's own part (joinShardRecord; the base's run and extra seconds, which
/// every shard's record already holds, are counted once), the measurements of every (scene,
/// sampler) from the last dir that has them (mergeSamplerShard, in the given order), the
/// equal-time rows and images likewise, then scene_curves.csv; rows of scenes outside the base are
/// kept from outDir's earlier files. Throws std::runtime_error when a shard's record has other
/// settings or another reference error than the base's (it did not join). Returns the section.
/// `command` (when not empty) replaces the merged records' command lists: the driver's command
/// line, instead of one oas-study command per task.
std::string mergeSceneShards(const std::string& outDir, const std::string& baseDir, const std::vector<std::string>& shardDirs,
                             const std::vector<SamplerSpec>& samplers, const std::string& command = "");

/// Runs the scene study on the Vulkan device for the chosen scenes and merges them into outDir's
/// scenes.csv, scene_references.csv and scene_equal_time.csv (the rows of scenes not run are kept:
/// see mergeSceneRecords), rewrites scene_curves.csv from the merged data, and writes reference
/// and equal-time images under outDir/scenes/. Returns sceneSection() of the merged data.
std::string runSceneStudy(const SceneStudyOptions& options, const std::vector<SamplerSpec>& samplers, oas::vk::Context& context);

}  // namespace oas::study
