#pragma once
/// A contact sheet: pictures laid out in a labelled grid (one cell per picture, its label under
/// it), drawn on the CPU with the bitmap font of text.h. A cell whose picture could not be made
/// shows its message instead.

#include "ui/render/scene.h"

#include "io/png.h"

#include <string>
#include <vector>

namespace atelier::render {

struct SheetCell {
    io::RgbaImage picture; ///< any size (fitted into the cell), or empty when `message` says why
    /// Under the picture: lines separated by '\n' (each cut with ".." to the cell's width;
    /// lines past SheetOptions::labelLines are dropped).
    std::string label;
    std::string message; ///< drawn wrapped in the cell in place of a picture, or empty
};

struct SheetOptions {
    int columns = 4;      ///< cells per row (≥ 1)
    int cellWidth = 256;  ///< picture area of a cell [pixels]
    int cellHeight = 256; ///< [pixels]
    int gap = 8;          ///< between cells and around the grid [pixels]
    int labelLines = 1;   ///< text lines under each cell
    Colour background{1.0f, 1.0f, 1.0f, 1.0f};
    Colour ink{0.15f, 0.15f, 0.15f, 1.0f};   ///< labels
    Colour alarm{0.70f, 0.10f, 0.10f, 1.0f}; ///< messages of failed cells
};

/// The height of a cell's label strip [pixels]: labelLines lines at the scale labels use.
int sheetLabelHeight(const SheetOptions& options);

/// The sheet: ceil(|cells| / columns) rows. Pictures are scaled down (area average, aspect
/// kept) to fit their cell, never up, centred, and blended over the background by their alpha;
/// the sheet is opaque. Labels are drawn at twice the font's size when the cell is at least
/// 192 pixels wide, else at its size.
io::RgbaImage contactSheet(const std::vector<SheetCell>& cells, const SheetOptions& options = {});

/// `image` resampled to `width`×`height` (≥ 1): each output pixel the alpha-weighted average
/// of the input pixels it covers (nearest pixel when enlarging).
io::RgbaImage resizeImage(const io::RgbaImage& image, int width, int height);

} // namespace atelier::render
