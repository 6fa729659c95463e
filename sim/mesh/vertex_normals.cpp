#include "sim/mesh/vertex_normals.h"

#include <Eigen/Geometry>

#include <cmath>

namespace atelier::sim {

void vertexNormals(const MatX3& x, const MatX3i& triangles, MatX3& normals) {
    normals.setZero(x.rows(), 3);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const Vec3 a = x.row(triangles(f, 0));
        const Vec3 b = x.row(triangles(f, 1));
        const Vec3 c = x.row(triangles(f, 2));
        const Vec3 n = (b - a).cross(c - a); // length = 2 × area: area weighting
        for (int k = 0; k < 3; ++k) {
            normals.row(triangles(f, k)) += n.transpose();
        }
    }
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
        const double len = normals.row(i).norm();
        if (len > 0 && std::isfinite(len)) {
            normals.row(i) /= len;
        } else {
            normals.row(i) = Vec3(0, 0, 1).transpose();
        }
    }
}

} // namespace atelier::sim
