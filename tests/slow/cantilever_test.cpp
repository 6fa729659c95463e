/// `atelier-cli bench cantilever` at 10 mm on the three meshes against the exact heavy elastica
/// (Peirce's cantilever, ASTM D1388).

#include "io/temp_dir.h"

#include "slow/csv_rows.h"

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace atelier {
namespace {

/// Largest |simulated − exact| tip-line angle over ρgL³/B = 1…50 at 10 mm [deg]: what the
/// model reaches (measured 1.16° on the criss-cross grid, too soft; 1.65° on the Delaunay strip
/// and 2.62° on the strip cut at 45° out of a square lattice, both too stiff: the shape
/// operator stores ~10% and ~20% above the continuum on those meshes; docs/benchmarks.md), not
/// the 1° target.
const std::map<std::string, double> TOLERANCE_DEG{
    {"regular", 1.4}, {"irregular", 2.0}, {"rotated", 3.0}};

struct Row {
    std::string mesh;
    double ratio = 0;
    double angle = 0;
    double exact = 0;
    bool atRest = false;
};

std::vector<Row> readCsv(const std::filesystem::path& path) {
    const std::vector<std::vector<std::string>> lines = test::csvRows(path);
    std::vector<Row> rows;
    for (std::size_t k = 1; k < lines.size(); ++k) { // after the header
        const std::vector<std::string>& cells = lines[k];
        if (cells.size() < 12) {
            continue;
        }
        rows.push_back({cells[0], std::stod(cells[2]), std::stod(cells[5]), std::stod(cells[6]),
                        cells[11] == "1"});
    }
    return rows;
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
    for (const Row& r : rows) {
        SCOPED_TRACE(r.mesh + " ratio " + std::to_string(r.ratio));
        EXPECT_TRUE(r.atRest);
        EXPECT_NEAR(r.angle, r.exact, TOLERANCE_DEG.at(r.mesh));
    }
}

} // namespace
} // namespace atelier
