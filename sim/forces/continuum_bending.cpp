#include "sim/forces/continuum_bending.h"

#include "sim/core/parallel.h"
#include "sim/forces/bending.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace atelier::sim {

std::optional<std::string> bendingRigidity(const Material& material, BendingRigidity& out) {
    const auto valid = [](double v) { return std::isfinite(v) && v >= 0; };
    if (!valid(material.bending) || !valid(material.bendingWeft) || !valid(material.bendingWarp) ||
        !valid(material.bendingBias)) {
        return "bending rigidities must be finite and not negative";
    }
    out.weft = material.bendingWeft > 0 ? material.bendingWeft : material.bending;
    out.warp = material.bendingWarp > 0 ? material.bendingWarp : material.bending;
    if (!(out.weft > 0) || !(out.warp > 0)) {
        out = {};
        return material.bendingBias > 0
                   ? std::optional<std::string>("a bias rigidity needs weft and warp ones")
                   : std::nullopt; // no bending at all
    }
    if (material.bendingBias > 0) {
        const double inverse = 4.0 / material.bendingBias - 1.0 / out.weft - 1.0 / out.warp;
        if (!(inverse > 0)) {
            out = {};
            return "the bias rigidity must be below 4/(1/B_weft + 1/B_warp) (the stiffest a "
                   "plate with these weft and warp rigidities can be at 45°)";
        }
        out.twist = 1.0 / inverse;
    } else {
        out.twist = 0.5 * std::sqrt(out.weft * out.warp);
    }
    return std::nullopt;
}

double stripRigidity(const BendingRigidity& rigidity, double angle) {
    const double c2 = std::cos(angle) * std::cos(angle);
    const double s2 = std::sin(angle) * std::sin(angle);
    const double compliance =
        c2 * c2 / rigidity.weft + s2 * s2 / rigidity.warp + c2 * s2 / rigidity.twist;
    return 1.0 / compliance;
}

namespace {

/// −(n₁², n₂², 2n₁n₂) for the in-plane unit normal n̄ of the rest edge p₀→p₁: the direction of
/// a hinge's column in the shape operator (the sign makes κ the Hessian of the height over a
/// surface whose triangles face +z; the energy does not depend on it). Zero when degenerate.
Vec3 edgeNormalTensor(const Vec2& p0, const Vec2& p1) {
    const Vec2 e = p1 - p0;
    const double length = e.norm();
    if (!(length > 0)) {
        return Vec3::Zero();
    }
    const Vec2 n(e.y() / length, -e.x() / length);
    return -Vec3(n.x() * n.x(), n.y() * n.y(), 2 * n.x() * n.y());
}

std::uint64_t edgeKey(int a, int b) {
    const auto lo = static_cast<std::uint64_t>(std::min(a, b));
    const auto hi = static_cast<std::uint64_t>(std::max(a, b));
    return (hi << 32U) | lo;
}

} // namespace

