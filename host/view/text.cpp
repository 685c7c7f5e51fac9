#include "view/text.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "stb_easy_font.h"

namespace oas::view {
namespace {

/// stb_easy_font's vertex: x, y, z, RGBA; four per quad.
struct Vertex {
    float x, y, z;
    unsigned char rgba[4];
};

/// The glyph rectangles of `text` in font units (top-left origin, y down).
struct Rect {
    int x0, y0, x1, y1;
};

std::vector<Rect> glyphRects(const std::string& text)
{
    // ~270 bytes a character (stb_easy_font's estimate); one line, so newlines are spaces.
    std::string line = text;
    std::replace(line.begin(), line.end(), '\n', ' ');
    std::vector<Vertex> buffer(line.size() * 24 + 64);
    const int quads = stb_easy_font_print(0, 0, line.data(), nullptr, buffer.data(), int(buffer.size() * sizeof(Vertex)));
    std::vector<Rect> rects;
    rects.reserve(std::size_t(quads));
    for (int q = 0; q < quads; ++q) {
        const Vertex* v = &buffer[std::size_t(q) * 4];
        float x0 = v[0].x, x1 = v[0].x, y0 = v[0].y, y1 = v[0].y;
        for (int i = 1; i < 4; ++i) {
            x0 = std::min(x0, v[i].x), x1 = std::max(x1, v[i].x);
            y0 = std::min(y0, v[i].y), y1 = std::max(y1, v[i].y);
        }
        rects.push_back({int(std::lround(x0)), int(std::lround(y0)), int(std::lround(x1)), int(std::lround(y1))});
    }
    return rects;
}

}  // namespace

std::uint32_t textWidth(const std::string& text, std::uint32_t scale)
{
    std::string line = text;
    std::replace(line.begin(), line.end(), '\n', ' ');
    return std::uint32_t(stb_easy_font_width(line.data())) * scale;
}

std::uint32_t textHeight(std::uint32_t scale)
{
    // Capitals span 7 font units from the top; descenders (g, p, y) reach 2 more.
    return 9 * scale;
}

void drawText(Frame& f, int x, int y, const std::string& text, const std::uint8_t rgb[3], std::uint32_t scale, bool upward)
{
    const int s = int(scale);
    for (const Rect& r : glyphRects(text))
        for (int gy = r.y0 * s; gy < r.y1 * s; ++gy)
            for (int gx = r.x0 * s; gx < r.x1 * s; ++gx) {
                // Turned a quarter left: the glyph's x runs up the frame, its y runs right.
                const int px = upward ? x + gy : x + gx;
                const int py = upward ? y - 1 - gx : y + gy;
                if (px < 0 || py < 0 || px >= int(f.width) || py >= int(f.height)) continue;
                std::uint8_t* p = f.at(std::uint32_t(px), std::uint32_t(py));
                p[0] = rgb[0], p[1] = rgb[1], p[2] = rgb[2];
            }
}

}  // namespace oas::view
