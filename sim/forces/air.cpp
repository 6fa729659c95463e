#include "sim/forces/air.h"

#include "sim/core/parallel.h"

#include <Eigen/Geometry>

#include <cmath>

namespace atelier::sim {

namespace {

/// Smallest |n| = 2·area [m²] for which a triangle feels drag.
constexpr double MIN_NORMAL = 1e-20;

Mat3 crossMatrix(const Vec3& a) {
    Mat3 m;
    m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
    return m;
}

} // namespace

AirDrag::AirDrag(const ClothMesh& mesh, int offset, const AirOptions& air)
    : m_offset(offset), m_triangles(mesh.triangles), m_coefficient(air.dragCoefficient),
      m_wind(air.wind), m_gather(mesh.triangles, offset) {}

void AirDrag::addForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    const std::int64_t nf = m_triangles.rows();
    MatX3 buffer(3 * nf, 3);
    parallelFor(nf, [&](std::int64_t tt) {
        const int i0 = m_offset + m_triangles(tt, 0);
        const int i1 = m_offset + m_triangles(tt, 1);
        const int i2 = m_offset + m_triangles(tt, 2);
        const Vec3 x0 = x.row(i0).transpose();
        const Vec3 n = (x.row(i1).transpose() - x0).cross(x.row(i2).transpose() - x0);
        const double len = n.norm();
        Vec3 fv = Vec3::Zero();
        if (len > MIN_NORMAL) {
            const Vec3 u = (v.row(i0) + v.row(i1) + v.row(i2)).transpose() / 3.0 - m_wind;
            fv = (-m_coefficient / 6.0 * u.dot(n) / len) * n; // a third of f_tri
        }
        for (int a = 0; a < 3; ++a) {
            buffer.row(3 * tt + a) = fv.transpose();
        }
    });
    m_gather.gather(buffer, f);
}

void AirDrag::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    m_gather.addPattern(pairs);
}

void AirDrag::addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                          BlockSparseMatrix& J) const {
    const std::int64_t nf = m_triangles.rows();
    std::vector<Mat3> blocks(static_cast<std::size_t>(nf) * 9, Mat3::Zero());
    const bool exact = mode == JacobianMode::Exact;
    parallelFor(nf, [&](std::int64_t tt) {
        const Vec3 x0 = x.row(m_offset + m_triangles(tt, 0)).transpose();
        const Vec3 x1 = x.row(m_offset + m_triangles(tt, 1)).transpose();
        const Vec3 x2 = x.row(m_offset + m_triangles(tt, 2)).transpose();
        const Vec3 n = (x1 - x0).cross(x2 - x0);
        const double len = n.norm();
        if (!(len > MIN_NORMAL)) {
            return;
        }
        const double c6 = m_coefficient / 6.0;
        // ∂f_a/∂v_b = -(c/18) n nᵀ/|n| for every a, b.
        const Mat3 dv = (-c6 / 3.0 / len) * (n * n.transpose());
        std::array<Mat3, 3> dx{Mat3::Zero(), Mat3::Zero(), Mat3::Zero()};
        if (exact) {
            const Vec3 u =
                (v.row(m_offset + m_triangles(tt, 0)) + v.row(m_offset + m_triangles(tt, 1)) +
                 v.row(m_offset + m_triangles(tt, 2)))
                        .transpose() /
                    3.0 -
                m_wind;
            const Vec3 nh = n / len;
            // dφ/dn of φ(n) = -(c/6)(u·n) n/|n|.
            const Mat3 dn =
                -c6 * (nh * u.transpose() + u.dot(nh) * (Mat3::Identity() - nh * nh.transpose()));
            dx[0] = dn * crossMatrix(x2 - x1);
            dx[1] = dn * crossMatrix(x0 - x2);
            dx[2] = dn * crossMatrix(x1 - x0);
        }
        for (int a = 0; a < 3; ++a) {
            for (int b = 0; b < 3; ++b) {
                blocks[static_cast<std::size_t>((3 * tt + a) * 3 + b)] =
                    kx * dx[static_cast<std::size_t>(b)] + kv * dv;
            }
        }
    });
    m_gather.gatherJacobian(blocks, J);
}

} // namespace atelier::sim
