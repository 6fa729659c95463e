#include "sim/forces/bending.h"

#include "sim/core/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace atelier::sim {

namespace {

/// Forward-mode dual number a + b·ε (ε² = 0) for the Hessian of θ.
struct Dual {
    double v = 0; ///< value
    double d = 0; ///< derivative along the seeded direction
    Dual() = default;
    Dual(double value, double derivative = 0) : v(value), d(derivative) {} // NOLINT(*-explicit-*)
};
Dual operator+(Dual a, Dual b) {
    return {a.v + b.v, a.d + b.d};
}
Dual operator-(Dual a, Dual b) {
    return {a.v - b.v, a.d - b.d};
}
Dual operator-(Dual a) {
    return {-a.v, -a.d};
}
Dual operator*(Dual a, Dual b) {
    return {a.v * b.v, a.d * b.v + a.v * b.d};
}
Dual operator/(Dual a, Dual b) {
    return {a.v / b.v, (a.d * b.v - a.v * b.d) / (b.v * b.v)};
}
Dual sqrt(Dual a) {
    const double s = std::sqrt(a.v);
    return {s, s > 0 ? 0.5 * a.d / s : 0.0};
}
double value(Dual a) {
    return a.v;
}
double value(double a) {
    return a;
}
using std::sqrt;

template <typename T> using V3 = std::array<T, 3>;

template <typename T> V3<T> sub(const V3<T>& a, const V3<T>& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <typename T> T dot(const V3<T>& a, const V3<T>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <typename T> V3<T> cross(const V3<T>& a, const V3<T>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <typename T> V3<T> scale(const V3<T>& a, T s) {
    return {a[0] * s, a[1] * s, a[2] * s};
}
template <typename T> V3<T> add(const V3<T>& a, const V3<T>& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}

/// Closed-form ∇θ (Bridson et al. 2003) over any scalar type; false when degenerate.
template <typename T> bool gradientT(const std::array<V3<T>, 4>& x, std::array<V3<T>, 4>& g) {
    const V3<T> e = sub(x[1], x[0]);
    const T e2 = dot(e, e);
    const V3<T> n0 = cross(e, sub(x[2], x[0]));
    const V3<T> n1 = cross(sub(x[3], x[0]), e);
    const T n0sq = dot(n0, n0);
    const T n1sq = dot(n1, n1);
    // |n_i|² = |e|²·h_i²: refuse heights below 1e-12·|e| and edges below 1e-15 m.
    const double tiny = 1e-24 * value(e2) * value(e2);
    if (!(value(e2) > 1e-30) || !(value(n0sq) > tiny) || !(value(n1sq) > tiny)) {
        return false;
    }
    const T el = sqrt(e2);
    const V3<T> u0 = scale(n0, T(1) / n0sq); // n₀/|n₀|²
    const V3<T> u1 = scale(n1, T(1) / n1sq); // n₁/|n₁|²
    g[2] = scale(u0, -el);
    g[3] = scale(u1, -el);
    const T inv = T(1) / el;
    g[0] = scale(
        add(scale(u0, dot(sub(x[2], x[1]), e) * inv), scale(u1, dot(sub(x[3], x[1]), e) * inv)),
        T(-1));
    g[1] = add(scale(u0, dot(sub(x[2], x[0]), e) * inv), scale(u1, dot(sub(x[3], x[0]), e) * inv));
    return true;
}

} // namespace

double dihedralAngle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3) {
    const Vec3 e = x1 - x0;
    const double el = e.norm();
    if (!(el > 0)) {
        return 0.0;
    }
    const Vec3 n0 = e.cross(x2 - x0);
    const Vec3 n1 = (x3 - x0).cross(e);
    const double s = n0.cross(n1).dot(e) / el;
    const double c = n0.dot(n1);
    if (s == 0.0 && c == 0.0) {
        return 0.0;
    }
    return std::atan2(s, c);
}

bool dihedralAngleGradient(const std::array<Vec3, 4>& x, std::array<Vec3, 4>& grad) {
    std::array<V3<double>, 4> p;
    std::array<V3<double>, 4> g;
    for (int a = 0; a < 4; ++a) {
        const auto i = static_cast<std::size_t>(a);
        p[i] = {x[i].x(), x[i].y(), x[i].z()};
    }
    const bool ok = gradientT(p, g);
    for (std::size_t a = 0; a < 4; ++a) {
        grad[a] = ok ? Vec3(g[a][0], g[a][1], g[a][2]) : Vec3::Zero();
    }
    return ok;
}

bool dihedralAngleHessian(const std::array<Vec3, 4>& x, Eigen::Matrix<double, 12, 12>& hessian) {
    std::array<V3<Dual>, 4> p;
    for (std::size_t a = 0; a < 4; ++a) {
        p[a] = {Dual{x[a].x(), 0}, Dual{x[a].y(), 0}, Dual{x[a].z(), 0}};
    }
    std::array<V3<Dual>, 4> g;
    for (int col = 0; col < 12; ++col) {
        auto& seed = p[static_cast<std::size_t>(col / 3)][static_cast<std::size_t>(col % 3)];
        seed.d = 1.0;
        const bool ok = gradientT(p, g);
        seed.d = 0.0;
        if (!ok) {
            hessian.setZero();
            return false;
        }
        for (int row = 0; row < 12; ++row) {
            hessian(row, col) =
                g[static_cast<std::size_t>(row / 3)][static_cast<std::size_t>(row % 3)].d;
        }
    }
    hessian = 0.5 * (hessian + hessian.transpose()).eval();
    return true;
}

BendingRigidity bendingRigidity(const Material& material) {
    const double b = std::max(material.bending, 0.0);
    BendingRigidity r;
    r.weft = material.bendingWeft > 0 ? material.bendingWeft : b;
    r.warp = material.bendingWarp > 0 ? material.bendingWarp : b;
    r.twist = material.bendingBias > 0
                  ? std::max(0.0, material.bendingBias - 0.25 * (r.weft + r.warp))
                  : 0.5 * std::sqrt(r.weft * r.warp);
    return r;
}

DihedralBending::DihedralBending(const ClothMesh& mesh, int offset, const Material& material,
                                 const VecX& restAngles, bool plasticity)
    : m_offset(offset), m_hinges(mesh.hinges), m_restAngle(VecX::Zero(mesh.hinges.rows())),
      m_damping(std::max(material.damping, 0.0)),
      m_plasticity(plasticity && material.plasticYieldAngle > 0),
      m_yieldAngle(material.plasticYieldAngle), m_plasticRate(std::max(material.plasticRate, 0.0)),
      m_gather(mesh.hinges, offset) {
    const int nh = static_cast<int>(m_hinges.rows());
    m_gradientCap = VecX::Zero(nh);
    if (restAngles.size() == nh) {
        m_restAngle = restAngles;
    }
    const BendingRigidity rigidity = bendingRigidity(material);
    // The plate's energy density ½(B₁κ_xx² + 4D₆₆κ_xy² + B₂κ_yy²) on (κ_xx, κ_xy, κ_yy).
    const Eigen::Vector3d plate(rigidity.weft, 4.0 * rigidity.twist, rigidity.warp);

    // Per hinge: the curvature weight w_h = |ē|/(Ā₀ + Ā₁) = 2/(h₀ + h₁) and the gradient cap.
    VecX weight = VecX::Zero(nh);
    std::unordered_map<std::int64_t, int> hingeOfEdge;
    const std::int64_t nv = mesh.vertexCount();
    const auto edgeKey = [nv](int a, int b) {
        return static_cast<std::int64_t>(std::min(a, b)) * nv + std::max(a, b);
    };
    for (int h = 0; h < nh; ++h) {
        std::array<Vec2, 4> p;
        for (int a = 0; a < 4; ++a) {
            p[static_cast<std::size_t>(a)] = mesh.rest.row(m_hinges(h, a)).transpose();
        }
        const double a0 = std::abs(signedArea(p[0], p[1], p[2]));
        const double a1 = std::abs(signedArea(p[1], p[0], p[3]));
        const double e = (p[1] - p[0]).norm();
        weight[h] = a0 + a1 > 0 ? e / (a0 + a1) : 0.0;
        // |∇θ| at a wing tip is 1/height; allow GRADIENT_CAP times the rest value.
        const double hmin = e > 0 ? 2.0 * std::min(a0, a1) / e : 0.0;
        m_gradientCap[h] = hmin > 0 ? GRADIENT_CAP / hmin : 0.0;
        hingeOfEdge[edgeKey(m_hinges(h, 0), m_hinges(h, 1))] = h;
    }

    // Per triangle: κ_T = Σ_i w_i θ_i n_i n_iᵀ as (κ_xx, κ_xy, κ_yy) = G·θ, M_T = Ā_T GᵀDG.
    std::vector<std::vector<std::pair<int, double>>> entries(static_cast<std::size_t>(nh));
    std::vector<std::array<int, 6>> stencils;
    for (int t = 0; t < mesh.triangleCount(); ++t) {
        std::array<int, 3> v{mesh.triangles(t, 0), mesh.triangles(t, 1), mesh.triangles(t, 2)};
        std::array<Vec2, 3> p;
        for (std::size_t i = 0; i < 3; ++i) {
            p[i] = mesh.rest.row(v[i]).transpose();
        }
        const double area = std::abs(signedArea(p[0], p[1], p[2]));
        std::array<int, 3> hinge{-1, -1, -1};
        Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
        int count = 0;
        for (std::size_t i = 0; i < 3; ++i) {
            const auto found = hingeOfEdge.find(edgeKey(v[(i + 1) % 3], v[(i + 2) % 3]));
            const Vec2 e = p[(i + 2) % 3] - p[(i + 1) % 3];
            const double len = e.norm();
            if (found == hingeOfEdge.end() || !(len > 0)) {
                continue; // a free border: the triangle's own gradient, no contribution
            }
            hinge[i] = found->second;
            const Vec2 n(-e.y() / len, e.x() / len);
            g.col(static_cast<int>(i)) << n.x() * n.x(), n.x() * n.y(), n.y() * n.y();
            g.col(static_cast<int>(i)) *= weight[found->second];
            ++count;
        }
        if (count == 0 || !(area > 0)) {
            continue;
        }
        const Eigen::Matrix3d mt = area * g.transpose() * plate.asDiagonal() * g;
        for (std::size_t i = 0; i < 3; ++i) {
            for (std::size_t j = 0; j < 3; ++j) {
                if (hinge[i] >= 0 && hinge[j] >= 0) {
                    entries[static_cast<std::size_t>(hinge[i])].emplace_back(
                        hinge[j], mt(static_cast<int>(i), static_cast<int>(j)));
                }
            }
        }
        if (count < 2) {
            continue;
        }
        // The 6-vertex stencil: the triangle's corners, then the vertex across each edge.
        std::array<int, 6> stencil{v[0], v[1], v[2], -1, -1, -1};
        std::array<std::array<int, 4>, 3> slots{};
        std::array<double, 9> coupling{};
        for (std::size_t i = 0; i < 3; ++i) {
            const int h = hinge[i];
            if (h < 0) {
                continue;
            }
            for (int a = 2; a < 4; ++a) {
                if (m_hinges(h, a) != v[i]) {
                    stencil[3 + i] = m_hinges(h, a);
                }
            }
            for (int a = 0; a < 4; ++a) {
                const auto at = std::find(stencil.begin(), stencil.end(), m_hinges(h, a));
                slots[i][static_cast<std::size_t>(a)] =
                    static_cast<int>(std::distance(stencil.begin(), at));
            }
            for (std::size_t j = 0; j < 3; ++j) {
                coupling[3 * i + j] = mt(static_cast<int>(i), static_cast<int>(j));
            }
        }
        stencils.push_back(stencil);
        m_stencilHinges.push_back(hinge);
        m_stencilSlot.push_back(slots);
        m_stencilM.push_back(coupling);
    }

    // M in CSR, the diagonal first in each row.
    m_start.assign(static_cast<std::size_t>(nh) + 1, 0);
    for (int h = 0; h < nh; ++h) {
        auto& row = entries[static_cast<std::size_t>(h)];
        std::sort(row.begin(), row.end(), [h](const auto& a, const auto& b) {
            if ((a.first == h) != (b.first == h)) {
                return a.first == h;
            }
            return a.first < b.first;
        });
        if (row.empty() || row.front().first != h) {
            row.insert(row.begin(), {h, 0.0});
        }
        for (std::size_t k = 0; k < row.size(); ++k) {
            if (k > 0 && row[k].first == m_column.back()) {
                m_value.back() += row[k].second;
            } else {
                m_column.push_back(row[k].first);
                m_value.push_back(row[k].second);
            }
        }
        m_start[static_cast<std::size_t>(h) + 1] = static_cast<int>(m_column.size());
    }
    Eigen::MatrixXi stencilMatrix(static_cast<Eigen::Index>(stencils.size()), 6);
    for (std::size_t s = 0; s < stencils.size(); ++s) {
        for (std::size_t a = 0; a < 6; ++a) {
            stencilMatrix(static_cast<Eigen::Index>(s), static_cast<Eigen::Index>(a)) =
                stencils[s][a];
        }
    }
    if (!stencils.empty()) {
        m_stencilGather = ElementGather(stencilMatrix, offset);
    }
}

double DihedralBending::coupled(int h, const VecX& values) const {
    double sum = 0;
    for (int k = m_start[static_cast<std::size_t>(h)]; k < m_start[static_cast<std::size_t>(h) + 1];
         ++k) {
        sum += m_value[static_cast<std::size_t>(k)] * values[m_column[static_cast<std::size_t>(k)]];
    }
    return sum;
}

double DihedralBending::gradientScale(const std::array<Vec3, 4>& g, int h) const {
    double largest = 0;
    for (const Vec3& ga : g) {
        largest = std::max(largest, ga.norm());
    }
    const double cap = m_gradientCap[h];
    return largest > cap ? cap / largest : 1.0;
}

std::array<Vec3, 4> DihedralBending::corners(const MatX3& x, int h) const {
    std::array<Vec3, 4> c;
    for (int a = 0; a < 4; ++a) {
        c[static_cast<std::size_t>(a)] = x.row(m_offset + m_hinges(h, a)).transpose();
    }
    return c;
}

double DihedralBending::angle(const MatX3& x, int h) const {
    const auto c = corners(x, h);
    return dihedralAngle(c[0], c[1], c[2], c[3]);
}

void DihedralBending::evaluateHinges(const MatX3& x, const MatX3& v, bool hessianV) const {
    const std::int64_t nh = m_hinges.rows();
    m_psi.setZero(nh);
    m_cos.setOnes(nh);
    m_rate.setZero(nh);
    m_grad.resize(static_cast<std::size_t>(nh));
    if (hessianV) {
        m_hessianV.resize(static_cast<std::size_t>(nh));
    }
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        const auto k = static_cast<std::size_t>(hh);
        const auto c = corners(x, h);
        std::array<Vec3, 4>& g = m_grad[k];
        if (hessianV) {
            m_hessianV[k].setZero();
        }
        if (!dihedralAngleGradient(c, g)) {
            return; // zero gradient: the hinge contributes nothing
        }
        const double d = dihedralAngle(c[0], c[1], c[2], c[3]) - m_restAngle[h];
        m_psi[h] = 2.0 * std::sin(0.5 * d);
        m_cos[h] = std::cos(0.5 * d);
        const double s = gradientScale(g, h);
        const auto cv = corners(v, h);
        double rate = 0;
        for (std::size_t a = 0; a < 4; ++a) {
            g[a] *= s;
            rate += g[a].dot(cv[a]);
        }
        m_rate[h] = rate;
        if (hessianV) {
            Eigen::Matrix<double, 12, 12> hess;
            if (dihedralAngleHessian(c, hess)) {
                Eigen::Matrix<double, 12, 1> vel;
                for (std::size_t a = 0; a < 4; ++a) {
                    vel.segment<3>(3 * static_cast<int>(a)) = cv[a];
                }
                m_hessianV[k] = s * hess * vel;
            }
        }
    });
}

