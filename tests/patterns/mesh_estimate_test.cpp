/// The mesh size estimated before meshing, against the mesher on the samples.

#include "io/project_file.h"

#include "patterns/mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace atelier {
namespace {

TEST(MeshEstimate, WithinAFifthOfTheSamplesMeshes) {
    for (const char* name : {"skirt", "dress", "trousers", "tshirt"}) {
        const auto project = io::loadProject(std::string(ATELIER_SOURCE_DIR) + "/assets/garments/" +
                                             name + ".atelier");
        ASSERT_TRUE(project.ok()) << project.error().toString();
        const patterns::Garment& garment = project.value().garment;
        for (double h : {0.02, 0.01}) {
            patterns::MeshOptions options;
            options.particleDistance = h;
            patterns::GarmentMesh mesh;
            ASSERT_FALSE(patterns::meshGarment(garment, options, mesh).has_value());
            long vertices = 0;
            for (const patterns::PanelMesh& p : mesh.panels) {
                vertices += static_cast<long>(p.rest.rows());
            }
            const patterns::MeshEstimate e = patterns::estimateGarmentMesh(garment, h);
            const std::string label = std::string(name) + " at " + std::to_string(h) + " m";
            EXPECT_NEAR(static_cast<double>(e.vertices) / static_cast<double>(vertices), 1.0, 0.2)
                << label << ": " << e.vertices << " estimated, " << vertices << " meshed";
            EXPECT_NEAR(static_cast<double>(e.triangles) / static_cast<double>(mesh.triangleCount),
                        1.0, 0.2)
                << label << ": " << e.triangles << " estimated, " << mesh.triangleCount;
        }
    }
}

TEST(MeshEstimate, AParticleDistanceOfAMicronIsHuge) {
    const auto project =
        io::loadProject(std::string(ATELIER_SOURCE_DIR) + "/assets/garments/skirt.atelier");
    ASSERT_TRUE(project.ok());
    EXPECT_GT(patterns::estimateGarmentMesh(project.value().garment, 1e-5).vertices, 1000000000L);
    EXPECT_GT(patterns::estimateGarmentMesh(project.value().garment, 0.0).vertices, 1000000000L);
    EXPECT_GT(patterns::estimateGarmentMesh(project.value().garment, std::nan("")).vertices,
              1000000000L);
}

} // namespace
} // namespace atelier