ContinuumBending::ContinuumBending(const ClothMesh& mesh, int offset, const Material& material,
                                   const VecX& restAngles, bool plasticity,
                                   const std::vector<char>& held)
    : m_offset(offset), m_hinges(mesh.hinges), m_restAngle(VecX::Zero(mesh.hinges.rows())),
      m_damping(std::max(material.damping, 0.0)),
      m_plasticity(plasticity && material.plasticYieldAngle > 0),
      m_yieldAngle(material.plasticYieldAngle), m_plasticRate(std::max(material.plasticRate, 0.0)),
      m_hingeGather(mesh.hinges, offset) {
    const int nh = static_cast<int>(m_hinges.rows());
    const int nf = mesh.triangleCount();
    if (restAngles.size() == nh) {
        m_restAngle = restAngles;
    }
    BendingRigidity rigidity;
    const bool bends = !bendingRigidity(material, rigidity) && rigidity.weft > 0;
    const Vec3 stiffness =
        bends ? Vec3(rigidity.weft, rigidity.warp, rigidity.twist) : Vec3::Zero();

    // Triangles of each edge, found from the triangle list.
    m_triHinges.setConstant(nf, 3, -1);
    Eigen::Matrix<int, Eigen::Dynamic, 6, Eigen::RowMajor> stencil(nf, 6);
    stencil.setConstant(-1);
    for (int t = 0; t < nf; ++t) {
        for (int i = 0; i < 3; ++i) {
            stencil(t, i) = mesh.triangles(t, i);
        }
    }
    // Slot i of triangle t is the edge opposite its vertex i.
    const auto slotOf = [&](int t, int wing) {
        for (int i = 0; i < 3; ++i) {
            if (mesh.triangles(t, i) == wing) {
                return i;
            }
        }
        return -1;
    };
    std::unordered_map<std::uint64_t, std::array<int, 2>> trianglesOfEdge;
    trianglesOfEdge.reserve(static_cast<std::size_t>(2 * nf));
    for (int t = 0; t < nf; ++t) {
        for (int i = 0; i < 3; ++i) {
            const auto key =
                edgeKey(mesh.triangles(t, (i + 1) % 3), mesh.triangles(t, (i + 2) % 3));
            auto [it, inserted] = trianglesOfEdge.try_emplace(key, std::array<int, 2>{t, -1});
            if (!inserted) {
                it->second[1] = t;
            }
        }
    }

    m_gradientCap = VecX::Zero(nh);
    // Rigid triangles: all three corners held (a clamp).
    const auto rigid = [&](int t) {
        if (held.empty()) {
            return false;
        }
        for (int i = 0; i < 3; ++i) {
            const auto g = static_cast<std::size_t>(offset + mesh.triangles(t, i));
            if (g >= held.size() || held[g] == 0) {
                return false;
            }
        }
        return true;
    };
    // Shape-operator weight of each (triangle, slot): |ē|/(Ā₀+Ā₁), or |ē|/Ā_T (the whole jump)
    // in a free triangle beside a rigid one, and 0 in the rigid one.
    Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> weight(nf, 3);
    weight.setZero();
    for (int h = 0; h < nh; ++h) {
        std::array<Vec2, 4> p;
        for (int a = 0; a < 4; ++a) {
            p[static_cast<std::size_t>(a)] = mesh.rest.row(m_hinges(h, a)).transpose();
        }
        const double e = (p[1] - p[0]).norm();
        const double h0 = e > 0 ? 2.0 * std::abs(signedArea(p[0], p[1], p[2])) / e : 0.0;
        const double h1 = e > 0 ? 2.0 * std::abs(signedArea(p[1], p[0], p[3])) / e : 0.0;
        const double hmin = std::min(h0, h1);
        m_gradientCap[h] = hmin > 0 ? GRADIENT_CAP / hmin : 0.0;

        const auto found = trianglesOfEdge.find(edgeKey(m_hinges(h, 0), m_hinges(h, 1)));
        if (found == trianglesOfEdge.end() || found->second[1] < 0) {
            continue;
        }
        const double a0 = std::abs(signedArea(p[0], p[1], p[2]));
        const double a1 = std::abs(signedArea(p[1], p[0], p[3]));
        const bool rigid0 = rigid(found->second[0]);
        const bool rigid1 = rigid(found->second[1]);
        for (const int t : found->second) {
            // The wing of this triangle is v2 or v3; the other is opposite across the edge.
            int slot = slotOf(t, m_hinges(h, 2));
            int other = m_hinges(h, 3);
            if (slot < 0) {
                slot = slotOf(t, m_hinges(h, 3));
                other = m_hinges(h, 2);
            }
            if (slot < 0) {
                continue;
            }
            m_triHinges(t, slot) = h;
            stencil(t, 3 + slot) = other;
            const bool own = t == found->second[0] ? rigid0 : rigid1;
            const bool beside = t == found->second[0] ? rigid1 : rigid0;
            const double ownArea = slotOf(t, m_hinges(h, 2)) == slot ? a0 : a1;
            if (own || !(a0 + a1 > 0)) {
                continue;
            }
            weight(t, slot) = beside ? (ownArea > 0 ? e / ownArea : 0.0) : e / (a0 + a1);
        }
    }

    // Per triangle: Q_T, the curvature map and the corner slots.
    m_q.assign(static_cast<std::size_t>(nf), Mat3::Zero());
    m_curvatureMap.assign(static_cast<std::size_t>(nf), Mat3::Zero());
    m_cornerSlot.assign(static_cast<std::size_t>(nf), {});
    struct Entry {
        int row, col;
        double value;
    };
    std::vector<Entry> entries;
    entries.reserve(static_cast<std::size_t>(9 * nf));
    const Mat3 plate = stiffness.asDiagonal();
    for (int t = 0; t < nf; ++t) {
        auto& corner = m_cornerSlot[static_cast<std::size_t>(t)];
        corner.fill(-1);
        Mat3& map = m_curvatureMap[static_cast<std::size_t>(t)];
        for (int i = 0; i < 3; ++i) {
            const int h = m_triHinges(t, i);
            if (h < 0) {
                continue;
            }
            for (int a = 0; a < 4; ++a) {
                const int v = m_hinges(h, a);
                for (int s = 0; s < 6; ++s) {
                    if (stencil(t, s) == v) {
                        corner[static_cast<std::size_t>(4 * i + a)] = s;
                    }
                }
            }
            const int e0 = mesh.triangles(t, (i + 1) % 3);
            const int e1 = mesh.triangles(t, (i + 2) % 3);
            map.col(i) = weight(t, i) * edgeNormalTensor(mesh.rest.row(e0).transpose(),
                                                         mesh.rest.row(e1).transpose());
        }
        const Mat3 q = std::max(mesh.restArea[t], 0.0) * map.transpose() * plate * map;
        m_q[static_cast<std::size_t>(t)] = q;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                if (m_triHinges(t, i) >= 0 && m_triHinges(t, j) >= 0 && q(i, j) != 0.0) {
                    entries.push_back({m_triHinges(t, i), m_triHinges(t, j), q(i, j)});
                }
            }
        }
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
        return a.row != b.row ? a.row < b.row : a.col < b.col;
    });
    m_wStart.assign(static_cast<std::size_t>(nh) + 1, 0);
    for (std::size_t k = 0; k < entries.size(); ++k) {
        const Entry& e = entries[k];
        if (!m_wColumn.empty() && k > 0 && entries[k - 1].row == e.row &&
            entries[k - 1].col == e.col) {
            m_wValue.back() += e.value;
        } else {
            m_wColumn.push_back(e.col);
            m_wValue.push_back(e.value);
            ++m_wStart[static_cast<std::size_t>(e.row) + 1];
        }
    }
    for (int h = 0; h < nh; ++h) {
        m_wStart[static_cast<std::size_t>(h) + 1] += m_wStart[static_cast<std::size_t>(h)];
    }
    m_triangleGather = ElementGather(stencil, offset);
}

