/// Golden pictures: the sample skirt on its body at 256×256 from two views against reference
/// PNGs in tests/ui/render/golden/. A pixel differs when a channel is more than 16 levels off;
/// a picture fails when more than 0.5% of its pixels differ (antialiasing and driver rounding
/// stay well under that). On failure the picture and a diff (differing pixels red over a
/// faded copy) are written under the build folder. ATELIER_UPDATE_GOLDEN=1 rewrites the
/// references instead.

#include "render_fixture.h"

#include <cstdlib>
#include <filesystem>

namespace atelier::render::test {
namespace {

constexpr int CHANNEL_THRESHOLD = 16;
constexpr double MAX_DIFFERING_SHARE = 0.005;

struct Comparison {
    double differingShare = 1;
    io::RgbaImage diff;
};

Comparison compare(const io::RgbaImage& actual, const io::RgbaImage& expected) {
    Comparison c;
    if (actual.width != expected.width || actual.height != expected.height) {
        return c;
    }
    c.diff = io::RgbaImage(actual.width, actual.height);
    long differing = 0;
    for (int y = 0; y < actual.height; ++y) {
        for (int x = 0; x < actual.width; ++x) {
            const bool same = samePixel(actual.at(x, y), expected.at(x, y), CHANNEL_THRESHOLD);
            differing += same ? 0 : 1;
            std::uint8_t* d = c.diff.at(x, y);
            for (int k = 0; k < 3; ++k) {
                d[k] = same ? static_cast<std::uint8_t>(128 + actual.at(x, y)[k] / 2)
                            : static_cast<std::uint8_t>(k == 0 ? 255 : 0);
            }
            d[3] = 255;
        }
    }
    c.differingShare = double(differing) / (double(actual.width) * actual.height);
    return c;
}

void expectMatchesGolden(const io::RgbaImage& actual, const std::string& name) {
    const std::filesystem::path reference =
        std::filesystem::path(ATELIER_SOURCE_DIR) / "tests/ui/render/golden" / (name + ".png");
    if (const char* update = std::getenv("ATELIER_UPDATE_GOLDEN");
        update != nullptr && std::string(update) == "1") {
        ASSERT_TRUE(io::writePng(reference, actual).ok());
        GTEST_SKIP() << "wrote " << reference;
    }
    const auto expected = io::readPng(reference);
    ASSERT_TRUE(expected.ok()) << expected.error().toString();
    const Comparison c = compare(actual, expected.value());
    if (c.differingShare > MAX_DIFFERING_SHARE) {
        const std::filesystem::path out = std::filesystem::path(ATELIER_GOLDEN_OUT_DIR);
        std::filesystem::create_directories(out);
        EXPECT_TRUE(io::writePng(out / (name + "-actual.png"), actual).ok());
        if (c.diff.width > 0) {
            EXPECT_TRUE(io::writePng(out / (name + "-diff.png"), c.diff).ok());
        }
        ADD_FAILURE() << name << ": " << 100 * c.differingShare << "% of pixels differ (at most "
                      << 100 * MAX_DIFFERING_SHARE << "%); picture and diff written to " << out;
    }
}

TEST_F(RenderTest, GoldenSkirtThreeQuarter) {
    RenderOptions o;
    o.width = 256;
    o.height = 256;
    o.view = View::ThreeQuarter;
    expectMatchesGolden(draw(skirtOnBody(), o), "skirt-three-quarter");
}

TEST_F(RenderTest, GoldenSkirtFrontWireframe) {
    RenderOptions o;
    o.width = 256;
    o.height = 256;
    o.view = View::Front;
    o.wireframe = true;
    expectMatchesGolden(draw(skirtOnBody(), o), "skirt-front-wireframe");
}

TEST(GoldenCompare, CountsPixelsBeyondTheThreshold) {
    io::RgbaImage a(10, 10);
    io::RgbaImage b = a;
    b.at(3, 3)[1] = CHANNEL_THRESHOLD + 1; // differs
    b.at(4, 4)[2] = CHANNEL_THRESHOLD;     // within the threshold
    const Comparison c = compare(a, b);
    EXPECT_DOUBLE_EQ(c.differingShare, 0.01);
    EXPECT_EQ(c.diff.at(3, 3)[0], 255);
    EXPECT_DOUBLE_EQ(compare(a, io::RgbaImage(5, 5)).differingShare, 1);
}

} // namespace
} // namespace atelier::render::test
