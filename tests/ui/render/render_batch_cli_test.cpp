/// `atelier-cli render-batch`, the overlays of `render` and `render --frames-dir` on tiny
/// inputs: exit codes, the files written and what the pictures show.

#include "app/cli_run.h"

#include "ui/render/headless_context.h"

#include "io/png.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

#include <string>

namespace atelier {
namespace {

using test::CliRun;
using test::runCli;

std::string quoted(const std::filesystem::path& p) {
    return test::inQuotes(p);
}

/// Two 0.2×0.4 m panels side by side, their front facing +z, sewn along x = 0 (vertices 2/5
/// of the left at the place of 7/10 of the right); UVs = the pattern, cut 10% shorter across
/// than drawn in the left panel (stretched), to size in the right one.
const char* const PANELS = R"(v -0.2 0.8 0
v 0 0.8 0
v -0.2 1.2 0
v 0 1.2 0
v 0 0.8 0
v 0.2 0.8 0
v 0 1.2 0
v 0.2 1.2 0
vt 0 0
vt 0.18 0
vt 0 0.4
vt 0.18 0.4
vt 0 0
vt 0.2 0
vt 0 0.4
vt 0.2 0.4
g left
f 1/1 2/2 4/4
f 1/1 4/4 3/3
g right
f 5/5 6/6 8/8
f 5/5 8/8 7/7
)";

/// A box behind the panels (z from -0.3 to -0.001): its front face 1 mm behind the cloth.
const char* const BOX = R"(v -0.3 0.7 -0.3
v 0.3 0.7 -0.3
v 0.3 1.3 -0.3
v -0.3 1.3 -0.3
v -0.3 0.7 -0.001
v 0.3 0.7 -0.001
v 0.3 1.3 -0.001
v -0.3 1.3 -0.001
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

class RenderBatchCli : public ::testing::Test {
  protected:
    void SetUp() override {
        if (auto context = render::HeadlessContext::create(); !context.ok()) {
            GTEST_SKIP() << "no headless OpenGL context: " << context.error().toString();
        }
        std::filesystem::create_directories(m_dir / "items");
        m_dir.write("items/panels.obj", PANELS);
        m_dir.write("items/panels.body.obj", BOX);
        m_dir.write("items/broken.obj", "v 0 0 0\nf 1 2 3\n");
    }
    io::RgbaImage picture(const std::string& name) {
        auto image = io::readPng(m_dir / name);
        EXPECT_TRUE(image.ok()) << name;
        return image.ok() ? std::move(image).value() : io::RgbaImage();
    }
    test::TempDir m_dir;
};

TEST_F(RenderBatchCli, AFolderGivesPicturesAndASheetAndAFailedItemDoesNotStopTheRest) {
    const CliRun run =
        runCli(m_dir, "render-batch " + quoted(m_dir / "items") + " --out " +
                          quoted(m_dir / "out") + " --views front,back,top --size 64x48");
    EXPECT_EQ(run.exitCode, 1) << run.stderrText;
    EXPECT_NE(run.stderrText.find("broken.obj"), std::string::npos) << run.stderrText;
    EXPECT_NE(run.stderrText.find("2 items x 3 views"), std::string::npos) << run.stderrText;
    for (const char* view : {"front", "back", "top"}) {
        const io::RgbaImage image = picture("out/panels-" + std::string(view) + ".png");
        EXPECT_EQ(image.width, 64);
        EXPECT_EQ(image.height, 48);
        EXPECT_FALSE(std::filesystem::exists(m_dir / ("out/broken-" + std::string(view) + ".png")));
    }
    // Items in name order (broken, panels), one row each: 3 columns of 64x48 cells.
    const io::RgbaImage sheet = picture("out/contact-sheet.png");
    EXPECT_EQ(sheet.width, 8 + 3 * (64 + 8));
    EXPECT_GT(sheet.height, 8 + 2 * (48 + 8));
    // The failed row shows its message in red ink, the other row the pictures.
    int alarm = 0;
    for (int y = 8; y < 8 + 48; ++y) {
        for (int x = 8; x < 8 + 64; ++x) {
            const std::uint8_t* p = sheet.at(x, y);
            alarm += p[0] > 140 && p[1] < 60 && p[2] < 60 ? 1 : 0;
        }
    }
    EXPECT_GT(alarm, 20);
}

TEST_F(RenderBatchCli, AListWithCommentsAndColumns) {
    m_dir.write("list.txt", "# the good one only\n\n  items/panels.obj  \n");
    const CliRun run = runCli(m_dir, "render-batch " + quoted(m_dir / "list.txt") + " --out " +
                                         quoted(m_dir / "sheet") +
                                         " --views front,left,right,three-quarter --size 40x40 "
                                         "--sheet-columns 2 --background transparent");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const io::RgbaImage front = picture("sheet/panels-front.png");
    EXPECT_EQ(front.at(0, 0)[3], 0) << "the pictures keep the transparent background";
    const io::RgbaImage sheet = picture("sheet/contact-sheet.png");
    EXPECT_EQ(sheet.width, 8 + 2 * (40 + 8));
    EXPECT_EQ(sheet.at(0, 0)[3], 255) << "the sheet is opaque";
}

TEST_F(RenderBatchCli, ProjectsAreDrapedFirstAndAMissingOneFails) {
    const std::string skirt = std::string(ATELIER_SOURCE_DIR) + "/assets/garments/skirt.atelier";
    m_dir.write("projects.txt", skirt + "\nmissing.atelier\n");
    const CliRun run = runCli(
        m_dir, "render-batch " + quoted(m_dir / "projects.txt") + " --out " + quoted(m_dir / "p") +
                   " --views front --size 48x48 --particle-distance 40 --time-limit 0.02 "
                   "--threads 1 --overlay seams");
    EXPECT_EQ(run.exitCode, 1) << run.stderrText;
    EXPECT_NE(run.stderrText.find("missing.atelier: the drape failed"), std::string::npos)
        << run.stderrText;
    EXPECT_NE(run.stderrText.find("seam edges (sewn)"), std::string::npos) << run.stderrText;
    EXPECT_EQ(picture("p/skirt-front.png").width, 48);
    EXPECT_FALSE(std::filesystem::exists(m_dir / "p/missing-front.png"));
    EXPECT_TRUE(std::filesystem::exists(m_dir / "p/contact-sheet.png"));
}

TEST_F(RenderBatchCli, BadInputExitsWithTwo) {
    m_dir.write("empty.txt", "# nothing\n");
    const auto out = quoted(m_dir / "o");
    for (const std::string& args :
         {quoted(m_dir / "empty.txt") + " --out " + out,
          quoted(m_dir / "none.txt") + " --out " + out,
          quoted(m_dir / "items") + " --out " + out + " --views front,sideways",
          quoted(m_dir / "items") + " --out " + out + " --size 10",
          quoted(m_dir / "items") + " --out " + out + " --overlay sparkles",
          quoted(m_dir / "items") + " --out " + out +
              " --sheet-cell 4096 --size 4096x4096 --views " + "front,back,left,right,top"}) {
        const CliRun run = runCli(m_dir, "render-batch " + args);
        EXPECT_EQ(run.exitCode, 2) << args << "\n" << run.stderrText;
    }
}

/// Share of the picture's pixels that are clearly red (stretched cloth on the strain ramp).
double redShare(const io::RgbaImage& image, int x0, int x1) {
    long red = 0;
    for (int y = 0; y < image.height; ++y) {
        for (int x = x0; x < x1; ++x) {
            const std::uint8_t* p = image.at(x, y);
            red += p[0] > p[1] + 60 && p[0] > p[2] + 60 ? 1 : 0;
        }
    }
    return double(red) / (double(x1 - x0) * image.height);
}

TEST_F(RenderBatchCli, StrainOverlayColoursTheStretchedPanelAndDrawsALegend) {
    const auto out = m_dir / "strain.png";
    const CliRun run =
        runCli(m_dir, "render " + quoted(m_dir / "items/panels.obj") + " --out " + quoted(out) +
                          " --size 256x256 --view front --overlay strain");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const io::RgbaImage image = picture("strain.png");
    // Left panel 11% stretched (red beyond the 10% range), right panel at rest (white).
    EXPECT_GT(redShare(image, 40, 120), 0.2);
    EXPECT_LT(redShare(image, 136, 170), 0.01);
    // The legend at the right edge: blue at the bottom of its bar, dark label ink.
    int blue = 0;
    int ink = 0;
    for (int y = 0; y < 256; ++y) {
        for (int x = 200; x < 256; ++x) {
            const std::uint8_t* p = image.at(x, y);
            blue += p[2] > 150 && p[0] < 90 ? 1 : 0;
            ink += p[0] + p[1] + p[2] < 150 ? 1 : 0;
        }
    }
    EXPECT_GT(blue, 20);
    EXPECT_GT(ink, 40);

    m_dir.write("plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const CliRun noUv = runCli(m_dir, "render " + quoted(m_dir / "plain.obj") + " --out " +
                                          quoted(m_dir / "x.png") + " --overlay strain");
    EXPECT_EQ(noUv.exitCode, 2);
    EXPECT_NE(noUv.stderrText.find("no pattern UVs"), std::string::npos) << noUv.stderrText;
}

TEST_F(RenderBatchCli, SeamAndContactOverlays) {
    const auto plain = m_dir / "plain.png";
    ASSERT_EQ(runCli(m_dir, "render " + quoted(m_dir / "items/panels.obj") + " --out " +
                                quoted(plain) + " --size 128x128 --view front")
                  .exitCode,
              0);
    const auto seams = m_dir / "seams.png";
    CliRun run = runCli(m_dir, "render " + quoted(m_dir / "items/panels.obj") + " --out " +
                                   quoted(seams) + " --size 128x128 --view front --overlay seams");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const io::RgbaImage a = picture("plain.png");
    const io::RgbaImage b = picture("seams.png");
    // The seam runs down the middle (x = 0): dark there, the rest as without it.
    int dark = 0;
    long changed = 0;
    for (int y = 0; y < 128; ++y) {
        for (int x = 0; x < 128; ++x) {
            const std::uint8_t* p = b.at(x, y);
            const std::uint8_t* o = a.at(x, y);
            const bool differs = std::abs(p[0] - o[0]) + std::abs(p[1] - o[1]) > 6;
            changed += differs ? 1 : 0;
            dark += differs && std::abs(x - 64) <= 3 && p[0] + p[1] + p[2] < 120 ? 1 : 0;
        }
    }
    EXPECT_GT(dark, 20);
    EXPECT_LT(changed, 128 * 12) << "only the seam line changed";

    // Contact: the cloth lies 1 mm in front of the box, inside the 4 mm default: amber.
    run = runCli(m_dir, "render " + quoted(m_dir / "items/panels.obj") + " --out " +
                            quoted(m_dir / "contact.png") +
                            " --size 128x128 --view front --overlay contact");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const io::RgbaImage c = picture("contact.png");
    const std::uint8_t* centre = c.at(64, 64);
    EXPECT_GT(centre[0], centre[2] + 60) << "amber, not the clear grey-blue";
    run = runCli(m_dir, "render " + quoted(m_dir / "items/panels.obj") + " --out " +
                            quoted(m_dir / "clear.png") +
                            " --size 128x128 --view front --overlay contact --contact-thickness "
                            "0.5");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const io::RgbaImage clearImage = picture("clear.png");
    const std::uint8_t* clear = clearImage.at(64, 64);
    EXPECT_LT(std::abs(clear[0] - clear[2]), 40) << "farther than 0.5 mm: not in contact";
    // 1 mm is above 0.9 mm but within the contact layer over it (25% more): resting, green.
    run = runCli(m_dir, "render " + quoted(m_dir / "items/panels.obj") + " --out " +
                            quoted(m_dir / "resting.png") +
                            " --size 128x128 --view front --overlay contact --contact-thickness "
                            "0.9");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const io::RgbaImage restingImage = picture("resting.png");
    const std::uint8_t* resting = restingImage.at(64, 64);
    EXPECT_GT(resting[1], resting[0] + 30) << "green";
    const CliRun noBody = runCli(m_dir, "render " + quoted(m_dir / "items/broken.obj") + " --out " +
                                            quoted(m_dir / "x.png") + " --overlay contact");
    EXPECT_EQ(noBody.exitCode, 2);
}

TEST_F(RenderBatchCli, FramesAreDrawnWithOneCamera) {
    std::filesystem::create_directories(m_dir / "frames");
    // Two frames of a square: the second moved up by 0.2 m. With one camera for both it moves
    // in the pictures; framed one by one it would not.
    const auto square = [](double y) {
        std::string s;
        for (const auto& [x, dy] : {std::pair{-0.1, 0.0}, {0.1, 0.0}, {0.1, 0.2}, {-0.1, 0.2}}) {
            s += "v " + std::to_string(x) + " " + std::to_string(y + dy) + " 0\n";
        }
        return s + "f 1 2 3\nf 1 3 4\n";
    };
    m_dir.write("frames/frame_00000.obj", square(1.0));
    m_dir.write("frames/frame_00001.obj", square(1.2));
    const CliRun run = runCli(m_dir, "render --frames-dir " + quoted(m_dir / "frames") + " --out " +
                                         quoted(m_dir / "pngs") + " --size 64x64 --view front");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    EXPECT_NE(run.stderrText.find("2 frames 64x64 written"), std::string::npos) << run.stderrText;
    EXPECT_NE(run.stderrText.find("(1 by position updates)"), std::string::npos) << run.stderrText;
    const auto centreRow = [](const io::RgbaImage& image) {
        double sum = 0;
        double n = 0;
        for (int y = 0; y < image.height; ++y) {
            for (int x = 0; x < image.width; ++x) {
                if (image.at(x, y)[0] < 250) {
                    sum += y;
                    n += 1;
                }
            }
        }
        return n > 0 ? sum / n : -1.0;
    };
    const double y0 = centreRow(picture("pngs/frame_00000.png"));
    const double y1 = centreRow(picture("pngs/frame_00001.png"));
    EXPECT_GT(y0 - y1, 10) << "the second frame is higher in the picture";
    EXPECT_EQ(runCli(m_dir, "render --frames-dir " + quoted(m_dir / "items") + " --out " +
                                quoted(m_dir / "p2"))
                  .exitCode,
              2)
        << "no frame_NNNNN.obj there";
}

} // namespace
} // namespace atelier
