#pragma once
/// PNG pictures: 8-bit RGBA images encoded and decoded with zlib (no Qt, no libpng), written
/// atomically.

#include "io/limits.h"
#include "io/result.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::io {

/// An 8-bit RGBA picture: rows top to bottom, 4 bytes per pixel (R, G, B, A), straight (not
/// premultiplied) alpha.
struct RgbaImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels; ///< (height × width × 4)

    RgbaImage() = default;
    RgbaImage(int w, int h) : width(w), height(h), pixels(std::size_t(w) * std::size_t(h) * 4) {}
    /// The first of the 4 bytes of pixel (x, y), y = 0 at the top.
    std::uint8_t* at(int x, int y) {
        return pixels.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4;
    }
    const std::uint8_t* at(int x, int y) const {
        return pixels.data() + (std::size_t(y) * std::size_t(width) + std::size_t(x)) * 4;
    }
};

/// The PNG bytes of `image` (colour type 6, 8 bits, each row filtered with Paeth).
Result<std::string> encodePng(const RgbaImage& image);

/// Decodes a PNG of 8-bit RGBA or RGB (colour types 6 and 2, not interlaced): what encodePng
/// writes and what common tools write for such pictures. `name` prefixes the error messages.
Result<RgbaImage> decodePng(std::string_view bytes, const std::string& name = "");

/// Writes `image` as a PNG file, atomically (writeFileAtomically).
Result<void> writePng(const std::filesystem::path& path, const RgbaImage& image);

/// Reads a PNG file of at most `maxBytes`.
Result<RgbaImage> readPng(const std::filesystem::path& path,
                          std::uint64_t maxBytes = Limits{}.maxMeshBytes);

} // namespace atelier::io
