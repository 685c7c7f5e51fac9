#pragma once
// Image files for renders: float32 OpenEXR (lossless, with string metadata) and 8-bit sRGB PNG
// previews. Every writer is atomic: the bytes go to a temporary file beside the target, which is
// renamed over it only once complete; on failure the temporary file is removed and the target is
// left as it was.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace oas::image {

/// A linear-light RGBA image: 4 floats per pixel, row-major, top row first.
struct Image {
    std::uint32_t width = 0, height = 0;
    std::vector<float> rgba;  ///< width * height * 4 values

    Image() = default;
    /// A width x height image filled with (r, g, b, a).
    Image(std::uint32_t w, std::uint32_t h, float r = 0, float g = 0, float b = 0, float a = 1);

    std::size_t pixelCount() const { return std::size_t(width) * height; }
    float* pixel(std::uint32_t x, std::uint32_t y) { return rgba.data() + (std::size_t(y) * width + x) * 4; }
    const float* pixel(std::uint32_t x, std::uint32_t y) const { return rgba.data() + (std::size_t(y) * width + x) * 4; }
};

/// Throws std::invalid_argument unless rgba.size() == width * height * 4 (`what` names the image).
void checkLayout(const Image& image, const char* what = "image");

/// Channels of 32-bit unsigned integers stored beside R, G, B, A: name -> width * height values,
/// row-major (exact data, e.g. a render's fixed-point sums, that floats cannot hold).
using UintChannels = std::map<std::string, std::vector<std::uint32_t>>;

/// Writes `image` as a scanline OpenEXR file with float32 R, G, B, A channels (ZIP compression,
/// lossless: reading it back gives the same bits, NaN payloads included), plus `uintChannels` as
/// OpenEXR UINT channels (names must not be R, G, B or A). Each entry of
/// `headerAttributes` becomes an OpenEXR string attribute (e.g. "oas.spp" -> "64"); names must be
/// non-empty and must not clash with the standard header attributes ("channels", "compression",
/// ...). The file is written to "<path>.tmp.<pid>.<n>" and renamed over `path`.
/// Throws std::invalid_argument for a malformed image / attribute name, std::runtime_error naming
/// `path` when the file cannot be written (the temporary file is removed, `path` is untouched).
void writeExr(const std::string& path, const Image& image, const std::map<std::string, std::string>& headerAttributes = {},
              const UintChannels& uintChannels = {});

/// Reads the R, G, B and (optional, default 1) A channels of an OpenEXR file's data window (part 0
/// of a multi-part file; scanline or tiled); half, float and uint channels are converted to float.
/// When `attributes` is given it receives every string attribute of the header. Throws
/// std::runtime_error naming `path` when the file cannot be opened or read or lacks R, G or B.
/// When `uintChannels` is given it receives every channel of OpenEXR type UINT, bit for bit.
Image readExr(const std::string& path, std::map<std::string, std::string>* attributes = nullptr,
              UintChannels* uintChannels = nullptr);

/// The 8-bit sRGB value of a linear value: clamp(v * 2^exposure, 0, 1), the sRGB OETF
/// (12.92 v below 0.0031308, else 1.055 v^(1/2.4) - 0.055), times 255, rounded to nearest. NaN maps
/// to 0.
std::uint8_t linearToSrgb8(float v, float exposure = 0);

/// The 8-bit sRGB RGB bytes of `image` (alpha dropped) through linearToSrgb8: what the PNG preview
/// holds and what oas-view shows.
std::vector<std::uint8_t> srgb8(const Image& image, float exposure = 0);

/// Encodes width x height 8-bit RGB pixels (row-major, 3 bytes each) as a PNG; returns the bytes.
std::string encodePngRgb8(std::uint32_t width, std::uint32_t height, const std::vector<std::uint8_t>& rgb);

/// Encodes `image` as an 8-bit RGB PNG: encodePngRgb8(srgb8(image, exposure)).
std::string encodePngPreview(const Image& image, float exposure = 0);

/// encodePngPreview, written atomically to `path` (oas::writeFileAtomically). `exposure` is in
/// stops: values are scaled by 2^exposure before clamping. Throws std::runtime_error naming `path`.
void writePngPreview(const std::string& path, const Image& image, float exposure = 0);

}  // namespace oas::image
