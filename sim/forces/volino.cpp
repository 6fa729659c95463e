#include "sim/forces/volino.h"

#include "sim/core/parallel.h"
#include "sim/forces/springs.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace atelier::sim {

VolinoStretch::VolinoStretch(const ClothMesh& mesh, int offset, const Material& material,
                             const VecX& localMasses)
    : m_damping(material.damping) {
    const double nu = std::clamp(material.poisson, 0.0, 0.49);
    m_elements.reserve(static_cast<std::size_t>(mesh.triangleCount()));
    for (int t = 0; t < mesh.triangleCount(); ++t) {
        Element el{};
        std::array<Vec2, 3> p;
        std::array<double, 3> invMass{};
        for (int k = 0; k < 3; ++k) {
            const int local = mesh.triangles(t, k);
            el.v[static_cast<std::size_t>(k)] = local + offset;
            p[static_cast<std::size_t>(k)] = mesh.rest.row(local);
            const double m = localMasses[local];
            invMass[static_cast<std::size_t>(k)] = m > 0 ? 1.0 / m : 0.0;
        }
        // Edge I joins vertices I+1 and I+2.
        std::array<Vec2, 3> dir;
        for (int I = 0; I < 3; ++I) {
            const Vec2 d =
                p[static_cast<std::size_t>((I + 2) % 3)] - p[static_cast<std::size_t>((I + 1) % 3)];
            el.rest[static_cast<std::size_t>(I)] = d.norm();
            dir[static_cast<std::size_t>(I)] = d / d.norm();
        }
        // Cosine of the angle at vertex k, between the two edges meeting there.
        std::array<double, 3> c{};
        for (int k = 0; k < 3; ++k) {
            const Vec2 a =
                p[static_cast<std::size_t>((k + 1) % 3)] - p[static_cast<std::size_t>(k)];
            const Vec2 b =
                p[static_cast<std::size_t>((k + 2) % 3)] - p[static_cast<std::size_t>(k)];
            c[static_cast<std::size_t>(k)] = a.dot(b) / (a.norm() * b.norm());
        }
        Mat3 A = Mat3::Identity();
        for (int I = 0; I < 3; ++I) {
            for (int J = 0; J < 3; ++J) {
                if (I == J) {
                    continue;
                }
                const int k = 3 - I - J; // vertex shared by edges I and J
                const double mi = invMass[static_cast<std::size_t>(I)];
                const double mk = invMass[static_cast<std::size_t>(k)];
                const double w = (mi + mk) > 0 ? mk / (mi + mk) : 0.5;
                A(I, J) = w * c[static_cast<std::size_t>(k)];
            }
        }
        const double area = mesh.restArea[t];
        Eigen::FullPivLU<Mat3> lu(A);
        Mat3 Ainv = lu.isInvertible() ? Mat3(lu.inverse()) : Mat3::Identity();
        if (!Ainv.allFinite()) {
            Ainv = Mat3::Identity();
        }
        Eigen::Vector3d k2mu;
        double ySum = 0;
        for (int I = 0; I < 3; ++I) {
            const double y = directionalModulus(material, dir[static_cast<std::size_t>(I)]);
            ySum += y;
            const double L = el.rest[static_cast<std::size_t>(I)];
            k2mu[I] = y / (1.0 + nu) * area / (L * L);
        }
        Mat3 G = k2mu.asDiagonal() * Ainv;
        // Poisson term: tr ε = β·e with e_I = n_Iᵀ ε n_I the edge strains.
        Mat3 N;
        for (int I = 0; I < 3; ++I) {
            const Vec2& n = dir[static_cast<std::size_t>(I)];
            N.row(I) << n.x() * n.x(), n.y() * n.y(), 2.0 * n.x() * n.y();
        }
        const Eigen::Vector3d beta = N.transpose().fullPivLu().solve(Eigen::Vector3d(1, 1, 0));
        const double yMean = ySum / 3.0;
        const double lambda = yMean * nu / (1.0 - nu * nu);
        Eigen::Vector3d betaOverL;
        for (int I = 0; I < 3; ++I) {
            betaOverL[I] = beta[I] / el.rest[static_cast<std::size_t>(I)];
        }
        if (betaOverL.allFinite()) {
            G += lambda * area * betaOverL * betaOverL.transpose();
        }
        el.G = G;
        const Mat3 sym = 0.5 * (G + G.transpose());
        Eigen::SelfAdjointEigenSolver<Mat3> eig(sym);
        const Eigen::Vector3d ev = eig.eigenvalues().cwiseMax(0.0);
        el.Gdefinite = eig.eigenvectors() * ev.asDiagonal() * eig.eigenvectors().transpose();
        m_elements.push_back(el);
    }
    m_gather = ElementGather(mesh.triangles.cast<int>(), offset);
    m_buffer.resize(3 * static_cast<Eigen::Index>(m_elements.size()), 3);
}

