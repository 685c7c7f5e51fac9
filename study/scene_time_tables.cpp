// The scene section's tables at equal render time, with every time from the scene's one cost run:
// the error at three budgets (and the short answer at the top of the section), the time to reach
// a target error, each sampler's cost inside a frame, and the equal-time error images.
#include "scene_study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <utility>

#include "scene_tables.hpp"
#include "stats.hpp"

namespace oas::study::detail {
namespace {

/// A sampler's error-versus-time curve, times ascending: times need not rise with the count (noise
/// in tiny renders; a count over a costlier field), so it runs through the points no larger count
/// beats on time (errorTimeCurvePoints). Both the equal-time and the time-to-target tables read it.
void errorTimeCurve(const SceneCurve& c, std::vector<double>& ts, std::vector<Estimate>& es)
{
    for (size_t i : errorTimeCurvePoints(c)) ts.push_back(c.seconds[i]), es.push_back(c.relMseE[i]);
}

// Where a scene has no cost run, its time tables say so instead of using pooled times.
std::string noCostRun(const SceneRecord& info)
{
    return "| " + info.name + " | *no cost run: `oas-study --parts scene-costs --scene " + info.name + "` measures one* |";
}

constexpr int kBudgets = 3;
const char* const kBudgetName[kBudgets] = {"T₁", "T₂", "T₃"};
// The comparison the equal-time goal rests on is fixed in advance: BoseCMJ, the OA the chooser
// picks for these scenes (`--sampler oa`: Bose, CMJ offsets), against Sobol. Picking "the best OA"
// as the lowest of 6-7 OA means and then testing it would favour a win.
const char* const kGoalOa = "BoseCMJ";

/// One row of the short answer: the lowest error on a scene at one budget on one device.
struct AnswerRow {
    std::string scene;
    int budget = 0;
    std::string best;      ///< the sampler with the lowest mean relMSE
    std::string tiedWith;  ///< the runner-up where compare() does not separate the two; else empty
    std::string text;      ///< the markdown row
};

/// Error at equal time, at three budgets per scene, timed on tables.device; returns the short
/// answer's rows.
std::vector<AnswerRow> writeEqualTime(const SceneTables& tables, std::ostream& md)
{
    const bool twin = tables.device == CostDevice::CpuTwin;
    const auto& infos = tables.infos;
    const auto& samplers = tables.samplers;
    // --- Equal time and time to target ---------------------------------------------------------
    // Budgets are fixed before looking at any result, from the scene's cost run: T₁ Sobol's time
    // at 128 spp, T₂ the largest budget every sampler's curve reaches (the shortest of the
    // samplers' longest renders), T₃ the same over the samplers that rendered the paper's high
    // count (the 4096-spp budget of the 7D and 9D scenes; samplers without it show —).
    constexpr double kPaperHighCount = 3969;
    const auto& budgetName = kBudgetName;
    const std::string goalOa = kGoalOa;
    int scenesOa[kBudgets][3] = {};  // per budget: goalOa lower / tie / higher than Sobol
    size_t comparisons = 0;
    if (twin)
        md << "### Error at equal time on the CPU twin\n\n"
           << "The same table with every time from the scene's cost run on the CPU twin (the C++ tracer of "
              "`oas-render --device cpu`, on all cores), what a user without a GPU runs; the errors are the same "
              "accuracy renders (the twin runs the same integrator, the shared GLSL compiled as C++, and its images "
              "agree with the GPU's to float rounding, so its error at a sample count is the GPU's). The samplers' relative "
              "costs differ between the devices (the twin makes OA values in vectorized runs; lavapipe loads "
              "storage buffers one lane at a time), so the verdicts may too.\n\n";
    else
        md << "### Error at equal time\n\n"
           << "relMSE read off each sampler's error-versus-time curve (log-log interpolation between measured points, "
          "leaving out a point where a larger count of the sampler took no longer, as a renderer would; — "
          "where the budget lies outside the sampler's measured range) at three budgets per scene: T₁ Sobol's time at "
          "128 spp, T₂ the largest budget every sampler's curve reaches (the shortest of the samplers' longest "
          "renders), T₃ the same over the samplers that rendered the paper's high count (≥ 3969 spp: the 4096-spp "
          "budget of the 7D and 9D scenes). Times come from the scene's one cost run "
          "(every point timed in alternating rounds on one machine: "
          "[`scene_costs.csv`](study/scene_costs.csv)); errors from the accuracy renders. Ratios are to Sobol; "
          "n is the smaller of the two interpolated points' n. Every sampler is a row: with 12 rows × 3 budgets "
          "per scene a table holds 36 comparisons with Sobol, so at 2 s.e. about one \"lower\" or \"higher\" per "
          "scene is expected by chance alone; the goal below rests on one comparison fixed in advance.\n\n"
       << "| scene | sampler | relMSE @ T₁ | ÷ Sobol | vs Sobol | relMSE @ T₂ | ÷ Sobol | vs Sobol | relMSE @ T₃ | ÷ Sobol | vs "
          "Sobol |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::vector<AnswerRow> answer;  // the short answer at the top of the section
    for (const auto& info : infos) {
        const SceneCurve* sob = tables.timedCurveOf(info.name, "Sobol");
        if (!sob) {
            md << noCostRun(info) << "\n";
            continue;
        }
        double budgets[kBudgets] = {NAN, 1e300, NAN};
        for (size_t i = 0; i < sob->spp.size(); ++i)
            if (sob->spp[i] == 128) budgets[0] = sob->seconds[i];
        // T₂: the largest budget every sampler's curve reaches; T₃: the same over the samplers that
        // rendered the paper's high count (>= 3969 spp), so that it sits at the top of the range.
        budgets[2] = 1e300;
        for (const auto& c : tables.timedCurves)
            if (c.scene == info.name && !c.seconds.empty()) {
                const double longest = *std::max_element(c.seconds.begin(), c.seconds.end());
                budgets[1] = std::min(budgets[1], longest);
                if (c.spp.back() >= kPaperHighCount) budgets[2] = std::min(budgets[2], longest);
            }
        if (budgets[2] == 1e300) budgets[2] = NAN;
        md << "| " << info.name << " | *budgets*";
        for (int b = 0; b < kBudgets; ++b)
            md << " | " << budgetName[b] << " = " << (std::isfinite(budgets[b]) ? fmtF(budgets[b] * 1000, 0) + " ms" : "—")
               << " | |";
        md << " |\n";
        Estimate sobAt[kBudgets], goalAt[kBudgets] = {kNoEstimate, kNoEstimate, kNoEstimate};
        std::vector<std::pair<Estimate, std::string>> ranking[kBudgets];
        {
            std::vector<double> ts;
            std::vector<Estimate> es;
            errorTimeCurve(*sob, ts, es);
            for (int b = 0; b < kBudgets; ++b) sobAt[b] = interpEstimate(ts, es, budgets[b], info.relSeTarget);
        }
        for (const auto& s : samplers) {
            const SceneCurve* c = tables.timedCurveOf(info.name, s.label);
            if (!c) continue;
            std::vector<double> ts;
            std::vector<Estimate> es;
            errorTimeCurve(*c, ts, es);
            md << "| " << info.name << " | " << s.label;
            for (int b = 0; b < kBudgets; ++b) {
                const Estimate e = interpEstimate(ts, es, budgets[b], info.relSeTarget);
                md << " | " << fmtEstimate(e) << " | " << fmtRatio(ratioTo(e, sobAt[b], s.label == "Sobol")) << " | "
                   << (s.label == "Sobol" ? "—" : verdictCell(e, sobAt[b]));
                if (std::isfinite(e.mean)) ranking[b].push_back({e, s.label});
                if (s.label != "Sobol" && std::isfinite(e.mean) && std::isfinite(sobAt[b].mean)) ++comparisons;
                if (s.label == goalOa) goalAt[b] = e;
            }
            md << " |\n";
        }
        for (int b = 0; b < kBudgets; ++b)
            if (std::isfinite(goalAt[b].mean) && std::isfinite(sobAt[b].mean)) {
                const Verdict v = compare(goalAt[b], sobAt[b]);
                ++scenesOa[b][v == Verdict::FirstLower ? 0 : v == Verdict::Tie ? 1 : 2];
            }
        const SceneCost& run = tables.costRunOf.at(info.name);
        for (int b = 0; b < kBudgets; ++b) {
            std::stable_sort(ranking[b].begin(), ranking[b].end(),
                             [](const auto& x, const auto& y) { return x.first.mean < y.first.mean; });
            if (ranking[b].empty()) continue;
            Estimate rndAt = kNoEstimate;
            for (const auto& [e, label] : ranking[b])
                if (label == "Random") rndAt = e;
            const auto& [best, bestLabel] = ranking[b].front();
            // A single best is named only where compare() separates it from the runner-up.
            const bool separated = ranking[b].size() < 2 || compare(best, ranking[b][1].first) != Verdict::Tie;
            // The best sampler's count at this budget: the point of its curve nearest the budget (in log).
            double bestSpp = NAN;
            if (const SceneCurve* c = tables.timedCurveOf(info.name, bestLabel)) {
                double gap = 1e300;
                for (size_t i : errorTimeCurvePoints(*c))
                    if (std::abs(std::log(c->seconds[i] / budgets[b])) < gap)
                        gap = std::abs(std::log(c->seconds[i] / budgets[b])), bestSpp = c->spp[i];
            }
            std::ostringstream row;
            row << "| " << info.name << " (" << info.dims << "D) | " << budgetName[b] << " = " << fmtF(budgets[b], 2) << " s"
                << (b == 0   ? " (Sobol's 128 spp)"
                    : b == 2 ? " (≈ 4096 spp)"
                             : "")
                << " | " << bestLabel << " at ≈ " << fmtF(bestSpp, 0) << " spp"
                << (separated ? "" : " (tie with " + ranking[b][1].second + ")") << " | "
                << fmtRatio(ratioTo(best, sobAt[b], bestLabel == "Sobol")) << " | "
                << fmtRatio(ratioTo(best, rndAt, bestLabel == "Random")) << " | "
                << (std::isfinite(goalAt[b].mean) ? fmtRatio(ratioOf(goalAt[b], sobAt[b])) : std::string("—")) << " | "
                << run.device << ", " << run.machine << ", " << run.date << " |\n";
            answer.push_back({info.name, b, bestLabel, separated ? std::string() : ranking[b][1].second, row.str()});
        }
    }
    // Goal: on at least two of three scenes the chooser's OA is at or below Sobol at every budget.
    // "at or below" counts a lower verdict as met and a higher one as missed; ties decide nothing.
    const int need = 2;
    std::string goalTime;
    {
        bool met = true, missed = false;
        for (int b = 0; b < kBudgets; ++b) {
            met = met && scenesOa[b][0] >= need;
            missed = missed || scenesOa[b][0] + scenesOa[b][1] < need;
        }
        goalTime = met ? "met" : missed ? "not met" : "tie (not decided by the error bars)";
        // A scene without a cost run has no verdict: the goal is open until the missing ones are timed.
        if (!met && tables.costRunOf.size() < infos.size())
            goalTime = "open: " + std::to_string(tables.costRunOf.size()) + " of " + std::to_string(infos.size()) +
                       " scenes have a cost run";
    }
    md << "\n**Goal (at equal time" << (twin ? " on the CPU twin" : "") << ", " << goalOa
       << " below Owen-scrambled Sobol on at least two of three scenes at every budget): " << goalTime << "** — " << goalOa << " lower / tie / higher than Sobol:";
    for (int b = 0; b < kBudgets; ++b)
        md << (b ? "; " : " ") << scenesOa[b][0] << " / " << scenesOa[b][1] << " / " << scenesOa[b][2] << " of " << infos.size()
           << " scenes at " << budgetName[b];
    md << ". The table holds " << comparisons << " comparisons with Sobol in all.\n\n";
    return answer;
}

/// The short answer: both devices' rows of each scene and budget next to each other, and one line
/// naming where the two devices' lowest-error samplers differ.
std::string shortAnswer(const SceneTables& tables, const std::vector<AnswerRow>& gpu, const std::vector<AnswerRow>& twin)
{
    const std::string goalOa = kGoalOa;
    std::ostringstream head;
    head << "### The short answer: lowest error for the same render time\n\n"
         << "Per scene and render-time budget (T₁ = Sobol's time at 128 spp, T₂ = the longest every sampler "
            "reached, T₃ = the longest every sampler with a count ≥ 3969 reached, i.e. the 4096-spp budget; seconds "
            "from the scene's one cost run on the device and machine named"
         << (twin.empty() ? "" : ": the GPU tracer (Vulkan) and the CPU twin (`oas-render --device cpu`), each its own run")
         << "): the sampler with the lowest mean relMSE at that time, its error ÷ Owen-scrambled "
            "Sobol's and ÷ Random's (± s.e.; below 1: better), and "
         << goalOa
         << " (the chooser's OA) ÷ Sobol. \"tie with\" where the runner-up is within twice the combined s.e. The "
            "tables below give every sampler, the counts, n, the crops and the costs.\n\n"
            "| scene | budget | lowest error | ÷ Sobol | ÷ Random | "
         << goalOa
         << " ÷ Sobol | timed on |\n"
            "|---|---|---|---|---|---|---|\n";
    // A disagreement the error bars decide (one device separates its best from the runner-up),
    // and one they do not (both devices call the same two samplers a tie, in other orders).
    std::vector<std::string> disagreements, withinErrorBars;
    for (const auto& info : tables.infos)
        for (int b = 0; b < kBudgets; ++b) {
            const AnswerRow *onGpu = nullptr, *onTwin = nullptr;
            for (const auto& r : gpu)
                if (r.scene == info.name && r.budget == b) onGpu = &r;
            for (const auto& r : twin)
                if (r.scene == info.name && r.budget == b) onTwin = &r;
            if (onGpu) head << onGpu->text;
            if (onTwin) head << onTwin->text;
            if (onGpu && onTwin && onGpu->best != onTwin->best) {
                if (onGpu->tiedWith == onTwin->best && onTwin->tiedWith == onGpu->best) {
                    withinErrorBars.push_back(info.name + " at " + kBudgetName[b] + " (" + onGpu->best +
                                              " has the lower mean on the GPU, " + onTwin->best +
                                              " on the CPU twin, a tie on both)");
                    continue;
                }
                auto named = [](const AnswerRow& r) {
                    return r.best + (r.tiedWith.empty() ? "" : " (tie with " + r.tiedWith + ")");
                };
                disagreements.push_back(info.name + " at " + kBudgetName[b] + ": " + named(*onGpu) + " on the GPU, " +
                                        named(*onTwin) + " on the CPU twin");
            }
        }
    head << "\n";
    if (!twin.empty()) {
        if (disagreements.empty())
            head << "The two devices agree wherever the error bars decide: the same sampler has the lowest error on "
                    "every scene at every budget";
        else {
            head << "Where the devices disagree (" << disagreements.size() << " of " << gpu.size() << "): ";
            for (size_t i = 0; i < disagreements.size(); ++i) head << (i ? "; " : "") << disagreements[i];
        }
        if (!withinErrorBars.empty()) {
            head << (disagreements.empty() ? ", except within the error bars at " : "; within the error bars at ");
            for (size_t i = 0; i < withinErrorBars.size(); ++i) head << (i ? "; " : "") << withinErrorBars[i];
        }
        head << ".\n\n";
    }
    return head.str();
}

/// Time to reach a target error.
void writeTimeToTarget(const SceneTables& tables, std::ostream& md)
{
    const auto& infos = tables.infos;
    const auto& samplers = tables.samplers;
    md << "### Time to reach a target error\n\n"
       << "Targets per scene: the relMSE Random reaches at 128 spp, at the ladder count nearest the geometric mean "
          "of 128 and the ladder's largest count, and at that largest count (means; their s.e. enter the times' "
          "s.e.). Times from the scene's cost run, as above. Time read off each curve (first crossing of the means, "
          "log-log interpolation) ± a delta-method s.e.; ≤ marks a sampler already below the target at its "
          "smallest count (a bound, no s.e.), > one that does not reach it within the measured range.\n\n"
       << "| scene | sampler | time to target 1 (ms) | ÷ Random | vs Random | time to target 2 (ms) | ÷ Random | vs Random "
          "| time to target 3 (ms) | ÷ Random | vs Random |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        const SceneCurve* rnd = tables.timedCurveOf(info.name, "Random");
        if (!rnd) {
            md << noCostRun(info) << "\n";
            continue;
        }
        const double middle = nearest(rnd->spp, std::sqrt(128.0 * info.maxSpp));
        const Estimate targets[3] = {estAt(*rnd, 128), estAt(*rnd, middle), estAt(*rnd, info.maxSpp)};
        std::vector<double> rndTs;
        std::vector<Estimate> rndEs;
        errorTimeCurve(*rnd, rndTs, rndEs);
        CrossingEstimate rndTime[3];
        for (int b = 0; b < 3; ++b) rndTime[b] = firstCrossing(rndTs, rndEs, targets[b]);
        md << "| " << info.name << " | *targets*";
        for (int b = 0; b < 3; ++b) md << " | relMSE " << fmtEstimate(targets[b]) << " | |";
        md << " |\n";
        for (const auto& s : samplers) {
            const SceneCurve* c = tables.timedCurveOf(info.name, s.label);
            if (!c) continue;
            std::vector<double> ts;
            std::vector<Estimate> es;
            errorTimeCurve(*c, ts, es);
            md << "| " << info.name << " | " << s.label;
            for (int b = 0; b < 3; ++b) {
                const CrossingEstimate x = firstCrossing(ts, es, targets[b]);
                if (!x.crossing.found) {
                    md << " | > " << fmtF(ts.back() * 1000, 0) << " | — | —";
                    continue;
                }
                Estimate ms = x.x;
                ms.mean *= 1000;
                ms.se *= 1000;
                md << " | "
                   << (x.crossing.atFirst ? "≤ " + fmtF(ms.mean, 0) + " (n=" + std::to_string(ms.n) + ")" : fmtEstimate(ms, 3))
                   << " | " << fmtRatio(ratioTo(x.x, rndTime[b].x, s.label == "Random")) << " | "
                   << (s.label == "Random" || x.crossing.atFirst ? "—" : verdictCell(x.x, rndTime[b].x));
            }
            md << " |\n";
        }
    }
}

/// Sampler cost inside a frame.
void writeSamplerCost(const SceneTables& tables, std::ostream& md)
{
    const auto& infos = tables.infos;
    const auto& samplers = tables.samplers;
    // --- Sampler cost inside a frame -----------------------------------------------------------
    if (tables.device == CostDevice::CpuTwin)
        md << "\n### Sampler cost inside a frame on the CPU twin\n\nThe same from the CPU twin's cost runs.\n\n| sampler |";
    else
        md << "\n### Sampler cost inside a frame\n\n"
           << "Time per sample per pixel from a least-squares line of render time on spp over each sampler's "
              "ladder; the share is the part of the frame time above independent (Random) sampling, "
              "1 − t_Random / t_sampler, i.e. what generating that sampler's numbers costs inside the path "
              "tracer. Times from each scene's cost run on the GPU.\n\n| sampler |";
    for (const auto& info : infos) md << " " << info.name << " Mpaths/s | share |";
    md << "\n|---|";
    for (size_t i = 0; i < infos.size(); ++i) md << "---|---|";
    md << "\n";
    std::map<std::string, double> perSampleRandom;
    for (const auto& info : infos)
        if (const SceneCurve* r = tables.timedCurveOf(info.name, "Random"))
            perSampleRandom[info.name] = fitLine(r->spp, r->seconds).slope;
    for (const auto& s : samplers) {
        md << "| " << s.label;
        for (const auto& info : infos) {
            const SceneCurve* c = tables.timedCurveOf(info.name, s.label);
            if (!c || c->spp.size() < 2) {
                md << " | — | —";
                continue;
            }
            const double perSample = fitLine(c->spp, c->seconds).slope;
            const double mpaths = double(info.width) * info.height / perSample / 1e6;
            md << " | " << fmtF(mpaths, 2) << " | " << fmtF(100 * (1 - perSampleRandom[info.name] / perSample), 0) << "%";
        }
        md << " |\n";
    }
}

/// Error images at equal time (written when each scene was measured).
void writeErrorImages(std::ostream& md)
{
    md << "\n### Error images at equal time\n\n"
       << "Per-pixel relative squared error in false colour (log scale, 1e-5 to 10, dark to bright; the ramp of "
          "`oas-diff`), for each sampler's render whose time is nearest the budget T₁ (its spp and time are in "
          "[`scene_equal_time.csv`](study/scene_equal_time.csv) and in the panel titles).\n\n"
       << "![equal-time error images](study/scene_equal_time.png)\n\n";
}

}  // namespace

std::string writeTimeTables(const SceneTables& tables, const SceneTables& twin, std::ostream& md)
{
    const bool twinTimed = !twin.costRunOf.empty();
    const auto gpuAnswer = writeEqualTime(tables, md);
    const auto twinAnswer = twinTimed ? writeEqualTime(twin, md) : std::vector<AnswerRow>{};
    writeTimeToTarget(tables, md);
    writeSamplerCost(tables, md);
    if (twinTimed) writeSamplerCost(twin, md);
    writeErrorImages(md);
    return shortAnswer(tables, gpuAnswer, twinAnswer);
}

}  // namespace oas::study::detail
