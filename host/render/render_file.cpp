#include "render/render_file.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>
#include <stdexcept>

#include "image/image.hpp"
#include "render/fnv1a.hpp"
#include "oas/pattern.hpp"

namespace oas::render {
namespace {

/// The sums' UINT channels, in word order (pixel word k is kSumChannels[k]); the spare word is
/// not stored.
const std::vector<std::string>& sumChannels()
{
    static const std::vector<std::string> names = {"sum.R0", "sum.R1", "sum.R2", "sum.G0",      "sum.G1",      "sum.G2",
                                                   "sum.B0", "sum.B1", "sum.B2", "sum.samples", "sum.rejected"};
    return names;
}

/// A decimal uint32 making up the whole of `text`.
bool parseUint(std::string_view text, std::uint32_t& value)
{
    if (text.empty() || text.front() < '0' || text.front() > '9') return false;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    return ec == std::errc() && end == text.data() + text.size();
}

std::string hex(std::uint64_t v, int digits)
{
    char buffer[24];
    std::snprintf(buffer, sizeof buffer, "%0*llx", digits, static_cast<unsigned long long>(v));
    return buffer;
}

std::string sceneHash(const SceneData& data)
{
    Fnv1a f;
    f.items(data.shapes);
    f.items(data.materials);
    f.items(data.lights);
    f.items(data.nodes);
    f.bytes(&data.globals, sizeof data.globals);
    return hex(f.h, 16);
}

std::string patternWords(const Pattern& pattern)
{
    std::uint32_t words[sizeof(Pattern) / 4];
    std::memcpy(words, &pattern, sizeof words);
    std::string out;
    for (std::uint32_t w : words) {
        if (!out.empty()) out += ' ';
        out += hex(w, 8);
    }
    return out;
}

/// Parses oas.samples: "A:B[,C:D...]", sorted, disjoint, non-adjacent, non-empty ranges.
std::vector<SampleRange> parseRanges(const std::string& text, const std::string& path)
{
    std::vector<SampleRange> ranges;
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string_view item(text.data() + start, comma - start);
        const std::size_t colon = item.find(':');
        SampleRange r;
        if (colon == std::string_view::npos || !parseUint(item.substr(0, colon), r.first) ||
            !parseUint(item.substr(colon + 1), r.end) || r.first >= r.end || (!ranges.empty() && r.first <= ranges.back().end))
            throw InvalidArgument(path + ": header field oas.samples is '" + text +
                                  "': valid a list of increasing, disjoint ranges A:B (A < B), e.g. 0:16 or 0:4,9:16");
        ranges.push_back(r);
        start = comma + 1;
    }
    return ranges;
}

std::uint64_t totalSamples(const std::vector<SampleRange>& ranges)
{
    std::uint64_t n = 0;
    for (const SampleRange& r : ranges) n += r.size();
    return n;
}

/// Sorts and joins touching ranges; false when two overlap.
bool normalize(std::vector<SampleRange>& ranges)
{
    std::sort(ranges.begin(), ranges.end(), [](auto& a, auto& b) { return a.first < b.first; });
    std::vector<SampleRange> out;
    for (const SampleRange& r : ranges) {
        if (!out.empty() && r.first < out.back().end) return false;
        if (!out.empty() && r.first == out.back().end)
            out.back().end = r.end;
        else
            out.push_back(r);
    }
    ranges = out;
    return true;
}

}  // namespace

SampleRange parseSampleRange(const std::string& text, std::uint32_t spp, const std::string& what)
{
    const std::size_t colon = text.find(':');
    SampleRange r;
    if (colon == std::string::npos || !parseUint(std::string_view(text).substr(0, colon), r.first) ||
        !parseUint(std::string_view(text).substr(colon + 1), r.end) || r.first >= r.end || r.end > spp)
        throw InvalidArgument(what + " " + text + ": valid A:B, the sample indices [A, B) with 0 <= A < B <= " +
                              std::to_string(spp) + " (the frame's samples per pixel), e.g. 0:" + std::to_string((spp + 1) / 2));
    return r;
}

