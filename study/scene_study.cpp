#include "scene_study.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "image/image.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "render/tracer.hpp"
#include "scene/scene.hpp"
#include "stats.hpp"
#include "scene_costs.hpp"
#include "tracer_cache.hpp"

namespace oas::study {
namespace {

using Clock = std::chrono::steady_clock;

/// The count of a ladder nearest (in log) to `target`.
double nearest(const std::vector<double>& counts, double target)
{
    double best = 0, bestD = 1e300;
    for (double c : counts) {
        const double d = std::abs(std::log(c / target));
        if (d < bestD) bestD = d, best = c;
    }
    return best;
}

bool isOa(const SamplerSpec& s) { return s.strength > 0; }

std::string sci(double v) { return std::isfinite(v) ? fmtG(v, 3) : "—"; }

/// A reference relMSE with its s.e., or with the bound used where the run did not record one.
std::string referenceCell(double value, double se)
{
    return sci(value) + (std::isfinite(se) ? " ± " + fmtG(se, 2) : " (s.e. ≤ itself)");
}

/// The curve with each point's time from `rows` (its scene's cost run, scene_costs.hpp); points
/// the cost run did not time are dropped.
SceneCurve withCostTimes(const SceneCurve& c, const std::vector<SceneCost>& rows)
{
    SceneCurve t;
    t.scene = c.scene;
    t.sampler = c.sampler;
    for (size_t i = 0; i < c.spp.size(); ++i) {
        const auto row = std::find_if(rows.begin(), rows.end(), [&](const SceneCost& r) {
            return r.sampler == c.sampler && double(r.spp) == c.spp[i];
        });
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

struct Render {
    oas::image::Image image;
    double seconds = 0;
};

Render render(oas::render::GpuTracer& tracer, const oas::render::DimensionPlan& plan, std::uint32_t width,
              std::uint32_t height, std::uint32_t spp, std::uint32_t seed)
{
    tracer.clear();
    const auto start = Clock::now();
    oas::render::forEachBatch(width, height, spp, oas::render::samplesPerBatch(plan), seed,
                              [&](const oas::render::SampleBatch& b) { tracer.trace(b); });
    Render r;
    r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    r.image = tracer.accumulation().image();
    return r;
}

std::string slug(std::string s)
{
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

}  // namespace

std::vector<SceneCase> studyScenes()
{
    return {
        {"cornell7d.json", 0.5, 0.5, 0.5, 0.5, "the moving, defocused sphere and its shadow (lower right quarter)", true, 4},
        {"blue_spheres9d.json", 0.0, 0.3, 0.55, 0.45, "the defocused, moving spheres on the left", true},
        {"interior_deep.json", 0.25, 0.35, 0.5, 0.4, "the table and rug lit indirectly (centre)", false},
    };
}

oas::image::Crop cropPixels(const SceneCase& c, std::uint32_t width, std::uint32_t height)
{
    oas::image::Crop crop;
    crop.x = std::min(width - 1, std::uint32_t(std::floor(c.cropX * width)));
    crop.y = std::min(height - 1, std::uint32_t(std::floor(c.cropY * height)));
    crop.w = std::clamp(std::uint32_t(std::lround(c.cropW * width)), 1u, width - crop.x);
    crop.h = std::clamp(std::uint32_t(std::lround(c.cropH * height)), 1u, height - crop.y);
    return crop;
}

std::vector<double> pixelRelErrors(const oas::image::Image& image, const oas::image::Image& reference, double eps)
{
    if (image.width != reference.width || image.height != reference.height)
        throw std::invalid_argument("pixelRelErrors: images differ in size");
    std::vector<double> e(image.pixelCount());
    for (std::size_t p = 0; p < e.size(); ++p) {
        double sum = 0;
        for (int c = 0; c < 3; ++c) {
            const double i = image.rgba[4 * p + c], r = reference.rgba[4 * p + c];
            sum += (i - r) * (i - r) / (r * r + eps);
        }
        e[p] = sum / 3;
    }
    return e;
}

double referenceErrorSe(const std::vector<double>& pixelErrors)
{
    if (pixelErrors.empty()) return NAN;
    double squares = 0;
    for (double e : pixelErrors) squares += e * e;
    return std::sqrt(2.0 / 3.0 * squares) / (4.0 * double(pixelErrors.size()));
}

double worstPixelsContribution(std::vector<double> e, double fraction)
{
    if (e.empty()) return 0;
    const std::size_t k =
        std::min(e.size(), std::max<std::size_t>(1, std::size_t(std::ceil(fraction * double(e.size())))));
    std::nth_element(e.begin(), e.begin() + (k - 1), e.end(), std::greater<double>());
    double top = 0;
    for (std::size_t i = 0; i < k; ++i) top += e[i];
    return top / double(e.size());
}

std::vector<std::uint32_t> rarePixelsOf(const oas::image::Image& a, const oas::image::Image& b,
                                        const oas::image::Image& reference, std::uint32_t k, double eps)
{
    if (a.width != reference.width || a.height != reference.height || b.width != reference.width ||
        b.height != reference.height)
        throw std::invalid_argument("rarePixelsOf: images differ in size");
    std::vector<double> d(reference.pixelCount());
    for (std::size_t p = 0; p < d.size(); ++p) {
        double sum = 0;
        for (int c = 0; c < 3; ++c) {
            const double x = a.rgba[4 * p + c] - b.rgba[4 * p + c], r = reference.rgba[4 * p + c];
            sum += x * x / (r * r + eps);
        }
        d[p] = sum / 3;
    }
    std::vector<std::uint32_t> order(d.size());
    for (std::uint32_t p = 0; p < order.size(); ++p) order[p] = p;
    const std::size_t n = std::min<std::size_t>(k, order.size());
    // Largest first; ties by pixel index, so that the choice does not depend on the sort.
    std::partial_sort(order.begin(), order.begin() + n, order.end(),
                      [&](std::uint32_t x, std::uint32_t y) { return d[x] > d[y] || (d[x] == d[y] && x < y); });
    order.resize(n);
    return order;
}

std::string formatPixels(const std::vector<std::uint32_t>& pixels, std::uint32_t width)
{
    std::string out;
    for (auto p : pixels)
        out += (out.empty() ? "" : " ") + std::to_string(p % width) + ":" + std::to_string(p / width);
    return out;
}

std::vector<std::uint32_t> parsePixels(const std::string& text, std::uint32_t width, std::uint32_t height)
{
    std::vector<std::uint32_t> out;
    std::istringstream in(text);
    for (std::string item; in >> item;) {
        unsigned long x = 0, y = 0;
        char* end = nullptr;
        const size_t colon = item.find(':');
        bool ok = colon != std::string::npos && colon > 0 && colon + 1 < item.size() &&
                  std::isdigit(static_cast<unsigned char>(item[0])) &&
                  std::isdigit(static_cast<unsigned char>(item[colon + 1]));
        if (ok) {
            x = std::strtoul(item.c_str(), &end, 10);
            ok = end == item.c_str() + colon;
        }
        if (ok) {
            y = std::strtoul(item.c_str() + colon + 1, &end, 10);
            ok = end == item.c_str() + item.size();
        }
        if (!ok || x >= width || y >= height)
            throw std::invalid_argument("rare pixels: \"" + item + "\" is not x:y inside the " + std::to_string(width) +
                                        "x" + std::to_string(height) + " image");
        out.push_back(std::uint32_t(y * width + x));
    }
    return out;
}

double rarePixelsShareCpu(const oas::render::SceneData& data, const oas::render::DimensionPlan& plan,
                          const oas::Pattern& pattern, const std::vector<std::uint32_t>& pixels, std::uint32_t spp,
                          std::uint32_t seed, const oas::image::Image& reference, oas::render::Accumulation& scratch, double eps)
{
    oas::image::checkLayout(reference, "rarePixelsShareCpu: reference");
    scratch = oas::render::Accumulation(reference.width, reference.height);
    double share = 0;
    for (auto pix : pixels) {
        if (pix >= reference.pixelCount()) throw std::invalid_argument("rarePixelsShareCpu: pixel outside the reference");
        oas::render::SampleBatch b;
        b.x0 = pix % reference.width;
        b.y0 = pix / reference.width;
        b.width = b.height = 1;
        b.firstSample = 0;
        b.count = spp;
        b.seed = seed;
        oas::render::traceCpu(data, plan, pattern, b, scratch, 1);
        // As Accumulation::image and pixelRelErrors compute it from a GPU render.
        double e = 0;
        for (int c = 0; c < 3; ++c) {
            const double v = oas::render::meanValue(scratch.pixel(pix), c), r = reference.rgba[4 * pix + c];
            e += (v - r) * (v - r) / (r * r + eps);
        }
        share += e / 3;
    }
    return share / double(reference.pixelCount());
}

bool moreRareRendersHelp(const Estimate& rest, const Estimate& rare, double relSeTarget)
{
    const Estimate sum = sumOf(rest, rare);
    if (sum.se <= relSeTarget * std::abs(sum.mean)) return false;
    const bool restAboveTarget = rest.se > relSeTarget * std::abs(sum.mean);
    return !(restAboveTarget && rare.se <= rest.se / 3);
}

std::vector<SceneCurve> curvesOf(const std::vector<SceneMeasurement>& measurements, double relSeTarget)
{
    std::vector<SceneCurve> curves;
    std::map<std::pair<std::string, std::string>, std::map<std::uint32_t, std::vector<const SceneMeasurement*>>> by;
    std::vector<std::pair<std::string, std::string>> order;
    for (const auto& m : measurements) {
        const auto key = std::make_pair(m.scene, m.sampler);
        if (!by.count(key)) order.push_back(key);
        by[key][m.spp].push_back(&m);
    }
    auto mark = [&](Estimate e) {
        e.capped = !(e.relSe() <= relSeTarget);
        return e;
    };
    for (const auto& key : order) {
        SceneCurve c;
        c.scene = key.first;
        c.sampler = key.second;
        for (const auto& [spp, ms] : by[key]) {
            std::vector<double> t, e, ec, rest, worst, withoutRare, rare;
            for (auto* m : ms) {
                if (m->rareOnly) {
                    rare.push_back(m->relMseRare);
                    continue;
                }
                t.push_back(m->seconds);
                e.push_back(m->relMse);
                ec.push_back(m->relMseCrop);
                rest.push_back(m->relMse - m->relMseWorst);
                worst.push_back(m->relMseWorst);
                withoutRare.push_back(m->relMse - m->relMseRare);
            }
            if (t.empty()) continue;  // rare-pixel rows without their image renders: no point
            Estimate full = estimateOf(e);
            // The stratified sum (independent renders): its n is the image renders'.
            if (!rare.empty()) full = sumOf(estimateOf(withoutRare), estimateOf(rare));
            c.rareRenders.push_back(std::uint32_t(rare.size()) * kRareBatch);
            c.spp.push_back(spp);
            c.seconds.push_back(median(t));
            c.relMseE.push_back(mark(full));
            c.relMseCropE.push_back(mark(estimateOf(ec)));
            c.relMseRestE.push_back(mark(estimateOf(rest)));
            c.worstE.push_back(mark(estimateOf(worst)));
            c.relMse.push_back(c.relMseE.back().mean);
            c.relMseCrop.push_back(c.relMseCropE.back().mean);
        }
        curves.push_back(std::move(c));
    }
    return curves;
}

namespace {

const std::vector<std::string> kEqualTimeColumns = {"scene", "sampler", "spp", "seconds", "budget_seconds", "rel_mse", "image"};

const std::vector<std::string> kMeasurementColumns = {"scene",          "sampler",      "pattern",          "spp",
                                                      "trial",          "seconds",      "rel_mse",          "rel_mse_crop",
                                                      "rel_mse_raw",    "rel_mse_crop_raw", "rel_mse_worst",
                                                      "rel_mse_rare",   "rare_only"};

const std::vector<std::string> kRecordColumns = {
    "scene",     "width",     "height",       "dims",        "reference_sampler", "reference_spp", "ref_rel_mse",
    "ref_rel_mse_crop", "seconds", "crop_x", "crop_y",       "crop_w",      "crop_h",            "largest_spp",
    "device",    "machine",   "date",         "command",     "mode",              "min_spp",       "max_spp",
    "paper_spp", "min_renders", "max_renders", "rel_se_target", "extra_seconds", "run_seconds",
    "rare_count", "rare_pixels", "ref_rel_mse_se", "ref_rel_mse_crop_se"};

/// scene_equal_time.csv's rows (cells in kEqualTimeColumns order); none when the file is absent.
std::vector<std::vector<std::string>> readEqualTimeRows(const std::string& path)
{
    std::vector<std::vector<std::string>> rows;
    if (!std::filesystem::exists(path)) return rows;
    const CsvRows old = readCsv(path);
    for (const auto& row : old.rows) {
        std::vector<std::string> cells;
        for (const auto& name : kEqualTimeColumns) cells.push_back(row[old.column(name, path)]);
        rows.push_back(cells);
    }
    return rows;
}

/// Position of a sampler label in studySamplers() (unknown labels after them).
size_t samplerRank(const std::string& label)
{
    const auto every = studySamplers();
    return size_t(std::find_if(every.begin(), every.end(), [&](const SamplerSpec& e) { return e.label == label; }) -
                  every.begin());
}

/// Whether the file has column `name` (columns added later are optional: older files lack them).
bool hasColumn(const CsvRows& t, const std::string& name)
{
    return std::find(t.header.begin(), t.header.end(), name) != t.header.end();
}

/// Position of a scene in studyScenes() (unknown names after them).
size_t sceneRank(const std::string& name)
{
    const auto cases = studyScenes();
    for (size_t i = 0; i < cases.size(); ++i)
        if (std::filesystem::path(cases[i].file).stem().string() == name) return i;
    return cases.size();
}

/// What the scene's crop shows (studyScenes()); empty for other scenes.
std::string cropWhatOf(const std::string& name)
{
    for (const auto& c : studyScenes())
        if (std::filesystem::path(c.file).stem().string() == name) return c.cropWhat;
    return "";
}

/// `kept` without the rows whose key (keyOf) a row of `fresh` has, then `fresh`, in scene order.
template <class T, class NameOf, class KeyOf>
std::vector<T> mergeByKey(const std::vector<T>& kept, const std::vector<T>& fresh, NameOf nameOf, KeyOf keyOf)
{
    std::vector<T> all;
    for (const auto& k : kept)
        if (std::none_of(fresh.begin(), fresh.end(), [&](const T& f) { return keyOf(f) == keyOf(k); }))
            all.push_back(k);
    all.insert(all.end(), fresh.begin(), fresh.end());
    // Scene order (studyScenes(), then first appearance); rows keep their order within a scene.
    std::vector<std::string> order;
    for (const auto& a : all)
        if (std::find(order.begin(), order.end(), nameOf(a)) == order.end()) order.push_back(nameOf(a));
    std::stable_sort(order.begin(), order.end(),
                     [](const std::string& a, const std::string& b) { return sceneRank(a) < sceneRank(b); });
    std::vector<T> sorted;
    for (const auto& name : order)
        for (const auto& a : all)
            if (nameOf(a) == name) sorted.push_back(a);
    return sorted;
}

template <class T, class NameOf>
std::vector<T> mergeByScene(const std::vector<T>& kept, const std::vector<T>& fresh, NameOf nameOf)
{
    return mergeByKey(kept, fresh, nameOf, nameOf);
}

/// Each record's curves, its points marked capped by its own s.e. target. Every relMSE is the
/// render's error less the reference's own estimated error (refErr), so its s.e. includes the
/// reference's: √(s.e.² + s.e.(refErr)²), with s.e.(refErr) = refErr itself for records that did
/// not measure it (referenceErrorSe came later).
std::vector<SceneCurve> curvesOfRecords(const std::vector<SceneRecord>& records,
                                        const std::vector<SceneMeasurement>& measurements)
{
    std::vector<SceneCurve> curves;
    for (const auto& r : records) {
        std::vector<SceneMeasurement> mine;
        for (const auto& m : measurements)
            if (m.scene == r.name) mine.push_back(m);
        const double refSe = std::isfinite(r.refErrSe) ? r.refErrSe : std::abs(r.refErr);
        const double refSeCrop = std::isfinite(r.refErrCropSe) ? r.refErrCropSe : std::abs(r.refErrCrop);
        for (auto& c : curvesOf(mine, r.relSeTarget)) {
            for (auto& e : c.relMseE) e.se = std::hypot(e.se, refSe);
            for (auto& e : c.relMseCropE) e.se = std::hypot(e.se, refSeCrop);
            curves.push_back(std::move(c));
        }
    }
    return curves;
}

/// Every point with its n and standard errors; "capped" = the s.e. target was not reached (full
/// image or crop) before maxTrials. plot.py draws the error bars from the *_se columns.
void writeCurves(const std::string& path, const std::vector<SceneCurve>& curves)
{
    CsvTable curveCsv({"scene", "sampler", "spp", "seconds", "rel_mse", "rel_mse_crop", "n", "rel_mse_se",
                       "rel_mse_crop_se", "capped", "rel_mse_without_worst", "rel_mse_without_worst_se",
                       "rel_mse_worst", "rel_mse_worst_se", "rare_renders"});
    for (const auto& c : curves)
        for (size_t i = 0; i < c.spp.size(); ++i)
            curveCsv.add({c.scene, c.sampler, fmtG(c.spp[i]), fmtG(c.seconds[i]), fmtG(c.relMse[i]),
                          fmtG(c.relMseCrop[i]), std::to_string(c.relMseE[i].n), fmtG(c.relMseE[i].se),
                          fmtG(c.relMseCropE[i].se), c.relMseE[i].capped || c.relMseCropE[i].capped ? "1" : "0",
                          fmtG(c.relMseRestE[i].mean), fmtG(c.relMseRestE[i].se), fmtG(c.worstE[i].mean),
                          fmtG(c.worstE[i].se), std::to_string(c.rareRenders[i])});
    curveCsv.write(path);
}

}  // namespace

void writeSceneRecords(const std::string& path, const std::vector<SceneRecord>& records)
{
    CsvTable t(kRecordColumns);
    for (const auto& r : records)
        t.add({r.name, std::to_string(r.width), std::to_string(r.height), std::to_string(r.dims), r.referenceSampler,
               std::to_string(r.referenceSpp), fmtG(r.refErr, 9), fmtG(r.refErrCrop, 9), fmtG(r.refSeconds),
               std::to_string(r.crop.x), std::to_string(r.crop.y), std::to_string(r.crop.w), std::to_string(r.crop.h),
               std::to_string(r.largestSpp), r.device, r.machine, r.date, r.command, r.modeLabel,
               std::to_string(r.minSpp), std::to_string(r.maxSpp), std::to_string(r.paperHighSpp),
               std::to_string(r.minTrials), std::to_string(r.maxTrials), fmtG(r.relSeTarget), fmtG(r.extraSeconds),
               fmtG(r.runSeconds), std::to_string(r.rareCount), r.rarePixels, fmtG(r.refErrSe, 9),
               fmtG(r.refErrCropSe, 9)});
    t.write(path);
}

std::vector<SceneRecord> readSceneRecords(const std::string& path)
{
    const CsvRows t = readCsv(path);
    std::vector<SceneRecord> out;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const auto& row = t.rows[i];
        auto text = [&](const char* name) { return row[t.column(name, path)]; };
        auto num = [&](const char* name) { return csvNumber(t, row, name, path, i); };
        auto cnt = [&](const char* name) { return csvCount(t, row, name, path, i); };
        SceneRecord r;
        r.name = text("scene");
        r.width = cnt("width");
        r.height = cnt("height");
        r.dims = cnt("dims");
        r.referenceSampler = text("reference_sampler");
        r.referenceSpp = cnt("reference_spp");
        r.refErr = num("ref_rel_mse");
        r.refErrCrop = num("ref_rel_mse_crop");
        if (hasColumn(t, "ref_rel_mse_se")) {  // added later; "nan" when a run did not measure it
            r.refErrSe = num("ref_rel_mse_se");
            r.refErrCropSe = num("ref_rel_mse_crop_se");
        }
        r.refSeconds = num("seconds");
        r.crop = {cnt("crop_x"), cnt("crop_y"), cnt("crop_w"), cnt("crop_h")};
        r.largestSpp = cnt("largest_spp");
        r.device = text("device");
        r.machine = text("machine");
        r.date = text("date");
        r.command = text("command");
        r.modeLabel = text("mode");
        r.minSpp = cnt("min_spp");
        r.maxSpp = cnt("max_spp");
        r.paperHighSpp = cnt("paper_spp");
        r.minTrials = cnt("min_renders");
        r.maxTrials = cnt("max_renders");
        r.relSeTarget = num("rel_se_target");
        r.extraSeconds = num("extra_seconds");
        r.runSeconds = num("run_seconds");
        if (hasColumn(t, "rare_count")) r.rareCount = cnt("rare_count");
        if (hasColumn(t, "rare_pixels")) r.rarePixels = text("rare_pixels");
        if (r.name.empty() || r.width == 0 || r.height == 0 || r.crop.w == 0 || r.crop.h == 0 ||
            r.crop.x + r.crop.w > r.width || r.crop.y + r.crop.h > r.height || !(r.relSeTarget > 0))
            throw std::runtime_error(path + ": row " + std::to_string(i + 1) +
                                     ": the scene name, size, crop (inside the image) or s.e. target is invalid");
        try {
            parsePixels(r.rarePixels, r.width, r.height);
        } catch (const std::invalid_argument& e) {
            throw std::runtime_error(path + ": row " + std::to_string(i + 1) + ", column \"rare_pixels\": " + e.what());
        }
        if (std::any_of(out.begin(), out.end(), [&](const SceneRecord& o) { return o.name == r.name; }))
            throw std::runtime_error(path + ": scene \"" + r.name + "\" appears twice");
        out.push_back(std::move(r));
    }
    return out;
}

void writeSceneMeasurements(const std::string& path, const std::vector<SceneMeasurement>& measurements)
{
    CsvTable csv(kMeasurementColumns);
    for (const auto& m : measurements)
        csv.add({m.scene, m.sampler, m.pattern, std::to_string(m.spp), std::to_string(m.trial), fmtG(m.seconds),
                 fmtG(m.relMse), fmtG(m.relMseCrop), fmtG(m.relMseRaw), fmtG(m.relMseCropRaw), fmtG(m.relMseWorst),
                 fmtG(m.relMseRare), m.rareOnly ? "1" : "0"});
    csv.write(path);
}

std::vector<SceneMeasurement> readSceneMeasurements(const std::string& path)
{
    const CsvRows t = readCsv(path);
    std::vector<SceneMeasurement> out;
    for (size_t i = 0; i < t.rows.size(); ++i) {
        const auto& row = t.rows[i];
        auto num = [&](const char* name) { return csvNumber(t, row, name, path, i); };
        SceneMeasurement m;
        m.scene = row[t.column("scene", path)];
        m.sampler = row[t.column("sampler", path)];
        m.pattern = row[t.column("pattern", path)];
        m.spp = csvCount(t, row, "spp", path, i);
        m.trial = csvCount(t, row, "trial", path, i);
        m.seconds = num("seconds");
        m.relMse = num("rel_mse");
        m.relMseCrop = num("rel_mse_crop");
        m.relMseRaw = num("rel_mse_raw");
        m.relMseCropRaw = num("rel_mse_crop_raw");
        m.relMseWorst = num("rel_mse_worst");
        if (hasColumn(t, "rel_mse_rare")) m.relMseRare = num("rel_mse_rare");
        if (hasColumn(t, "rare_only")) {
            const std::uint32_t flag = csvCount(t, row, "rare_only", path, i);
            if (flag > 1)
                throw std::runtime_error(path + ": row " + std::to_string(i + 1) + ", column \"rare_only\": " +
                                         std::to_string(flag) + " is not 0 or 1");
            m.rareOnly = flag == 1;
        }
        if (m.spp == 0 || !(m.seconds >= 0))
            throw std::runtime_error(path + ": row " + std::to_string(i + 1) + ": spp must be >= 1 and seconds >= 0");
        out.push_back(std::move(m));
    }
    return out;
}

std::vector<SceneRecord> mergeSceneRecords(const std::vector<SceneRecord>& kept, const std::vector<SceneRecord>& fresh)
{
    return mergeByScene(kept, fresh, [](const SceneRecord& r) { return r.name; });
}

std::vector<SceneMeasurement> mergeSceneMeasurements(const std::vector<SceneMeasurement>& kept,
                                                     const std::vector<SceneMeasurement>& fresh)
{
    return mergeByScene(kept, fresh, [](const SceneMeasurement& m) { return m.scene; });
}

std::vector<SceneMeasurement> mergeSamplerShard(const std::vector<SceneMeasurement>& kept,
                                                const std::vector<SceneMeasurement>& fresh)
{
    return mergeByKey(
        kept, fresh, [](const SceneMeasurement& m) { return m.scene; },
        [](const SceneMeasurement& m) { return std::make_pair(m.scene, m.sampler); });
}

bool sameSceneSettings(const SceneRecord& a, const SceneRecord& b, std::string* why)
{
    auto differs = [&](const char* what, const std::string& x, const std::string& y) {
        if (x == y) return false;
        if (why) *why = std::string(what) + " " + x + " vs " + y;
        return true;
    };
    auto num = [](double v) { return fmtG(v, 9); };
    auto crop = [](const oas::image::Crop& c) {
        return std::to_string(c.w) + "x" + std::to_string(c.h) + "+" + std::to_string(c.x) + "+" + std::to_string(c.y);
    };
    return !(differs("scene", a.name, b.name) ||
             differs("size", std::to_string(a.width) + "x" + std::to_string(a.height),
                     std::to_string(b.width) + "x" + std::to_string(b.height)) ||
             differs("dims", std::to_string(a.dims), std::to_string(b.dims)) || differs("crop", crop(a.crop), crop(b.crop)) ||
             differs("reference", a.referenceSampler + "@" + std::to_string(a.referenceSpp),
                     b.referenceSampler + "@" + std::to_string(b.referenceSpp)) ||
             differs("spp ladder", std::to_string(a.minSpp) + "-" + std::to_string(a.maxSpp) + "/" + std::to_string(a.paperHighSpp),
                     std::to_string(b.minSpp) + "-" + std::to_string(b.maxSpp) + "/" + std::to_string(b.paperHighSpp)) ||
             differs("renders per point", std::to_string(a.minTrials) + "-" + std::to_string(a.maxTrials),
                     std::to_string(b.minTrials) + "-" + std::to_string(b.maxTrials)) ||
             differs("s.e. target", num(a.relSeTarget), num(b.relSeTarget)) || differs("mode", a.modeLabel, b.modeLabel) ||
             differs("rare pixels", std::to_string(a.rareCount), std::to_string(b.rareCount)) ||
             differs("device", a.device, b.device));
}

SceneRecord joinShardRecord(const SceneRecord& kept, const SceneRecord& fresh)
{
    // "a + b", b added only when a does not list it yet.
    auto join = [](const std::string& list, const std::string& item, const std::string& sep) {
        if (list.empty()) return item;
        size_t at = 0;
        while (at <= list.size()) {
            const size_t end = std::min(list.find(sep, at), list.size());
            if (list.compare(at, end - at, item) == 0) return list;
            at = end + sep.size();
        }
        return list + sep + item;
    };
    SceneRecord r = fresh;
    r.referenceSampler = kept.referenceSampler;
    r.referenceSpp = kept.referenceSpp;
    r.refErr = kept.refErr;
    r.refErrCrop = kept.refErrCrop;
    r.refErrSe = kept.refErrSe;
    r.refErrCropSe = kept.refErrCropSe;
    r.refSeconds = kept.refSeconds;
    r.rarePixels = kept.rarePixels;  // chosen with the reference
    r.largestSpp = std::max(kept.largestSpp, fresh.largestSpp);
    r.extraSeconds = kept.extraSeconds + fresh.extraSeconds;
    r.runSeconds = kept.runSeconds + fresh.runSeconds;
    r.date = join(kept.date, fresh.date, " + ");
    r.machine = join(kept.machine, fresh.machine, " + ");
    r.command = join(kept.command, fresh.command, " ; ");
    return r;
}

/// outDir's scene_costs.csv, or none.
static std::vector<SceneCost> costsIn(const std::string& outDir)
{
    const std::string path = outDir + "/scene_costs.csv";
    return std::filesystem::exists(path) ? readSceneCosts(path) : std::vector<SceneCost>{};
}

std::string sceneSectionFromFiles(const std::string& outDir, const std::vector<SamplerSpec>& samplers)
{
    const std::string refPath = outDir + "/scene_references.csv", csvPath = outDir + "/scenes.csv";
    if (!std::filesystem::exists(refPath) || !std::filesystem::exists(csvPath)) return "";
    return sceneSection(readSceneRecords(refPath), readSceneMeasurements(csvPath), samplers, costsIn(outDir));
}

std::string runSceneStudy(const SceneStudyOptions& o, const std::vector<SamplerSpec>& samplers, oas::vk::Context& context)
{
    const auto t0 = Clock::now();
    namespace fs = std::filesystem;
    const std::string imgDir = o.outDir + "/scenes";
    fs::create_directories(imgDir);
    const std::string deviceName = context.deviceName();

    std::vector<SceneCase> cases;
    for (const auto& c : studyScenes()) {
        const std::string stem = fs::path(c.file).stem().string();
        if (o.scenes.empty() || std::find(o.scenes.begin(), o.scenes.end(), stem) != o.scenes.end())
            cases.push_back(c);
    }
    if (cases.empty()) throw std::invalid_argument("--scene: none of the given names is a study scene "
                                                   "(cornell7d, blue_spheres9d, interior_deep)");

    // The scenes measured before (other shards): kept, and merged with this run's at the end.
    const std::string refPath = o.outDir + "/scene_references.csv", csvPath = o.outDir + "/scenes.csv",
                      eqPath = o.outDir + "/scene_equal_time.csv";
    std::vector<SceneRecord> keptRecords;
    std::vector<SceneMeasurement> keptMeasurements;
    std::vector<std::vector<std::string>> keptEq;
    if (fs::exists(refPath) && fs::exists(csvPath)) {
        try {
            keptRecords = readSceneRecords(refPath);
            keptMeasurements = readSceneMeasurements(csvPath);
            keptEq = readEqualTimeRows(eqPath);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "note: the earlier scene data are not merged (%s); the section has only the scenes run now\n",
                         e.what());
            keptRecords.clear();
            keptMeasurements.clear();
            keptEq.clear();
        }
    }
    // A sample's seed uses the sampler's place in studySamplers(), not in this run's list, so that
    // the samplers of different shards never share seeds.
    const auto every = studySamplers();
    auto seedIndex = [&](std::uint32_t k) {
        for (std::uint32_t i = 0; i < every.size(); ++i)
            if (every[i].label == samplers[k].label) return i;
        return std::uint32_t(every.size() + k);
    };

    std::vector<SceneMeasurement> all;
    std::vector<SceneRecord> records;
    std::vector<std::string> joinedScenes;          // sampler shards and top-ups that joined the scene's earlier record
    std::vector<std::vector<std::string>> freshEq;  // scene_equal_time.csv rows of this run
    // Random and Halton also render at Bose's counts (matched spp with the OAs).
    const SamplerSpec bose = studySamplers().front();

    for (std::uint32_t si = 0; si < cases.size(); ++si) {
        const SceneCase& sc = cases[si];
        auto scene = oas::scene::loadScene(o.scenesDir + "/" + sc.file);
        scene.height = std::max(1u, scene.height * o.width / scene.width);
        scene.width = o.width;
        const auto plan = oas::render::planDimensions(scene);
        const auto data = oas::render::flattenScene(scene);
        TracerCache cache(context, data, plan);
        const auto sceneStart = Clock::now();
        SceneRecord info;
        // trial-0 images per (sampler, spp), for the equal-time error pictures
        std::map<std::pair<std::string, std::uint32_t>, oas::image::Image> images;
        oas::image::Image reference;
        info.device = deviceName;
        info.machine = o.machine;
        info.date = o.date;
        info.command = o.command;
        info.modeLabel = o.modeLabel;
        info.minSpp = o.minSpp;
        info.maxSpp = o.maxSpp;
        info.paperHighSpp = sc.paperHighCount && o.paperHighSpp > o.maxSpp ? o.paperHighSpp : 0;
        info.minTrials = o.minTrials;
        info.maxTrials = std::max(o.minTrials, o.maxTrials);
        info.relSeTarget = o.relSeTarget;
        info.extraSeconds = o.extraSecondsPerScene;
        info.rareCount = std::uint32_t(o.rarePixels >= 0 ? o.rarePixels : sc.rarePixels);
        info.name = scene.name;
        info.width = scene.width;
        info.height = scene.height;
        info.dims = plan.usedDims;
        info.crop = cropPixels(sc, scene.width, scene.height);

        // Every (sampler, spp) pattern first, so that all pipelines can be built up front.
        std::vector<std::vector<std::pair<std::uint32_t, oas::Pattern>>> runs(samplers.size());
        std::vector<oas::Pattern> allPatterns;
        for (std::uint32_t k = 0; k < samplers.size(); ++k) {
            const SamplerSpec& s = samplers[k];
            std::vector<std::uint32_t> ladder = countLadder(s, plan.sampleDims, o.minSpp, o.maxSpp);
            // Random and Halton take any count: add the Bose counts, for comparisons at matched spp.
            const bool anyCount = s.sampler == "random" || s.sampler == "halton";
            if (anyCount)
                for (auto c : countLadder(bose, plan.sampleDims, o.minSpp, o.maxSpp)) ladder.push_back(c);
            // The paper's high count: the sampler's valid count nearest paperHighSpp. Halton takes
            // Bose's; Random every sampler's, so that each is compared with Random at its own count
            // (no extrapolation beyond the ladder).
            if (sc.paperHighCount && o.paperHighSpp > o.maxSpp) {
                std::vector<const SamplerSpec*> from{anyCount ? &bose : &s};
                if (s.sampler == "random")
                    for (const auto& other : every) from.push_back(&other);
                for (const SamplerSpec* f : from)
                    if (const std::uint32_t c = nearestCount(
                            f->sampler == "random" || f->sampler == "halton" ? bose : *f, plan.sampleDims, o.paperHighSpp))
                        ladder.push_back(c);
            }
            std::sort(ladder.begin(), ladder.end());
            ladder.erase(std::unique(ladder.begin(), ladder.end()), ladder.end());
            for (std::uint32_t spp : ladder) {
                try {
                    runs[k].push_back({spp, oas::makePattern(patternRequest(s, spp, plan.sampleDims))});
                    allPatterns.push_back(runs[k].back().second);
                } catch (const std::exception& e) {
                    std::fprintf(stderr, "  skip %s at %u spp: %s\n", s.label.c_str(), spp, e.what());
                }
            }
        }
        SamplerSpec sobolSpec{"Sobol", "sobol", "cmj", 0, false, true};
        // The reference has 16x the samples of the scene's largest count (a power of two, so that
        // each half is a Sobol count), unless the caller chose one.
        std::uint32_t largest = 0;
        for (const auto& r : runs)
            for (const auto& [spp, pattern] : r) largest = std::max(largest, spp);
        std::uint32_t referenceSpp = o.referenceSpp;
        if (referenceSpp == 0) {
            referenceSpp = 256;
            while (referenceSpp < 16ull * largest && referenceSpp < (1u << 24)) referenceSpp *= 2;
        }
        info.referenceSpp = referenceSpp;
        info.largestSpp = largest;
        // A sampler shard joins the scene's earlier record (and reuses its reference image) when
        // the settings match; otherwise the scene starts over.
        const std::string refExr = imgDir + "/" + info.name + "_reference.exr";
        const SceneRecord* kept = nullptr;
        for (const auto& r : keptRecords)
            if (r.name == info.name) kept = &r;
        bool joined = false;
        // A shard that cannot join starts the scene over, with a note; a top-up stops instead (it
        // was asked to add to the earlier renders, not to replace them).
        auto cannotJoin = [&](const std::string& why) {
            if (o.topUp)
                throw std::invalid_argument("--scene-top-up: " + info.name + " cannot be topped up: " + why +
                                            "; run it without --scene-top-up");
            if (o.mustJoin)
                throw std::invalid_argument("--scene-join: " + info.name + " cannot join its kept record: " + why);
            std::fprintf(stderr, "note: %s starts over: %s\n", info.name.c_str(), why.c_str());
        };
        if ((o.topUp || o.mustJoin) && !kept) cannotJoin("it has no earlier record in " + refPath);
        if ((o.samplerShard || o.topUp || o.mustJoin) && kept) {
            // A top-up may raise the renders-per-point cap (that is what it is for), not lower it.
            SceneRecord asKept = info;
            if (o.topUp && info.maxTrials >= kept->maxTrials) asKept.maxTrials = kept->maxTrials;
            std::string why;
            if (!sameSceneSettings(*kept, asKept, &why)) {
                cannotJoin("its earlier rows were measured with other settings (" + why + ")");
            } else if (!fs::exists(refExr)) {
                cannotJoin("its earlier reference image " + refExr + " is missing");
            } else {
                reference = oas::image::readExr(refExr);
                joined = reference.width == info.width && reference.height == info.height;
                if (!joined)
                    cannotJoin(refExr + " is " + std::to_string(reference.width) + "x" + std::to_string(reference.height) +
                               ", not " + std::to_string(info.width) + "x" + std::to_string(info.height));
            }
        }
        const oas::Pattern refPattern = oas::makePattern(patternRequest(sobolSpec, referenceSpp / 2, plan.sampleDims));
        if (!joined) allPatterns.push_back(refPattern);
        const auto tp = Clock::now();
        cache.prepare(allPatterns);
        std::fprintf(stderr, "  pipelines built in %.0f s\n", std::chrono::duration<double>(Clock::now() - tp).count());
        if (joined) {
            std::fprintf(stderr, "[scenes] %s %ux%u, %uD: %s, reference %s (Sobol, %u spp) reused\n", info.name.c_str(),
                         scene.width, scene.height, plan.usedDims, o.topUp ? "top-up of the kept renders" : "sampler shard",
                         refExr.c_str(), kept->referenceSpp);
            info.refErr = kept->refErr;
            info.refErrCrop = kept->refErrCrop;
            info.refErrSe = kept->refErrSe;
            info.refErrCropSe = kept->refErrCropSe;
            info.rarePixels = kept->rarePixels;
        } else {
            // Reference: Owen-scrambled Sobol, two independent halves. For independent renders A and
            // B of equal variance, E relMSE(A, B) = 2 var(half) and the average's variance is
            // var(half) / 2, so relMSE(A, B) / 4 estimates the reference's own relative error. It is
            // subtracted from every measurement (E relMSE(I, R) = relMSE(I) + relMSE(R) for independent
            // I, R) and reported, so the reader can see how far below the smallest measurement it is.
            std::fprintf(stderr, "[scenes] %s %ux%u, %uD: reference (Sobol, 2 x %u spp)...\n", info.name.c_str(),
                         scene.width, scene.height, plan.usedDims, referenceSpp / 2);
            auto& refTracer = cache.get(refPattern);
            const Render a = render(refTracer, plan, scene.width, scene.height, referenceSpp / 2, 0xA5A5A5A5u + si);
            const Render b = render(refTracer, plan, scene.width, scene.height, referenceSpp / 2, 0x5A5A5A5Au + si);
            reference = a.image;
            for (std::size_t i = 0; i < reference.rgba.size(); ++i)
                reference.rgba[i] = 0.5f * (a.image.rgba[i] + b.image.rgba[i]);
            info.refErr = oas::image::compare(a.image, b.image).relMse / 4;
            info.refErrCrop = oas::image::compare(a.image, b.image, info.crop).relMse / 4;
            const std::vector<double> halfErrors = pixelRelErrors(a.image, b.image);
            std::vector<double> cropErrors;
            for (std::uint32_t y = info.crop.y; y < info.crop.y + info.crop.h; ++y)
                for (std::uint32_t x = info.crop.x; x < info.crop.x + info.crop.w; ++x)
                    cropErrors.push_back(halfErrors[std::size_t(y) * info.width + x]);
            info.refErrSe = referenceErrorSe(halfErrors);
            info.refErrCropSe = referenceErrorSe(cropErrors);
            info.refSeconds = a.seconds + b.seconds;
            // The rare pixels: where the halves disagree most, relative to the value (independent
            // of every measured render, which all have other seeds).
            if (info.rareCount)
                info.rarePixels = formatPixels(rarePixelsOf(a.image, b.image, reference, info.rareCount), info.width);
            oas::image::writePngPreview(imgDir + "/" + info.name + "_reference.png", reference);
            // Kept for later sampler shards of the scene (exact floats: the same relMSE for each).
            oas::image::writeExr(refExr, reference, {{"oas.scene", info.name}, {"oas.reference_spp", std::to_string(referenceSpp)}});
        }

        // Every (sampler, spp) of the scene is one point of a shared render-time budget
        // (SceneStudyOptions, budgetedMeans): minTrials renders each, then the extra renders go
        // where they shrink a relative s.e. most per second.
        struct Point {
            std::uint32_t sampler, spp;
            const oas::Pattern* pattern;
        };
        std::vector<Point> points;
        for (std::uint32_t k = 0; k < samplers.size(); ++k)
            for (const auto& [spp, pattern] : runs[k]) points.push_back({k, spp, &pattern});
        AdaptiveOptions ao;
        ao.nMin = o.minTrials;
        ao.nMax = std::max(o.minTrials, o.maxTrials);
        ao.relTarget = o.relSeTarget;
        std::uint32_t lastSampler = ~0u;
        const size_t firstOfScene = all.size();
        const std::vector<std::uint32_t> rare = parsePixels(info.rarePixels, info.width, info.height);
        // A top-up's earlier rows per point: image renders by trial, rare-pixel batches by batch.
        std::vector<std::vector<SceneMeasurement>> keptImage(points.size()), keptRare(points.size());
        std::vector<std::uint32_t> keptCounts(points.size(), 0);
        if (o.topUp) {
            std::map<std::pair<std::string, std::uint32_t>, std::size_t> pointOf;  // (label, spp) -> point
            for (std::size_t p = 0; p < points.size(); ++p) pointOf[{samplers[points[p].sampler].label, points[p].spp}] = p;
            for (const auto& m : keptMeasurements) {
                const auto it = m.scene == info.name ? pointOf.find({m.sampler, m.spp}) : pointOf.end();
                if (it != pointOf.end()) (m.rareOnly ? keptRare : keptImage)[it->second].push_back(m);
            }
            for (std::size_t p = 0; p < points.size(); ++p) {
                for (auto* rows : {&keptImage[p], &keptRare[p]}) {
                    std::sort(rows->begin(), rows->end(), [](const auto& a, const auto& b) { return a.trial < b.trial; });
                    const std::uint32_t first = rows == &keptRare[p] ? 65536u : 0u;
                    for (std::uint32_t i = 0; i < rows->size(); ++i)
                        if ((*rows)[i].trial != first + i)
                            throw std::runtime_error(csvPath + ": " + info.name + " " + samplers[points[p].sampler].label +
                                                     "@" + std::to_string(points[p].spp) + ": trials are not " +
                                                     std::to_string(first) + ", " + std::to_string(first + 1) +
                                                     ", ... (a top-up continues them)");
                }
                keptCounts[p] = std::uint32_t(keptImage[p].size());
            }
        }
        // What a render costs the shared budget (SceneStudyOptions::costRunCosts): its measured
        // seconds, or its point's seconds in the scene's cost run, so that the choice of the next
        // render does not depend on this run's timing.
        std::vector<double> costRunCost;
        if (o.costRunCosts && o.extraSecondsPerScene > 0) {
            const auto sceneCosts = costsOfScene(costsIn(o.outDir), info.name);
            if (sceneCosts.empty())
                throw std::invalid_argument("--scene-render-cost cost-run: " + info.name + " has no cost run in " +
                                            o.outDir + "/scene_costs.csv: run --parts scene-costs --scene " +
                                            info.name + " first, or give --scene-extra-seconds 0");
            for (const auto& pt : points) costRunCost.push_back(costRunSeconds(sceneCosts, samplers[pt.sampler].label, pt.spp));
        }
        // What budgetedMeans targets per render: the full image (without the rare pixels where
        // they get their own renders below) and the crop.
        auto drawOf = [&](std::size_t p, const SceneMeasurement& m) {
            return CostedDraw{{rare.empty() ? m.relMse : m.relMse - m.relMseRare, m.relMseCrop},
                              costRunCost.empty() ? m.seconds : costRunCost[p]};
        };
        const auto results = budgetedMeans(
            points.size(),
            [&](std::size_t p, std::uint32_t t) {
                const Point& pt = points[p];
                const SamplerSpec& s = samplers[pt.sampler];
                if (t == keptCounts[p] && pt.sampler != lastSampler) {
                    std::fprintf(stderr, "  %s: %s (%.0f s so far)\n", info.name.c_str(), s.label.c_str(),
                                 std::chrono::duration<double>(Clock::now() - t0).count());
                    lastSampler = pt.sampler;
                }
                if (t < keptCounts[p]) {
                    all.push_back(keptImage[p][t]);
                    return drawOf(p, keptImage[p][t]);
                }
                auto& tracer = cache.get(*pt.pattern);
                const Render r =
                    render(tracer, plan, scene.width, scene.height, pt.spp, mixSeed(si, seedIndex(pt.sampler), pt.spp, t));
                SceneMeasurement m;
                m.scene = info.name;
                m.sampler = s.label;
                m.pattern = oas::describe(*pt.pattern);
                m.spp = pt.spp;
                m.trial = t;
                m.seconds = r.seconds;
                m.relMseRaw = oas::image::compare(r.image, reference).relMse;
                m.relMseCropRaw = oas::image::compare(r.image, reference, info.crop).relMse;
                m.relMse = m.relMseRaw - info.refErr;
                m.relMseCrop = m.relMseCropRaw - info.refErrCrop;
                const std::vector<double> pixelErrors = pixelRelErrors(r.image, reference);
                for (auto pixel : rare) m.relMseRare += pixelErrors[pixel] / double(pixelErrors.size());
                m.relMseWorst = worstPixelsContribution(pixelErrors);
                all.push_back(m);
                if (t == 0) images[{s.label, pt.spp}] = r.image;
                // With the rare-pixel split the renders target the rest of the image; the rare
                // pixels' share gets its own renders below.
                return drawOf(p, m);
            },
            2, ao, o.extraSecondsPerScene, keptCounts);
        if (!rare.empty()) {
            std::fprintf(stderr, "  %s: rare pixels %s on the CPU (%.0f s so far)\n", info.name.c_str(), info.rarePixels.c_str(),
                         std::chrono::duration<double>(Clock::now() - t0).count());
            for (std::size_t p = 0; p < points.size(); ++p) {
                const Point& pt = points[p];
                const SamplerSpec& s = samplers[pt.sampler];
                // Batches of kRareBatch renders of the rare pixels while they can still bring the
                // stratified sum's s.e. (curvesOf) to the target (moreRareRendersHelp), at least 2
                // batches, at most maxRareRenders.
                const Estimate restE = results[p][0].estimate;
                std::vector<double> batches;
                for (const auto& m : keptRare[p]) {
                    all.push_back(m);
                    batches.push_back(m.relMseRare);
                }
                const std::uint32_t maxBatches = std::max(2u, o.maxRareRenders / kRareBatch);
                // The stratified sum so far (as curvesOf forms it): the rest of the image plus the
                // rare pixels' batches.
                auto sum = [&] { return sumOf(restE, estimateOf(batches)); };
                auto converged = [&](const Estimate& e) { return e.se <= o.relSeTarget * std::abs(e.mean); };
                while (batches.size() < maxBatches) {
                    if (batches.size() >= 2 && !moreRareRendersHelp(restE, estimateOf(batches), o.relSeTarget)) break;
                    const std::uint32_t batch = std::uint32_t(batches.size());
                    const auto start = Clock::now();
                    std::vector<double> shares(kRareBatch, 0.0);
                    std::atomic<std::uint32_t> next{0};
                    std::vector<std::thread> pool;
                    for (unsigned w = 0; w < std::max(1u, std::thread::hardware_concurrency()); ++w)
                        pool.emplace_back([&] {
                            oas::render::Accumulation scratch;
                            for (std::uint32_t j; (j = next++) < kRareBatch;) {
                                // Render seeds beyond any image render's trial (< 2^16), one per render.
                                const std::uint32_t seed =
                                    mixSeed(si, seedIndex(pt.sampler), pt.spp, 65536u + batch * kRareBatch + j);
                                shares[j] = rarePixelsShareCpu(data, plan, *pt.pattern, rare, pt.spp, seed, reference, scratch);
                            }
                        });
                    for (auto& th : pool) th.join();
                    SceneMeasurement m;
                    m.scene = info.name;
                    m.sampler = s.label;
                    m.pattern = oas::describe(*pt.pattern);
                    m.spp = pt.spp;
                    m.trial = 65536u + batch;
                    m.seconds = std::chrono::duration<double>(Clock::now() - start).count();
                    m.rareOnly = true;
                    for (double v : shares) m.relMseRare += v / kRareBatch;
                    all.push_back(m);
                    batches.push_back(m.relMseRare);
                }
                // One line per point: this stage runs for minutes in full mode and was silent.
                const Estimate e = sum();
                const bool restAbove = restE.se > o.relSeTarget * std::abs(e.mean);
                std::fprintf(stderr, "    %s@%u: %zu rare renders, relMSE %.3g +- %.2g (%.0f%%%s, %.0f s so far)\n",
                             s.label.c_str(), pt.spp, batches.size() * kRareBatch, e.mean, e.se, 100.0 * e.relSe(),
                             converged(e) ? "" : restAbove ? ", cap: the image renders' part" : ", cap",
                             std::chrono::duration<double>(Clock::now() - t0).count());
            }
        }
        std::fprintf(stderr, "  %s done (%.0f s so far)\n", info.name.c_str(),
                     std::chrono::duration<double>(Clock::now() - t0).count());
        info.runSeconds = std::chrono::duration<double>(Clock::now() - sceneStart).count();

        // Equal-time error images: for each sampler, the trial-0 render whose time is nearest (in
        // log) to the budget T1, the time Sobol took at 128 spp (as in the section's equal-time table;
        // in a sampler shard without Sobol, from the scene's earlier shards).
        const std::vector<SceneMeasurement> mine(all.begin() + firstOfScene, all.end());
        const auto curves = curvesOf(mine, o.relSeTarget);
        std::vector<SceneMeasurement> sceneSoFar;
        for (const auto& m : joined ? mergeSamplerShard(keptMeasurements, mine) : mine)
            if (m.scene == info.name) sceneSoFar.push_back(m);
        double budget = NAN;
        for (const auto& c : curvesOf(sceneSoFar, o.relSeTarget))
            if (c.sampler == "Sobol")
                for (size_t i = 0; i < c.spp.size(); ++i)
                    if (c.spp[i] == 128) budget = c.seconds[i];
        for (const auto& c : curves) {
            if (!std::isfinite(budget) || c.spp.empty()) break;
            size_t best = 0;
            for (size_t i = 1; i < c.spp.size(); ++i)
                if (std::abs(std::log(c.seconds[i] / budget)) < std::abs(std::log(c.seconds[best] / budget))) best = i;
            const std::uint32_t spp = std::uint32_t(c.spp[best]);
            const auto it = images.find({c.sampler, spp});
            if (it == images.end()) continue;
            const std::string file = info.name + "_" + slug(c.sampler) + "_error.png";
            oas::image::writePngPreview(imgDir + "/" + file, oas::image::falseColourError(it->second, reference));
            oas::image::writePngPreview(imgDir + "/" + info.name + "_" + slug(c.sampler) + ".png", it->second);
            freshEq.push_back({info.name, c.sampler, std::to_string(spp), fmtG(c.seconds[best]), fmtG(budget),
                    fmtG(oas::image::compare(it->second, reference).relMse - info.refErr), file});
        }
        if (joined) {
            info = joinShardRecord(*kept, info);
            joinedScenes.push_back(info.name);
        }
        records.push_back(std::move(info));
    }

    // Merge with the scenes measured before (other shards), write the data, and build the section
    // from what was written: a section assembled later from the files alone is the same. A scene run
    // now replaces its earlier rows, except that a sampler shard which joined the scene's record
    // replaces only its own samplers' rows.
    const auto mergedRecords = mergeSceneRecords(keptRecords, records);
    auto isMerged = [&](const std::string& scene) {
        return std::any_of(mergedRecords.begin(), mergedRecords.end(), [&](const SceneRecord& r) { return r.name == scene; });
    };
    auto isFresh = [&](const std::string& scene) {
        return std::any_of(records.begin(), records.end(), [&](const SceneRecord& r) { return r.name == scene; });
    };
    auto isJoined = [&](const std::string& scene) {
        return std::find(joinedScenes.begin(), joinedScenes.end(), scene) != joinedScenes.end();
    };
    auto isFreshSampler = [&](const std::string& scene, const std::string& sampler) {
        return std::any_of(all.begin(), all.end(), [&](const SceneMeasurement& m) { return m.scene == scene && m.sampler == sampler; });
    };
    std::vector<SceneMeasurement> keptNow;  // without the rows of the scenes that start over
    for (const auto& m : keptMeasurements)
        if (!isFresh(m.scene) || isJoined(m.scene)) keptNow.push_back(m);
    std::vector<SceneMeasurement> mergedMeasurements;
    for (auto& m : mergeSamplerShard(keptNow, all))
        if (isMerged(m.scene)) mergedMeasurements.push_back(std::move(m));  // no rows without a record
    std::vector<std::vector<std::string>> eqRows;
    // A top-up renders no new trial-0 images, so its scenes keep their equal-time pictures.
    for (const auto& row : keptEq)
        if (isMerged(row[0]) &&
            (!isFresh(row[0]) || (isJoined(row[0]) && (o.topUp || !isFreshSampler(row[0], row[1])))))
            eqRows.push_back(row);
    eqRows.insert(eqRows.end(), freshEq.begin(), freshEq.end());
    // Scene order, then table order (a joined shard's rows would otherwise come last).
    std::stable_sort(eqRows.begin(), eqRows.end(), [&](const auto& a, const auto& b) {
        return std::make_pair(sceneRank(a[0]), samplerRank(a[1])) < std::make_pair(sceneRank(b[0]), samplerRank(b[1]));
    });
    CsvTable mergedEq(kEqualTimeColumns);
    for (const auto& row : eqRows) mergedEq.add(row);
    writeSceneMeasurements(csvPath, mergedMeasurements);
    writeSceneRecords(refPath, mergedRecords);
    mergedEq.write(eqPath);
    const auto writtenRecords = readSceneRecords(refPath);
    const auto writtenMeasurements = readSceneMeasurements(csvPath);
    writeCurves(o.outDir + "/scene_curves.csv", curvesOfRecords(writtenRecords, writtenMeasurements));
    return sceneSection(writtenRecords, writtenMeasurements, samplers, costsIn(o.outDir));
}

std::string sceneSection(const std::vector<SceneRecord>& infos, const std::vector<SceneMeasurement>& measurements,
                         const std::vector<SamplerSpec>& samplers, const std::vector<SceneCost>& costs)
{
    const auto curves = curvesOfRecords(infos, measurements);
    // Every time in the equal-time, time-to-target and cost tables comes from the scene's one cost
    // run (scene_costs.csv; costsOfScene refuses a scene whose rows mix runs): the accuracy
    // renders' own times pool runs and days, and a machine's speed drifts between them.
    std::vector<SceneCurve> timedCurves;
    std::map<std::string, SceneCost> costRunOf;  // per scene: a row of its cost run (run id, machine, date)
    for (const auto& info : infos) {
        const auto rows = costsOfScene(costs, info.name);
        if (rows.empty()) continue;
        costRunOf[info.name] = rows.front();
        for (const auto& c : curves)
            if (c.scene == info.name) timedCurves.push_back(withCostTimes(c, rows));
    }
    auto timedCurveOf = [&](const std::string& scene, const std::string& sampler) -> const SceneCurve* {
        for (const auto& c : timedCurves)
            if (c.scene == scene && c.sampler == sampler && !c.spp.empty()) return &c;
        return nullptr;
    };
    // "cornell7d 122880 spp = 30× its largest count, ..." from the records (the reference count is
    // a setting of each run).
    auto referenceRatios = [&] {
        std::string out;
        for (const auto& info : infos) {
            if (!out.empty()) out += "; ";
            out += info.name + " " + std::to_string(info.referenceSpp) + " spp = " +
                   fmtF(double(info.referenceSpp) / std::max(1u, info.largestSpp), 1) + "× its largest count";
        }
        return out;
    };
    // Where a scene has no cost run, its time tables say so instead of using pooled times.
    auto noCostRun = [&](const SceneRecord& info) {
        return "| " + info.name + " | *no cost run: `oas-study --parts scene-costs --scene " + info.name +
               "` measures one* |";
    };
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const Estimate none{nan, nan, 0, false};
    auto curveOf = [&](const std::string& scene, const std::string& sampler) -> const SceneCurve* {
        for (const auto& c : curves)
            if (c.scene == scene && c.sampler == sampler) return &c;
        return nullptr;
    };
    // which: 0 full image, 1 crop, 2 without the worst pixels, 3 the worst pixels' contribution.
    auto estAt = [&](const SceneCurve& c, double spp, int which = 0) {
        for (size_t i = 0; i < c.spp.size(); ++i)
            if (c.spp[i] == spp)
                return which == 0 ? c.relMseE[i] : which == 1 ? c.relMseCropE[i] : which == 2 ? c.relMseRestE[i] : c.worstE[i];
        return none;
    };
    // Random at a count it did not render (e.g. Addelman-Kempthorne's 162): its curve is dense
    // (powers of two and Bose's counts) and ∝ 1/spp, so log-log interpolation is accurate.
    auto cmj2dAt128 = [&](const std::string& scene) {
        const SceneCurve* cmj = curveOf(scene, "CMJ2D-pad");
        return cmj ? estAt(*cmj, 128) : none;
    };
    auto randomAt = [&](const SceneCurve* rnd, double spp, int which = 0) {
        if (!rnd) return none;
        const Estimate exact = estAt(*rnd, spp, which);
        if (std::isfinite(exact.mean)) return exact;
        double target = 0.1;
        for (const auto& info : infos)
            if (info.name == rnd->scene) target = info.relSeTarget;
        return interpEstimate(rnd->spp, which == 0 ? rnd->relMseE : which == 2 ? rnd->relMseRestE : rnd->relMseCropE, spp,
                              target);
    };
    // a ÷ b with its s.e.; for a sampler against itself (same = true) the ratio is exactly 1 and its
    // ± is the number's own relative s.e. (ratioOf assumes independent a and b: √2 too wide).
    auto ratioTo = [](const Estimate& a, const Estimate& b, bool same) {
        if (!same) return ratioOf(a, b);
        Estimate r = a;
        r.mean = std::isfinite(a.mean) && std::isfinite(b.mean) ? 1.0 : a.mean / b.mean;
        r.se = a.relSe();
        return r;
    };
    // A verdict cell: "lower"/"higher"/"tie" of a against b, by compare() (2 combined s.e.).
    auto verdictCell = [](const Estimate& a, const Estimate& b) {
        if (!std::isfinite(a.mean) || !std::isfinite(b.mean)) return std::string("—");
        return verdictWord(compare(a, b));
    };
    // Per scene, its capped points and what finishing them would cost. The s.e. falls as 1/√n, so
    // a point at relative s.e. r after n renders needs about n·(r/target)² renders in all; with
    // heavy tails (fireflies) the sample s.e. tends to be low, so this is a lower estimate. In a
    // scene with the rare-pixel split the rare stage stops once the image renders' part is the larger
    // s.e. (moreRareRendersHelp), so there too it is image renders that a capped point lacks.
    std::uint32_t cappedPoints = 0, points = 0;
    std::ostringstream capCost;
    const char* sep = " (per scene: ";
    for (const auto& info : infos) {
        std::uint32_t capped = 0, total = 0;
        double seconds = 0;
        for (const auto& c : curves) {
            if (c.scene != info.name) continue;
            for (size_t i = 0; i < c.spp.size(); ++i) {
                ++total;
                if (!c.relMseE[i].capped && !c.relMseCropE[i].capped) continue;
                ++capped;
                const double r = std::max(c.relMseCropE[i].relSe(), c.relMseE[i].relSe());
                if (std::isfinite(r) && r > info.relSeTarget)
                    seconds += c.relMseE[i].n * ((r / info.relSeTarget) * (r / info.relSeTarget) - 1) * c.seconds[i];
            }
        }
        if (!total) continue;
        cappedPoints += capped;
        points += total;
        capCost << sep << info.name << " " << capped << " of " << total;
        sep = "; ";
        if (capped && seconds > 0)
            capCost << ", about " << (seconds < 3600 ? fmtF(std::max(1.0, seconds / 60), 0) + " min" : fmtF(seconds / 3600, 1) + " h")
                    << " more of renders on its device to finish them";
    }
    if (sep[0] == ';') capCost << "; s.e. ∝ 1/√n, a lower estimate where fireflies make the tails heavy)";

    std::ostringstream md;
    // How the scenes were run: one row per scene (shards may differ in settings, device and date).
    // A scene measured in sampler shards that are not all in yet lacks some samplers' curves.
    auto missingSamplers = [&](const std::string& scene) {
        std::vector<std::string> missing;
        for (const auto& s : samplers)
            if (!curveOf(scene, s.label)) missing.push_back(s.label);
        if (missing.size() == samplers.size()) missing.clear();  // a section about other samplers
        return missing;
    };
    bool allFull = !infos.empty();
    std::set<std::string> devices;
    for (const auto& info : infos) {
        allFull = allFull && info.modeLabel == "full mode" && missingSamplers(info.name).empty();
        devices.insert(info.device);
    }
    const bool allLavapipe = std::all_of(devices.begin(), devices.end(), [](const std::string& d) {
        return d.find("llvmpipe") != std::string::npos;
    });
    md << "## Scenes: relative MSE versus samples and versus time\n\n"
       << "- Runs: each scene's device, machine, date, command and settings are in the table below. Scenes can be "
          "measured in separate runs (`oas-study --parts scenes --scene NAME` replaces only that scene's rows in "
          "the data files and reassembles this section from them), so they may differ.\n"
       << "- Mode: " << (allFull ? "full mode for every scene" : "**not every scene is from the full mode with every sampler** (table)")
       << "; time is wall-clock time on the scene's device"
       << (allLavapipe ? " (lavapipe, the CI machine's Vulkan, for every scene)" : " (not the same device for every scene: compare times within a scene only)")
       << ".\n"
       << "- Error bars: every relMSE is the mean over n independent renders (each its own seed) ± its standard "
          "error s.e. = sd/√n (sd with n − 1). n is chosen per point: at least the scene's minimum number of "
          "renders; then the scene's budget of extra render seconds is shared by its points, each further render "
          "going to the point whose relative s.e. it shrinks most per second (relative s.e. ÷ (n × seconds per "
          "render)) among the points whose full-image or crop s.e. is above the target fraction of the mean, up to "
          "the scene's maximum renders per point. Numbers still above the target are marked \"cap\" with the s.e. "
          "reached. "
       << cappedPoints << " of " << points << " points hit the cap" << capCost.str()
       << ". Stopping on the s.e. biases it slightly low (the minimum n limits this). "
          "Ratios carry a first-order (delta-method) s.e. for independent numbers (a sampler's ratio to "
          "itself is 1 ± its own relative s.e.), values read off curves (equal time, time to target) "
          "the s.e. of the interpolated log error (timing noise not included); a value read between two points "
          "is marked \"cap\" where one of them is and its own s.e. is still above the target, a time to target "
          "wherever one of them is (its s.e. divides by the curve's local slope, which a capped point makes "
          "unsure).\n"
       << "- Verdicts (\"lower\", \"higher\", goals, rankings) are stated only where two numbers differ by more "
          "than twice their combined s.e., 2·√(s.e.₁² + s.e.₂²); otherwise the table says **tie**.\n"
       << "- relMSE = mean over pixels and R, G, B of (I − R)² / (R² + 0.01) (Rousselle et al.; the paper's metric), "
          "for the full image and for a crop; the reference (Owen-scrambled Sobol as two independent halves, at "
       << referenceRatios()
       << ") has its own relMSE, estimated from its two halves, subtracted (table below), and its standard error "
          "added to every point's: s.e. = √(s.e.(renders)² + s.e.(reference)²).\n"
       << "- Time: wall-clock of a render's dispatches, pipeline build excluded, from the scene's cost run: every "
          "(sampler, spp) point rendered once per round, all points in the same order in each round, at least 3 "
          "rounds, in one run on one machine (mean ± s.e. over rounds in [`scene_costs.csv`](study/scene_costs.csv), "
          "whose rows name the run, machine, device and date). The accuracy renders' own times are not used: they "
          "pool runs and days, and the same machine's speed drifts between them.\n"
       << "- Data: [`scenes.csv`](study/scenes.csv) (every render), [`scene_curves.csv`](study/scene_curves.csv) "
          "(per point: mean, s.e., n, capped), [`scene_references.csv`](study/scene_references.csv) (per scene: "
          "reference, settings, device); figures "
          "`study/scene_error_vs_spp.png`, `study/scene_error_vs_time.png` (± 1 s.e. bars), "
          "`study/scene_equal_time.png`.\n\n";

    md << "| scene | device | machine, date | command (mode) | image | spp | renders per point | extra render s | s.e. target | scene run time |\n"
          "|---|---|---|---|---|---|---|---|---|---|\n";
    // A joined sampler shard's record lists its commands with " ; " between them.
    auto commandsCell = [](const std::string& commands) {
        std::string out;
        for (size_t at = 0; at <= commands.size();) {
            const size_t end = std::min(commands.find(" ; ", at), commands.size());
            out += (out.empty() ? "`build/" : " then `build/") + commands.substr(at, end - at) + "`";
            at = end + 3;
        }
        return out;
    };
    for (const auto& info : infos)
        md << "| " << info.name << " | " << info.device << " | " << info.machine << ", " << info.date << " | "
           << commandsCell(info.command) << " (" << info.modeLabel << ") | " << info.width << " px wide | " << info.minSpp << "–"
           << info.maxSpp << (info.paperHighSpp ? " and the count nearest " + std::to_string(info.paperHighSpp) : std::string())
           << " | " << info.minTrials << " to " << info.maxTrials << " | " << fmtG(info.extraSeconds) << " | "
           << fmtF(100 * info.relSeTarget, 0) << "% | " << fmtF(info.runSeconds, 0) << " s |\n";
    md << "\n";
    // The rare-pixel split, where a scene used it (SceneStudyOptions::rarePixels).
    for (const auto& info : infos) {
        if (!info.rareCount) continue;
        std::uint32_t lo = ~0u, hi = 0;
        for (const auto& c : curves)
            if (c.scene == info.name)
                for (auto m : c.rareRenders) lo = std::min(lo, m), hi = std::max(hi, m);
        md << "**" << info.name << ": rare-pixel split.** Its " << info.rareCount << " pixels whose two reference halves "
           << "differ most relative to their value (" << info.rarePixels << ") are estimated apart: each full-image "
           << "relMSE is the mean over the n image renders of the relMSE without those pixels, plus the mean of those "
           << "pixels' share over " << (hi ? std::to_string(lo) + "–" + std::to_string(hi) : std::string("no"))
           << " further renders of just those pixels per point (the same samples and estimator, traced on the CPU, "
           << "their own seeds), s.e. = √(s.e.₁² + s.e.₂²); n in the tables counts the image renders. "
           << "The crop, worst-pixel and time figures are from the image renders alone.\n\n";
    }
    // A scene measured in sampler shards that are not all in yet says which samplers it lacks.
    for (const auto& info : infos) {
        const auto missing = missingSamplers(info.name);
        if (missing.empty()) continue;
        md << "**" << info.name << " has " << samplers.size() - missing.size() << " of the " << samplers.size()
           << " samplers so far** (sampler shards); not yet measured, so absent from its tables: ";
        for (size_t i = 0; i < missing.size(); ++i) md << (i ? ", " : "") << missing[i];
        md << ".\n\n";
    }

    md << "| scene | size | integrand dims | crop | reference spp | reference relMSE (full / crop) | smallest measured relMSE (full / crop) |\n"
          "|---|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        double minFull = 1e300, minCrop = 1e300;
        for (const auto& c : curves)
            if (c.scene == info.name)
                for (size_t i = 0; i < c.spp.size(); ++i)
                    minFull = std::min(minFull, c.relMse[i]), minCrop = std::min(minCrop, c.relMseCrop[i]);
        md << "| " << info.name << " | " << info.width << "×" << info.height << " | " << info.dims << " | "
           << info.crop.w << "×" << info.crop.h << " at (" << info.crop.x << ", " << info.crop.y << "): " << cropWhatOf(info.name)
           << " | " << info.referenceSpp << " | " << referenceCell(info.refErr, info.refErrSe) << " / "
           << referenceCell(info.refErrCrop, info.refErrCropSe) << " | " << sci(minFull) << " / " << sci(minCrop)
           << " |\n";
    }
    md << "\nThe smallest measured relMSE is the smallest per-point mean. The reference's s.e. comes from its "
          "halves' per-pixel differences (√((2/3) Σ e_p²) / 4P: each term taken as its mean times a χ²₁ variable, "
          "which errs large); a scene measured before that was recorded shows \"s.e. ≤ itself\" and its points "
          "take the reference relMSE itself as that s.e.\n\n"
       << "![relMSE vs spp](study/scene_error_vs_spp.png)\n\n![relMSE vs time](study/scene_error_vs_time.png)\n\n";

