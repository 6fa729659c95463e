#include "ui/render/contact_sheet.h"

#include "ui/render/text.h"

#include <algorithm>
#include <cmath>

namespace atelier::render {

namespace {

int labelScale(const SheetOptions& options) {
    return options.cellWidth >= 192 ? 2 : 1;
}

std::uint8_t roundToByte(double value) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0, 255.0)));
}

} // namespace

int sheetLabelHeight(const SheetOptions& options) {
    return std::max(options.labelLines, 0) * LINE_HEIGHT * labelScale(options) + 4;
}

io::RgbaImage resizeImage(const io::RgbaImage& image, int width, int height) {
    width = std::max(width, 1);
    height = std::max(height, 1);
    io::RgbaImage out(width, height);
    if (image.width < 1 || image.height < 1) {
        return out;
    }
    for (int y = 0; y < height; ++y) {
        const int y0 = y * image.height / height;
        const int y1 = std::max(y0 + 1, (y + 1) * image.height / height);
        for (int x = 0; x < width; ++x) {
            const int x0 = x * image.width / width;
            const int x1 = std::max(x0 + 1, (x + 1) * image.width / width);
            double sum[4] = {0, 0, 0, 0};
            for (int j = y0; j < y1; ++j) {
                for (int i = x0; i < x1; ++i) {
                    const std::uint8_t* p = image.at(i, j);
                    const double a = p[3];
                    sum[0] += p[0] * a;
                    sum[1] += p[1] * a;
                    sum[2] += p[2] * a;
                    sum[3] += a;
                }
            }
            std::uint8_t* q = out.at(x, y);
            const double count = double(x1 - x0) * double(y1 - y0);
            for (int k = 0; k < 3; ++k) {
                q[k] = sum[3] > 0 ? roundToByte(sum[k] / sum[3]) : 0;
            }
            q[3] = roundToByte(sum[3] / count);
        }
    }
    return out;
}

io::RgbaImage contactSheet(const std::vector<SheetCell>& cells, const SheetOptions& options) {
    const int columns = std::max(options.columns, 1);
    const int rows = std::max(1, (static_cast<int>(cells.size()) + columns - 1) / columns);
    const int scale = labelScale(options);
    const int label = sheetLabelHeight(options);
    const int pitchX = options.cellWidth + options.gap;
    const int pitchY = options.cellHeight + label + options.gap;
    io::RgbaImage sheet(options.gap + columns * pitchX, options.gap + rows * pitchY);
    Colour background = options.background;
    background.a = 1.0f;
    fillRect(sheet, 0, 0, sheet.width, sheet.height, background);

    for (std::size_t k = 0; k < cells.size(); ++k) {
        const SheetCell& cell = cells[k];
        const int left = options.gap + static_cast<int>(k) % columns * pitchX;
        const int top = options.gap + static_cast<int>(k) / columns * pitchY;
        if (cell.picture.width > 0 && cell.picture.height > 0) {
            const double fit = std::min({1.0, double(options.cellWidth) / cell.picture.width,
                                         double(options.cellHeight) / cell.picture.height});
            const int w = std::max(1, static_cast<int>(std::lround(cell.picture.width * fit)));
            const int h = std::max(1, static_cast<int>(std::lround(cell.picture.height * fit)));
            const io::RgbaImage fitted = fit < 1.0 ? resizeImage(cell.picture, w, h) : cell.picture;
            const int x0 = left + (options.cellWidth - w) / 2;
            const int y0 = top + (options.cellHeight - h) / 2;
            for (int y = 0; y < h; ++y) {
                for (int x = 0; x < w; ++x) {
                    const std::uint8_t* p = fitted.at(x, y);
                    fillRect(sheet, x0 + x, y0 + y, 1, 1,
                             {p[0] / 255.0f, p[1] / 255.0f, p[2] / 255.0f, p[3] / 255.0f});
                }
            }
        } else {
            // A failed cell: a pale frame and the message, wrapped.
            const Colour frame{options.alarm.r, options.alarm.g, options.alarm.b, 0.08f};
            fillRect(sheet, left, top, options.cellWidth, options.cellHeight, frame);
            const int textScale = 1;
            const std::vector<std::string> lines =
                wrapText(cell.message, options.cellWidth - 8, textScale);
            for (std::size_t i = 0; i < lines.size(); ++i) {
                const int y = top + 4 + static_cast<int>(i) * LINE_HEIGHT * textScale;
                if (y + GLYPH_HEIGHT * textScale > top + options.cellHeight) {
                    break;
                }
                drawText(sheet, left + 4, y, lines[i], textScale, options.alarm);
            }
        }
        std::size_t begin = 0;
        for (int line = 0; line < options.labelLines && begin <= cell.label.size(); ++line) {
            const std::size_t end = std::min(cell.label.find('\n', begin), cell.label.size());
            const std::string text = fitText(
                std::string_view(cell.label).substr(begin, end - begin), options.cellWidth, scale);
            drawText(sheet, left + (options.cellWidth - textWidth(text, scale)) / 2,
                     top + options.cellHeight + 3 + line * LINE_HEIGHT * scale, text, scale,
                     cell.message.empty() ? options.ink : options.alarm);
            begin = end + 1;
        }
    }
    return sheet;
}

} // namespace atelier::render
