#include "ui/render/ambient_occlusion.h"

#include "sim/collision/bvh.h"
#include "sim/mesh/vertex_normals.h"

#include <algorithm>
#include <cmath>

namespace atelier::render {

std::vector<std::vector<float>> ambientOcclusion(const Scene& scene,
                                                 const AmbientOcclusionOptions& options) {
    std::vector<sim::SurfaceBvh> trees;
    trees.reserve(scene.meshes.size());
    for (const DrawMesh& mesh : scene.meshes) {
        trees.emplace_back(mesh.triangles, mesh.positions);
        if (mesh.triangles.rows() > 0) {
            trees.back().refit(mesh.positions, nullptr, 0.0);
        }
    }
    const int samples = std::max(options.samples, 1);
    std::vector<std::vector<float>> out;
    for (const DrawMesh& mesh : scene.meshes) {
        sim::MatX3 normals = mesh.normals;
        if (normals.rows() == 0) {
            sim::vertexNormals(mesh.positions, mesh.triangles, normals);
        }
        std::vector<float> visibility(static_cast<std::size_t>(mesh.positions.rows()), 1.0f);
        for (Eigen::Index i = 0; i < mesh.positions.rows(); ++i) {
            const sim::Vec3 p = mesh.positions.row(i).transpose();
            const sim::Vec3 n = normals.row(i).transpose();
            if (!(n.squaredNorm() > 0.25)) {
                continue; // a vertex of no triangle: nothing to shade
            }
            double occlusion = 0;
            for (int k = 0; k < samples; ++k) {
                const double r = options.radius * std::ldexp(1.0, k - samples + 1);
                const sim::Vec3 q = p + r * n;
                double nearest = r;
                for (std::size_t m = 0; m < trees.size(); ++m) {
                    if (scene.meshes[m].triangles.rows() == 0) {
                        continue;
                    }
                    const auto [triangle, point] =
                        trees[m].closestTriangle(scene.meshes[m].positions, q, nearest);
                    if (triangle >= 0) {
                        nearest = std::min(nearest, point.distance);
                    }
                }
                occlusion += (r - nearest) / r;
            }
            visibility[static_cast<std::size_t>(i)] = static_cast<float>(
                std::clamp(1.0 - options.strength * occlusion / samples, 0.0, 1.0));
        }
        out.push_back(std::move(visibility));
    }
    return out;
}

} // namespace atelier::render
