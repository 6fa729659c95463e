#include "io/png.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

namespace atelier::io {
namespace {

RgbaImage gradient(int width, int height) {
    RgbaImage image(width, height);
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            std::uint8_t* p = image.at(x, y);
            p[0] = static_cast<std::uint8_t>(x * 7);
            p[1] = static_cast<std::uint8_t>(y * 13);
            p[2] = static_cast<std::uint8_t>((x * y) % 251);
            p[3] = static_cast<std::uint8_t>(255 - x);
        }
    }
    return image;
}

TEST(Png, RoundTripIsExact) {
    test::TempDir dir;
    const RgbaImage image = gradient(37, 19);
    ASSERT_TRUE(writePng(dir / "g.png", image).ok());
    const auto read = readPng(dir / "g.png");
    ASSERT_TRUE(read.ok()) << read.error().toString();
    EXPECT_EQ(read.value().width, 37);
    EXPECT_EQ(read.value().height, 19);
    EXPECT_EQ(read.value().pixels, image.pixels);
}

TEST(Png, HeaderSaysRgba8) {
    const auto bytes = encodePng(gradient(3, 2));
    ASSERT_TRUE(bytes.ok());
    const std::string& s = bytes.value();
    EXPECT_EQ(s.substr(1, 3), "PNG");
    EXPECT_EQ(s.substr(12, 4), "IHDR");
    EXPECT_EQ(static_cast<int>(s[24]), 8); // bit depth
    EXPECT_EQ(static_cast<int>(s[25]), 6); // colour type RGBA
}

TEST(Png, RefusesWhatItCannotRead) {
    EXPECT_FALSE(decodePng("not a png").ok());
    EXPECT_FALSE(encodePng(RgbaImage()).ok());
    std::string bytes = encodePng(gradient(4, 4)).value();
    const auto truncated = decodePng(bytes.substr(0, bytes.size() - 30), "t.png");
    ASSERT_FALSE(truncated.ok());
    EXPECT_EQ(truncated.error().file, "t.png");
    bytes[25] = 3; // palette colour type
    EXPECT_FALSE(decodePng(bytes).ok());
}

} // namespace
} // namespace atelier::io
