#include "image/metrics.hpp"

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace oas::image {

namespace {

std::string sizeOf(const Image& image)
{
    return std::to_string(image.width) + "x" + std::to_string(image.height);
}

void checkPair(const Image& image, const Image& reference)
{
    checkLayout(image, "image");
    checkLayout(reference, "reference");
    if (image.width != reference.width || image.height != reference.height)
        throw std::invalid_argument("image is " + sizeOf(image) + " but reference is " + sizeOf(reference));
}

void checkEpsilon(double relEpsilon)
{
    if (!(relEpsilon > 0) || !std::isfinite(relEpsilon))
        throw std::invalid_argument("relMSE epsilon must be a finite number > 0, not " + std::to_string(relEpsilon));
}

/// Mean over R, G, B of the squared error and the relative squared error at one pixel.
struct PixelError {
    double sq = 0, rel = 0;
};

inline PixelError pixelError(const float* i, const float* r, double eps)
{
    PixelError e;
    for (int c = 0; c < 3; ++c) {
        const double d = double(i[c]) - double(r[c]);
        const double ref = r[c];
        e.sq += d * d;
        e.rel += d * d / (ref * ref + eps);
    }
    return e;
}

}  // namespace

NonFinitePixels findNonFinite(const Image& image, std::size_t keep)
{
    checkLayout(image);
    NonFinitePixels bad;
    for (std::uint32_t y = 0; y < image.height; ++y)
        for (std::uint32_t x = 0; x < image.width; ++x) {
            const float* p = &image.rgba[(std::size_t(y) * image.width + x) * 4];
            if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) continue;
            if (bad.first.size() < keep) bad.first.push_back({x, y});
            ++bad.count;
        }
    return bad;
}

std::string describeNonFinite(const Image& image, const NonFinitePixels& bad)
{
    std::string text =
        std::to_string(bad.count) + (bad.count == 1 ? " pixel holds" : " pixels hold") + " NaN or infinite values, first at";
    for (const auto& [x, y] : bad.first) {
        const float* p = &image.rgba[(std::size_t(y) * image.width + x) * 4];
        char rgb[96];
        std::snprintf(rgb, sizeof rgb, " (%u, %u) = [%g, %g, %g]", x, y, p[0], p[1], p[2]);
        text += rgb;
    }
    return text;
}

ErrorMetrics compare(const Image& image, const Image& reference, std::optional<Crop> crop, double relEpsilon)
{
    checkPair(image, reference);
    checkEpsilon(relEpsilon);
    Crop area{0, 0, image.width, image.height};
    if (crop) {
        area = *crop;
        const std::string name = "crop x,y,w,h = " + std::to_string(area.x) + "," + std::to_string(area.y) + "," +
                                 std::to_string(area.w) + "," + std::to_string(area.h);
        if (area.w == 0 || area.h == 0) throw std::invalid_argument(name + " is empty");
        if (std::uint64_t(area.x) + area.w > image.width || std::uint64_t(area.y) + area.h > image.height)
            throw std::invalid_argument(name + " reaches outside the " + sizeOf(image) + " image");
    }
    ErrorMetrics m;
    m.pixels = std::uint64_t(area.w) * area.h;
    if (m.pixels == 0) throw std::invalid_argument("nothing to compare: the images are " + sizeOf(image));
    double sumSq = 0, sumRel = 0;
    for (std::uint32_t y = area.y; y < area.y + area.h; ++y) {
        double rowSq = 0, rowRel = 0;  // per-row partial sums keep rounding error small
        const float* i = image.pixel(area.x, y);
        const float* r = reference.pixel(area.x, y);
        for (std::uint32_t x = 0; x < area.w; ++x, i += 4, r += 4) {
            const PixelError e = pixelError(i, r, relEpsilon);
            rowSq += e.sq;
            rowRel += e.rel;
        }
        sumSq += rowSq;
        sumRel += rowRel;
    }
    const double terms = double(m.pixels) * 3.0;
    m.mse = sumSq / terms;
    m.relMse = sumRel / terms;
    m.rmse = std::sqrt(m.mse);
    return m;
}

