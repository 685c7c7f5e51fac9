// 8-bit sRGB PNG previews, encoded in memory by stb_image_write and written atomically.
#include "image/image.hpp"

#include <climits>
#include <cmath>
#include <stdexcept>

#include "oas/atomic_file.hpp"

// stb_image_write's implementation, private to this file (static functions, no stdio API).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include "stb_image_write.h"
#pragma GCC diagnostic pop

namespace oas::image {

std::uint8_t linearToSrgb8(float v, float exposure)
{
    const double x = double(v) * std::exp2(double(exposure));
    if (!(x > 0)) return 0;  // negative, zero, NaN
    if (x >= 1) return 255;
    const double s = x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
    return std::uint8_t(std::lround(s * 255.0));
}

std::vector<std::uint8_t> srgb8(const Image& image, float exposure)
{
    checkLayout(image);
    std::vector<std::uint8_t> rgb(image.pixelCount() * 3);
    for (std::size_t i = 0; i < image.pixelCount(); ++i)
        for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = linearToSrgb8(image.rgba[i * 4 + c], exposure);
    return rgb;
}

std::string encodePngRgb8(std::uint32_t width, std::uint32_t height, const std::vector<std::uint8_t>& rgb)
{
    if (width == 0 || height == 0 || width > INT_MAX / 3 || height > INT_MAX)
        throw std::invalid_argument("a PNG preview must be 1x1 .. 715827882 wide, not " + std::to_string(width) + "x" +
                                    std::to_string(height));
    if (rgb.size() != std::size_t(width) * height * 3)
        throw std::invalid_argument("PNG pixels: " + std::to_string(rgb.size()) + " bytes for " + std::to_string(width) + "x" +
                                    std::to_string(height) + " RGB");
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data), std::size_t(size));
    };
    const int w = int(width), h = int(height);
    if (!stbi_write_png_to_func(append, &bytes, w, h, 3, rgb.data(), w * 3))
        throw std::runtime_error("PNG encoding failed (" + std::to_string(w) + "x" + std::to_string(h) + ")");
    return bytes;
}

std::string encodePngPreview(const Image& image, float exposure)
{
    checkLayout(image);
    if (image.width == 0 || image.height == 0 || image.width > INT_MAX / 3 || image.height > INT_MAX)
        throw std::invalid_argument("a PNG preview must be 1x1 .. 715827882 wide, not " + std::to_string(image.width) + "x" +
                                    std::to_string(image.height));
    return encodePngRgb8(image.width, image.height, srgb8(image, exposure));
}

void writePngPreview(const std::string& path, const Image& image, float exposure)
{
    std::string bytes;
    try {
        bytes = encodePngPreview(image, exposure);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("cannot write '" + path + "': " + e.what());
    } catch (const std::exception& e) {
        throw std::runtime_error("cannot write '" + path + "': " + e.what());
    }
    oas::writeFileAtomically(path, bytes);
}

}  // namespace oas::image
