#include "io/mesh_export.h"
#include "io/mesh_import.h"
#include "io/obj.h"
#include "io/temp_dir.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

namespace atelier {
namespace {

/// Two panels of two triangles each, side by side in x, with a seam along x = 0 (front vertices
/// 1, 3 on the seam; back vertices 4, 6 on it): each panel has its own 4 vertices and UVs.
struct TwoPanels {
    sim::MatX3 x;
    sim::MatX3i triangles;
    sim::MatX2 uvs;
    std::vector<io::ObjGroup> groups;
    std::vector<std::pair<int, int>> welds;
};

TwoPanels twoPanels() {
    TwoPanels p;
    p.x.resize(8, 3);
    p.x << -0.2, 0.0, 0.1, 0.0, 0.0, 0.1, -0.2, 0.3, 0.1, 0.0, 0.3, 0.1, //
        0.0, 0.0, 0.1, 0.2, 0.0, 0.0, 0.0, 0.3, 0.1, 0.2, 0.3, 0.0;
    p.triangles.resize(4, 3);
    p.triangles << 0, 1, 3, 0, 3, 2, 4, 5, 7, 4, 7, 6;
    p.uvs.resize(8, 2);
    p.uvs << 0, 0, 0.2, 0, 0, 0.3, 0.2, 0.3, //
        0, 0, 0.22, 0, 0, 0.3, 0.22, 0.3;
    p.groups = {io::ObjGroup{"front", 0, 2}, io::ObjGroup{"side panel", 2, 2}};
    p.welds = {{1, 4}, {3, 6}};
    return p;
}

io::SurfaceMesh welded() {
    const TwoPanels p = twoPanels();
    return io::weldedSurface(p.x, p.triangles, p.uvs, p.groups, p.welds);
}

TEST(WeldedSurface, SeamVerticesBecomeOneWithAUvPerPanel) {
    const io::SurfaceMesh s = welded();
    EXPECT_EQ(s.positions.rows(), 6);
    EXPECT_EQ(s.uvs.rows(), 8);
    EXPECT_EQ(s.uvTriangles, twoPanels().triangles);
    // The two triangles across the seam share the vertices of its edge.
    EXPECT_EQ(s.triangles(0, 1), s.triangles(2, 0));
    EXPECT_EQ(s.triangles(0, 2), s.triangles(3, 2));
    const io::EdgeFigures edges = io::edgeFigures(s.triangles, s.positions.rows());
    EXPECT_EQ(edges.boundaryEdges, 6); // the outline of the two panels together
    EXPECT_EQ(edges.nonManifoldEdges, 0);
    const TwoPanels p = twoPanels();
    const io::SurfaceMesh split = io::weldedSurface(p.x, p.triangles, p.uvs, p.groups, {});
    EXPECT_EQ(split.positions.rows(), 8);
    EXPECT_EQ(io::edgeFigures(split.triangles, 8).boundaryEdges, 8);
}

TEST(MeshExport, FormatsFollowTheExtensionOrTheirName) {
    EXPECT_EQ(io::meshFormatOfPath("a/b.OBJ"), io::MeshFormat::Obj);
    EXPECT_EQ(io::meshFormatOfPath("b.glb"), io::MeshFormat::Glb);
    EXPECT_EQ(io::meshFormatOfPath("b.fbx"), io::MeshFormat::Fbx);
    EXPECT_EQ(io::meshFormatOfPath("b.ply"), io::MeshFormat::Ply);
    EXPECT_EQ(io::meshFormatOfPath("b.gltf"), std::nullopt);
    EXPECT_EQ(io::parseMeshFormat("fbx-ascii"), io::MeshFormat::FbxAscii);
    EXPECT_EQ(io::parseMeshFormat("stl"), std::nullopt);
    EXPECT_EQ(io::meshFormatList(), "obj, glb, fbx, fbx-ascii, ply");
}

TEST(MeshExport, ObjKeepsSharedVerticesAndHasAGroupAndMaterialPerPanel) {
    const test::TempDir dir;
    const io::SurfaceMesh s = welded();
    ASSERT_TRUE(io::exportMesh(dir / "g.obj", s, io::MeshFormat::Obj).ok());
    const std::string mtl = test::readText(dir / "g.mtl");
    EXPECT_NE(mtl.find("newmtl front\n"), std::string::npos) << mtl;
    EXPECT_NE(mtl.find("newmtl side_panel\n"), std::string::npos) << mtl;
    const std::string text = test::readText(dir / "g.obj");
    EXPECT_NE(text.find("mtllib g.mtl\n"), std::string::npos);
    EXPECT_NE(text.find("g side_panel\nusemtl side_panel\n"), std::string::npos) << text;

    // Our reader: 6 positions; with UVs it splits each (v, vt) pair, so the 2 seam vertices
    // come back as 4, and `sourceVertex` names the shared `v`.
    auto back = io::readObj(dir / "g.obj");
    ASSERT_TRUE(back.ok()) << back.error().toString();
    EXPECT_EQ(back.value().triangles.rows(), 4);
    EXPECT_EQ(back.value().positions.rows(), 8);
    EXPECT_EQ(*std::max_element(back.value().sourceVertex.begin(), back.value().sourceVertex.end()),
              5);
    ASSERT_EQ(back.value().groups.size(), 2u);
    EXPECT_EQ(back.value().groups[1].name, "side_panel");
    for (Eigen::Index i = 0; i < back.value().positions.rows(); ++i) {
        const int v = back.value().sourceVertex[static_cast<std::size_t>(i)];
        EXPECT_EQ(back.value().positions.row(i), s.positions.row(v)); // exact
    }
    // assimp reads it with the materials of the MTL.
    auto viaAssimp = io::readMesh(dir / "g.obj");
    ASSERT_TRUE(viaAssimp.ok()) << viaAssimp.error().toString();
    EXPECT_EQ(viaAssimp.value().triangles.rows(), 4);
    EXPECT_EQ(std::set<std::string>(viaAssimp.value().materials.begin(),
                                    viaAssimp.value().materials.end()),
              (std::set<std::string>{"front", "side_panel"}));
}

/// Every read position is one of the surface's, to single precision.
void expectPositionsFrom(const sim::MatX3& read, const sim::MatX3& written) {
    for (Eigen::Index i = 0; i < read.rows(); ++i) {
        double nearest = 1e300;
        for (Eigen::Index j = 0; j < written.rows(); ++j) {
            nearest = std::min(nearest, (read.row(i) - written.row(j)).norm());
        }
        EXPECT_LT(nearest, 1e-6) << "read vertex " << i;
    }
}

TEST(MeshExport, GlbFbxAndPlyReadBackWithTheirCountsAndPositions) {
    const test::TempDir dir;
    const io::SurfaceMesh s = welded();
    struct Case {
        std::string name;
        io::MeshFormat format;
        long vertices; ///< as assimp reads them back (its FBX reader: one per face corner)
        std::size_t meshes;
    };
    // glTF and FBX: one mesh per panel, 4 vertices each; PLY: the 6 shared vertices, one
    // mesh (no UVs: a seam vertex has two).
    for (const Case& c : {Case{"g.glb", io::MeshFormat::Glb, 8, 2},
                          Case{"g-ascii.fbx", io::MeshFormat::FbxAscii, 12, 2},
                          Case{"g.ply", io::MeshFormat::Ply, 6, 1}}) {
        SCOPED_TRACE(c.name);
        ASSERT_TRUE(io::exportMesh(dir / c.name, s, c.format).ok());
        auto back = io::readMesh(dir / c.name);
        ASSERT_TRUE(back.ok()) << back.error().toString();
        EXPECT_EQ(back.value().triangles.rows(), 4);
        EXPECT_EQ(back.value().positions.rows(), c.vertices);
        EXPECT_EQ(back.value().materials.size(), c.meshes);
        EXPECT_EQ(back.value().hasUvs, c.format != io::MeshFormat::Ply);
        expectPositionsFrom(back.value().positions, s.positions);
        if (c.meshes == 2) {
            EXPECT_EQ(
                std::set<std::string>(back.value().materials.begin(), back.value().materials.end()),
                (std::set<std::string>{"front", "side_panel"}));
        }
    }
    // assimp cannot read its own binary FBX back: check its header and that it holds more
    // than the header.
    ASSERT_TRUE(io::exportMesh(dir / "g.fbx", s, io::MeshFormat::Fbx).ok());
    const std::string fbx = test::readText(dir / "g.fbx");
    const std::string magic("Kaydara FBX Binary  \0", 21);
    EXPECT_EQ(fbx.substr(0, magic.size()), magic);
    EXPECT_GT(fbx.size(), 1000u);
    // A split surface (one UV per vertex) keeps its UVs in PLY.
    const TwoPanels p = twoPanels();
    ASSERT_TRUE(io::exportMesh(dir / "split.ply",
                               io::weldedSurface(p.x, p.triangles, p.uvs, p.groups, {}),
                               io::MeshFormat::Ply)
                    .ok());
    auto split = io::readMesh(dir / "split.ply");
    ASSERT_TRUE(split.ok());
    EXPECT_TRUE(split.value().hasUvs);
    EXPECT_EQ(split.value().positions.rows(), 8);
}

TEST(MeshExport, BadSurfacesAndPathsGiveErrors) {
    const test::TempDir dir;
    io::SurfaceMesh s = welded();
    s.positions(0, 0) = std::nan("");
    auto r = io::exportMesh(dir / "n.glb", s, io::MeshFormat::Glb);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().toString(),
              (dir / "n.glb").string() + ": the surface has a non-finite position");
    EXPECT_FALSE(std::filesystem::exists(dir / "n.glb"));
    io::SurfaceMesh empty;
    EXPECT_FALSE(io::exportMesh(dir / "e.ply", empty, io::MeshFormat::Ply).ok());
    r = io::exportMesh(dir / "missing" / "x.glb", welded(), io::MeshFormat::Glb);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().file, (dir / "missing" / "x.glb").string());
}

} // namespace
} // namespace atelier