std::array<Vec3, 4> ContinuumBending::corners(const MatX3& x, int h) const {
    std::array<Vec3, 4> c;
    for (int a = 0; a < 4; ++a) {
        c[static_cast<std::size_t>(a)] = x.row(m_offset + m_hinges(h, a)).transpose();
    }
    return c;
}

void ContinuumBending::evaluateHinges(const MatX3& x, const MatX3* v) const {
    const std::int64_t nh = m_hinges.rows();
    m_state.resize(static_cast<std::size_t>(nh));
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        HingeState& st = m_state[static_cast<std::size_t>(h)];
        st = HingeState{};
        const auto c = corners(x, h);
        if (!dihedralAngleGradient(c, st.grad)) {
            return;
        }
        double largest = 0;
        for (const Vec3& g : st.grad) {
            largest = std::max(largest, g.norm());
        }
        const double cap = m_gradientCap[h];
        if (largest > cap) {
            st.scale = cap / largest;
            for (Vec3& g : st.grad) {
                g *= st.scale;
            }
        }
        const double half = 0.5 * (dihedralAngle(c[0], c[1], c[2], c[3]) - m_restAngle[h]);
        st.s = std::sin(half);
        st.c = std::cos(half);
        st.phi = 2.0 * st.s;
        if (v != nullptr) {
            const auto cv = corners(*v, h);
            for (std::size_t a = 0; a < 4; ++a) {
                st.thetaDot += st.grad[a].dot(cv[a]);
            }
            st.phiDot = st.c * st.thetaDot;
        }
        st.ok = true;
    });
}

