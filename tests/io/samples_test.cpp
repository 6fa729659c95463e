// The sample garments (assets/garments/*.atelier) on the default mannequin: they load, mesh
// into good triangles with seams matched one to one, and start placed outside the body with
// no intersections.
#include "io/body_file.h"
#include "io/project_file.h"

#include "patterns/assemble.h"
#include "patterns/mesh.h"

#include "sim/simulation.h"

#include "source_paths.h"

#include <gtest/gtest.h>

#include <array>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>
#include <vector>

namespace atelier::io {
namespace {

TEST(Samples, MeshAndStartOutsideTheDefaultBody) {
    if (!std::filesystem::is_directory(test::GARMENTS_DIR)) {
        GTEST_SKIP() << "no sample garments in " << test::GARMENTS_DIR;
    }
    const auto body =
        loadBody(patterns::BodySource{}, test::GARMENTS_DIR, test::GARMENTS_DIR / "default");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(test::GARMENTS_DIR)) {
        if (entry.path().extension() != ".atelier") {
            continue;
        }
        SCOPED_TRACE(entry.path().filename().string());
        const auto project = loadProject(entry.path());
        ASSERT_TRUE(project.ok()) << project.error().toString();
        const patterns::Project& p = project.value();
        EXPECT_TRUE(p.body.meshPath.empty()); // the samples use the mannequin
        patterns::MeshOptions options;
        options.particleDistance = p.drape.particleDistance;
        patterns::GarmentMesh mesh;
        const auto error = patterns::meshGarment(p.garment, options, mesh);
        ASSERT_FALSE(error.has_value()) << *error;
        EXPECT_GE(mesh.minAngleDeg, 25.0);
        EXPECT_FALSE(mesh.seamPairs.empty());
        // The two sides of every seam are as long as each other, within the ease tolerance: the
        // tshirt's sleeve cap was 10% longer than its armhole, and gathered in it curled the
        // bodice beside the side seam (README, "Patterns, the mannequin and draping").
        for (const std::string& warning : mesh.warnings) {
            ADD_FAILURE() << warning;
        }
        // One to one: within a seam, a vertex is sewn to one vertex of each other panel (a
        // vertex at the junction of two pieces, like a sleeve cap's top between front and
        // back, meets one vertex of each).
        std::set<std::tuple<int, int, int, int>> used;
        for (std::size_t k = 0; k < mesh.seamPairs.size(); ++k) {
            const auto& pair = mesh.seamPairs[k];
            for (int side = 0; side < 2; ++side) {
                const patterns::VertexRef& v = pair[static_cast<std::size_t>(side)];
                const patterns::VertexRef& w = pair[static_cast<std::size_t>(1 - side)];
                EXPECT_TRUE(used.insert({mesh.seamOfPair[k], v.panel, v.vertex, w.panel}).second)
                    << "seam " << mesh.seamOfPair[k] << " sews vertex " << v.vertex << " of panel "
                    << v.panel << " twice to panel " << w.panel;
            }
        }
        patterns::AssembledGarment assembled;
        const auto assembleError =
            patterns::assembleGarment(p.garment, mesh, body.value(), p.drape, assembled);
        ASSERT_FALSE(assembleError.has_value()) << *assembleError;
        sim::Simulation simulation(assembled.scene);
        ASSERT_TRUE(simulation.error().empty()) << simulation.error();
        EXPECT_EQ(simulation.penetration(), 0.0);
        EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
        EXPECT_NEAR(patterns::areaRatio(assembled.scene, simulation.positions()), 1.0, 0.005);
        // Each seam runs the way its two sides are placed: between two panels, its pairs start
        // closer together than they would with one side reversed (a reversed edge sews a
        // sleeve's cap top to the underarm, which no sewing can close).
        std::map<std::tuple<int, int, int>, std::vector<std::array<int, 2>>> bySeam;
        for (std::size_t k = 0; k < mesh.seamPairs.size(); ++k) {
            std::array<int, 2> ends{};
            for (std::size_t side = 0; side < 2; ++side) {
                const patterns::VertexRef& v = mesh.seamPairs[k][side];
                ends[side] = assembled.panelOffsets[static_cast<std::size_t>(v.panel)] + v.vertex;
            }
            bySeam[{mesh.seamOfPair[k], mesh.seamPairs[k][0].panel, mesh.seamPairs[k][1].panel}]
                .push_back(ends);
        }
        const sim::MatX3& x = simulation.positions();
        for (const auto& [key, pairs] : bySeam) {
            const int seam = std::get<0>(key);
            if (seam < 0) {
                continue; // a dart
            }
            double placed = 0, reversed = 0;
            for (std::size_t i = 0; i < pairs.size(); ++i) {
                placed += (x.row(pairs[i][0]) - x.row(pairs[i][1])).norm();
                reversed += (x.row(pairs[i][0]) - x.row(pairs[pairs.size() - 1 - i][1])).norm();
            }
            EXPECT_LE(placed, reversed)
                << "seam \"" << p.garment.seams[static_cast<std::size_t>(seam)].name
                << "\" between panels " << std::get<1>(key) << " and " << std::get<2>(key)
                << ": mean gap " << placed / static_cast<double>(pairs.size()) << " m as placed, "
                << reversed / static_cast<double>(pairs.size()) << " m with one side reversed";
        }
        ++count;
    }
    EXPECT_GE(count, 3);
}

} // namespace
} // namespace atelier::io