namespace {

struct Lab {
    double L, a, b;
};

/// OKLab -> linear sRGB (Björn Ottosson's published matrices).
std::array<double, 3> oklabToLinearSrgb(const Lab& lab)
{
    const double l_ = lab.L + 0.3963377774 * lab.a + 0.2158037573 * lab.b;
    const double m_ = lab.L - 0.1055613458 * lab.a - 0.0638541728 * lab.b;
    const double s_ = lab.L - 0.0894841775 * lab.a - 1.2914855480 * lab.b;
    const double l = l_ * l_ * l_, m = m_ * m_ * m_, s = s_ * s_ * s_;
    return {+4.0767416621 * l - 3.3077115913 * m + 0.2309699292 * s, -1.2684380046 * l + 2.6097574011 * m - 0.3413193965 * s,
            -0.0041960863 * l - 0.7034186147 * m + 1.7076147010 * s};
}

bool inGamut(const std::array<double, 3>& rgb)
{
    for (double v : rgb)
        if (v < 0 || v > 1) return false;
    return true;
}

/// Ramp anchors in OKLCh (chroma, hue in degrees) at t = 0, 1/4, 1/2, 3/4, 1; lightness is linear in t.
/// Chosen by eye here: violet, blue, teal, green, yellow.
struct Anchor {
    double chroma, hue;
};
constexpr Anchor kAnchors[5] = {{0.10, 300}, {0.14, 265}, {0.11, 195}, {0.15, 135}, {0.17, 105}};
constexpr double kLightness0 = 0.18, kLightness1 = 0.95;

}  // namespace

std::array<float, 3> errorRamp(double t)
{
    if (!(t >= 0)) t = 0;  // NaN too
    if (t > 1) t = 1;
    const double L = kLightness0 + (kLightness1 - kLightness0) * t;
    // Chroma and hue follow Catmull-Rom splines through the anchors (no kinks, hence no Mach bands).
    const double pos = t * 4;
    const int k = std::min(3, int(pos));
    const double f = pos - k;
    auto spline = [&](double Anchor::*field) {
        const double p0 = kAnchors[std::max(k - 1, 0)].*field, p1 = kAnchors[k].*field;
        const double p2 = kAnchors[k + 1].*field, p3 = kAnchors[std::min(k + 2, 4)].*field;
        const double m1 = 0.5 * (p2 - p0), m2 = 0.5 * (p3 - p1);
        const double f2 = f * f, f3 = f2 * f;
        return (2 * f3 - 3 * f2 + 1) * p1 + (f3 - 2 * f2 + f) * m1 + (-2 * f3 + 3 * f2) * p2 + (f3 - f2) * m2;
    };
    const double chroma = std::max(0.0, spline(&Anchor::chroma));
    const double hue = spline(&Anchor::hue) * (M_PI / 180.0);
    auto at = [&](double c) { return oklabToLinearSrgb({L, c * std::cos(hue), c * std::sin(hue)}); };
    std::array<double, 3> rgb = at(chroma);
    if (!inGamut(rgb)) {  // bisect on chroma: chroma 0 (grey of lightness L) is always in gamut
        double lo = 0, hi = chroma;
        for (int it = 0; it < 40; ++it) {
            const double mid = 0.5 * (lo + hi);
            (inGamut(at(mid)) ? lo : hi) = mid;
        }
        rgb = at(lo);
    }
    return {float(std::clamp(rgb[0], 0.0, 1.0)), float(std::clamp(rgb[1], 0.0, 1.0)), float(std::clamp(rgb[2], 0.0, 1.0))};
}

Image falseColourError(const Image& image, const Image& reference, const FalseColourOptions& options)
{
    checkPair(image, reference);
    checkEpsilon(options.relEpsilon);
    if (!(options.minError > 0) || !(options.maxError > options.minError) || !std::isfinite(options.maxError))
        throw std::invalid_argument("false-colour error range must satisfy 0 < minError < maxError < inf, not " +
                                    std::to_string(options.minError) + " .. " + std::to_string(options.maxError));
    // A lookup table of the ramp: 1024 entries are finer than any 8-bit output can show.
    constexpr int kSteps = 1024;
    std::vector<std::array<float, 3>> lut(kSteps + 1);
    for (int s = 0; s <= kSteps; ++s) lut[s] = errorRamp(double(s) / kSteps);
    const double logMin = std::log10(options.minError), logRange = std::log10(options.maxError) - logMin;

    Image out(image.width, image.height, 0, 0, 0, 1);
    for (std::size_t p = 0; p < image.pixelCount(); ++p) {
        const double e = pixelError(&image.rgba[p * 4], &reference.rgba[p * 4], options.relEpsilon).rel / 3.0;
        std::array<float, 3> colour;
        if (!std::isfinite(e)) {
            colour = kNonFiniteErrorColour;
        } else {
            const double t = e <= options.minError ? 0.0 : std::min(1.0, (std::log10(e) - logMin) / logRange);
            colour = lut[std::size_t(std::lround(t * kSteps))];
        }
        std::copy(colour.begin(), colour.end(), &out.rgba[p * 4]);
    }
    return out;
}

}  // namespace oas::image
