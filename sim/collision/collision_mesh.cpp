#include "sim/collision/collision_mesh.h"

#include <algorithm>
#include <numeric>

namespace atelier::sim {

namespace {

/// Representative of each vertex's sewn group (union–find over the scene's seam pairs).
std::vector<int> sewnAliases(const SceneSpec& scene, int n) {
    std::vector<int> alias(static_cast<std::size_t>(n));
    std::iota(alias.begin(), alias.end(), 0);
    auto root = [&](int v) {
        while (alias[static_cast<std::size_t>(v)] != v) {
            v = alias[static_cast<std::size_t>(v)];
        }
        return v;
    };
    for (const SeamPair& sp : scene.seams) {
        const int ra = root(sp.a), rb = root(sp.b);
        if (ra != rb) {
            alias[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
        }
    }
    for (int v = 0; v < n; ++v) {
        alias[static_cast<std::size_t>(v)] = root(v);
    }
    return alias;
}

} // namespace

CollisionMesh::CollisionMesh(const SceneSpec& scene, const std::vector<int>& offsets) {
    const int n = offsets.back();
    // Sewn vertices are one vertex for adjacency: their triangles touch by design.
    alias = sewnAliases(scene, n);
    clothOf.assign(static_cast<std::size_t>(n), 0);
    thickness.resize(n);
    int triangleCount = 0, edgeCount = 0;
    for (const ClothSpec& c : scene.cloths) {
        triangleCount += c.mesh.triangleCount();
        edgeCount += static_cast<int>(c.mesh.edges.rows());
    }
    triangles.resize(triangleCount, 3);
    edges.resize(edgeCount, 2);
    ownedVertices.assign(static_cast<std::size_t>(triangleCount), {});
    ownedEdges.assign(static_cast<std::size_t>(triangleCount), {});
    neighbours.assign(static_cast<std::size_t>(n), {});
    std::vector<char> owned(static_cast<std::size_t>(n), 0);
    vertexTriangle.assign(static_cast<std::size_t>(n), 0);
    vertexTriangles.assign(static_cast<std::size_t>(n), {});
    int t0 = 0, e0 = 0;
    for (std::size_t ci = 0; ci < scene.cloths.size(); ++ci) {
        const ClothSpec& c = scene.cloths[ci];
        const int off = offsets[ci];
        selfCloth.push_back(c.selfCollision ? 1 : 0);
        anySelf = anySelf || c.selfCollision;
        maxThickness = std::max(maxThickness, c.thickness);
        for (int i = 0; i < c.mesh.vertexCount(); ++i) {
            clothOf[static_cast<std::size_t>(off + i)] = static_cast<int>(ci);
            thickness[off + i] = c.thickness;
        }
        for (int t = 0; t < c.mesh.triangleCount(); ++t) {
            triangleCloth.push_back(static_cast<int>(ci));
            for (int k = 0; k < 3; ++k) {
                const int v = c.mesh.triangles(t, k) + off;
                triangles(t0 + t, k) = v;
                vertexTriangles[static_cast<std::size_t>(v)].push_back(t0 + t);
                if (!owned[static_cast<std::size_t>(v)]) {
                    owned[static_cast<std::size_t>(v)] = 1;
                    vertexTriangle[static_cast<std::size_t>(v)] = t0 + t;
                    ownedVertices[static_cast<std::size_t>(t0 + t)].push_back(v);
                }
            }
        }
        for (int e = 0; e < c.mesh.edges.rows(); ++e) {
            const int a = c.mesh.edges(e, 0) + off, b = c.mesh.edges(e, 1) + off;
            edges(e0 + e, 0) = a;
            edges(e0 + e, 1) = b;
            ownedEdges[static_cast<std::size_t>(t0 + c.mesh.edgeTriangles(e, 0))].push_back(e0 + e);
            neighbours[static_cast<std::size_t>(a)].push_back(b);
            neighbours[static_cast<std::size_t>(b)].push_back(a);
        }
        t0 += c.mesh.triangleCount();
        e0 += static_cast<int>(c.mesh.edges.rows());
    }
}

std::vector<int> CollisionMesh::trianglesAround(const std::vector<int>& vertices) const {
    std::vector<int> out;
    for (int v : vertices) {
        const std::vector<int>& incident = vertexTriangles[static_cast<std::size_t>(v)];
        out.insert(out.end(), incident.begin(), incident.end());
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

} // namespace atelier::sim
