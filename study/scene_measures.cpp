// The study's scenes and what is measured on a render: per-pixel relative errors against the
// reference, the worst pixels' share, the rare pixels (estimated apart, traced on the CPU), and the
// curves (per point: mean, s.e., n) of the renders' rows. scene_accuracy.cpp renders the scenes;
// scene_records.cpp reads and writes their rows.
#include "scene_study.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>

#include "image/image.hpp"
#include "render/tracer.hpp"
#include "scene_internal.hpp"
#include "stats.hpp"

namespace oas::study {

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
    const std::size_t k = std::min(e.size(), std::max<std::size_t>(1, std::size_t(std::ceil(fraction * double(e.size())))));
    std::nth_element(e.begin(), e.begin() + (k - 1), e.end(), std::greater<double>());
    double top = 0;
    for (std::size_t i = 0; i < k; ++i) top += e[i];
    return top / double(e.size());
}

std::vector<std::uint32_t> rarePixelsOf(const oas::image::Image& a, const oas::image::Image& b,
                                        const oas::image::Image& reference, std::uint32_t k, double eps)
{
    if (a.width != reference.width || a.height != reference.height || b.width != reference.width || b.height != reference.height)
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
    for (auto p : pixels) {
        // A space before every item but the first (appended apart: GCC 12 reads `"" + std::string`
        // here as an overlapping copy, a false -Wrestrict).
        if (!out.empty()) out += ' ';
        out += std::to_string(p % width) + ":" + std::to_string(p / width);
    }
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
                  std::isdigit(static_cast<unsigned char>(item[0])) && std::isdigit(static_cast<unsigned char>(item[colon + 1]));
        if (ok) {
            x = std::strtoul(item.c_str(), &end, 10);
            ok = end == item.c_str() + colon;
        }
        if (ok) {
            y = std::strtoul(item.c_str() + colon + 1, &end, 10);
            ok = end == item.c_str() + item.size();
        }
        if (!ok || x >= width || y >= height)
            throw std::invalid_argument("rare pixels: \"" + item + "\" is not x:y inside the " + std::to_string(width) + "x" +
                                        std::to_string(height) + " image");
        out.push_back(std::uint32_t(y * width + x));
    }
    return out;
}

double rarePixelsShareCpu(const oas::render::SceneData& data, const oas::render::DimensionPlan& plan, const oas::Pattern& pattern,
                          const std::vector<std::uint32_t>& pixels, std::uint32_t spp, std::uint32_t seed,
                          const oas::image::Image& reference, oas::render::Accumulation& scratch, double eps)
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

namespace detail {

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

}  // namespace detail

}  // namespace oas::study
