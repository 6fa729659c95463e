#include "sim/forces/bending.h"

#include "sim/core/parallel.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace atelier::sim {

namespace {

/// A hinge's corners may feel |∇θ| up to this many times their rest value (the header's cap).
constexpr double HINGE_GRADIENT_CAP = 50.0;

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

void HingeSet::resize(int count) {
    corners.setZero(count, 4);
    weight.setZero(count);
    gradientCap.setZero(count);
    restAngle.setZero(count);
    stiffness.setZero(count);
    damping.setZero(count);
}

void HingeSet::setRestShape(int h, double edgeSquared, double area0, double area1) {
    const double areas = std::abs(area0) + std::abs(area1);
    weight[h] = areas > 0 ? 3.0 * edgeSquared / areas : 0.0;
    const double edge = std::sqrt(edgeSquared);
    // |∇θ| at a wing tip is 1/height; allow HINGE_GRADIENT_CAP times the rest value.
    const double h0 = edge > 0 ? 2.0 * std::abs(area0) / edge : 0.0;
    const double h1 = edge > 0 ? 2.0 * std::abs(area1) / edge : 0.0;
    const double hmin = std::min(h0, h1);
    gradientCap[h] = hmin > 0 ? HINGE_GRADIENT_CAP / hmin : 0.0;
}

namespace {

/// The hinges of one cloth, shifted to global indices, with its material's k and τ.
HingeSet clothHinges(const ClothMesh& mesh, int offset, const Material& material,
                     const VecX& restAngles) {
    HingeSet set;
    const int nh = static_cast<int>(mesh.hinges.rows());
    set.resize(nh);
    set.corners = mesh.hinges.array() + offset;
    set.stiffness.setConstant(std::max(material.bending, 0.0));
    set.damping.setConstant(std::max(material.damping, 0.0));
    if (restAngles.size() == nh) {
        set.restAngle = restAngles;
    }
    // Each hinge's triangles: the rest areas come from the pattern coordinates.
    for (int h = 0; h < nh; ++h) {
        const Vec2 p0 = mesh.rest.row(mesh.hinges(h, 0)).transpose();
        const Vec2 p1 = mesh.rest.row(mesh.hinges(h, 1)).transpose();
        const Vec2 p2 = mesh.rest.row(mesh.hinges(h, 2)).transpose();
        const Vec2 p3 = mesh.rest.row(mesh.hinges(h, 3)).transpose();
        set.setRestShape(h, (p1 - p0).squaredNorm(), signedArea(p0, p1, p2),
                         signedArea(p1, p0, p3));
    }
    return set;
}

} // namespace

DihedralBending::DihedralBending(const ClothMesh& mesh, int offset, const Material& material,
                                 const VecX& restAngles, bool plasticity)
    : DihedralBending(clothHinges(mesh, offset, material, restAngles), "bending") {
    m_plasticity = plasticity && material.plasticYieldAngle > 0;
    m_yieldAngle = material.plasticYieldAngle;
    m_plasticRate = std::max(material.plasticRate, 0.0);
}

DihedralBending::DihedralBending(HingeSet hinges, std::string_view name)
    : m_set(std::move(hinges)), m_name(name), m_plasticity(false), m_yieldAngle(0),
      m_plasticRate(0), m_gather(m_set.corners, 0) {}

double DihedralBending::gradientScale(const std::array<Vec3, 4>& g, int h) const {
    double largest = 0;
    for (const Vec3& ga : g) {
        largest = std::max(largest, ga.norm());
    }
    const double cap = m_set.gradientCap[h];
    return largest > cap ? cap / largest : 1.0;
}

std::array<Vec3, 4> DihedralBending::corners(const MatX3& x, int h) const {
    std::array<Vec3, 4> c;
    for (int a = 0; a < 4; ++a) {
        c[static_cast<std::size_t>(a)] = x.row(m_set.corners(h, a)).transpose();
    }
    return c;
}

double DihedralBending::angle(const MatX3& x, int h) const {
    const auto c = corners(x, h);
    return dihedralAngle(c[0], c[1], c[2], c[3]);
}

void DihedralBending::addForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    const std::int64_t nh = m_set.corners.rows();
    MatX3& buffer = m_buffer;
    buffer.setZero(4 * nh, 3);
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        if (!active(h)) {
            return;
        }
        const auto c = corners(x, h);
        std::array<Vec3, 4> g;
        if (!dihedralAngleGradient(c, g)) {
            return;
        }
        const auto cv = corners(v, h);
        double thetaDot = 0;
        for (std::size_t a = 0; a < 4; ++a) {
            thetaDot += g[a].dot(cv[a]);
        }
        const double theta = dihedralAngle(c[0], c[1], c[2], c[3]);
        // dE/dθ = k w sin(θ − θ̄): continuous when the hinge folds through ±π (see header).
        const double s = -m_set.stiffness[h] * m_set.weight[h] * gradientScale(g, h) *
                         (std::sin(theta - m_set.restAngle[h]) + m_set.damping[h] * thetaDot);
        for (std::size_t a = 0; a < 4; ++a) {
            buffer.row(4 * hh + static_cast<std::int64_t>(a)) = s * g[a].transpose();
        }
    });
    m_gather.gather(buffer, f);
}

