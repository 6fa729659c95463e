#pragma once
/// Text and flat shapes drawn into pictures on the CPU (labels of a contact sheet, the strain
/// legend): a bitmap font of our own, 5×7 pixels per glyph for ASCII 32–126, scaled by whole
/// numbers. No font library and no Qt: atelier-cli draws its labels with this alone.

#include "ui/render/scene.h"

#include "io/png.h"

#include <string>
#include <string_view>
#include <vector>

namespace atelier::render {

/// The font's metrics at scale 1 [pixels]: a glyph is 5×7, the pen advances 6 per character,
/// lines are 9 apart (2 pixels of leading, room for descenders drawn inside the 7 rows).
inline constexpr int GLYPH_WIDTH = 5;
inline constexpr int GLYPH_HEIGHT = 7;
inline constexpr int GLYPH_ADVANCE = 6;
inline constexpr int LINE_HEIGHT = 9;

/// The rows of the glyph of `ch`, top first; bit 4 is the leftmost column. A character outside
/// ASCII 32–126 has the glyph of '?'.
const std::uint8_t* glyphRows(char ch);

/// Width of `text` drawn at `scale` [pixels] (one line; no trailing space column).
int textWidth(std::string_view text, int scale = 1);

/// Draws `text` with its top-left corner at (x, y) [pixels, y down], each font pixel a
/// `scale`×`scale` block blended over the picture with `colour`'s alpha. Clipped to the
/// picture.
void drawText(io::RgbaImage& image, int x, int y, std::string_view text, int scale,
              const Colour& colour);

/// Fills the rectangle [x, x + w) × [y, y + h), blended with `colour`'s alpha, clipped.
void fillRect(io::RgbaImage& image, int x, int y, int w, int h, const Colour& colour);

/// `text` cut to at most `maxWidth` pixels at `scale`, ending in ".." when cut.
std::string fitText(std::string_view text, int maxWidth, int scale = 1);

/// `text` broken into lines of at most `maxWidth` pixels at `scale`: at spaces where it can,
/// inside a word longer than a line where it must.
std::vector<std::string> wrapText(std::string_view text, int maxWidth, int scale = 1);

} // namespace atelier::render
