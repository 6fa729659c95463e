// The garment document: conversion to and from the index-based garment meshes the four samples
// identically, and their documents pass the reference check.

#include "io/project_file.h"

#include "patterns/curve.h"
#include "patterns/document.h"
#include "patterns/mesh.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

namespace atelier::patterns {
namespace {

const std::filesystem::path SAMPLES = std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/garments";

/// The sample garments by file name, loaded once.
const std::map<std::string, Garment>& samples() {
    static const std::map<std::string, Garment> loaded = [] {
        std::map<std::string, Garment> out;
        for (const auto& entry : std::filesystem::directory_iterator(SAMPLES)) {
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

GarmentMesh meshOf(const Garment& g) {
    MeshOptions options;
    options.particleDistance = 0.02;
    GarmentMesh mesh;
    const auto error = meshGarment(g, options, mesh);
    EXPECT_FALSE(error.has_value()) << *error;
    return mesh;
}

TEST(DocumentConversion, SamplesRoundTripToIdenticalMeshes) {
    ASSERT_EQ(samples().size(), 4U);
    for (const auto& [name, garment] : samples()) {
        SCOPED_TRACE(name);
        const GarmentDocument d = fromGarment(garment);
        const auto check = checkDocument(d);
        EXPECT_TRUE(check.ok()) << (check.ok() ? "" : check.error().toString());
        const Garment back = toGarment(d);
        const GarmentMesh a = meshOf(garment), b = meshOf(back);
        EXPECT_GT(a.triangleCount, 0);
        ASSERT_EQ(a.panels.size(), b.panels.size());
        for (std::size_t p = 0; p < a.panels.size(); ++p) {
            EXPECT_TRUE(a.panels[p].pattern == b.panels[p].pattern);
            EXPECT_TRUE(a.panels[p].triangles == b.panels[p].triangles);
            EXPECT_TRUE(a.panels[p].rest == b.panels[p].rest);
        }
        EXPECT_EQ(a.seamPairs, b.seamPairs);
        // And the document of the converted garment is the same document.
        EXPECT_EQ(dumpDocument(fromGarment(back)), dumpDocument(d));
    }
}

} // namespace
} // namespace atelier::patterns