double DihedralBending::energy(const MatX3& x) const {
    const std::int64_t nh = m_set.corners.rows();
    VecX w = VecX::Zero(nh);
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        if (active(h)) {
            const double d = angle(x, h) - m_set.restAngle[h];
            w[h] = m_set.stiffness[h] * m_set.weight[h] * (1.0 - std::cos(d));
        }
    });
    return w.sum();
}

void DihedralBending::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    m_gather.addPattern(pairs);
}

void DihedralBending::addJacobian(const MatX3& x, const MatX3& v, double kx, double kv,
                                  JacobianMode mode, BlockSparseMatrix& J) const {
    const std::int64_t nh = m_set.corners.rows();
    // Reused between calls and filled in the parallel loop (allocated and zeroed serially up
    // front, 16 blocks per hinge were 28 MB a step for the 10 mm tshirt).
    std::vector<Mat3>& blocks = m_blocks;
    blocks.resize(static_cast<std::size_t>(nh) * 16);
    const bool exact = mode == JacobianMode::Exact;
    parallelFor(nh, [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        const auto c = corners(x, h);
        std::array<Vec3, 4> g;
        if (!active(h) || !dihedralAngleGradient(c, g)) {
            for (std::size_t k = 0; k < 16; ++k) {
                blocks[static_cast<std::size_t>(16 * h) + k].setZero();
            }
            return;
        }
        Eigen::Matrix<double, 12, 1> grad;
        Eigen::Matrix<double, 12, 1> vel;
        const auto cv = corners(v, h);
        for (std::size_t a = 0; a < 4; ++a) {
            grad.segment<3>(3 * static_cast<int>(a)) = g[a];
            vel.segment<3>(3 * static_cast<int>(a)) = cv[a];
        }
        const double kw = m_set.stiffness[h] * m_set.weight[h] * gradientScale(g, h);
        const double tau = m_set.damping[h];
        const Eigen::Matrix<double, 12, 12> ggT = grad * grad.transpose();
        const double d = dihedralAngle(c[0], c[1], c[2], c[3]) - m_set.restAngle[h];
        Eigen::Matrix<double, 12, 12> K;
        if (exact) {
            K = -kw * std::cos(d) * ggT;
            Eigen::Matrix<double, 12, 12> H;
            if (dihedralAngleHessian(c, H)) {
                const double thetaDot = grad.dot(vel);
                const double s = std::sin(d) + tau * thetaDot;
                K -= kw * (s * H + tau * grad * (H * vel).transpose());
            }
        } else {
            K = -kw * std::max(0.0, std::cos(d)) * ggT;
        }
        const Eigen::Matrix<double, 12, 12> total = kx * K - (kv * kw * tau) * ggT;
        for (int a = 0; a < 4; ++a) {
            for (int b = 0; b < 4; ++b) {
                blocks[static_cast<std::size_t>((4 * h + a) * 4 + b)] =
                    total.block<3, 3>(3 * a, 3 * b);
            }
        }
    });
    m_gather.gatherJacobian(blocks, J);
}

void DihedralBending::acceptStep(const MatX3& x, double dt) {
    if (m_plasticity) {
        flowRestAngles(m_set.restAngle, m_yieldAngle, m_plasticRate, dt,
                       [&](int h) { return angle(x, h); });
    }
}

void flowRestAngles(VecX& restAngle, double yieldAngle, double rate, double dt,
                    const std::function<double(int)>& foldOf) {
    if (!(dt > 0)) {
        return;
    }
    const double fraction = std::min(1.0, rate * dt);
    parallelFor(restAngle.size(), [&](std::int64_t hh) {
        const int h = static_cast<int>(hh);
        const double d = foldOf(h) - restAngle[h];
        const double excess = std::abs(d) - yieldAngle;
        if (excess > 0 && std::isfinite(d)) {
            restAngle[h] += fraction * std::copysign(excess, d);
        }
    });
}

} // namespace atelier::sim