void ContinuumBending::addForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    evaluateHinges(x, &v);
    const std::int64_t nh = m_hinges.rows();
    m_buffer.setZero(4 * nh, 3);
    parallelFor(nh, [&](std::int64_t hh) {
        const auto h = static_cast<std::size_t>(hh);
        const HingeState& st = m_state[h];
        if (!st.ok) {
            return;
        }
        double mu = 0;
        for (int k = m_wStart[h]; k < m_wStart[h + 1]; ++k) {
            const HingeState& sj = m_state[static_cast<std::size_t>(m_wColumn[k])];
            mu += m_wValue[static_cast<std::size_t>(k)] * (sj.phi + m_damping * sj.phiDot);
        }
        const double scale = -mu * st.c;
        for (std::size_t a = 0; a < 4; ++a) {
            m_buffer.row(4 * hh + static_cast<std::int64_t>(a)) = scale * st.grad[a].transpose();
        }
    });
    m_hingeGather.gather(m_buffer, f);
}

double ContinuumBending::energy(const MatX3& x) const {
    evaluateHinges(x, nullptr);
    const std::int64_t nh = m_hinges.rows();
    VecX e = VecX::Zero(nh);
    parallelFor(nh, [&](std::int64_t hh) {
        const auto h = static_cast<std::size_t>(hh);
        double wphi = 0;
        for (int k = m_wStart[h]; k < m_wStart[h + 1]; ++k) {
            wphi += m_wValue[static_cast<std::size_t>(k)] *
                    m_state[static_cast<std::size_t>(m_wColumn[k])].phi;
        }
        e[hh] = 0.5 * m_state[h].phi * wphi;
    });
    return e.sum();
}

Vec3 ContinuumBending::curvature(const MatX3& x, int t) const {
    Vec3 phi = Vec3::Zero();
    for (int i = 0; i < 3; ++i) {
        const int h = m_triHinges(t, i);
        if (h >= 0) {
            const auto c = corners(x, h);
            phi[i] = dihedralAngle(c[0], c[1], c[2], c[3]) - m_restAngle[h];
        }
    }
    return m_curvatureMap[static_cast<std::size_t>(t)] * phi;
}

void ContinuumBending::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    m_triangleGather.addPattern(pairs);
}

