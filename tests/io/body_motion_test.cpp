#include "io/mesh_import.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

using namespace atelier;

namespace {

/// A closed box 170 units tall along z (a "body" in centimetres, Z up), moved by (dx, dy, dz),
/// its first corner written twice (a split vertex the import welds).
std::string boxObj(double dx, double dy, double dz) {
    const double w = 40, d = 25, h = 170;
    const double corners[8][3] = {{0, 0, 0}, {w, 0, 0}, {w, d, 0}, {0, d, 0},
                                  {0, 0, h}, {w, 0, h}, {w, d, h}, {0, d, h}};
    std::ostringstream text;
    for (const auto& c : corners) {
        text << "v " << c[0] + dx << " " << c[1] + dy << " " << c[2] + dz << "\n";
    }
    text << "v " << dx << " " << dy << " " << dz << "\n";
    // Outward triangles (vertex 9 is corner 1 again).
    text << "f 9 3 2\nf 1 4 3\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\n"
            "f 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";
    return text.str();
}

} // namespace

TEST(BodyMotion, EveryFrameGetsTheFirstFramesUnitAxisFloorAndWeld) {
    const test::TempDir dir;
    std::vector<std::filesystem::path> files;
    const char* const names[3] = {"f0.obj", "f1.obj", "f2.obj"};
    for (int k = 0; k < 3; ++k) {
        // The box rises 10 cm per frame and moves 5 cm along x: the motion must be kept, not
        // stood on the floor again frame by frame.
        files.push_back(dir.write(names[k], boxObj(5.0 * k, 0, 10.0 * k)));
    }
    auto motion = io::importBodyMotion(files);
    ASSERT_TRUE(motion.ok()) << motion.error().toString();
    const io::BodyMotion& m = motion.value();
    EXPECT_EQ(m.first.report.units, io::LengthUnit::Centimetre);
    EXPECT_EQ(m.first.report.up, io::UpAxis::Z);
    ASSERT_EQ(m.first.vertices.rows(), 8); // the split corner welded
    ASSERT_EQ(m.frames.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
        ASSERT_EQ(m.frames[k].rows(), 8);
        const sim::MatX3 moved = m.frames[k] - m.first.vertices;
        for (Eigen::Index i = 0; i < moved.rows(); ++i) {
            // Z up becomes Y up: file z → y, file x → x.
            EXPECT_NEAR(moved(i, 0), 0.05 * static_cast<double>(k), 1e-9);
            EXPECT_NEAR(moved(i, 1), 0.10 * static_cast<double>(k), 1e-9);
            EXPECT_NEAR(moved(i, 2), 0.0, 1e-9);
        }
    }
    EXPECT_NEAR(m.frames[0].col(1).minCoeff(), 0.0, 1e-12);
}

TEST(BodyMotion, RefusesFramesOfAnotherMeshAndASingleFrame) {
    const test::TempDir dir;
    const auto first = dir.write("a.obj", boxObj(0, 0, 0));
    std::string other = boxObj(0, 0, 0);
    other += "f 1 2 3\n";
    const auto second = dir.write("b.obj", other);
    auto mixed = io::importBodyMotion({first, second});
    ASSERT_FALSE(mixed.ok());
    EXPECT_NE(mixed.error().toString().find(second.string()), std::string::npos);
    EXPECT_NE(mixed.error().toString().find("same mesh"), std::string::npos)
        << mixed.error().toString();

    auto single = io::importBodyMotion({first});
    ASSERT_FALSE(single.ok());
    EXPECT_NE(single.error().toString().find("at least two frames"), std::string::npos);

    const auto missing = dir / "missing.obj";
    auto absent = io::importBodyMotion({first, missing});
    ASSERT_FALSE(absent.ok());
    EXPECT_NE(absent.error().toString().find(missing.string()), std::string::npos);
}