std::pair<std::uint32_t, std::uint32_t> parseResolution(const std::string& text, const std::string& what)
{
    const std::size_t x = text.find('x');
    std::uint32_t w = 0, h = 0;
    if (x == std::string::npos || !parseUint(std::string_view(text).substr(0, x), w) ||
        !parseUint(std::string_view(text).substr(x + 1), h) || w < 1 || h < 1 || w > scene::kMaxResolution ||
        h > scene::kMaxResolution)
        throw InvalidArgument(what + " " + text + ": valid WxH, the image's width and height in pixels, each 1 .. " +
                              std::to_string(scene::kMaxResolution) + " (e.g. 640x480)");
    return {w, h};
}

PixelWindow parseCropWindow(const std::vector<std::string>& values, std::uint32_t width, std::uint32_t height,
                            const std::string& what)
{
    std::string given;
    for (const std::string& v : values) given += " " + v;
    double f[4] = {};
    bool ok = values.size() == 4;
    for (std::size_t i = 0; ok && i < 4; ++i) {
        const std::string& v = values[i];
        const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), f[i]);
        ok = !v.empty() && ec == std::errc() && end == v.data() + v.size() && f[i] >= 0.0 && f[i] <= 1.0;
    }
    ok = ok && f[0] < f[1] && f[2] < f[3];
    const auto pixel = [](double fraction, std::uint32_t size) { return std::uint32_t(std::ceil(fraction * size)); };
    const PixelWindow w{ok ? pixel(f[0], width) : 0, ok ? pixel(f[1], width) : 0, ok ? pixel(f[2], height) : 0,
                        ok ? pixel(f[3], height) : 0};
    if (!ok)
        throw InvalidArgument(what + given +
                              ": valid x0 x1 y0 y1, fractions of the image with 0 <= x0 < x1 <= 1 "
                              "and 0 <= y0 < y1 <= 1 (e.g. 0.25 0.75 0 0.5)");
    if (w.x0 >= w.x1 || w.y0 >= w.y1)
        throw InvalidArgument(what + given + " holds no pixel of the " + std::to_string(width) + "x" + std::to_string(height) +
                              " image (pixels [ceil(W x0), ceil(W x1)) x [ceil(H y0), "
                              "ceil(H y1))): valid a wider window");
    return w;
}

std::string formatCropWindow(const PixelWindow& window, std::uint32_t width, std::uint32_t height)
{
    return "[" + std::to_string(window.x0) + ", " + std::to_string(window.x1) + ") x [" + std::to_string(window.y0) + ", " +
           std::to_string(window.y1) + ") of " + std::to_string(width) + "x" + std::to_string(height);
}

std::string prepareRenderOutput(const std::string& output, const std::string& option)
{
    namespace fs = std::filesystem;
    std::string ext = fs::path(output).extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".exr" || fs::path(output).stem().empty())
        throw InvalidArgument(option + " " + output +
                              ": the output is an OpenEXR image with its PNG preview "
                              "beside it: valid a file name ending in .exr (e.g. out/render.exr)");
    if (fs::is_directory(output))
        throw InvalidArgument(option + " " + output + " is a directory: valid a file name ending in .exr");
    if (const auto parent = fs::path(output).parent_path(); !parent.empty()) fs::create_directories(parent);
    return fs::path(output).replace_extension(".png").string();
}

std::string formatRanges(const std::vector<SampleRange>& ranges)
{
    std::string out;
    for (const SampleRange& r : ranges) {
        if (!out.empty()) out += ',';
        out += std::to_string(r.first) + ":" + std::to_string(r.end);
    }
    return out;
}

