#include "sim/forces/springs.h"

#include "sim/core/parallel.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace atelier::sim {

double directionalModulus(const Material& m, const Vec2& d) {
    const double len2 = d.squaredNorm();
    const double c2 = len2 > 0 ? d.x() * d.x() / len2 : 0.5;
    return m.stretchWeft * c2 + m.stretchWarp * (1.0 - c2);
}

SpringStretch::SpringStretch(const ClothMesh& mesh, int offset, const Material& material,
                             bool crossSprings)
    : m_damping(material.damping), m_cross(crossSprings) {
    const int ne = static_cast<int>(mesh.edges.rows());
    for (int e = 0; e < ne; ++e) {
        const int a = mesh.edges(e, 0);
        const int b = mesh.edges(e, 1);
        const Vec2 d = mesh.rest.row(b) - mesh.rest.row(a);
        const double len = d.norm();
        double area = 0;
        for (int s = 0; s < 2; ++s) {
            const int t = mesh.edgeTriangles(e, s);
            if (t >= 0) {
                area += mesh.restArea[t] / 3.0;
            }
        }
        m_ends.push_back({a + offset, b + offset});
        m_rest.push_back(len);
        m_stiffness.push_back(directionalModulus(material, d) * area / (len * len));
    }
    if (crossSprings) {
        for (int h = 0; h < mesh.hinges.rows(); ++h) {
            const int a = mesh.hinges(h, 2);
            const int b = mesh.hinges(h, 3);
            const double len = (mesh.rest.row(b) - mesh.rest.row(a)).norm();
            if (len <= LENGTH_EPS) {
                continue;
            }
            // Area of the two triangles of the hinge, from the 4 rest points.
            const Vec2 p0 = mesh.rest.row(mesh.hinges(h, 0));
            const Vec2 p1 = mesh.rest.row(mesh.hinges(h, 1));
            const double area = std::abs(signedArea(p0, p1, mesh.rest.row(a))) +
                                std::abs(signedArea(p1, p0, mesh.rest.row(b)));
            m_ends.push_back({a + offset, b + offset});
            m_rest.push_back(len);
            m_stiffness.push_back(material.shear * area / 3.0 / (len * len));
        }
    }
    Eigen::MatrixXi ends(static_cast<Eigen::Index>(m_ends.size()), 2);
    for (std::size_t s = 0; s < m_ends.size(); ++s) {
        ends(static_cast<Eigen::Index>(s), 0) = m_ends[s][0] - offset;
        ends(static_cast<Eigen::Index>(s), 1) = m_ends[s][1] - offset;
    }
    m_gather = ElementGather(ends, offset);
    m_buffer.resize(2 * static_cast<Eigen::Index>(m_ends.size()), 3);
}

void SpringStretch::addForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    const auto n = static_cast<std::int64_t>(m_rest.size());
    parallelFor(n, [&](std::int64_t s) {
        const auto k = static_cast<std::size_t>(s);
        const int i = m_ends[k][0];
        const int j = m_ends[k][1];
        const Vec3 d = x.row(j) - x.row(i);
        const double l = d.norm();
        Vec3 fi = Vec3::Zero();
        if (l > LENGTH_EPS) {
            const Vec3 u = d / l;
            const double rate = (v.row(j) - v.row(i)).dot(u);
            fi = m_stiffness[k] * ((l - m_rest[k]) + m_damping * rate) * u;
        }
        m_buffer.row(2 * s) = fi.transpose();
        m_buffer.row(2 * s + 1) = -fi.transpose();
    });
    m_gather.gather(m_buffer, f);
}

double SpringStretch::energy(const MatX3& x) const {
    double e = 0;
    for (std::size_t s = 0; s < m_rest.size(); ++s) {
        const double dl = (x.row(m_ends[s][1]) - x.row(m_ends[s][0])).norm() - m_rest[s];
        e += 0.5 * m_stiffness[s] * dl * dl;
    }
    return e;
}

void SpringStretch::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    for (const auto& e : m_ends) {
        pairs.emplace_back(e[0], e[1]);
    }
}

void SpringStretch::addJacobian(const MatX3& x, const MatX3& v, double kx, double kv,
                                JacobianMode mode, BlockSparseMatrix& J) const {
    for (std::size_t s = 0; s < m_rest.size(); ++s) {
        const int i = m_ends[s][0];
        const int j = m_ends[s][1];
        const Vec3 d = x.row(j) - x.row(i);
        const double l = d.norm();
        if (l <= LENGTH_EPS) {
            continue;
        }
        const Vec3 u = d / l;
        const double k = m_stiffness[s];
        const Vec3 dv = v.row(j) - v.row(i);
        const double rate = dv.dot(u);
        const Mat3 uu = u * u.transpose();
        const Mat3 P = (Mat3::Identity() - uu) / l; // ∂u/∂x_j
        // f_i = T u, T = k((l - L) + c·rate). ∂f_i/∂x_j = k uu + T P + k c u (dv^T P).
        Mat3 Kx;
        if (mode == JacobianMode::Exact) {
            const double tension = k * ((l - m_rest[s]) + m_damping * rate);
            Kx = k * uu + tension * P + k * m_damping * u * (dv.transpose() * P);
        } else {
            const double tension = std::max(0.0, k * (l - m_rest[s]));
            Kx = k * uu + tension * P;
        }
        const Mat3 Kv = k * m_damping * uu; // ∂f_i/∂v_j
        const Mat3 B = kx * Kx + kv * Kv;
        // f_i depends on x_j - x_i: ∂f_i/∂x_i = -B, ∂f_i/∂x_j = B; f_j = -f_i.
        J.add(i, i, -B);
        J.add(i, j, B);
        J.add(j, i, B);
        J.add(j, j, -B);
    }
}

} // namespace atelier::sim
