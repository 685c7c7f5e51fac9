// What the scene section's tables share (scene_tables.hpp): the records' curves, the same curves
// timed by each scene's cost run, and the lookups, ratios and verdicts every table uses.
#include "scene_tables.hpp"

#include <algorithm>
#include <cmath>

#include "scene_costs.hpp"
#include "scene_internal.hpp"
#include "stats.hpp"

namespace oas::study {
namespace detail {
namespace {

/// The curve with each point's time from `rows` (its scene's cost run, scene_costs.hpp); points
/// the cost run did not time are dropped.
SceneCurve withCostTimes(const SceneCurve& c, const std::vector<SceneCost>& rows)
{
    SceneCurve t;
    t.scene = c.scene;
    t.sampler = c.sampler;
    for (size_t i = 0; i < c.spp.size(); ++i) {
        const auto row = std::find_if(rows.begin(), rows.end(),
                                      [&](const SceneCost& r) { return r.sampler == c.sampler && double(r.spp) == c.spp[i]; });
        if (row == rows.end()) continue;
        t.spp.push_back(c.spp[i]);
        t.seconds.push_back(row->seconds);
        t.relMse.push_back(c.relMse[i]);
        t.relMseCrop.push_back(c.relMseCrop[i]);
        t.relMseE.push_back(c.relMseE[i]);
        t.relMseCropE.push_back(c.relMseCropE[i]);
        t.relMseRestE.push_back(c.relMseRestE[i]);
        t.worstE.push_back(c.worstE[i]);
        if (i < c.rareRenders.size()) t.rareRenders.push_back(c.rareRenders[i]);
    }
    return t;
}

}  // namespace

SceneTables::SceneTables(const std::vector<SceneRecord>& infos, const std::vector<SceneMeasurement>& measurements,
                         const std::vector<SamplerSpec>& samplers, const std::vector<SceneCost>& costs,
                         CostDevice device)
    : infos(infos), device(device), samplers(samplers), curves(curvesOfRecords(infos, measurements))
{
    for (const auto& info : infos) {
        const auto rows = costsOfScene(costs, info.name, device);
        if (rows.empty()) continue;
        costRunOf[info.name] = rows.front();
        for (const auto& c : curves)
            if (c.scene == info.name) timedCurves.push_back(withCostTimes(c, rows));
    }
}

std::vector<size_t> errorTimeCurvePoints(const SceneCurve& c)
{
    std::vector<size_t> idx(c.spp.size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
    // Fastest first; of equal times, the larger count first, so that it leaves the smaller out.
    std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) {
        return c.seconds[a] != c.seconds[b] ? c.seconds[a] < c.seconds[b] : c.spp[a] > c.spp[b];
    });
    std::vector<size_t> kept;
    for (size_t i : idx)
        if (kept.empty() || c.spp[i] > c.spp[kept.back()]) kept.push_back(i);  // kept counts ascend with time
    return kept;
}

const SceneCurve* SceneTables::curveOf(const std::string& scene, const std::string& sampler) const
{
    for (const auto& c : curves)
        if (c.scene == scene && c.sampler == sampler) return &c;
    return nullptr;
}

const SceneCurve* SceneTables::timedCurveOf(const std::string& scene, const std::string& sampler) const
{
    for (const auto& c : timedCurves)
        if (c.scene == scene && c.sampler == sampler && !c.spp.empty()) return &c;
    return nullptr;
}

Estimate SceneTables::cmj2dAt128(const std::string& scene) const
{
    const SceneCurve* cmj = curveOf(scene, "CMJ2D-pad");
    return cmj ? estAt(*cmj, 128) : kNoEstimate;
}

Estimate SceneTables::randomAt(const SceneCurve* rnd, double spp, int which) const
{
    if (!rnd) return kNoEstimate;
    const Estimate exact = estAt(*rnd, spp, which);
    if (std::isfinite(exact.mean)) return exact;
    double target = 0.1;
    for (const auto& info : infos)
        if (info.name == rnd->scene) target = info.relSeTarget;
    return interpEstimate(rnd->spp, which == 0 ? rnd->relMseE : which == 2 ? rnd->relMseRestE : rnd->relMseCropE, spp, target);
}

double nearest(const std::vector<double>& counts, double target)
{
    double best = 0, bestD = 1e300;
    for (double c : counts) {
        const double d = std::abs(std::log(c / target));
        if (d < bestD) bestD = d, best = c;
    }
    return best;
}

Estimate estAt(const SceneCurve& c, double spp, int which)
{
    for (size_t i = 0; i < c.spp.size(); ++i)
        if (c.spp[i] == spp)
            return which == 0 ? c.relMseE[i] : which == 1 ? c.relMseCropE[i] : which == 2 ? c.relMseRestE[i] : c.worstE[i];
    return kNoEstimate;
}

Estimate ratioTo(const Estimate& a, const Estimate& b, bool same)
{
    if (!same) return ratioOf(a, b);
    Estimate r = a;
    r.mean = std::isfinite(a.mean) && std::isfinite(b.mean) ? 1.0 : a.mean / b.mean;
    r.se = a.relSe();
    return r;
}

std::string verdictCell(const Estimate& a, const Estimate& b)
{
    if (!std::isfinite(a.mean) || !std::isfinite(b.mean)) return std::string("—");
    return verdictWord(compare(a, b));
}

}  // namespace detail
}  // namespace oas::study
