/// The bitmap font and the text drawn with it (no GL needed).

#include "ui/render/text.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>
#include <string>
#include <vector>

namespace atelier::render {
namespace {

using Glyph = std::array<std::uint8_t, GLYPH_HEIGHT>;

Glyph glyph(char ch) {
    Glyph out{};
    std::copy_n(glyphRows(ch), GLYPH_HEIGHT, out.begin());
    return out;
}

TEST(BitmapFont, EveryPrintableGlyphHasInkWithinItsCellAndIsItsOwn) {
    std::set<Glyph> seen;
    for (int c = 33; c <= 126; ++c) {
        const auto rows = glyph(static_cast<char>(c));
        int ink = 0;
        for (const std::uint8_t row : rows) {
            EXPECT_EQ(row >> GLYPH_WIDTH, 0) << "glyph " << char(c) << " wider than the cell";
            ink += __builtin_popcount(row);
        }
        EXPECT_GE(ink, 2) << "glyph " << char(c);
        EXPECT_TRUE(seen.insert(rows).second) << "glyph " << char(c) << " repeats another";
    }
    for (const std::uint8_t row : glyph(' ')) {
        EXPECT_EQ(row, 0);
    }
    EXPECT_EQ(glyph('\t'), glyph('?'));
    EXPECT_EQ(glyph(static_cast<char>(200)), glyph('?'));
}

TEST(BitmapFont, TextIsDrawnWhereAndAsLargeAsAsked) {
    io::RgbaImage image(60, 30);
    for (std::uint8_t& b : image.pixels) {
        b = 255;
    }
    EXPECT_EQ(textWidth("AB", 2), 2 * 11);
    drawText(image, 10, 5, "AB", 2, {0, 0, 0, 1});
    int x0 = 99;
    int x1 = -1;
    int y0 = 99;
    int y1 = -1;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            if (image.at(x, y)[0] == 0) {
                x0 = std::min(x0, x);
                x1 = std::max(x1, x);
                y0 = std::min(y0, y);
                y1 = std::max(y1, y);
            }
        }
    }
    EXPECT_EQ(x0, 10);
    EXPECT_EQ(x1, 10 + textWidth("AB", 2) - 1);
    EXPECT_EQ(y0, 5);
    EXPECT_EQ(y1, 5 + 2 * GLYPH_HEIGHT - 1);
    // Clipped at the picture's edges, not written past them.
    drawText(image, 50, 25, "WWWW", 3, {0, 0, 0, 1});
    EXPECT_EQ(image.pixels.size(), std::size_t(60 * 30 * 4));
}

TEST(BitmapFont, FitAndWrap) {
    EXPECT_EQ(fitText("short", 100), "short");
    const std::string cut = fitText("a rather long label", 50);
    EXPECT_LE(textWidth(cut), 50);
    EXPECT_EQ(cut.substr(cut.size() - 2), "..");
    const auto lines = wrapText("cannot read tshirt.obj: line 12: bad face", 60);
    ASSERT_GE(lines.size(), 3u);
    for (const std::string& line : lines) {
        EXPECT_LE(textWidth(line), 60) << line;
    }
    EXPECT_EQ(lines.front(), "cannot");
    const auto longWord = wrapText("abcdefghijklmnopqrstuvwxyz", 30);
    EXPECT_EQ(longWord.size(), 6u);
    EXPECT_TRUE(wrapText("", 30).empty());
}

} // namespace
} // namespace atelier::render
