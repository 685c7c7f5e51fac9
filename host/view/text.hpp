#pragma once
// Text in oas-view's CPU-made frames (labels of the points view): stb_easy_font's ASCII glyphs,
// which are axis-aligned rectangles, filled at an integer scale. No font files, no graphics
// pipeline: the same pixels in the window and in --screenshot.
#include <cstdint>
#include <string>

#include "view/presenter.hpp"

namespace oas::view {

/// Size in pixels of `text` drawn at `scale` (one line; the height covers descenders).
std::uint32_t textWidth(const std::string& text, std::uint32_t scale);
std::uint32_t textHeight(std::uint32_t scale);

/// Draws `text` with its top-left corner at (x, y); pixels outside the frame are dropped.
/// Upright text reads left to right; with `upward` it is turned a quarter left, reading bottom to
/// top from (x, y) as its bottom-left corner (a vertical axis's name).
void drawText(Frame& f, int x, int y, const std::string& text, const std::uint8_t rgb[3], std::uint32_t scale,
              bool upward = false);

}  // namespace oas::view
