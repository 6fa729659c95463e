#include "sim/forces/fem.h"

#include "sim/core/parallel.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace atelier::sim {

namespace {

using Mat32 = Eigen::Matrix<double, 3, 2>;
using Mat23 = Eigen::Matrix<double, 2, 3>;

/// Voigt vector (E_xx, E_yy, 2E_xy) of sym(a bᵀ) for 2-vectors a, b.
Vec3 symOuterVoigt(const Vec2& a, const Vec2& b) {
    return {a.x() * b.x(), a.y() * b.y(), a.x() * b.y() + a.y() * b.x()};
}

/// 2×2 symmetric stress from its Voigt form (S_xx, S_yy, S_xy).
Mat2 stressMatrix(const Vec3& s) {
    Mat2 m;
    m << s.x(), s.z(), s.z(), s.y();
    return m;
}

/// Green strain (E_xx, E_yy, 2E_xy) of F.
Vec3 greenVoigt(const Mat32& F) {
    const Mat2 c = F.transpose() * F;
    return {0.5 * (c(0, 0) - 1.0), 0.5 * (c(1, 1) - 1.0), c(0, 1)};
}

/// Symmetric 2×2 with eigenvalues clamped at ≥ 0.
Mat2 clampPositive(const Mat2& s) {
    Eigen::SelfAdjointEigenSolver<Mat2> eig(s);
    const Vec2 lambda = eig.eigenvalues().cwiseMax(0.0);
    return eig.eigenvectors() * lambda.asDiagonal() * eig.eigenvectors().transpose();
}

} // namespace

Mat3 orthotropicStiffness(const Material& m) {
    const double e1 = m.stretchWeft;
    const double e2 = m.stretchWarp;
    const double nu12 = m.poisson;
    const double nu21 = e1 > 0 ? nu12 * e2 / e1 : 0.0;
    const double d = std::max(1.0 - nu12 * nu21, 1e-6);
    Mat3 c = Mat3::Zero();
    c(0, 0) = e1 / d;
    c(0, 1) = nu21 * e1 / d;
    c(1, 0) = nu12 * e2 / d;
    c(1, 1) = e2 / d;
    c(2, 2) = m.shear;
    return c;
}

FemStretch::FemStretch(const ClothMesh& mesh, int offset, const Material& material)
    : m_offset(offset), m_triangles(mesh.triangles), m_restArea(mesh.triangleCount()),
      m_stiffness(orthotropicStiffness(material)), m_damping(std::max(material.damping, 0.0)),
      m_gather(mesh.triangles, offset) {
    if (material.stretchKnee > 0) {
        m_knee = material.stretchKnee;
        m_stiffening = Vec2(std::max(material.stretchWeftBeyond - material.stretchWeft, 0.0),
                            std::max(material.stretchWarpBeyond - material.stretchWarp, 0.0));
        m_biphasic = m_stiffening.maxCoeff() > 0;
    }
    const int nf = mesh.triangleCount();
    m_shapeGradient.resize(static_cast<std::size_t>(nf));
    for (int t = 0; t < nf; ++t) {
        const Vec2 p0 = mesh.rest.row(m_triangles(t, 0)).transpose();
        Mat2 dm;
        dm.col(0) = mesh.rest.row(m_triangles(t, 1)).transpose() - p0;
        dm.col(1) = mesh.rest.row(m_triangles(t, 2)).transpose() - p0;
        const double det = dm.determinant();
        Mat23& b = m_shapeGradient[static_cast<std::size_t>(t)];
        // Degenerate rest triangle (buildClothMesh refuses these): contributes zero.
        if (!(std::abs(det) > 1e-14 * std::max(dm.squaredNorm(), 1e-300))) {
            b.setZero();
            m_restArea[t] = 0.0;
            continue;
        }
        const Mat2 inv = dm.inverse();
        b.col(1) = inv.row(0).transpose();
        b.col(2) = inv.row(1).transpose();
        b.col(0) = -b.col(1) - b.col(2);
        m_restArea[t] = 0.5 * std::abs(det);
    }
}

Vec2 FemStretch::beyondKnee(const Vec3& e) const {
    return {std::max(e.x() - m_knee, 0.0), std::max(e.y() - m_knee, 0.0)};
}

Vec3 FemStretch::stiffeningStress(const Vec3& e) const {
    const Vec2 beyond = beyondKnee(e);
    return {m_stiffening.x() * beyond.x(), m_stiffening.y() * beyond.y(), 0.0};
}

Vec2 FemStretch::stiffeningTangent(const Vec3& e) const {
    return {e.x() > m_knee ? m_stiffening.x() : 0.0, e.y() > m_knee ? m_stiffening.y() : 0.0};
}

Eigen::Matrix<double, 3, 2> FemStretch::deformationGradient(const MatX3& x, int t) const {
    const Mat23& b = m_shapeGradient[static_cast<std::size_t>(t)];
    Mat32 F = Mat32::Zero();
    for (int a = 0; a < 3; ++a) {
        F.noalias() += x.row(m_offset + m_triangles(t, a)).transpose() * b.col(a).transpose();
    }
    return F;
}

Vec3 FemStretch::greenStrain(const MatX3& x, int t) const {
    return greenVoigt(deformationGradient(x, t));
}

Vec3 FemStretch::stress(const MatX3& x, int t) const {
    const Vec3 e = greenStrain(x, t);
    Vec3 s = m_stiffness * e;
    if (m_biphasic) {
        s += stiffeningStress(e);
    }
    return s;
}