    // One row of the tables at a paper count: the sampler's estimate at ladder count n, against
    // Random at the same count and against CMJ2D-pad's estimate `cmjRef`.
    auto countRow = [&](const SceneRecord& info, const SamplerSpec& s, const SceneCurve& c, double n,
                        const SceneCurve* rnd, const Estimate& cmjRef) {
        const Estimate e = estAt(c, n, 0), ec = estAt(c, n, 1);
        const Estimate r = randomAt(rnd, n);
        double secs = NAN;
        if (const SceneCurve* t = timedCurveOf(info.name, s.label))
            for (size_t i = 0; i < t->spp.size(); ++i)
                if (t->spp[i] == n) secs = t->seconds[i];
        md << "| " << info.name << " | " << s.label << " | " << n << " | " << fmtEstimate(e) << " | "
           << fmtEstimate(ec) << " | " << fmtRatio(ratioTo(e, r, s.label == "Random")) << " | "
           << (s.label == "Random" ? "—" : verdictCell(e, r)) << " | "
           << fmtRatio(ratioTo(e, cmjRef, s.label == "CMJ2D-pad")) << " | "
           << (s.label == "CMJ2D-pad" ? "—" : verdictCell(e, cmjRef)) << " | " << fmtF(secs * 1000, 0) << " |\n";
        return std::pair<Estimate, Estimate>{e, r};
    };
    // --- At the paper's sample count (~121/128 spp) -------------------------------------------
    std::string goal7d = "not measured";
    std::string goal7dText;
    md << "### At the paper's sample count (about 121/128 spp)\n\n"
       << "Each sampler at its ladder count nearest 128 (OAs: 121 = 11², Bose–Bush 128, Addelman–Kempthorne 2q², "
          "CMJND s⁴; baselines 128; Random and Halton also at 121, a matched count). Ratios are to Random at the "
          "same count and to CMJ2D-pad at 128, the paper's comparison; \"vs\" columns give the verdict.\n\n"
       << "| scene | sampler | spp | relMSE ± s.e. (n) | crop relMSE ± s.e. (n) | ÷ Random (same spp) | vs Random | "
          "÷ CMJ2D-pad@128 | vs CMJ2D-pad | ms per frame |\n"
          "|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        const SceneCurve* rnd = curveOf(info.name, "Random");
        const Estimate cmj128 = cmj2dAt128(info.name);
        Estimate bestOa = none, bestOaRnd = none;
        std::string bestOaName;
        for (const auto& s : samplers) {
            const SceneCurve* c = curveOf(info.name, s.label);
            if (!c) continue;
            const double n = nearest(c->spp, 128);
            const auto [e, r] = countRow(info, s, *c, n, rnd, cmj128);
            // The goal is about the paper's count: an OA whose nearest count is above 128 (Addelman-
            // Kempthorne's 162) has more samples, so it does not compete for "best OA at <= 128".
            if (isOa(s) && n <= 128 && std::isfinite(e.mean) && !(e.mean >= bestOa.mean))
                bestOa = e, bestOaName = s.label + "@" + fmtG(n), bestOaRnd = r;
        }
        if (info.name == "cornell7d" && std::isfinite(bestOaRnd.mean) && std::isfinite(cmj128.mean)) {
            // Goal: best OA <= 0.5 x Random (at its count) and < CMJ2D-pad@128. Each half is "met"
            // only if compare() separates the numbers, "not met" only if it separates them the other
            // way; otherwise the goal is a tie.
            Estimate halfRnd = bestOaRnd;
            halfRnd.mean *= 0.5;
            halfRnd.se *= 0.5;
            const Verdict v1 = compare(bestOa, halfRnd), v2 = compare(bestOa, cmj128);
            goal7d = v1 == Verdict::FirstLower && v2 == Verdict::FirstLower  ? "met"
                     : v1 == Verdict::SecondLower || v2 == Verdict::SecondLower ? "not met"
                                                                                  : "tie (not decided by the error bars)";
            goal7dText = "best OA at <= 128 spp (lowest mean) " + bestOaName + ": relMSE " + fmtEstimate(bestOa) + " = " +
                         fmtRatio(ratioOf(bestOa, bestOaRnd)) + "× Random at the same spp (goal ≤ 0.50: " +
                         verdictWord(v1) + " than 0.5× Random) and " + fmtRatio(ratioOf(bestOa, cmj128)) +
                         "× CMJ2D-pad@128 (goal < 1: " + verdictWord(v2) + ")";
        }
    }
    // Side by side with the paper (Jarosz et al. 2019: relative MSE, PBRT-v3, per-pixel samplers). Ratios,
    // not absolute errors: the scenes are ours, modelled on the paper's.
    // The paper's row names where they are not ours: its one "OA" row of the 9D and 43D scenes
    // names no construction, so it is set beside our BoseCMJ and labelled as the paper's "OA";
    // in the 7D scene its "OA" row is BushMJ (t=2), and BoseCMJ has its own value.
    struct PaperValue {
        const char* scene;
        const char* sampler;
        double relMse;
        const char* paperRow = nullptr;  ///< the paper's label where it differs from ours
    };
    static const PaperValue paper[] = {
        {"cornell7d", "Random", 1.481e-3},      {"cornell7d", "Jittered2D-pad", 1.036e-3},
        {"cornell7d", "CMJ2D-pad", 8.721e-4},   {"cornell7d", "ZeroTwo-pad", 8.299e-4},
        {"cornell7d", "Halton", 7.819e-4},      {"cornell7d", "Sobol", 6.510e-4},
        {"cornell7d", "BushMJ(t=2)", 7.864e-4, "OA (BushMJ t=2)"}, {"cornell7d", "BoseCMJ", 7.680e-4},
        {"blue_spheres9d", "Random", 3.959e-3}, {"blue_spheres9d", "CMJ2D-pad", 1.557e-3},
        {"blue_spheres9d", "Sobol", 1.117e-3},  {"blue_spheres9d", "BoseCMJ", 1.215e-3, "OA"},
        {"interior_deep", "Random", 8.701e-4},  {"interior_deep", "CMJ2D-pad", 6.524e-4},
        {"interior_deep", "Sobol", 5.994e-4},   {"interior_deep", "BoseCMJ", 6.024e-4, "OA"},
    };
    auto paperOf = [&](const std::string& scene, const std::string& sampler) {
        for (const auto& p : paper)
            if (scene == p.scene && sampler == p.sampler) return p.relMse;
        return std::numeric_limits<double>::quiet_NaN();
    };
    auto paperRowOf = [&](const std::string& scene, const std::string& sampler) {
        for (const auto& p : paper)
            if (scene == p.scene && sampler == p.sampler && p.paperRow) return std::string(p.paperRow);
        return sampler;
    };
    md << "\n#### Side by side with the paper\n\n"
       << "The paper's relative MSE (Jarosz et al. 2019, as tabulated in a co-author's thesis; CornellBox 7D and BlueSpheres 9D at 121/128 spp, Barcelona 43D "
          "at 3969/4096 spp) as ratios to its Random and its "
          "CMJ2D-pad, next to ours (± s.e.) at about 128 spp (our Random at the same count as the sampler; our "
          "interior_deep stands in for Barcelona at 32× fewer samples). The paper gives no error bars. Its row "
          "names are in the second column where they differ from ours: in 9D and 43D it has one \"OA\" row whose "
          "construction it does not name, set here beside our BoseCMJ; in 7D its \"OA\" row is BushMJ (t=2), and "
          "BoseCMJ has a value of its own.\n\n"
       << "| scene | sampler | paper's row | paper ÷ Random | ours ÷ Random | paper ÷ CMJ2D-pad | ours ÷ CMJ2D-pad@128 |\n"
          "|---|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        const SceneCurve* rnd = curveOf(info.name, "Random");
        const Estimate cmj128 = cmj2dAt128(info.name);
        for (const auto& s : samplers) {
            const double pv = paperOf(info.name, s.label);
            const SceneCurve* c = curveOf(info.name, s.label);
            if (!std::isfinite(pv) || !c) continue;
            const double n = nearest(c->spp, 128);
            const Estimate e = estAt(*c, n);
            const Estimate r = randomAt(rnd, n);
            auto ratio = [](double a, double b) { return std::isfinite(a / b) ? fmtF(a / b, 2) : std::string("—"); };
            md << "| " << info.name << " | " << s.label << " | " << paperRowOf(info.name, s.label) << " | "
               << ratio(pv, paperOf(info.name, "Random")) << " | "
               << fmtRatio(ratioTo(e, r, s.label == "Random")) << " | " << ratio(pv, paperOf(info.name, "CMJ2D-pad")) << " | "
               << fmtRatio(ratioTo(e, cmj128, s.label == "CMJ2D-pad")) << " |\n";
        }
    }
    md << "\n**Goal (7D scene at about 121 spp: best OA ≤ 0.50 × Random and below CMJ2D-pad): " << goal7d << "**";
    md << (goal7dText.empty() ? " (cornell7d not studied)" : " — " + goal7dText) << ".\n\n";

    // --- At the paper's high count (3969/4096 spp), the 7D and 9D scenes --------------------
    std::uint32_t paperHigh = 0;
    for (const auto& info : infos) paperHigh = std::max(paperHigh, info.paperHighSpp);
    if (paperHigh > 0) {
        md << "### At the paper's high count (about " << paperHigh << " spp): the 7D and 9D scenes\n\n"
           << "Each sampler at its valid count nearest " << paperHigh << " (Bose 64² = 4096, the baselines "
              "4096; the paper's Barcelona figures are at 3969/4096, its 7D and 9D tables at 121/128 only, so there "
              "is no paper number to set beside these). Ratios to Random at the same count and to CMJ2D-pad at the "
              "same ladder point, each with its verdict.\n\n"
           << "| scene | sampler | spp | relMSE ± s.e. (n) | crop relMSE ± s.e. (n) | ÷ Random (same spp) | vs Random | "
              "÷ CMJ2D-pad | vs CMJ2D-pad | ms per frame |\n|---|---|---|---|---|---|---|---|---|---|\n";
        // Samplers without a valid count within a quarter octave of the paper's count (e.g. Bose-Bush,
        // 2q^2 with q a power of two: 2048 or 8192 near 4096) have no row; name them, with the largest
        // count they were measured at, rather than drop them.
        std::map<std::string, double> noCount;  // label -> largest measured count
        for (const auto& info : infos) {
            const SceneCurve* rnd = curveOf(info.name, "Random");
            const SceneCurve* cmj = curveOf(info.name, "CMJ2D-pad");
            if (!rnd || info.paperHighSpp == 0) continue;  // not a paper-count scene
            const double high = info.paperHighSpp;
            const Estimate cmjHigh = cmj ? estAt(*cmj, nearest(cmj->spp, high)) : none;
            for (const auto& s : samplers) {
                const SceneCurve* c = curveOf(info.name, s.label);
                if (!c) continue;
                const double n = nearest(c->spp, high);
                if (std::abs(std::log2(n / high)) > 0.26) {  // no count near it
                    double& largest = noCount[s.label];
                    largest = std::max(largest, *std::max_element(c->spp.begin(), c->spp.end()));
                    continue;
                }
                countRow(info, s, *c, n, rnd, cmjHigh);
            }
        }
        md << "\n";
        if (!noCount.empty()) {
            md << "No row for ";
            const char* sep = "";
            for (const auto& [label, largest] : noCount)
                md << sep << label << " (measured up to " << largest << ")", sep = ", ";
            md << ": no valid count within a quarter octave of " << paperHigh
               << "; the rare-events table below has each sampler at its largest measured count.\n\n";
        }
    }

    // --- Rare events: the worst pixels ---------------------------------------------------------
    md << "### Rare events: how much of the error is in the worst pixels\n\n"
       << "Per render, the worst " << fmtG(100 * kWorstPixelFraction) << "% of pixels by relative squared error "
          "(at least one pixel) and their contribution to the image's relMSE; \"without\" is the relMSE of the "
          "rest (the same mean over all pixels, the worst ones' terms left out), each a mean ± s.e. over the same "
          "renders. A large share means the error is a few rare paths (e.g. a light's corner hit by a small "
          "fraction of samples) that only more samples tame; where an OA's ratio to Random is lower without "
          "the worst pixels than with them, stratification helps the bulk of the image and the rare paths hide "
          "it. At about 128 spp and at each sampler's count nearest the scene's largest (4096 for the 7D and 9D "
          "scenes in full mode).\n\n"
       << "| scene | sampler | spp | relMSE | worst pixels' share | relMSE without them | ÷ Random (all) | "
          "÷ Random (without) | vs Random (without) |\n|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        const SceneCurve* rnd = curveOf(info.name, "Random");
        for (double target : {128.0, double(info.largestSpp)}) {
            for (const auto& s : samplers) {
                const SceneCurve* c = curveOf(info.name, s.label);
                if (!c) continue;
                const double n = nearest(c->spp, target);
                if (target != 128.0 && n == nearest(c->spp, 128.0)) continue;
                const Estimate e = estAt(*c, n, 0), rest = estAt(*c, n, 2), worst = estAt(*c, n, 3);
                const Estimate r = randomAt(rnd, n, 0), rr = randomAt(rnd, n, 2);
                const Estimate share = ratioOf(worst, Estimate{e.mean + info.refErr, e.se, e.n, e.capped});
                md << "| " << info.name << " | " << s.label << " | " << n << " | " << fmtEstimate(e) << " | "
                   << (std::isfinite(share.mean) ? fmtF(100 * share.mean, 0) + "% ± " + fmtF(100 * share.se, 0) + "%"
                                                 : std::string("—"))
                   << " | " << fmtEstimate(rest) << " | " << fmtRatio(ratioTo(e, r, s.label == "Random")) << " | "
                   << fmtRatio(ratioTo(rest, rr, s.label == "Random")) << " | " << (s.label == "Random" ? "—" : verdictCell(rest, rr))
                   << " |\n";
            }
        }
    }
    md << "\nThe share is of the uncorrected relMSE (the reference's own error is spread over all pixels).\n\n";

    // --- Equal time and time to target ---------------------------------------------------------
    // Budgets are fixed before looking at any result, from the scene's cost run: T₁ Sobol's time
    // at 128 spp, T₂ the largest budget every sampler's curve reaches (the shortest of the
    // samplers' longest renders), T₃ the same over the samplers that rendered the paper's high
    // count (the 4096-spp budget of the 7D and 9D scenes; samplers without it show —).
    constexpr int kBudgets = 3;
    constexpr double kPaperHighCount = 3969;
    const char* budgetName[kBudgets] = {"T₁", "T₂", "T₃"};
    // The comparison the goal rests on is fixed in advance too: BoseCMJ, the OA the chooser picks
    // for these scenes (`--sampler oa`: Bose, CMJ offsets), against Sobol. Picking "the best OA" as
    // the lowest of 6-7 OA means and then testing it would favour a win.
    const std::string goalOa = "BoseCMJ";
    int scenesOa[kBudgets][3] = {};  // per budget: goalOa lower / tie / higher than Sobol
    size_t comparisons = 0;
    md << "### Error at equal time\n\n"
       << "relMSE read off each sampler's error-versus-time curve (log-log interpolation between measured points; — "
          "where the budget lies outside the sampler's measured range) at three budgets per scene: T₁ Sobol's time at "
          "128 spp, T₂ the largest budget every sampler's curve reaches (the shortest of the samplers' longest "
          "renders), T₃ the same over the samplers that rendered the paper's high count (≥ 3969 spp: the 4096-spp "
          "budget of the 7D and 9D scenes). Times come from the scene's one cost run "
          "(every point timed in alternating rounds on one machine: "
          "[`scene_costs.csv`](study/scene_costs.csv)); errors from the accuracy renders. Ratios are to Sobol; "
          "n is the smaller of the two interpolated points' n. Every sampler is a row: with 12 rows × 3 budgets "
          "per scene a table holds 36 comparisons with Sobol, so at 2 s.e. about one \"lower\" or \"higher\" per "
          "scene is expected by chance alone; the goal below rests on one comparison fixed in advance.\n\n"
       << "| scene | sampler | relMSE @ T₁ | ÷ Sobol | vs Sobol | relMSE @ T₂ | ÷ Sobol | vs Sobol | relMSE @ T₃ | ÷ Sobol | vs Sobol |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::ostringstream answer;                // the short answer at the top of the section
    for (const auto& info : infos) {
        const SceneCurve* sob = timedCurveOf(info.name, "Sobol");
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
        for (const auto& c : timedCurves)
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
        Estimate sobAt[kBudgets], goalAt[kBudgets] = {none, none, none};
        std::vector<std::pair<Estimate, std::string>> ranking[kBudgets];
        // Curves may be non-monotone in time for tiny renders (noise): sort by time.
        auto byTime = [](const SceneCurve& c, std::vector<double>& ts, std::vector<Estimate>& es) {
            std::vector<size_t> idx(c.spp.size());
            for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
            std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return c.seconds[a] < c.seconds[b]; });
            for (size_t i : idx) ts.push_back(c.seconds[i]), es.push_back(c.relMseE[i]);
        };
        {
            std::vector<double> ts;
            std::vector<Estimate> es;
            byTime(*sob, ts, es);
            for (int b = 0; b < kBudgets; ++b) sobAt[b] = interpEstimate(ts, es, budgets[b], info.relSeTarget);
        }
        for (const auto& s : samplers) {
            const SceneCurve* c = timedCurveOf(info.name, s.label);
            if (!c) continue;
            std::vector<double> ts;
            std::vector<Estimate> es;
            byTime(*c, ts, es);
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
        const SceneCost& run = costRunOf.at(info.name);
        for (int b = 0; b < kBudgets; ++b) {
            std::stable_sort(ranking[b].begin(), ranking[b].end(),
                             [](const auto& x, const auto& y) { return x.first.mean < y.first.mean; });
            if (ranking[b].empty()) continue;
            Estimate rndAt = none;
            for (const auto& [e, label] : ranking[b])
                if (label == "Random") rndAt = e;
            const auto& [best, bestLabel] = ranking[b].front();
            // A single best is named only where compare() separates it from the runner-up.
            const bool separated = ranking[b].size() < 2 || compare(best, ranking[b][1].first) != Verdict::Tie;
            // The best sampler's count at this budget: its timed point nearest the budget (in log).
            double bestSpp = NAN;
            if (const SceneCurve* c = timedCurveOf(info.name, bestLabel)) {
                double gap = 1e300;
                for (size_t i = 0; i < c->spp.size(); ++i)
                    if (std::abs(std::log(c->seconds[i] / budgets[b])) < gap)
                        gap = std::abs(std::log(c->seconds[i] / budgets[b])), bestSpp = c->spp[i];
            }
            answer << "| " << info.name << " (" << info.dims << "D) | " << budgetName[b] << " = " << fmtF(budgets[b], 2)
                   << " s" << (b == 0 ? " (Sobol's 128 spp)" : b == 2 ? " (≈ 4096 spp)" : "")
                   << " | " << bestLabel << " at ≈ " << fmtF(bestSpp, 0) << " spp"
                   << (separated ? "" : " (tie with " + ranking[b][1].second + ")") << " | "
                   << fmtRatio(ratioTo(best, sobAt[b], bestLabel == "Sobol")) << " | "
                   << fmtRatio(ratioTo(best, rndAt, bestLabel == "Random")) << " | "
                   << (std::isfinite(goalAt[b].mean) ? fmtRatio(ratioOf(goalAt[b], sobAt[b])) : std::string("—"))
                   << " | " << run.device << ", " << run.machine << ", " << run.date << " |\n";
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
        if (!met && costRunOf.size() < infos.size())
            goalTime = "open: " + std::to_string(costRunOf.size()) + " of " + std::to_string(infos.size()) +
                       " scenes have a cost run";
    }
    std::ostringstream head;
    head << "### The short answer: lowest error for the same render time\n\n"
         << "Per scene and render-time budget (T₁ = Sobol's time at 128 spp, T₂ = the longest every sampler "
            "reached, T₃ = the longest every sampler with a count ≥ 3969 reached, i.e. the 4096-spp budget; seconds "
            "from the scene's one cost run on the device "
            "and machine named): the sampler with the lowest mean relMSE at that time, its error ÷ Owen-scrambled "
            "Sobol's and ÷ Random's (± s.e.; below 1: better), and " << goalOa
         << " (the chooser's OA) ÷ Sobol. \"tie with\" where the runner-up is within twice the combined s.e. The "
            "tables below give every sampler, the counts, n, the crops and the costs.\n\n"
            "| scene | budget | lowest error | ÷ Sobol | ÷ Random | " << goalOa << " ÷ Sobol | timed on |\n"
            "|---|---|---|---|---|---|---|\n"
         << answer.str() << "\n";
    md << "\n**Goal (at equal time, " << goalOa << " below Owen-scrambled Sobol on at least two of three scenes at "
       << "every budget): " << goalTime << "** — " << goalOa << " lower / tie / higher than Sobol:";
    for (int b = 0; b < kBudgets; ++b)
        md << (b ? "; " : " ") << scenesOa[b][0] << " / " << scenesOa[b][1] << " / " << scenesOa[b][2] << " of "
           << infos.size() << " scenes at " << budgetName[b];
    md << ". The table holds " << comparisons << " comparisons with Sobol in all.\n\n";

    md << "### Time to reach a target error\n\n"
       << "Targets per scene: the relMSE Random reaches at 128 spp, at the ladder count nearest the geometric mean "
          "of 128 and the ladder's largest count, and at that largest count (means; their s.e. enter the times' "
          "s.e.). Times from the scene's cost run, as above. Time read off each curve (first crossing of the means, "
          "log-log interpolation) ± a delta-method s.e.; ≤ marks a sampler already below the target at its "
          "smallest count (a bound, no s.e.), > one that does not reach it within the measured range.\n\n"
       << "| scene | sampler | time to target 1 (ms) | ÷ Random | vs Random | time to target 2 (ms) | ÷ Random | vs Random "
          "| time to target 3 (ms) | ÷ Random | vs Random |\n|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& info : infos) {
        const SceneCurve* rnd = timedCurveOf(info.name, "Random");
        if (!rnd) {
            md << noCostRun(info) << "\n";
            continue;
        }
        const double middle = nearest(rnd->spp, std::sqrt(128.0 * info.maxSpp));
        const Estimate targets[3] = {estAt(*rnd, 128), estAt(*rnd, middle), estAt(*rnd, info.maxSpp)};
        CrossingEstimate rndTime[3];
        for (int b = 0; b < 3; ++b) rndTime[b] = firstCrossing(rnd->seconds, rnd->relMseE, targets[b]);
        md << "| " << info.name << " | *targets*";
        for (int b = 0; b < 3; ++b) md << " | relMSE " << fmtEstimate(targets[b]) << " | |";
        md << " |\n";
        for (const auto& s : samplers) {
            const SceneCurve* c = timedCurveOf(info.name, s.label);
            if (!c) continue;
            md << "| " << info.name << " | " << s.label;
            for (int b = 0; b < 3; ++b) {
                const CrossingEstimate x = firstCrossing(c->seconds, c->relMseE, targets[b]);
                if (!x.crossing.found) {
                    md << " | > " << fmtF(c->seconds.back() * 1000, 0) << " | — | —";
                    continue;
                }
                Estimate ms = x.x;
                ms.mean *= 1000;
                ms.se *= 1000;
                md << " | " << (x.crossing.atFirst ? "≤ " + fmtF(ms.mean, 0) + " (n=" + std::to_string(ms.n) + ")"
                                                   : fmtEstimate(ms, 3))
                   << " | " << fmtRatio(ratioTo(x.x, rndTime[b].x, s.label == "Random")) << " | "
                   << (s.label == "Random" || x.crossing.atFirst ? "—" : verdictCell(x.x, rndTime[b].x));
            }
            md << " |\n";
        }
    }

    // --- Sampler cost inside a frame -----------------------------------------------------------
    md << "\n### Sampler cost inside a frame\n\n"
       << "Time per sample per pixel from a least-squares line of render time on spp over each sampler's "
          "ladder; the share is the part of the frame time above independent (Random) sampling, "
          "1 − t_Random / t_sampler, i.e. what generating that sampler's numbers costs inside the path "
          "tracer. Times from each scene's cost run.\n\n| sampler |";
    for (const auto& info : infos) md << " " << info.name << " Mpaths/s | share |";
    md << "\n|---|";
    for (size_t i = 0; i < infos.size(); ++i) md << "---|---|";
    md << "\n";
    std::map<std::string, double> perSampleRandom;
    for (const auto& info : infos)
        if (const SceneCurve* r = timedCurveOf(info.name, "Random")) perSampleRandom[info.name] = fitLine(r->spp, r->seconds).slope;
    for (const auto& s : samplers) {
        md << "| " << s.label;
        for (const auto& info : infos) {
            const SceneCurve* c = timedCurveOf(info.name, s.label);
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

    // --- Equal-time error images (written when each scene was measured) -----------------------
    md << "\n### Error images at equal time\n\n"
       << "Per-pixel relative squared error in false colour (log scale, 1e-5 to 10, dark to bright; the ramp of "
          "`oas-diff`), for each sampler's render whose time is nearest the budget T₁ (its spp and time are in "
          "[`scene_equal_time.csv`](study/scene_equal_time.csv) and in the panel titles).\n\n"
       << "![equal-time error images](study/scene_equal_time.png)\n\n";
    // The short answer goes right below the section's list of settings.
    std::string text = md.str();
    const size_t at = text.find("\n| scene | device |");
    return text.substr(0, at + 1) + head.str() + text.substr(at + 1);
}

std::string mergeSceneShards(const std::string& outDir, const std::string& baseDir, const std::vector<std::string>& shardDirs,
                             const std::vector<SamplerSpec>& samplers, const std::string& command)
{
    namespace fs = std::filesystem;
    auto recordsIn = [](const std::string& dir) { return readSceneRecords(dir + "/scene_references.csv"); };
    auto measurementsIn = [](const std::string& dir) { return readSceneMeasurements(dir + "/scenes.csv"); };
    const std::vector<SceneRecord> base = recordsIn(baseDir);
    std::vector<SceneRecord> joined = base;
    std::vector<SceneMeasurement> measurements = measurementsIn(baseDir);
    std::vector<std::vector<std::string>> eqRows = readEqualTimeRows(baseDir + "/scene_equal_time.csv");
    // A shard's record is joinShardRecord(base, its own run): its own part is what follows the
    // base's text in the listed fields, and its seconds less the base's.
    auto ownPart = [](const std::string& shardText, const std::string& baseText, const std::string& sep) {
        return shardText.size() > baseText.size() + sep.size() && shardText.compare(0, baseText.size(), baseText) == 0
                   ? shardText.substr(baseText.size() + sep.size())
                   : shardText;
    };
    for (const auto& dir : shardDirs) {
        for (const SceneRecord& shard : recordsIn(dir)) {
            const auto b = std::find_if(base.begin(), base.end(), [&](const SceneRecord& r) { return r.name == shard.name; });
            std::string why;
            if (b == base.end())
                why = "the base " + baseDir + " has no record of it";
            else if (!sameSceneSettings(*b, shard, &why) || shard.refErr != b->refErr || shard.refErrCrop != b->refErrCrop ||
                     shard.rarePixels != b->rarePixels)
                why = why.empty() ? "its reference differs from the base's" : why;
            if (!why.empty())
                throw std::runtime_error(dir + ": scene " + shard.name + " is not a shard of " + baseDir + " (" + why + ")");
            SceneRecord own = shard;
            own.runSeconds -= b->runSeconds;
            own.extraSeconds -= b->extraSeconds;
            own.date = ownPart(shard.date, b->date, " + ");
            own.machine = ownPart(shard.machine, b->machine, " + ");
            own.command = ownPart(shard.command, b->command, " ; ");
            for (auto& r : joined)
                if (r.name == shard.name) r = joinShardRecord(r, own);
        }
        measurements = mergeSamplerShard(measurements, measurementsIn(dir));
        // Equal-time rows and pictures: the shard's samplers' rows replace the earlier ones.
        const auto shardEq = readEqualTimeRows(dir + "/scene_equal_time.csv");
        std::vector<std::vector<std::string>> keptEq;
        for (const auto& row : eqRows)
            if (std::none_of(shardEq.begin(), shardEq.end(), [&](const auto& s) { return s[0] == row[0] && s[1] == row[1]; }))
                keptEq.push_back(row);
        keptEq.insert(keptEq.end(), shardEq.begin(), shardEq.end());
        eqRows = std::move(keptEq);
    }
    // Images: the base's (references), then each shard's (its equal-time pictures).
    fs::create_directories(outDir + "/scenes");
    for (const auto& dir : [&] { auto all = shardDirs; all.insert(all.begin(), baseDir); return all; }())
        if (fs::is_directory(dir + "/scenes"))
            for (const auto& entry : fs::directory_iterator(dir + "/scenes"))
                fs::copy_file(entry.path(), outDir + "/scenes/" + entry.path().filename().string(),
                              fs::copy_options::overwrite_existing);
    if (!command.empty())
        for (auto& r : joined) r.command = command;
    // The scenes outside the base keep their rows from outDir's earlier files.
    const std::string refPath = outDir + "/scene_references.csv", csvPath = outDir + "/scenes.csv",
                      eqPath = outDir + "/scene_equal_time.csv";
    if (fs::exists(refPath) && fs::exists(csvPath)) {
        joined = mergeSceneRecords(readSceneRecords(refPath), joined);
        measurements = mergeSceneMeasurements(readSceneMeasurements(csvPath), measurements);
        std::vector<std::vector<std::string>> kept;
        for (const auto& row : readEqualTimeRows(eqPath))
            if (std::none_of(base.begin(), base.end(), [&](const SceneRecord& r) { return r.name == row[0]; }))
                kept.push_back(row);
        eqRows.insert(eqRows.begin(), kept.begin(), kept.end());
    }
    std::stable_sort(eqRows.begin(), eqRows.end(), [&](const auto& a, const auto& b) {
        return std::make_pair(sceneRank(a[0]), samplerRank(a[1])) < std::make_pair(sceneRank(b[0]), samplerRank(b[1]));
    });
    CsvTable eq(kEqualTimeColumns);
    for (const auto& row : eqRows) eq.add(row);
    writeSceneMeasurements(csvPath, measurements);
    writeSceneRecords(refPath, joined);
    eq.write(eqPath);
    const auto writtenRecords = readSceneRecords(refPath);
    const auto writtenMeasurements = readSceneMeasurements(csvPath);
    writeCurves(outDir + "/scene_curves.csv", curvesOfRecords(writtenRecords, writtenMeasurements));
    return sceneSection(writtenRecords, writtenMeasurements, samplers, costsIn(outDir));
}

}  // namespace oas::study
