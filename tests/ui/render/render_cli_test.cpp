/// `atelier-cli render` and `drape --thumbnail` on tiny inputs: exit codes and the pictures.

#include "app/cli_run.h"

#include "ui/render/headless_context.h"

#include "io/png.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

namespace atelier {
namespace {

using test::CliRun;
using test::runCli;

std::string q(const std::filesystem::path& p) {
    return test::inQuotes(p);
}

/// A 0.4 m square in two panels (groups), its front facing +z.
const char* const TINY_GARMENT = R"(v -0.2 0.8 0
v 0 0.8 0
v 0.2 0.8 0
v -0.2 1.2 0
v 0 1.2 0
v 0.2 1.2 0
g left
f 1 2 5
f 1 5 4
g right
f 2 3 6
f 2 6 5
)";

/// A box behind it, as `drape --out` writes the body beside the garment.
const char* const TINY_BODY = R"(v -0.1 0.7 -0.3
v 0.1 0.7 -0.3
v 0.1 1.3 -0.3
v -0.1 1.3 -0.3
v -0.1 0.7 -0.1
v 0.1 0.7 -0.1
v 0.1 1.3 -0.1
v -0.1 1.3 -0.1
g body
f 5 6 7
f 5 7 8
f 2 1 4
f 2 4 3
f 1 5 8
f 1 8 4
f 6 2 3
f 6 3 7
f 8 7 3
f 8 3 4
f 1 2 6
f 1 6 5
)";

class RenderCli : public ::testing::Test {
  protected:
    void SetUp() override {
        if (auto context = render::HeadlessContext::create(); !context.ok()) {
            m_noContext = "no headless OpenGL context: " + context.error().toString();
        }
        m_garment = m_dir.write("tiny.obj", TINY_GARMENT);
        m_dir.write("tiny.body.obj", TINY_BODY);
    }
    std::string m_noContext; ///< why pictures cannot be drawn here, or empty
    test::TempDir m_dir;
    std::filesystem::path m_garment;
};

TEST_F(RenderCli, DrawsAGarmentAndItsBody) {
    if (!m_noContext.empty()) {
        GTEST_SKIP() << m_noContext;
    }
    const auto out = m_dir / "tiny.png";
    const CliRun run = runCli(m_dir, "render " + q(m_garment) + " --out " + q(out) +
                                         " --size 64x48 --view front --overlay wireframe");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    EXPECT_NE(run.stderrText.find("2 panels, body tiny.body.obj"), std::string::npos)
        << run.stderrText;
    const auto image = io::readPng(out);
    ASSERT_TRUE(image.ok()) << image.error().toString();
    EXPECT_EQ(image.value().width, 64);
    EXPECT_EQ(image.value().height, 48);
    const std::uint8_t* corner = image.value().at(0, 0);
    EXPECT_EQ(corner[0] + corner[1] + corner[2] + corner[3], 4 * 255);
    const std::uint8_t* centre = image.value().at(32, 24);
    EXPECT_LT(centre[0] + centre[1] + centre[2], 3 * 250);
}