void FemStretch::addForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    const std::int64_t nf = m_triangles.rows();
    MatX3 buffer(3 * nf, 3);
    parallelFor(nf, [&](std::int64_t tt) {
        const int t = static_cast<int>(tt);
        const Mat23& b = m_shapeGradient[static_cast<std::size_t>(t)];
        const Mat32 F = deformationGradient(x, t);
        const Mat32 Fdot = deformationGradient(v, t);
        // S + S_d = C:(E + τ·Ė), Ė = sym(Fᵀ Ḟ).
        const Mat2 fdf = F.transpose() * Fdot;
        const Vec3 edot(fdf(0, 0), fdf(1, 1), fdf(0, 1) + fdf(1, 0));
        const Vec3 e = greenVoigt(F);
        Vec3 s = m_stiffness * (e + m_damping * edot);
        if (m_biphasic) {
            s += stiffeningStress(e);
        }
        const Mat2 S = stressMatrix(s);
        const Eigen::Matrix3d h = -m_restArea[t] * (F * S) * b; // column a = f_a
        buffer.block<3, 3>(3 * tt, 0) = h.transpose();
    });
    m_gather.gather(buffer, f);
}

double FemStretch::energy(const MatX3& x) const {
    const std::int64_t nf = m_triangles.rows();
    VecX w(nf);
    parallelFor(nf, [&](std::int64_t tt) {
        const int t = static_cast<int>(tt);
        const Vec3 e = greenStrain(x, t);
        w[t] = 0.5 * m_restArea[t] * e.dot(m_stiffness * e);
        if (m_biphasic) {
            const Vec2 beyond = beyondKnee(e);
            w[t] += 0.5 * m_restArea[t] * beyond.dot(m_stiffening.cwiseProduct(beyond));
        }
    });
    return w.sum();
}

void FemStretch::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    m_gather.addPattern(pairs);
}

void FemStretch::addJacobian(const MatX3& x, const MatX3& v, double kx, double kv,
                             JacobianMode mode, BlockSparseMatrix& J) const {
    const std::int64_t nf = m_triangles.rows();
    const bool exact = mode == JacobianMode::Exact;
    std::vector<Mat3>& blocks = m_blocks; // every block is written below
    blocks.resize(static_cast<std::size_t>(nf) * 9);
    parallelFor(nf, [&](std::int64_t tt) {
        const int t = static_cast<int>(tt);
        const double a0 = m_restArea[t];
        const Mat23& b = m_shapeGradient[static_cast<std::size_t>(t)];
        const Mat32 F = deformationGradient(x, t);
        const Mat32 Fdot = deformationGradient(v, t);
        const Mat2 fdf = F.transpose() * Fdot;
        const Vec3 edot(fdf(0, 0), fdf(1, 1), fdf(0, 1) + fdf(1, 0));
        const Vec3 e = greenVoigt(F);
        Vec3 s = m_stiffness * (e + m_damping * edot);
        // The stiffening's tangent where a normal strain is past the knee (elastic only: the
        // damping's ∂f/∂v stays τ·C).
        Vec2 extra = Vec2::Zero();
        if (m_biphasic) {
            s += stiffeningStress(e);
            extra = stiffeningTangent(e);
        }
        const bool stiffened = extra.x() > 0 || extra.y() > 0;
        Mat2 S = stressMatrix(s);
        if (!exact) {
            S = clampPositive(S);
        }
        // Geometric term: -A₀ (b_aᵀ S b_b) I.
        const Mat3 geometric = -a0 * (b.transpose() * S * b);
        for (int bb = 0; bb < 3; ++bb) {
            const Vec2 bvec = b.col(bb);
            // Column k (direction e_k of x_b) of ∂f_a/∂x_b for every a: d f_a = -A₀ F dS b_a
            // with dS = C:sym(Fᵀ e_k b_bᵀ) (material) or τ C:sym(Ḟᵀ e_k b_bᵀ) (damping's
            // x-dependence through Ė). ∂f_a/∂v_b is τ times the material term.
            Eigen::Matrix<double, 9, 3> material; // row 3a+i, column k
            Eigen::Matrix<double, 9, 3> dampingX;
            Eigen::Matrix<double, 9, 3> stiffening; // the same with the stiffening's tangent
            for (int k = 0; k < 3; ++k) {
                const Vec3 sym = symOuterVoigt(F.row(k).transpose(), bvec);
                const Vec3 dS = m_stiffness * sym;
                const Vec3 dSd =
                    m_damping * (m_stiffness * symOuterVoigt(Fdot.row(k).transpose(), bvec));
                const Mat2 dSm = stressMatrix(dS);
                const Mat2 dSdm = stressMatrix(dSd);
                for (int a = 0; a < 3; ++a) {
                    material.block<3, 1>(3 * a, k) = -a0 * F * (dSm * b.col(a));
                    dampingX.block<3, 1>(3 * a, k) = -a0 * F * (dSdm * b.col(a));
                }
                if (stiffened) {
                    const Mat2 dSs =
                        stressMatrix(Vec3(extra.x() * sym.x(), extra.y() * sym.y(), 0));
                    for (int a = 0; a < 3; ++a) {
                        stiffening.block<3, 1>(3 * a, k) = -a0 * F * (dSs * b.col(a));
                    }
                }
            }
            for (int a = 0; a < 3; ++a) {
                Mat3 blk = (kx + kv * m_damping) * material.block<3, 3>(3 * a, 0);
                if (stiffened) {
                    blk += kx * stiffening.block<3, 3>(3 * a, 0);
                }
                blk.diagonal().array() += kx * geometric(a, bb);
                if (exact) {
                    blk += kx * dampingX.block<3, 3>(3 * a, 0);
                }
                blocks[static_cast<std::size_t>((3 * t + a) * 3 + bb)] = blk;
            }
        }
    });
    m_gather.gatherJacobian(blocks, J);
}

} // namespace atelier::sim
