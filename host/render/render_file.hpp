#pragma once
// Render files: the OpenEXR every render writes (oas-render, oas-view, oas-merge). Besides the
// mean radiance (float R, G, B, A, for any EXR viewer) it stores the exact per-pixel sums of
// render/accumulation.hpp as UINT channels and, in its header, which samples it holds and which
// frame they belong to. So a render of samples [A, B) is a shard: shards of one frame rendered
// anywhere add up (mergeRenders) to the one-process render of their union, bit for bit.
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "oas/pattern.hpp"
#include "render/accumulation.hpp"
#include "render/plan.hpp"
#include "render/scene_data.hpp"
#include "scene/scene.hpp"

namespace oas::render {

/// Sample indices [first, end) of every pixel.
struct SampleRange {
    std::uint32_t first = 0, end = 0;
    std::uint32_t size() const { return end - first; }
    bool operator==(const SampleRange& o) const { return first == o.first && end == o.end; }
};

/// Parses "A:B" (decimal, nothing else) as [A, B) with 0 <= A < B <= spp. Throws
/// oas::InvalidArgument naming `what` (e.g. "--samples"), the text and the valid range.
SampleRange parseSampleRange(const std::string& text, std::uint32_t spp, const std::string& what);
/// Parses "WxH" (decimal, a lower-case x, nothing else) as an image size with both sides in
/// 1 .. scene::kMaxResolution, the range a scene's "resolution" has. Throws oas::InvalidArgument
/// naming `what` (e.g. "--resolution"), the text and the valid range.
std::pair<std::uint32_t, std::uint32_t> parseResolution(const std::string& text, const std::string& what);

/// The pixels [x0, x1) x [y0, y1) of a frame.
struct PixelWindow {
    std::uint32_t x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    std::uint32_t width() const { return x1 - x0; }
    std::uint32_t height() const { return y1 - y0; }
};
/// pbrt's crop window: four fractions x0 x1 y0 y1 of the width x height image (decimal numbers
/// with 0 <= x0 < x1 <= 1, 0 <= y0 < y1 <= 1), as pbrt maps them to pixels: [ceil(W x0),
/// ceil(W x1)) x [ceil(H y0), ceil(H y1)). Throws oas::InvalidArgument naming `what`, the values
/// and the valid ranges for anything else, or for a window that holds no pixel.
PixelWindow parseCropWindow(const std::vector<std::string>& values, std::uint32_t width, std::uint32_t height,
                            const std::string& what);
/// The header field oas.cropWindow of a render of that window: "[x0, x1) x [y0, y1) of WxH".
std::string formatCropWindow(const PixelWindow& window, std::uint32_t width, std::uint32_t height);

/// "0:16" or, for several ranges, "0:4,9:16".
std::string formatRanges(const std::vector<SampleRange>& ranges);

/// Checks `output` as a render file's path for the command-line option `option` and returns its
/// PNG preview's path (the same name, .png). The two differ only in the extension, so the output
/// must end in .exr (any case): "-o x.png" would otherwise write the preview over the image. Throws
/// oas::InvalidArgument naming the option and the value for another name or a directory; creates
/// the parent directories otherwise.
std::string prepareRenderOutput(const std::string& output, const std::string& option);

/// Version tag of the format (header field oas.format): exact sums as 96-bit fixed point with 32
/// fractional bits (shaders/pt/pt_accumulate.glsl) in channels kSumChannels.
inline constexpr const char* kRenderFormat = "oas-accumulation-1";

/// The header fields that say which frame a render belongs to: two renders merge only when all
/// of them are equal (oas.format, oas.sceneHash, oas.resolution, oas.sampler, oas.pattern,
/// oas.dimensionPlan, oas.seed). oas.sceneHash hashes the flattened scene (geometry after mesh loading,
/// materials, lights, camera, resolution); oas.pattern holds the sampler's 16 pattern words (the
/// frame's spp, construction, offset, field); oas.dimensionPlan the plan (which effects take
/// which dimensions); oas.seed the user seed. A crop (oas-render --cropwindow) stores only its
/// window's pixels: its oas.resolution is the window's size, and oas.cropWindow (compared too when
/// merging, absent in a whole frame) says where the window lies in the frame.
const std::vector<std::string>& frameFields();

/// The frame fields of a render of `data` (scene's `scene`) with this plan, pattern and seed,
/// plus oas.format, oas.sampler (the pattern in words), oas.sppRequested and oas.scene (the
/// scene file as given). Writers add their own (timing, device, writer).
std::map<std::string, std::string> renderAttributes(const scene::Scene& scene, const SceneData& data, const DimensionPlan& plan,
                                                    const Pattern& pattern, std::uint32_t seed);

struct RenderFile {
    Accumulation sums;
    std::vector<SampleRange> ranges;  ///< sorted, disjoint, non-adjacent
    std::map<std::string, std::string> attributes;
};

/// Writes a render file (atomically, via image::writeExr): the mean image, the sums, and
/// `attributes` plus oas.samples (formatRanges), oas.spp (samples held per pixel) and
/// oas.rejectedSamples. Every pixel must hold exactly the ranges' samples. Returns the mean image
/// it wrote (sums.image(), e.g. for the PNG preview).
image::Image writeRenderFile(const std::string& path, const Accumulation& sums, const std::vector<SampleRange>& ranges,
                             std::map<std::string, std::string> attributes);

/// Reads and checks a render file. Throws oas::InvalidArgument naming `path` and the field at
/// fault: not an EXR or truncated, not a render file (no oas.format, an unknown one, or missing
/// sum channels), malformed oas.samples or oas.resolution, a pixel whose sample count disagrees
/// with oas.samples, a missing frame field.
RenderFile readRenderFile(const std::string& path);

/// Adds renders of one frame. `names[i]` names `renders[i]` in errors. Refuses (oas::InvalidArgument,
/// naming both files and the field) renders whose frame fields differ or whose sample ranges
/// overlap; the result holds the union of the ranges and the sums of the sums. Its attributes are
/// the first render's, with oas.renderTimeSeconds the sum of the renders', oas.device the distinct
/// devices joined by " + ", and oas.shards the number of renders merged.
RenderFile mergeRenders(const std::vector<RenderFile>& renders, const std::vector<std::string>& names);

}  // namespace oas::render
