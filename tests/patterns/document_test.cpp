// The garment document: conversion to and from the index-based garment meshes the four samples
// identically, and their documents pass the reference check.

#include "io/project_file.h"

#include "patterns/curve.h"
#include "patterns/document.h"
#include "patterns/mesh.h"
#include "patterns/sample_garments.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>

namespace atelier::patterns {
namespace {

TEST(DocumentConversion, SamplesRoundTripToIdenticalMeshes) {
    ASSERT_EQ(test::sampleGarments().size(), 4U);
    for (const auto& [name, garment] : test::sampleGarments()) {
        SCOPED_TRACE(name);
        const GarmentDocument d = fromGarment(garment);
        const auto check = checkDocument(d);
        EXPECT_TRUE(check.ok()) << (check.ok() ? "" : check.error().toString());
        const Garment back = toGarment(d);
        const GarmentMesh a = test::meshAt20mm(garment), b = test::meshAt20mm(back);
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