const std::vector<std::string>& frameFields()
{
    // oas.sampler before oas.pattern: the same fact, but a mismatch reads better in words.
    static const std::vector<std::string> fields = {"oas.format",  "oas.sceneHash",     "oas.resolution", "oas.sampler",
                                                    "oas.pattern", "oas.dimensionPlan", "oas.seed"};
    return fields;
}

std::map<std::string, std::string> renderAttributes(const scene::Scene& scene, const SceneData& data, const DimensionPlan& plan,
                                                    const Pattern& pattern, std::uint32_t seed)
{
    std::string planLine = plan.explain();
    planLine = planLine.substr(0, planLine.find('\n'));
    return {{"oas.format", kRenderFormat},
            {"oas.sceneHash", sceneHash(data)},
            {"oas.resolution", std::to_string(scene.width) + "x" + std::to_string(scene.height)},
            {"oas.pattern", patternWords(pattern)},
            {"oas.dimensionPlan", planLine},
            {"oas.seed", std::to_string(seed)},
            {"oas.sampler", oas::describe(pattern)},
            {"oas.sppRequested", std::to_string(scene.sampler.spp)},
            {"oas.scene", scene.path.string()}};
}

image::Image writeRenderFile(const std::string& path, const Accumulation& sums, const std::vector<SampleRange>& ranges,
                             std::map<std::string, std::string> attributes)
{
    const std::uint64_t held = totalSamples(ranges);
    for (std::size_t i = 0; i < sums.pixelCount(); ++i)
        if (sums.samples(i) != held)
            throw std::logic_error("writeRenderFile: pixel " + std::to_string(i) + " holds " + std::to_string(sums.samples(i)) +
                                   " samples, the ranges " + formatRanges(ranges));
    image::UintChannels channels;
    for (std::size_t k = 0; k < sumChannels().size(); ++k) {
        std::vector<std::uint32_t>& values = channels[sumChannels()[k]];
        values.resize(sums.pixelCount());
        for (std::size_t i = 0; i < sums.pixelCount(); ++i) values[i] = sums.pixel(i)[k];
    }
    attributes["oas.format"] = kRenderFormat;
    attributes["oas.samples"] = formatRanges(ranges);
    attributes["oas.spp"] = std::to_string(held);
    attributes["oas.rejectedSamples"] = std::to_string(sums.rejectedSamples());
    image::Image mean = sums.image();
    image::writeExr(path, mean, attributes, channels);
    return mean;
}

RenderFile readRenderFile(const std::string& path)
{
    RenderFile file;
    image::UintChannels channels;
    image::Image mean;
    try {
        mean = image::readExr(path, &file.attributes, &channels);
    } catch (const std::runtime_error& e) {
        throw InvalidArgument(e.what());
    }
    const auto field = [&](const std::string& name) -> const std::string& {
        const auto it = file.attributes.find(name);
        if (it == file.attributes.end())
            throw InvalidArgument(path + ": header field " + name + " is missing: this is not a render file of " +
                                  "oas-render, oas-view or oas-merge (those hold exact sums)");
        return it->second;
    };
    if (const std::string& format = field("oas.format"); format != kRenderFormat)
        throw InvalidArgument(path + ": header field oas.format is '" + format + "': valid '" + kRenderFormat +
                              "' (a render file of this version of oas)");
    for (const std::string& name : frameFields()) field(name);
    for (const std::string& name : sumChannels())
        if (!channels.count(name))
            throw InvalidArgument(path + ": channel " + name + " is missing: a render file holds the exact sums in " +
                                  "UINT channels sum.R0 ... sum.rejected");
    if (field("oas.resolution") != std::to_string(mean.width) + "x" + std::to_string(mean.height))
        throw InvalidArgument(path + ": header field oas.resolution is '" + field("oas.resolution") + "' but the image is " +
                              std::to_string(mean.width) + "x" + std::to_string(mean.height));
    file.ranges = parseRanges(field("oas.samples"), path);
    const std::uint64_t held = totalSamples(file.ranges);
    file.sums = Accumulation(mean.width, mean.height);
    for (std::size_t k = 0; k < sumChannels().size(); ++k) {
        const std::vector<std::uint32_t>& values = channels.at(sumChannels()[k]);
        for (std::size_t i = 0; i < file.sums.pixelCount(); ++i) file.sums.pixel(i)[k] = values[i];
    }
    for (std::size_t i = 0; i < file.sums.pixelCount(); ++i)
        if (file.sums.samples(i) != held || file.sums.rejected(i) > held)
            throw InvalidArgument(path + ": pixel " + std::to_string(i % mean.width) + "," + std::to_string(i / mean.width) +
                                  " holds " + std::to_string(file.sums.samples(i)) + " samples (" +
                                  std::to_string(file.sums.rejected(i)) + " rejected) but header field oas.samples says " +
                                  std::to_string(held) + " (" + field("oas.samples") + ")");
    return file;
}

