/// tools/drape_work_precision.py run end to end on a coarse skirt: one setting against a
/// reference, measured from the meshes the two drapes write.

#include "io/temp_dir.h"

#include "slow/csv_rows.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace atelier {
namespace {

// The skirt at 40 mm with a 20 ms step against the same with 10 ms and CG 1e-6 (about 10 s):
// the row says how long, how many steps and iterations, how far from the reference (a
// different step rests elsewhere, by millimetres to centimetres, never by metres) and that
// the drape is clean; the plot is written.
TEST(DrapeWorkPrecision, MeasuresASettingAgainstItsReferenceFromTheMeshes) {
    const test::TempDir dir;
    const std::string command =
        std::string("python3 \"") + ATELIER_SOURCE_DIR + "/tools/drape_work_precision.py\" \"" +
        ATELIER_SOURCE_DIR + "/assets/garments/skirt.atelier\" --cli \"" + ATELIER_CLI +
        "\" --particle-distance 40 --dts 0.02 --cg-tolerances 1e-3 --solvers block-jacobi "
        "--ref-dt 0.01 --ref-time-limit 3 --out \"" +
        (dir / "wp.csv").string() + "\" --plot \"" + (dir / "wp.svg").string() + "\" > \"" +
        (dir / "log").string() + "\" 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << command;
    const auto rows = test::csvRows(dir / "wp.csv");
    ASSERT_EQ(rows.size(), 2u) << "a header and one setting";
    ASSERT_EQ(rows[0].size(), 13u);
    EXPECT_EQ(rows[0][8], "rms_error_m");
    const auto& r = rows[1];
    ASSERT_EQ(r.size(), 13u);
    EXPECT_EQ(r[3], "block-jacobi");
    EXPECT_GT(std::stod(r[4]), 0.0) << "wall time";
    EXPECT_GT(std::stol(r[5]), 0) << "steps";
    EXPECT_GT(std::stol(r[6]), 0) << "CG iterations";
    EXPECT_GT(std::stod(r[7]), 0.0) << "rested at [s]";
    const double rms = std::stod(r[8]);
    const double largest = std::stod(r[9]);
    EXPECT_GT(rms, 1e-5);
    EXPECT_LT(rms, 0.1);
    EXPECT_GE(largest, rms);
    EXPECT_EQ(r[12], "clean");
    std::ifstream svg(dir / "wp.svg");
    std::string head;
    std::getline(svg, head);
    EXPECT_EQ(head.rfind("<svg", 0), 0u);
}

} // namespace
} // namespace atelier