TEST_F(RenderCli, EveryViewOnATransparentBackground) {
    if (!m_noContext.empty()) {
        GTEST_SKIP() << m_noContext;
    }
    const auto out = m_dir / "pic.png";
    const CliRun run = runCli(m_dir, "render " + q(m_garment) + " --out " + q(out) +
                                         " --size 32x32 --view all --background transparent");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    for (const char* view : {"front", "back", "left", "right", "three-quarter", "top"}) {
        const auto image = io::readPng(m_dir / ("pic-" + std::string(view) + ".png"));
        ASSERT_TRUE(image.ok()) << view;
        EXPECT_EQ(image.value().at(0, 0)[3], 0) << view;
    }
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST_F(RenderCli, BadArgumentsExitWithTwo) {
    const auto out = q(m_dir / "x.png");
    for (const char* args : {" --size 0x10", " --size 10", " --view sideways",
                             " --overlay sparkles", " --background bluish"}) {
        const CliRun run = runCli(m_dir, "render " + q(m_garment) + " --out " + out + args);
        EXPECT_EQ(run.exitCode, 2) << args;
        EXPECT_NE(run.stderrText.find("error: --"), std::string::npos) << run.stderrText;
    }
    EXPECT_EQ(runCli(m_dir, "render " + q(m_dir / "none.obj") + " --out " + out).exitCode, 2);
    const CliRun over = runCli(m_dir, "render " + q(m_garment) + " --out " + q(m_garment));
    EXPECT_EQ(over.exitCode, 2);
    EXPECT_NE(over.stderrText.find("--out"), std::string::npos) << over.stderrText;
}

/// Without an EGL driver the command fails and says what to install. glvnd's libEGL finds no
/// driver when pointed at a vendor file that does not exist (and a machine with no EGL at all
/// has none anyway).
TEST_F(RenderCli, WithoutADriverSaysWhatToInstall) {
    const CliRun run = runCli(m_dir, "render " + q(m_garment) + " --out " + q(m_dir / "x.png"),
                              "__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json ");
    if (run.exitCode == 0) { // a drawing machine whose libEGL is not glvnd
        GTEST_SKIP() << "this libEGL ignores __EGL_VENDOR_LIBRARY_FILENAMES (not glvnd)";
    }
    EXPECT_EQ(run.exitCode, 1);
    EXPECT_NE(run.stderrText.find("libegl-mesa0"), std::string::npos) << run.stderrText;
    EXPECT_FALSE(std::filesystem::exists(m_dir / "x.png"));
}

TEST_F(RenderCli, DrapeWritesAThumbnailAndRenderDrapesAProject) {
    if (!m_noContext.empty()) {
        GTEST_SKIP() << m_noContext;
    }
    const std::string skirt = std::string(ATELIER_SOURCE_DIR) + "/assets/garments/skirt.atelier";
    const auto thumb = m_dir / "thumb.png";
    CliRun run = runCli(m_dir, "drape " + q(skirt) +
                                   " --particle-distance 40 --time-limit 0.02 --threads 1 "
                                   "--thumbnail " +
                                   q(thumb));
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    auto image = io::readPng(thumb);
    ASSERT_TRUE(image.ok()) << run.stderrText;
    EXPECT_EQ(image.value().width, 256);
    EXPECT_EQ(image.value().height, 256);

    const auto out = m_dir / "skirt.png";
    run = runCli(m_dir, "render " + q(skirt) + " --out " + q(out) +
                            " --size 40x30 --particle-distance 40 --time-limit 0.02 --threads 1 "
                            "--overlay seams");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    // The project's seams come from its sewing (the skirt's two side seams, many edges each).
    const auto at = run.stderrText.find(" seam edges (sewn)");
    ASSERT_NE(at, std::string::npos) << run.stderrText;
    const auto from = run.stderrText.rfind("render: ", at);
    EXPECT_GE(std::stoi(run.stderrText.substr(from + 8, at - from - 8)), 4) << run.stderrText;
    image = io::readPng(out);
    ASSERT_TRUE(image.ok());
    EXPECT_EQ(image.value().width, 40);
}

/// Pixels of the pinhead's red (render/pin_markers.h): saturated, unlike the panel tones.
int redPinPixels(const io::RgbaImage& image) {
    int n = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            const std::uint8_t* p = image.at(x, y);
            n += p[0] > 170 && p[1] < 60 && p[2] < 70 ? 1 : 0;
        }
    }
    return n;
}

TEST_F(RenderCli, AProjectsPinsAreDrawnAsPinheadsUnlessTurnedOff) {
    if (!m_noContext.empty()) {
        GTEST_SKIP() << m_noContext;
    }
    const std::string source = ATELIER_SOURCE_DIR;
    const std::string drape = " --size 128x128 --view front --particle-distance 40 "
                              "--time-limit 0.05 --threads 1";
    const auto pinned = m_dir / "pinned.png";
    CliRun run = runCli(m_dir, "render " + q(source + "/assets/examples/apron-on-pins.atelier") +
                                   " --out " + q(pinned) + drape);
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    auto image = io::readPng(pinned);
    ASSERT_TRUE(image.ok());
    // Two heads of radius 4 px: about 2 × π × 2.5² of pure red inside their white rings.
    EXPECT_GE(redPinPixels(image.value()), 12) << "two pinheads";
    EXPECT_LE(redPinPixels(image.value()), 2 * 80);

    const auto hidden = m_dir / "hidden.png";
    run = runCli(m_dir, "render " + q(source + "/assets/examples/apron-on-pins.atelier") +
                            " --out " + q(hidden) + drape + " --no-pins");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    image = io::readPng(hidden);
    ASSERT_TRUE(image.ok());
    EXPECT_EQ(redPinPixels(image.value()), 0);

    const auto unpinned = m_dir / "unpinned.png";
    run = runCli(m_dir, "render " + q(source + "/assets/garments/skirt.atelier") + " --out " +
                            q(unpinned) + drape);
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    image = io::readPng(unpinned);
    ASSERT_TRUE(image.ok());
    EXPECT_EQ(redPinPixels(image.value()), 0) << "a project without pins has no pinheads";
}

} // namespace
} // namespace atelier
