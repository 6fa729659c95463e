/// `atelier-cli bench cantilever` at 10 mm on the three meshes against the exact heavy elastica
/// (Peirce's cantilever, ASTM D1388), and the 45° strip's rigidity against the straight one's.

#include "io/temp_dir.h"

#include "sim/analysis/heavy_elastica.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace atelier {
namespace {

/// Largest |simulated − exact| tip-line angle over ρgL³/B = 1…50 at 10 mm [deg]: what the model
/// reaches (measured 7.0° on the criss-cross grid, 4.1° and 4.9° on the Delaunay meshes, all of
/// them too soft, mostly at the clamp: docs/benchmarks.md), not the 1° target.
const std::map<std::string, double> TOLERANCE_DEG{
    {"regular", 7.5}, {"irregular", 5.0}, {"rotated", 5.0}};

struct Row {
    std::string mesh;
    double ratio = 0;
    double angle = 0;
    double exact = 0;
    bool atRest = false;
};

std::vector<Row> readCsv(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::string line;
    std::getline(in, line); // header
    std::vector<Row> rows;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream s(line);
        std::string cell;
        while (std::getline(s, cell, ',')) {
            cells.push_back(cell);
        }
        if (cells.size() < 12) {
            continue;
        }
        rows.push_back({cells[0], std::stod(cells[2]), std::stod(cells[5]), std::stod(cells[6]),
                        cells[11] == "1"});
    }
    return rows;
}

/// The ρgL³/B whose exact elastica hangs at `angleDeg`: a strip's effective rigidity.
double effectiveRatio(double angleDeg) {
    double lo = 1e-3;
    double hi = 1e4;
    for (int i = 0; i < 100; ++i) {
        const double mid = std::sqrt(lo * hi);
        const double deg = sim::solveHeavyElastica(mid).tipLineAngle * 180.0 / std::numbers::pi;
        (deg < angleDeg ? lo : hi) = mid;
    }
    return std::sqrt(lo * hi);
}

TEST(Cantilever, TipLineAngleFollowsTheHeavyElasticaOnEveryMesh) {
    const test::TempDir dir;
    const std::string command = std::string("\"") + ATELIER_CLI +
                                "\" bench cantilever --ratios 1,2,4,8,16,32,50 "
                                "--particle-distance 10 --mesh regular,irregular,rotated --out \"" +
                                (dir / "out").string() + "\" > \"" + (dir / "log").string() +
                                "\" 2>&1";
    const int status = std::system(command.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << command;
    const std::vector<Row> rows = readCsv(dir / "out" / "cantilever.csv");
    ASSERT_EQ(rows.size(), 21u);
    std::map<std::string, std::map<double, double>> angle;
    for (const Row& r : rows) {
        SCOPED_TRACE(r.mesh + " ratio " + std::to_string(r.ratio));
        EXPECT_TRUE(r.atRest);
        EXPECT_NEAR(r.angle, r.exact, TOLERANCE_DEG.at(r.mesh));
        EXPECT_GT(r.angle, r.exact); // too soft, never too stiff, at 10 mm
        angle[r.mesh][r.ratio] = r.angle;
    }
    // The strip cut at 45° to the weft (a weft-aligned lattice) bends like the straight strip
    // meshed the same way (Delaunay): the rigidities their angles imply agree within 3% up to
    // Peirce's ρgL³/B = 8 (measured within 1.1%; at 50, where the angle hardly moves with the
    // rigidity, 0.6° apart).
    for (double ratio : {1.0, 2.0, 4.0, 8.0}) {
        const double straight = effectiveRatio(angle["irregular"][ratio]);
        const double rotated = effectiveRatio(angle["rotated"][ratio]);
        EXPECT_NEAR(rotated / straight, 1.0, 0.03) << "ratio " << ratio;
    }
}

} // namespace
} // namespace atelier
