// The sample garments (assets/garments/*.atelier) on the default mannequin: they load, mesh
// into good triangles with seams matched one to one, and start placed outside the body with
// no intersections.
#include "io/body_file.h"
#include "io/project_file.h"

#include "patterns/assemble.h"
#include "patterns/mesh.h"

#include "sim/simulation.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <set>

namespace atelier::io {
namespace {

const std::filesystem::path SAMPLES = std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/garments";

TEST(Samples, MeshAndStartOutsideTheDefaultBody) {
    if (!std::filesystem::is_directory(SAMPLES)) {
        GTEST_SKIP() << "no sample garments in " << SAMPLES;
    }
    const auto body = loadBody(patterns::BodySource{}, SAMPLES, SAMPLES / "default");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    int count = 0;
    for (const auto& entry : std::filesystem::directory_iterator(SAMPLES)) {
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
                    << "seam " << mesh.seamOfPair[k] << " sews vertex " << v.vertex
                    << " of panel " << v.panel << " twice to panel " << w.panel;
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
        ++count;
    }
    EXPECT_GE(count, 3);
}

} // namespace
} // namespace atelier::io