void VolinoStretch::addForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    const auto count = static_cast<std::int64_t>(m_elements.size());
    parallelFor(count, [&](std::int64_t e) {
        const Element& el = m_elements[static_cast<std::size_t>(e)];
        const Vec3 x0 = x.row(el.v[0]);
        const Vec3 x1 = x.row(el.v[1]);
        const Vec3 x2 = x.row(el.v[2]);
        const Vec3 v0 = v.row(el.v[0]);
        const Vec3 v1 = v.row(el.v[1]);
        const Vec3 v2 = v.row(el.v[2]);
        // Edge I joins corners I+1 → I+2.
        const Vec3 d[3] = {x2 - x1, x0 - x2, x1 - x0};
        const Vec3 dv[3] = {v2 - v1, v0 - v2, v1 - v0};
        Vec3 u[3];
        Eigen::Vector3d stretch;
        for (int I = 0; I < 3; ++I) {
            const double l = d[I].norm();
            u[I] = l > LENGTH_EPS ? Vec3(d[I] / l) : Vec3::Zero();
            stretch[I] = (l - el.rest[static_cast<std::size_t>(I)]) + m_damping * dv[I].dot(u[I]);
        }
        const Eigen::Vector3d T = el.G * stretch;
        const Vec3 t0 = T[0] * u[0];
        const Vec3 t1 = T[1] * u[1];
        const Vec3 t2 = T[2] * u[2];
        // Corner a is the start of edge a+1 (pulled along +u) and the end of edge a+2.
        m_buffer.row(3 * e + 0) = (t2 - t1).transpose();
        m_buffer.row(3 * e + 1) = (t0 - t2).transpose();
        m_buffer.row(3 * e + 2) = (t1 - t0).transpose();
    });
    m_gather.gather(m_buffer, f);
}

void VolinoStretch::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    for (const Element& el : m_elements) {
        pairs.emplace_back(el.v[0], el.v[1]);
        pairs.emplace_back(el.v[1], el.v[2]);
        pairs.emplace_back(el.v[2], el.v[0]);
    }
}