RenderFile mergeRenders(const std::vector<RenderFile>& renders, const std::vector<std::string>& names)
{
    if (renders.empty() || names.size() != renders.size())
        throw std::invalid_argument("mergeRenders: one name per render, at least one render");
    RenderFile merged = renders.front();
    const auto value = [](const RenderFile& f, const std::string& name) {
        const auto it = f.attributes.find(name);
        return it == f.attributes.end() ? std::string("(missing)") : it->second;
    };
    // oas.cropWindow is no frame field (whole frames lack it) but crops of different windows of
    // one size must not add up.
    std::vector<std::string> mergeFields = frameFields();
    mergeFields.push_back("oas.cropWindow");
    double seconds = 0;
    std::vector<std::string> devices;
    std::vector<std::pair<SampleRange, std::size_t>> owners;  // every range with the render holding it
    for (std::size_t r = 0; r < renders.size(); ++r) {
        const RenderFile& f = renders[r];
        for (const std::string& name : mergeFields)
            if (value(f, name) != value(renders.front(), name))
                throw InvalidArgument(names[r] + ": header field " + name + " is '" + value(f, name) + "' but " + names.front() +
                                      " has '" + value(renders.front(), name) +
                                      "': shards of one frame share the scene, resolution, crop window, sampler, "
                                      "plan and seed");
        for (const SampleRange& range : f.ranges) owners.push_back({range, r});
        if (r > 0) merged.sums.add(f.sums);
        try {
            seconds += std::stod(value(f, "oas.renderTimeSeconds"));
        } catch (const std::exception&) {
        }
        const std::string device = value(f, "oas.device");
        if (std::find(devices.begin(), devices.end(), device) == devices.end()) devices.push_back(device);
    }
    std::sort(owners.begin(), owners.end(), [](auto& a, auto& b) { return a.first.first < b.first.first; });
    for (std::size_t i = 1; i < owners.size(); ++i)
        if (owners[i].first.first < owners[i - 1].first.end)
            throw InvalidArgument(names[owners[i].second] + ": samples " + formatRanges({owners[i].first}) + " overlap samples " +
                                  formatRanges({owners[i - 1].first}) + " of " + names[owners[i - 1].second] +
                                  ": each sample may be merged once");
    merged.ranges.clear();
    for (const auto& [range, owner] : owners) merged.ranges.push_back(range);
    normalize(merged.ranges);
    std::string deviceList;
    for (const std::string& d : devices) {
        if (!deviceList.empty()) deviceList += " + ";
        deviceList += d;
    }
    merged.attributes["oas.device"] = deviceList;
    merged.attributes["oas.renderTimeSeconds"] = std::to_string(seconds);
    merged.attributes["oas.shards"] = std::to_string(renders.size());
    merged.attributes["oas.samples"] = formatRanges(merged.ranges);
    merged.attributes["oas.spp"] = std::to_string(totalSamples(merged.ranges));
    merged.attributes["oas.rejectedSamples"] = std::to_string(merged.sums.rejectedSamples());
    return merged;
}

}  // namespace oas::render
