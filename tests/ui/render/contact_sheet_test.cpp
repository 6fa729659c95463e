/// Contact sheets: the grid, the pictures in their cells, the labels and failed cells (no GL).

#include "ui/render/contact_sheet.h"
#include "ui/render/text.h"

#include <gtest/gtest.h>

namespace atelier::render {
namespace {

io::RgbaImage filled(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b,
                     std::uint8_t a = 255) {
    io::RgbaImage image(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = image.at(x, y);
            p[0] = r;
            p[1] = g;
            p[2] = b;
            p[3] = a;
        }
    }
    return image;
}

/// Pixels in the rectangle that are not the colour (r, g, b).
int otherPixels(const io::RgbaImage& image, int x0, int y0, int w, int h, int r, int g, int b) {
    int n = 0;
    for (int y = y0; y < y0 + h; ++y) {
        for (int x = x0; x < x0 + w; ++x) {
            const std::uint8_t* p = image.at(x, y);
            n += std::abs(p[0] - r) + std::abs(p[1] - g) + std::abs(p[2] - b) > 6 ? 1 : 0;
        }
    }
    return n;
}

TEST(ContactSheet, CellsInAGridWithTheirLabelsAndFailures) {
    SheetOptions options;
    options.columns = 2;
    options.cellWidth = 200;
    options.cellHeight = 100;
    std::vector<SheetCell> cells(3);
    cells[0].picture = filled(200, 100, 255, 0, 0);
    cells[0].label = "red / front";
    cells[1].picture = filled(400, 200, 0, 0, 255); // scaled down to fit
    cells[1].label = "blue / back";
    cells[2].message = "cannot read bad.obj: line 3: face index 9 out of range";
    cells[2].label = "bad / front";
    const io::RgbaImage sheet = contactSheet(cells, options);
    const int label = sheetLabelHeight(options);
    ASSERT_EQ(sheet.width, options.gap + 2 * (200 + options.gap));
    ASSERT_EQ(sheet.height, options.gap + 2 * (100 + label + options.gap));
    for (std::size_t i = 0; i < sheet.pixels.size(); i += 4) {
        ASSERT_EQ(sheet.pixels[i + 3], 255) << "the sheet is opaque";
    }
    const int g = options.gap;
    EXPECT_EQ(otherPixels(sheet, g, g, 200, 100, 255, 0, 0), 0);
    EXPECT_EQ(otherPixels(sheet, g + 200 + g, g, 200, 100, 0, 0, 255), 0);
    // Each label puts ink in the strip under its cell; the gap between cells stays white.
    EXPECT_GT(otherPixels(sheet, g, g + 100, 200, label, 255, 255, 255), 50);
    EXPECT_GT(otherPixels(sheet, g + 200 + g, g + 100, 200, label, 255, 255, 255), 50);
    EXPECT_EQ(otherPixels(sheet, g + 200, 0, g, sheet.height, 255, 255, 255), 0);
    // The failed cell shows its message (ink in the alarm colour) and no picture.
    const int top = g + 100 + label + g;
    int alarm = 0;
    for (int y = top; y < top + 100; ++y) {
        for (int x = g; x < g + 200; ++x) {
            const std::uint8_t* p = sheet.at(x, y);
            alarm += p[0] > 140 && p[1] < 60 && p[2] < 60 ? 1 : 0;
        }
    }
    EXPECT_GT(alarm, 100);
}

TEST(ContactSheet, TransparentPicturesAreLaidOnTheBackground) {
    SheetOptions options;
    options.columns = 1;
    options.cellWidth = 20;
    options.cellHeight = 20;
    options.background = {0, 1, 0, 1};
    const io::RgbaImage sheet = contactSheet({{filled(20, 20, 255, 0, 0, 0), "", ""}}, options);
    EXPECT_EQ(otherPixels(sheet, options.gap, options.gap, 20, 20, 0, 255, 0), 0);
}

TEST(ContactSheet, LabelsOfTwoLines) {
    SheetOptions options;
    options.columns = 1;
    options.cellWidth = 200;
    options.cellHeight = 50;
    options.labelLines = 2;
    EXPECT_EQ(sheetLabelHeight(options), 2 * 2 * LINE_HEIGHT + 4);
    const io::RgbaImage sheet =
        contactSheet({{filled(200, 50, 0, 0, 0), "trousers\nthree-quarter", ""}}, options);
    const int top = options.gap + 50 + 3;
    const int line = 2 * LINE_HEIGHT;
    EXPECT_GT(otherPixels(sheet, options.gap, top, 200, line, 255, 255, 255), 30);
    EXPECT_GT(otherPixels(sheet, options.gap, top + line, 200, line, 255, 255, 255), 30);
}

TEST(ResizeImage, AveragesWhatEachPixelCoversWeightedByAlpha) {
    io::RgbaImage image = filled(4, 2, 0, 0, 0);
    for (int y = 0; y < 2; ++y) {
        image.at(0, y)[0] = 200;
        image.at(1, y)[0] = 100;
        image.at(2, y)[3] = 0; // transparent: adds no colour
        image.at(2, y)[1] = 255;
    }
    const io::RgbaImage half = resizeImage(image, 2, 1);
    EXPECT_EQ(half.at(0, 0)[0], 150);
    EXPECT_EQ(half.at(0, 0)[3], 255);
    EXPECT_EQ(half.at(1, 0)[1], 0);
    EXPECT_EQ(half.at(1, 0)[3], 128);
    const io::RgbaImage big = resizeImage(image, 8, 4);
    EXPECT_EQ(big.at(1, 3)[0], 200);
}

} // namespace
} // namespace atelier::render
