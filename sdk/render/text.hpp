// Text for pictures: a built-in 5 x 7 pixel font (digits, letters, a little punctuation; upper case
// drawn as lower case), scaled by whole pixels. Enough for plot titles, axis labels and numbers.
#pragma once

#include "render/raster.hpp"

#include <string>

namespace ssc::render {

// Width in pixels of text drawn at `scale` (6 * scale per character, the last without its gap).
int text_width(const std::string& text, int scale);
constexpr int text_height(int scale) { return 7 * scale; }

// Draws text with its top-left corner at (x, y); characters the font lacks are left blank.
void draw_text(Image& img, int x, int y, const std::string& text, int scale, const uint8_t colour[3]);

}  // namespace ssc::render