void DihedralBending::addForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    const std::int64_t nh = m_hinges.rows();
    evaluateHinges(x, v, false);
    MatX3& buffer = m_buffer;
    buffer.setZero(4 * nh, 3);
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        // ∂E/∂θ_h (see the header) plus the fold-rate damping.
        const double force = m_cos[h] * coupled(h, m_psi) + m_damping * coupled(h, m_rate);
        for (std::size_t a = 0; a < 4; ++a) {
            buffer.row(4 * hh + static_cast<std::int64_t>(a)) =
                -force * m_grad[static_cast<std::size_t>(hh)][a].transpose();
        }
    });
    m_gather.gather(buffer, f);
}

double DihedralBending::energy(const MatX3& x) const {
    const std::int64_t nh = m_hinges.rows();
    VecX d = VecX::Zero(nh);
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        d[h] = angle(x, h) - m_restAngle[h];
    });
    const VecX psi = 2.0 * (0.5 * d.array()).sin().matrix();
    VecX e = VecX::Zero(nh);
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        e[h] = 0.5 * psi[h] * coupled(h, psi);
    });
    return e.sum();
}

void DihedralBending::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    m_gather.addPattern(pairs);
    m_stencilGather.addPattern(pairs);
}

void DihedralBending::addJacobian(const MatX3& x, const MatX3& v, double kx, double kv,
                                  JacobianMode mode, BlockSparseMatrix& J) const {
    const std::int64_t nh = m_hinges.rows();
    const bool exact = mode == JacobianMode::Exact;
    evaluateHinges(x, v, exact);
    const auto gradient = [this](std::size_t h) {
        Eigen::Matrix<double, 12, 1> g;
        for (std::size_t a = 0; a < 4; ++a) {
            g.segment<3>(3 * static_cast<int>(a)) = m_grad[h][a];
        }
        return g;
    };
    // Reused between calls and filled in the parallel loop (allocated and zeroed serially up
    // front, 16 blocks per hinge were 28 MB a step for the 10 mm tshirt).
    std::vector<Mat3>& blocks = m_blocks;
    blocks.resize(static_cast<std::size_t>(nh) * 16);
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        const auto k = static_cast<std::size_t>(hh);
        const Eigen::Matrix<double, 12, 1> grad = gradient(k);
        const Eigen::Matrix<double, 12, 12> ggT = grad * grad.transpose();
        const double mhh = hingeStiffness(h);
        Eigen::Matrix<double, 12, 12> K;
        if (exact) {
            const double psiSum = coupled(h, m_psi);
            const double second = -0.25 * m_psi[h] * psiSum + mhh * m_cos[h] * m_cos[h];
            K = -second * ggT;
            const auto c = corners(x, h);
            Eigen::Matrix<double, 12, 12> H;
            if (grad.squaredNorm() > 0 && dihedralAngleHessian(c, H)) {
                const double force = m_cos[h] * psiSum + m_damping * coupled(h, m_rate);
                // s_h from the gradient's norm against the unscaled one.
                std::array<Vec3, 4> g0;
                dihedralAngleGradient(c, g0);
                const double s = gradientScale(g0, h);
                K -= force * s * H + (m_damping * mhh) * grad * m_hessianV[k].transpose();
            }
        } else {
            K = -mhh * m_cos[h] * m_cos[h] * ggT;
        }
        const Eigen::Matrix<double, 12, 12> total = kx * K - (kv * m_damping * mhh) * ggT;
        for (int a = 0; a < 4; ++a) {
            for (int b = 0; b < 4; ++b) {
                blocks[static_cast<std::size_t>((4 * h + a) * 4 + b)] =
                    total.block<3, 3>(3 * a, 3 * b);
            }
        }
    });
    m_gather.gatherJacobian(blocks, J);

    // Cross-hinge blocks of the triangles holding two or three hinges.
    const auto ns = static_cast<std::int64_t>(m_stencilHinges.size());
    if (ns == 0) {
        return;
    }
    std::vector<Mat3>& cross = m_stencilBlocks;
    cross.resize(static_cast<std::size_t>(ns) * 36);
    parallelFor(ns, [&](std::int64_t ss) {
        const auto s = static_cast<std::size_t>(ss);
        for (std::size_t k = 0; k < 36; ++k) {
            cross[36 * s + k].setZero();
        }
        const auto& hinge = m_stencilHinges[s];
        for (std::size_t i = 0; i < 3; ++i) {
            for (std::size_t j = 0; j < 3; ++j) {
                const double mij = m_stencilM[s][3 * i + j];
                if (i == j || hinge[i] < 0 || hinge[j] < 0 || mij == 0.0) {
                    continue;
                }
                const auto hi = static_cast<std::size_t>(hinge[i]);
                const auto hj = static_cast<std::size_t>(hinge[j]);
                const Eigen::Matrix<double, 12, 1> gi = gradient(hi);
                const Eigen::Matrix<double, 12, 1> gj = gradient(hj);
                const double ci = m_cos[hinge[i]];
                const double cj = m_cos[hinge[j]];
                Eigen::Matrix<double, 12, 12> K = -(mij * ci * cj) * gi * gj.transpose();
                if (exact) {
                    K -= (m_damping * mij) * gi * m_hessianV[hj].transpose();
                }
                const Eigen::Matrix<double, 12, 12> total =
                    kx * K - (kv * m_damping * mij) * gi * gj.transpose();
                for (std::size_t a = 0; a < 4; ++a) {
                    for (std::size_t b = 0; b < 4; ++b) {
                        const auto sa = static_cast<std::size_t>(m_stencilSlot[s][i][a]);
                        const auto sb = static_cast<std::size_t>(m_stencilSlot[s][j][b]);
                        cross[36 * s + 6 * sa + sb] +=
                            total.block<3, 3>(3 * static_cast<int>(a), 3 * static_cast<int>(b));
                    }
                }
            }
        }
    });
    m_stencilGather.gatherJacobian(cross, J);
}

void DihedralBending::acceptStep(const MatX3& x, double dt) {
    if (!m_plasticity || !(dt > 0)) {
        return;
    }
    const double fraction = std::min(1.0, m_plasticRate * dt);
    const std::int64_t nh = m_hinges.rows();
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        const double d = angle(x, h) - m_restAngle[h];
        const double excess = std::abs(d) - m_yieldAngle;
        if (excess > 0 && std::isfinite(d)) {
            m_restAngle[h] += fraction * std::copysign(excess, d);
        }
    });
}

} // namespace atelier::sim
