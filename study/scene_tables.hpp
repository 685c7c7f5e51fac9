#pragma once
// Internal to the scene section (sceneSection in scene_study.hpp): what its tables share
// (scene_tables.cpp). scene_report.cpp writes the section's method, runs and references and the
// tables at fixed sample counts; scene_time_tables.cpp the tables at equal render time.
#include <limits>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "scene_costs.hpp"
#include "scene_study.hpp"

namespace oas::study::detail {

/// No estimate (mean and s.e. NaN, n = 0): a table shows "—".
inline const Estimate kNoEstimate{std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(), 0, false};

/// What every table of the section reads: the records, the samplers, their curves, and the same
/// curves timed by each scene's cost run.
struct SceneTables {
    /// Times from the cost runs on `device` (scene_costs.hpp: the GPU tracer or the CPU twin).
    SceneTables(const std::vector<SceneRecord>& infos, const std::vector<SceneMeasurement>& measurements,
                const std::vector<SamplerSpec>& samplers, const std::vector<SceneCost>& costs,
                CostDevice device = CostDevice::Gpu);

    const std::vector<SceneRecord>& infos;
    CostDevice device;
    const std::vector<SamplerSpec>& samplers;
    std::vector<SceneCurve> curves;  ///< curvesOfRecords(infos, measurements)
    /// Every time in the equal-time, time-to-target and cost tables comes from the scene's one cost
    /// run (scene_costs.csv; costsOfScene refuses a scene whose rows mix runs): the accuracy
    /// renders' own times pool runs and days, and a machine's speed drifts between them.
    std::vector<SceneCurve> timedCurves;
    std::map<std::string, SceneCost> costRunOf;  ///< per scene: a row of its cost run (run id, machine, date)

    const SceneCurve* curveOf(const std::string& scene, const std::string& sampler) const;
    /// The sampler's curve timed by the scene's cost run; null without one, or without a timed point.
    const SceneCurve* timedCurveOf(const std::string& scene, const std::string& sampler) const;
    /// CMJ2D-pad's estimate at 128 spp on the scene (kNoEstimate without one).
    Estimate cmj2dAt128(const std::string& scene) const;
    /// Random at a count it did not render (e.g. Addelman-Kempthorne's 162): its curve is dense
    /// (powers of two and Bose's counts) and ∝ 1/spp, so log-log interpolation is accurate.
    Estimate randomAt(const SceneCurve* rnd, double spp, int which = 0) const;
};

/// The points of a sampler's timed curve that its error-versus-time curve runs through, in time
/// order: a point is left out where a larger count of the same sampler took no longer, because a
/// renderer with that budget would render the larger count. Bose CMJ at 81 spp (over GF(3²), whose
/// products cost more) took longer on lavapipe than at 121 (GF(11)), and read through, the curve
/// rose from 121 to 81 and gave Bose at a budget between them the error of 81 spp (cost run of
/// 2026-12-07: 1.27x Sobol's at blue_spheres9d's T1, where its 121-spp point is below Sobol's).
/// Chosen by count and time only, never by the measured errors, which would bias them low.
std::vector<size_t> errorTimeCurvePoints(const SceneCurve& c);

/// The count of a ladder nearest (in log) to `target`.
double nearest(const std::vector<double>& counts, double target);

/// The curve's estimate at `spp` (kNoEstimate where it has no such point). which: 0 full image,
/// 1 crop, 2 without the worst pixels, 3 the worst pixels' contribution.
Estimate estAt(const SceneCurve& c, double spp, int which = 0);

/// a ÷ b with its s.e.; for a sampler against itself (same = true) the ratio is exactly 1 and its
/// ± is the number's own relative s.e. (ratioOf assumes independent a and b: √2 too wide).
Estimate ratioTo(const Estimate& a, const Estimate& b, bool same);

/// A verdict cell: "lower"/"higher"/"tie" of a against b, by compare() (2 combined s.e.).
std::string verdictCell(const Estimate& a, const Estimate& b);

/// The tables at equal time (scene_time_tables.cpp): error at equal time, time to a target error,
/// sampler cost inside a frame, and the error images, from the GPU's cost runs (`tables`); error
/// at equal time and sampler cost again from the CPU twin's (`twin`) where it has cost runs.
/// Returns the short answer (which sampler has the lowest error at each budget on each device, and
/// where the devices disagree), which sceneSection puts at the top of the section.
std::string writeTimeTables(const SceneTables& tables, const SceneTables& twin, std::ostream& md);

}  // namespace oas::study::detail