void VolinoStretch::addJacobian(const MatX3& x, const MatX3& v, double kx, double kv,
                                JacobianMode mode, BlockSparseMatrix& J) const {
    const bool exact = mode == JacobianMode::Exact;
    for (const Element& el : m_elements) {
        // g_I = ∂l_I/∂x, nonzero on the edge's ends: -u on p, +u on q (as 9-vectors).
        Eigen::Matrix<double, 9, 3> g = Eigen::Matrix<double, 9, 3>::Zero();
        Eigen::Matrix<double, 9, 3> gdot = Eigen::Matrix<double, 9, 3>::Zero(); // ∂l̇_I/∂x
        Eigen::Vector3d stretch;
        Eigen::Vector3d elastic;
        Mat3 P[3];
        for (int I = 0; I < 3; ++I) {
            const int a = (I + 1) % 3;
            const int b = (I + 2) % 3;
            const int p = el.v[static_cast<std::size_t>(a)];
            const int q = el.v[static_cast<std::size_t>(b)];
            const Vec3 d = x.row(q) - x.row(p);
            const double l = d.norm();
            const Vec3 u = l > LENGTH_EPS ? Vec3(d / l) : Vec3::Zero();
            const Vec3 dv = v.row(q) - v.row(p);
            P[I] = l > LENGTH_EPS ? Mat3((Mat3::Identity() - u * u.transpose()) / l) : Mat3::Zero();
            g.block<3, 1>(3 * a, I) = -u;
            g.block<3, 1>(3 * b, I) = u;
            const Vec3 pd = P[I] * dv;
            gdot.block<3, 1>(3 * a, I) = -pd;
            gdot.block<3, 1>(3 * b, I) = pd;
            elastic[I] = l - el.rest[static_cast<std::size_t>(I)];
            stretch[I] = elastic[I] + m_damping * u.dot(dv);
        }
        Eigen::Matrix<double, 9, 9> Kx;
        if (exact) {
            const Eigen::Vector3d T = el.G * stretch;
            // f = -g T, T = G (l - L + τ l̇): ∂f/∂x = -g G (gᵀ + τ gdotᵀ) - Σ T_I ∂²l_I.
            Kx = -g * el.G * (g.transpose() + m_damping * gdot.transpose());
            for (int I = 0; I < 3; ++I) {
                const int a = (I + 1) % 3;
                const int b = (I + 2) % 3;
                // ∂(T_I g_I)/∂x through u: T_I · [[P, -P], [-P, P]] on (a, b); the damping
                // term's u-dependence inside T is in gdot above.
                const Mat3 B = T[I] * P[I];
                Kx.block<3, 3>(3 * a, 3 * a) -= B;
                Kx.block<3, 3>(3 * b, 3 * b) -= B;
                Kx.block<3, 3>(3 * a, 3 * b) += B;
                Kx.block<3, 3>(3 * b, 3 * a) += B;
            }
        } else {
            Kx = -g * el.Gdefinite * g.transpose();
            const Eigen::Vector3d T = el.G * elastic;
            for (int I = 0; I < 3; ++I) {
                const double tension = std::max(0.0, T[I]);
                const int a = (I + 1) % 3;
                const int b = (I + 2) % 3;
                const Mat3 B = tension * P[I];
                Kx.block<3, 3>(3 * a, 3 * a) -= B;
                Kx.block<3, 3>(3 * b, 3 * b) -= B;
                Kx.block<3, 3>(3 * a, 3 * b) += B;
                Kx.block<3, 3>(3 * b, 3 * a) += B;
            }
        }
        const Mat3& Gv = exact ? el.G : el.Gdefinite;
        const Eigen::Matrix<double, 9, 9> Kv = -m_damping * g * Gv * g.transpose();
        const Eigen::Matrix<double, 9, 9> K = kx * Kx + kv * Kv;
        for (int a = 0; a < 3; ++a) {
            for (int b = 0; b < 3; ++b) {
                J.add(el.v[static_cast<std::size_t>(a)], el.v[static_cast<std::size_t>(b)],
                      K.block<3, 3>(3 * a, 3 * b));
            }
        }
    }
}

void VolinoStretch::addDampingProduct(const MatX3& x, const MatX3& v, MatX3& f) const {
    // (−τ g G⁺ gᵀ) v per element: gᵀv is each edge's rate of lengthening.
    for (const Element& el : m_elements) {
        Vec3 u[3];
        Eigen::Vector3d rate;
        for (int I = 0; I < 3; ++I) {
            const int p = el.v[static_cast<std::size_t>((I + 1) % 3)];
            const int q = el.v[static_cast<std::size_t>((I + 2) % 3)];
            const Vec3 d = x.row(q) - x.row(p);
            const double l = d.norm();
            u[I] = l > LENGTH_EPS ? Vec3(d / l) : Vec3::Zero();
            rate[I] = u[I].dot(Vec3(v.row(q) - v.row(p)));
        }
        const Eigen::Vector3d T = -m_damping * (el.Gdefinite * rate);
        for (int I = 0; I < 3; ++I) {
            const int p = el.v[static_cast<std::size_t>((I + 1) % 3)];
            const int q = el.v[static_cast<std::size_t>((I + 2) % 3)];
            f.row(p) -= (T[I] * u[I]).transpose();
            f.row(q) += (T[I] * u[I]).transpose();
        }
    }
}

} // namespace atelier::sim