void ContinuumBending::addJacobian(const MatX3& x, const MatX3& v, double kx, double kv,
                                   JacobianMode mode, BlockSparseMatrix& J) const {
    using Vec12 = Eigen::Matrix<double, 12, 1>;
    using Vec18 = Eigen::Matrix<double, 18, 1>;
    using Mat12 = Eigen::Matrix<double, 12, 12>;
    using Mat18 = Eigen::Matrix<double, 18, 18>;
    const bool exact = mode == JacobianMode::Exact;
    evaluateHinges(x, &v);
    const std::int64_t nh = m_hinges.rows();
    const std::int64_t nf = m_triHinges.rows();

    // Per hinge (Exact): −μ_h (c_h ∇²θ_h − ½ s_h ∇θ_h∇θ_hᵀ), and ∇²θ_h·v for the triangles.
    std::vector<Vec12>& hessianV = m_hessianV;
    if (exact) {
        hessianV.assign(static_cast<std::size_t>(nh), Vec12::Zero());
        m_hingeBlocks.resize(static_cast<std::size_t>(nh) * 16);
        parallelFor(nh, [&](std::int64_t hh) {
            const auto h = static_cast<std::size_t>(hh);
            const HingeState& st = m_state[h];
            Mat12 K = Mat12::Zero();
            Mat12 H;
            if (st.ok && dihedralAngleHessian(corners(x, static_cast<int>(hh)), H)) {
                H *= st.scale; // the capped gradient scales ∇²θ alike (1 unless degenerate)
                Vec12 g;
                Vec12 vel;
                const auto cv = corners(v, static_cast<int>(hh));
                for (std::size_t a = 0; a < 4; ++a) {
                    g.segment<3>(3 * static_cast<int>(a)) = st.grad[a];
                    vel.segment<3>(3 * static_cast<int>(a)) = cv[a];
                }
                hessianV[h] = H * vel;
                double mu = 0;
                for (int k = m_wStart[h]; k < m_wStart[h + 1]; ++k) {
                    const HingeState& sj = m_state[static_cast<std::size_t>(m_wColumn[k])];
                    mu += m_wValue[static_cast<std::size_t>(k)] * (sj.phi + m_damping * sj.phiDot);
                }
                K = -kx * mu * (st.c * H - 0.5 * st.s * g * g.transpose());
            }
            for (int a = 0; a < 4; ++a) {
                for (int b = 0; b < 4; ++b) {
                    m_hingeBlocks[(4 * h + static_cast<std::size_t>(a)) * 4 +
                                  static_cast<std::size_t>(b)] = K.block<3, 3>(3 * a, 3 * b);
                }
            }
        });
        m_hingeGather.gatherJacobian(m_hingeBlocks, J);
    }

    // Per triangle: −(kx + kv τ) Σ_ij Q_ij G_i G_jᵀ, and (Exact) the fold-rate terms.
    m_triBlocks.resize(static_cast<std::size_t>(nf) * 36);
    parallelFor(nf, [&](std::int64_t tt) {
        const auto t = static_cast<std::size_t>(tt);
        const auto& slot = m_cornerSlot[t];
        std::array<Vec18, 3> G;
        std::array<Vec18, 3> D; // ∂φ̇_j/∂x (Exact)
        std::array<bool, 3> ok{};
        for (int i = 0; i < 3; ++i) {
            const auto si = static_cast<std::size_t>(i);
            G[si].setZero();
            D[si].setZero();
            const int h = m_triHinges(static_cast<Eigen::Index>(t), i);
            if (h < 0 || !m_state[static_cast<std::size_t>(h)].ok) {
                continue;
            }
            const HingeState& st = m_state[static_cast<std::size_t>(h)];
            ok[si] = true;
            for (int a = 0; a < 4; ++a) {
                const int s = slot[static_cast<std::size_t>(4 * i + a)];
                if (s < 0) {
                    continue;
                }
                G[si].segment<3>(3 * s) += st.c * st.grad[static_cast<std::size_t>(a)];
                if (exact) {
                    D[si].segment<3>(3 * s) +=
                        st.c * hessianV[static_cast<std::size_t>(h)].segment<3>(3 * a) -
                        0.5 * st.s * st.thetaDot * st.grad[static_cast<std::size_t>(a)];
                }
            }
        }
        const Mat3& q = m_q[t];
        Mat18 K = Mat18::Zero();
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                const auto si = static_cast<std::size_t>(i);
                const auto sj = static_cast<std::size_t>(j);
                if (!ok[si] || !ok[sj] || q(i, j) == 0.0) {
                    continue;
                }
                K -= (kx + kv * m_damping) * q(i, j) * G[si] * G[sj].transpose();
                if (exact) {
                    K -= kx * m_damping * q(i, j) * G[si] * D[sj].transpose();
                }
            }
        }
        for (int a = 0; a < 6; ++a) {
            for (int b = 0; b < 6; ++b) {
                m_triBlocks[(6 * t + static_cast<std::size_t>(a)) * 6 +
                            static_cast<std::size_t>(b)] = K.block<3, 3>(3 * a, 3 * b);
            }
        }
    });
    m_triangleGather.gatherJacobian(m_triBlocks, J);
}

void ContinuumBending::acceptStep(const MatX3& x, double dt) {
    if (m_plasticity) {
        flowRestAngles(m_restAngle, m_yieldAngle, m_plasticRate, dt, [&](int h) {
            const auto c = corners(x, h);
            return dihedralAngle(c[0], c[1], c[2], c[3]);
        });
    }
}

} // namespace atelier::sim
