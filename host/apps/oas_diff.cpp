// oas-diff: compare a rendered OpenEXR image with a reference, printing MSE, relMSE and RMSE over
// R, G, B (alpha ignored) for the whole image and optionally a crop, and optionally writing a
// false-colour PNG of the per-pixel relative squared error.
//
// --exact instead asks whether the two files hold the same pixels bit for bit (every channel,
// the exact sums of render files included): exit 0 when they do, 1 when they differ (the first
// difference is named); headers (times, devices) are not compared.
//
// Exit status: 0 on success; 2 for bad arguments, unreadable images, or images that cannot be
// compared (different sizes, crop outside the image, a NaN or infinite pixel, which would make
// every metric NaN), with a message on stderr and nothing on stdout; 1 when the error PNG cannot
// be written.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "apps/cli_main.hpp"
#include "image/image.hpp"
#include "image/metrics.hpp"

namespace {

struct UsageError : std::invalid_argument {
    using std::invalid_argument::invalid_argument;
};

/// Parses "x,y,w,h": four unsigned decimal integers, w and h at least 1, nothing else.
oas::image::Crop parseCrop(const std::string& text)
{
    std::uint32_t v[4] = {};
    const char* p = text.data();
    const char* end = text.data() + text.size();
    const std::string malformed = "--crop must be x,y,w,h (four unsigned integers), not '" + text + "'";
    for (int i = 0; i < 4; ++i) {
        if (i > 0 && (p == end || *p++ != ',')) throw UsageError(malformed);
        if (p == end || *p < '0' || *p > '9') throw UsageError(malformed);
        const auto [next, ec] = std::from_chars(p, end, v[i]);
        if (ec != std::errc()) throw UsageError(malformed);
        p = next;
    }
    if (p != end) throw UsageError(malformed);
    if (v[2] == 0 || v[3] == 0) throw UsageError("--crop width and height must be at least 1, not '" + text + "'");
    return {v[0], v[1], v[2], v[3]};
}

std::string number(double v)
{
    return fmt::format("{:.8e}", v);
}

/// Empty when a and b hold the same bits in every channel; else the first difference in words.
std::string exactDifference(const oas::image::Image& a, const oas::image::UintChannels& aUints, const oas::image::Image& b,
                            const oas::image::UintChannels& bUints)
{
    if (a.width != b.width || a.height != b.height)
        return fmt::format("sizes {}x{} and {}x{}", a.width, a.height, b.width, b.height);
    std::string aNames, bNames;
    for (const auto& entry : aUints) aNames += " " + entry.first;
    for (const auto& entry : bUints) bNames += " " + entry.first;
    if (aNames != bNames) return "uint channels [" + aNames + " ] and [" + bNames + " ]";
    for (std::size_t i = 0; i < a.rgba.size(); ++i)
        if (std::memcmp(&a.rgba[i], &b.rgba[i], sizeof(float)) != 0)
            return fmt::format("pixel {},{} channel {}: {} and {}", i / 4 % a.width, i / 4 / a.width, "RGBA"[i % 4],
                               number(a.rgba[i]), number(b.rgba[i]));
    for (const auto& [name, values] : aUints) {
        const auto& other = bUints.at(name);
        for (std::size_t i = 0; i < values.size(); ++i)
            if (values[i] != other[i])
                return fmt::format("pixel {},{} channel {}: {} and {}", i % a.width, i / a.width, name, values[i], other[i]);
    }
    return "";
}

/// Runs `step` on the input images; whatever stops it means they cannot be compared, which is
/// exit 2 (runCli), bad_alloc on a huge image included.
template <class Step>
auto unlessIncomparable(Step&& step)
{
    try {
        return step();
    } catch (const std::invalid_argument&) {
        throw;
    } catch (const std::exception& e) {
        throw UsageError(e.what());
    }
}

/// --exact: 0 when the two files hold the same bits in every channel, 1 when they differ.
int compareExactly(const std::string& imagePath, const std::string& referencePath)
{
    oas::image::UintChannels imageUints, referenceUints;
    const auto [a, b] = unlessIncomparable([&] {
        return std::pair{oas::image::readExr(imagePath, nullptr, &imageUints),
                         oas::image::readExr(referencePath, nullptr, &referenceUints)};
    });
    const std::string difference = unlessIncomparable([&] { return exactDifference(a, imageUints, b, referenceUints); });
    if (!difference.empty()) {
        std::cout << "differ: " << difference << "\n";
        return 1;
    }
    std::cout << "identical: " << a.width << "x" << a.height << ", RGBA and " << imageUints.size()
              << " uint channels bit for bit\n";
    return 0;
}

/// The metrics table on stdout, and the error PNG when asked for (exit 1 when it cannot be
/// written: the images themselves were fine).
int measure(const std::string& imagePath, const std::string& referencePath, const std::string& cropText,
            const std::string& errorPng, double epsilon)
{
    oas::image::Image image, reference;
    std::vector<std::pair<std::string, oas::image::ErrorMetrics>> rows;
    unlessIncomparable([&] {
        if (!(epsilon > 0) || !std::isfinite(epsilon))
            throw UsageError("--epsilon must be a finite number > 0, not " + fmt::format("{}", epsilon));
        std::optional<oas::image::Crop> crop;
        if (!cropText.empty()) crop = parseCrop(cropText);
        image = oas::image::readExr(imagePath);
        reference = oas::image::readExr(referencePath);
        for (const auto& [path, img] : {std::pair{&imagePath, &image}, std::pair{&referencePath, &reference}})
            if (const auto bad = oas::image::findNonFinite(*img); bad.count > 0)
                throw UsageError(*path + ": " + oas::image::describeNonFinite(*img, bad) +
                                 ": valid finite R, G, B in every pixel (the metrics would be NaN)");
        rows.emplace_back(fmt::format("whole {}x{}", image.width, image.height),
                          oas::image::compare(image, reference, std::nullopt, epsilon));
        if (crop)
            rows.emplace_back(fmt::format("crop {},{},{},{}", crop->x, crop->y, crop->w, crop->h),
                              oas::image::compare(image, reference, crop, epsilon));
    });

    if (!errorPng.empty()) {
        try {
            oas::image::FalseColourOptions options;
            options.relEpsilon = epsilon;
            oas::image::writePngPreview(errorPng, oas::image::falseColourError(image, reference, options));
        } catch (const std::exception& e) {
            throw std::runtime_error(e.what());  // exit 1, whatever the cause
        }
    }

    std::size_t regionWidth = std::string("region").size();
    for (const auto& row : rows) regionWidth = std::max(regionWidth, row.first.size());
    std::string out =
        fmt::format("{:<{}}  {:>10}  {:>15}  {:>15}  {:>15}\n", "region", regionWidth, "pixels", "MSE", "relMSE", "RMSE");
    for (const auto& [label, m] : rows)
        out += fmt::format("{:<{}}  {:>10}  {:>15}  {:>15}  {:>15}\n", label, regionWidth, m.pixels, number(m.mse),
                           number(m.relMse), number(m.rmse));
    out += fmt::format("(RGB, alpha ignored; relMSE eps = {})\n", epsilon);
    std::cout << out;
    if (!errorPng.empty()) std::cerr << "wrote " << errorPng << "\n";
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    CLI::App app{"oas-diff: compare an OpenEXR image with a reference (MSE, relMSE, RMSE over RGB)"};
    app.footer("relMSE = mean over pixels and R,G,B of (I - R)^2 / (R^2 + eps).\n"
               "Exit status: 0 ok, 2 bad arguments or unreadable/incomparable images (also: NaN or infinite\n"
               "pixels), 1 error PNG not written.\n"
               "--exact: 0 same pixels bit for bit in every channel, 1 they differ, 2 unreadable.");
    std::string imagePath, referencePath, cropText, errorPng;
    double epsilon = 1e-2;
    bool exact = false;
    app.add_option("IMAGE", imagePath, "the image to measure (OpenEXR)")->required();
    app.add_option("REF", referencePath, "the reference image (OpenEXR), same size")->required();
    app.add_option("--crop", cropText, "also report the crop x,y,w,h (pixels, origin top left)");
    app.add_option("--error-png", errorPng,
                   "write a false-colour PNG of the per-pixel relative squared error "
                   "(log scale, 1e-5 .. 10)");
    app.add_option("--epsilon", epsilon, "eps of relMSE (default 0.01)");
    app.add_flag("--exact", exact,
                 "only say whether the pixels are bit-identical in every channel (float and uint; headers ignored)");
    return oas::runCli("oas-diff", app, argc, argv, [&] {
        return exact ? compareExactly(imagePath, referencePath) : measure(imagePath, referencePath, cropText, errorPng, epsilon);
    });
}
