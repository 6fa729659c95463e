#pragma once
// The bundled sample garments (assets/garments/*.atelier), loaded once, for tests that run
// over every sample.

#include "io/project_file.h"

#include "patterns/garment.h"
#include "patterns/mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <string>

namespace atelier::test {

/// The sample garments by file name (stem), loaded once.
inline const std::map<std::string, patterns::Garment>& sampleGarments() {
    static const std::map<std::string, patterns::Garment> loaded = [] {
        std::map<std::string, patterns::Garment> out;
        const std::filesystem::path dir =
            std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/garments";
        for (const auto& entry : std::filesystem::directory_iterator(dir)) {
            if (entry.path().extension() == ".atelier") {
                const auto project = io::loadProject(entry.path());
                if (project.ok()) {
                    out[entry.path().stem().string()] = project.value().garment;
                } else {
                    ADD_FAILURE() << project.error().toString();
                }
            }
        }
        return out;
    }();
    return loaded;
}

/// The garment meshed at 20 mm (a failure is reported, and an empty mesh returned).
inline patterns::GarmentMesh meshAt20mm(const patterns::Garment& g) {
    patterns::MeshOptions options;
    options.particleDistance = 0.02;
    patterns::GarmentMesh mesh;
    const auto error = patterns::meshGarment(g, options, mesh);
    EXPECT_FALSE(error.has_value()) << *error;
    return mesh;
}

} // namespace atelier::test
