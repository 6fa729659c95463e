#include "patterns/mannequin.h"

#include "patterns/body_landmarks.h"
#include "patterns/body_measure.h"
#include "patterns/isosurface.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <variant>

namespace atelier::patterns {

using sim::Vec3;

namespace {

/// A-pose: arms at least this far from the vertical, more when the bust needs the room.
constexpr double MIN_ARM_ANGLE = 45.0 * std::numbers::pi / 180.0;

/// Girths the mannequin is fitted to, in this order.
enum Girth { Bust, UnderBust, Waist, Hip, Neck, UpperArm, Thigh, GIRTHS };
/// Fitted parameters: the girths' section scales, then the crotch's height shift [m].
constexpr int Crotch = GIRTHS;
using Fit = std::array<double, GIRTHS + 1>;

double smin(double a, double b, double k) {
    const double h = std::max(k - std::abs(a - b), 0.0) / k;
    return std::min(a, b) - h * h * k * 0.25;
}

/// Distance to a round cone: spheres of radii r1 at a and r2 at b and the cone tangent to
/// both (exact; Quílez's closed form).
double roundCone(const Vec3& p, const Vec3& a, const Vec3& b, double r1, double r2) {
    const Vec3 ba = b - a;
    const double l2 = ba.dot(ba);
    const double rr = r1 - r2;
    const double a2 = l2 - rr * rr;
    const double il2 = 1.0 / l2;
    const Vec3 pa = p - a;
    const double y = pa.dot(ba);
    const double z = y - l2;
    const double x2 = (pa * l2 - ba * y).squaredNorm();
    const double y2 = y * y * l2;
    const double z2 = z * z * l2;
    const double k = (rr > 0 ? 1.0 : rr < 0 ? -1.0 : 0.0) * rr * rr * x2;
    if ((z > 0 ? 1.0 : -1.0) * a2 * z2 > k) {
        return std::sqrt(x2 + z2) * il2 - r2;
    }
    if ((y > 0 ? 1.0 : -1.0) * a2 * y2 < k) {
        return std::sqrt(x2 + y2) * il2 - r1;
    }
    return (std::sqrt(x2 * a2 * il2) + y * rr) * il2 - r1;
}

/// Distance estimate to an ellipsoid with semi-axes r along the local frame (u, v, w)
/// centred at c (zero set exact).
double ellipsoid(const Vec3& p, const Vec3& c, const Vec3& u, const Vec3& v, const Vec3& w,
                 const Vec3& r) {
    const Vec3 q((p - c).dot(u), (p - c).dot(v), (p - c).dot(w));
    const double k0 = q.cwiseQuotient(r).norm();
    const double k1 = q.cwiseQuotient(r.cwiseProduct(r)).norm();
    if (k1 < 1e-12) {
        return -r.minCoeff();
    }
    return k0 * (k0 - 1.0) / k1;
}

/// One level of the torso sweep: superellipse |x/a|^p + |(z − zc)/b|^p = 1 at height y.
struct Section {
    double y, a, b, zc, p;
};

/// Perimeter of the superellipse with a = 1, b = k, exponent p.
double superellipsePerimeter(double k, double p) {
    constexpr int N = 720;
    double perimeter = 0;
    Vec3 prev;
    for (int i = 0; i <= N; ++i) {
        const double t = 2 * std::numbers::pi * i / N;
        const double c = std::cos(t);
        const double s = std::sin(t);
        const Vec3 q(std::copysign(std::pow(std::abs(c), 2.0 / p), c), 0,
                     k * std::copysign(std::pow(std::abs(s), 2.0 / p), s));
        if (i > 0) {
            perimeter += (q - prev).norm();
        }
        prev = q;
    }
    return perimeter;
}

/// Monotone cubic (Fritsch–Carlson) slopes for values v at knots y.
std::vector<double> monotoneSlopes(const std::vector<double>& y, const std::vector<double>& v) {
    const std::size_t n = y.size();
    std::vector<double> delta(n - 1);
    for (std::size_t i = 0; i + 1 < n; ++i) {
        delta[i] = (v[i + 1] - v[i]) / (y[i + 1] - y[i]);
    }
    std::vector<double> m(n);
    m[0] = delta[0];
    m[n - 1] = delta[n - 2];
    for (std::size_t i = 1; i + 1 < n; ++i) {
        m[i] = delta[i - 1] * delta[i] <= 0 ? 0.0 : (delta[i - 1] + delta[i]) / 2;
    }
    for (std::size_t i = 0; i + 1 < n; ++i) {
        if (delta[i] == 0) {
            m[i] = m[i + 1] = 0;
            continue;
        }
        const double al = m[i] / delta[i];
        const double be = m[i + 1] / delta[i];
        const double s = al * al + be * be;
        if (s > 9) {
            const double t = 3 / std::sqrt(s);
            m[i] = t * al * delta[i];
            m[i + 1] = t * be * delta[i];
        }
    }
    return m;
}

struct Limb {
    std::vector<Vec3> joints;
    std::vector<double> radii;
    // Hand or foot ellipsoid: centre, frame, semi-axes.
    Vec3 handCentre = Vec3::Zero();
    Vec3 handU = Vec3::UnitX();
    Vec3 handV = Vec3::UnitY();
    Vec3 handW = Vec3::UnitZ();
    Vec3 handRadii = Vec3::Ones();
    Vec3 boxMin = Vec3::Zero();
    Vec3 boxMax = Vec3::Zero();
};

/// The implicit body: everything derived from the measurements and the fitted scales.
class Shape {
  public:
    Shape(bool female, const BodyMeasurements& m, const Fit& scale) : m_female(female) {
        const double H = m.height;
        const double s = H / 1.68;
        MannequinLandmarks& L = m_landmarks;
        L.crotchY = m.inseam;
        L.hipY = m.inseam + 0.065 * H;
        L.waistY = 0.625 * H;
        L.underBustY = 0.685 * H;
        L.bustY = 0.72 * H;
        L.shoulderY = 0.815 * H;
        L.neckY = 0.857 * H;
        L.thighY = m.inseam - 0.06 * s;
        L.torsoZ = 0;

        const double rNeck = m.neck / (2 * std::numbers::pi) * scale[Neck];
        const double rUpperArm = m.upperArm / (2 * std::numbers::pi) * scale[UpperArm];
        const double rThigh = m.thigh / (2 * std::numbers::pi) * scale[Thigh];
        const double rShoulder = 1.08 * rUpperArm;
        const double halfShoulder = m.shoulderWidth / 2;

        auto girthSection = [](double y, double girth, double k, double zc, double p) {
            const double a = girth / superellipsePerimeter(k, p);
            return Section{y, a, k * a, zc, p};
        };
        const double cup = m_female ? std::max(0.0, m.bust - m.underBust) : 0.0;
        const Section hip = girthSection(L.hipY, m.hip * scale[Hip], 0.74, -0.012 * s, 2.3);
        const Section waist = girthSection(L.waistY, m.waist * scale[Waist], 0.74, 0, 2.2);
        const Section under =
            girthSection(L.underBustY, m.underBust * scale[UnderBust], 0.72, 0.004 * s, 2.3);
        const double bustTorso = m_female ? m.underBust + 0.25 * cup : m.bust;
        const Section bust =
            girthSection(L.bustY, bustTorso * scale[Bust], m_female ? 0.72 : 0.68, 0.004 * s, 2.4);
        const double hx = rThigh + 0.01 * s;
        // The torso's bottom is moved so that the blended crotch lands at the inseam.
        const double crotchShift = scale[Crotch];
        m_sections = {
            {L.crotchY + crotchShift, hx + 0.75 * rThigh, 0.95 * rThigh, hip.zc, 2.3},
            {0.5 * (L.crotchY + crotchShift + L.hipY), 0.5 * (hx + 0.9 * rThigh + hip.a),
             0.5 * (rThigh + hip.b), hip.zc, 2.3},
            hip,
            waist,
            under,
            bust,
            {0.745 * H, std::max(0.98 * bust.a, halfShoulder - 1.4 * rShoulder), 0.95 * bust.b, 0.0,
             2.5},
            {L.shoulderY - 0.9 * rShoulder, halfShoulder - 0.9 * rShoulder, 0.075 * s, -0.004 * s,
             2.6},
            {L.shoulderY, halfShoulder - 1.6 * rShoulder, 0.06 * s, -0.006 * s, 2.4},
            {0.838 * H, 1.3 * rNeck, 1.15 * rNeck, -0.01 * s, 2.2},
            {L.neckY, rNeck, rNeck, -0.006 * s, 2.0},
            {0.9 * H, 0.95 * rNeck, 0.95 * rNeck, 0.0, 2.0},
        };
        std::vector<double> ys;
        for (const Section& sec : m_sections) {
            ys.push_back(sec.y);
        }
        auto channel = [&](double Section::*field) {
            std::vector<double> v;
            for (const Section& sec : m_sections) {
                v.push_back(sec.*field);
            }
            return monotoneSlopes(ys, v);
        };
        m_slopeA = channel(&Section::a);
        m_slopeB = channel(&Section::b);
        m_slopeZ = channel(&Section::zc);
        m_slopeP = channel(&Section::p);

        // Head: an egg on top, its crown at the height.
        m_headRadii = Vec3(0.075 * s, 0.0655 * H, 0.095 * s);
        m_headCentre = Vec3(0, H - m_headRadii.y(), 0.012 * s);

        // Breasts (female base): ellipsoids on the front of the bust section.
        if (m_female) {
            const double depth = std::clamp(0.3 * cup, 0.015, 0.08) * scale[Bust];
            const Vec3 r(0.36 * bust.a, 0.33 * bust.a, 0.30 * bust.a + 0.5 * depth);
            for (int side = 0; side < 2; ++side) {
                const double sx = side == 0 ? 1.0 : -1.0;
                m_breastCentre[static_cast<std::size_t>(side)] =
                    Vec3(sx * 0.46 * bust.a, L.bustY + 0.01 * s, bust.zc + bust.b + depth - r.z());
            }
            m_breastRadii = r;
        }

        // The arm angle: the smallest from 45° up that keeps the upper arm 3 cm clear of the
        // bust (breasts included) at bust height.
        double bustHalfWidth = bust.a;
        if (m_female) {
            bustHalfWidth = std::max(bustHalfWidth, m_breastCentre[0].x() + m_breastRadii.x());
        }
        double angle = MIN_ARM_ANGLE;
        for (; angle < 70.0 * std::numbers::pi / 180.0; angle += 0.5 * std::numbers::pi / 180.0) {
            const double drop = L.shoulderY - 0.95 * rShoulder - L.bustY;
            const double centre = halfShoulder - rShoulder + drop * std::tan(angle);
            if (centre - rShoulder / std::cos(angle) >= bustHalfWidth + 0.03 * s) {
                break;
            }
        }
        L.armAngle = angle;
        const double ARM_ANGLE = angle;
        for (int side = 0; side < 2; ++side) {
            const auto i = static_cast<std::size_t>(side);
            const double sx = side == 0 ? 1.0 : -1.0;
            // Arm in A-pose.
            const Vec3 shoulderPoint(sx * halfShoulder, L.shoulderY, -0.006 * s);
            const Vec3 joint(sx * (halfShoulder - rShoulder), L.shoulderY - 0.95 * rShoulder,
                             -0.006 * s);
            const Vec3 d(sx * std::sin(ARM_ANGLE), -std::cos(ARM_ANGLE), 0);
            // Wrist along d from the joint, at the arm length from the shoulder point.
            const Vec3 ja = joint - shoulderPoint;
            const double bq = ja.dot(d);
            const double t =
                -bq + std::sqrt(bq * bq - ja.squaredNorm() + m.armLength * m.armLength);
            const Vec3 wrist = joint + t * d;
            const Vec3 elbow = joint + 0.53 * t * d;
            const Vec3 forearm = elbow + 0.25 * (wrist - elbow);
            Limb arm;
            arm.joints = {joint, elbow, forearm, wrist};
            arm.radii = {rShoulder, 0.74 * rUpperArm, 0.80 * rUpperArm, 0.55 * rUpperArm};
            arm.handU = d;
            arm.handV = Vec3(sx * std::cos(ARM_ANGLE), std::sin(ARM_ANGLE), 0); // palm normal
            arm.handW = Vec3::UnitZ();
            arm.handRadii = Vec3(0.09 * s, 0.024 * s, 0.043 * s);
            arm.handCentre = wrist + 0.075 * s * d;
            m_arms[i] = arm;
            L.shoulderPoint[i] = shoulderPoint;
            L.shoulderJoint[i] = joint;
            L.elbow[i] = elbow;
            L.wrist[i] = wrist;
            L.upperArmPoint[i] = joint + 0.5 * (elbow - joint);

            // Leg, spread about 6° like a dress form's: the thighs part below the crotch, so a
            // trouser leg can be sewn around each one.
            const Vec3 hipJoint(sx * hx, L.crotchY + 0.045 * s, -0.005 * s);
            const Vec3 knee(sx * (hx + 0.045 * s), 0.285 * H, 0.0);
            const Vec3 calf(sx * (hx + 0.054 * s), 0.21 * H, -0.008 * s);
            const Vec3 ankle(sx * (hx + 0.072 * s), 0.055 * H + 0.01 * s, -0.01 * s);
            Limb leg;
            leg.joints = {hipJoint, knee, calf, ankle};
            leg.radii = {rThigh, 0.60 * rThigh, 0.62 * rThigh, 0.38 * rThigh};
            leg.handU = Vec3::UnitX();
            leg.handV = Vec3::UnitY();
            leg.handW = Vec3::UnitZ();
            leg.handRadii = Vec3(0.042 * s, 0.035 * s, 0.125 * s);
            leg.handCentre = Vec3(sx * (hx + 0.075 * s), leg.handRadii.y(), 0.045 * s);
            m_legs[i] = leg;
            L.hipJoint[i] = hipJoint;
            // The thigh's axis at the measuring height.
            const double u = (L.thighY - hipJoint.y()) / (knee.y() - hipJoint.y());
            L.thighPoint[i] = hipJoint + u * (knee - hipJoint);
        }
        for (Limb* limb : {&m_arms[0], &m_arms[1], &m_legs[0], &m_legs[1]}) {
            limb->boxMin = Vec3::Constant(1e9);
            limb->boxMax = Vec3::Constant(-1e9);
            for (std::size_t j = 0; j < limb->joints.size(); ++j) {
                limb->boxMin =
                    limb->boxMin.cwiseMin(limb->joints[j] - Vec3::Constant(limb->radii[j]));
                limb->boxMax =
                    limb->boxMax.cwiseMax(limb->joints[j] + Vec3::Constant(limb->radii[j]));
            }
            const double rh = limb->handRadii.maxCoeff();
            limb->boxMin = limb->boxMin.cwiseMin(limb->handCentre - Vec3::Constant(rh));
            limb->boxMax = limb->boxMax.cwiseMax(limb->handCentre + Vec3::Constant(rh));
        }
        m_boxMin = Vec3::Constant(1e9);
        m_boxMax = Vec3::Constant(-1e9);
        for (const Limb* limb : {&m_arms[0], &m_arms[1], &m_legs[0], &m_legs[1]}) {
            m_boxMin = m_boxMin.cwiseMin(limb->boxMin);
            m_boxMax = m_boxMax.cwiseMax(limb->boxMax);
        }
        for (const Section& sec : m_sections) {
            m_boxMin = m_boxMin.cwiseMin(Vec3(-sec.a, sec.y, sec.zc - sec.b));
            m_boxMax = m_boxMax.cwiseMax(Vec3(sec.a, sec.y, sec.zc + sec.b + 0.1 * s));
        }
        m_boxMin = m_boxMin.cwiseMin(m_headCentre - m_headRadii);
        m_boxMax = m_boxMax.cwiseMax(m_headCentre + m_headRadii);
        m_boxMin -= Vec3::Constant(0.04);
        m_boxMax += Vec3::Constant(0.04);
    }

    const MannequinLandmarks& landmarks() const { return m_landmarks; }
    Vec3 boxMin() const { return m_boxMin; }
    Vec3 boxMax() const { return m_boxMax; }

    /// Which part is nearest: 0 torso (with head, neck, breasts), 1–2 arms, 3–4 legs.
    int part(const Vec3& p) const {
        double best = core(p);
        int which = 0;
        for (int i = 0; i < 2; ++i) {
            const double a = limb(m_arms[static_cast<std::size_t>(i)], p);
            if (a < best) {
                best = a;
                which = 1 + i;
            }
            const double l = limb(m_legs[static_cast<std::size_t>(i)], p);
            if (l < best) {
                best = l;
                which = 3 + i;
            }
        }
        return which;
    }

    double operator()(const Vec3& p) const {
        double f = core(p);
        for (const Limb& arm : m_arms) {
            f = blendLimb(f, arm, p, 0.025);
        }
        for (const Limb& leg : m_legs) {
            f = blendLimb(f, leg, p, 0.04);
        }
        return f;
    }

  private:
    double blendLimb(double f, const Limb& limb, const Vec3& p, double k) const {
        // Beyond the limb's box by more than the blend, it cannot change f.
        const Vec3 out = (limb.boxMin - p).cwiseMax(p - limb.boxMax).cwiseMax(0.0);
        if (out.norm() > f + k) {
            return f;
        }
        return smin(f, this->limb(limb, p), k);
    }

    double limb(const Limb& limb, const Vec3& p) const {
        double d = 1e9;
        for (std::size_t j = 0; j + 1 < limb.joints.size(); ++j) {
            d = smin(
                d,
                roundCone(p, limb.joints[j], limb.joints[j + 1], limb.radii[j], limb.radii[j + 1]),
                0.02);
        }
        return smin(
            d, ellipsoid(p, limb.handCentre, limb.handU, limb.handV, limb.handW, limb.handRadii),
            0.02);
    }

    Section sectionAt(double y) const {
        const std::size_t n = m_sections.size();
        if (y <= m_sections.front().y) {
            return m_sections.front();
        }
        if (y >= m_sections.back().y) {
            return m_sections.back();
        }
        std::size_t i = 0;
        while (i + 2 < n && y > m_sections[i + 1].y) {
            ++i;
        }
        const Section& s0 = m_sections[i];
        const Section& s1 = m_sections[i + 1];
        const double h = s1.y - s0.y;
        const double t = (y - s0.y) / h;
        const double h00 = (1 + 2 * t) * (1 - t) * (1 - t);
        const double h10 = t * (1 - t) * (1 - t);
        const double h01 = t * t * (3 - 2 * t);
        const double h11 = t * t * (t - 1);
        auto mix = [&](double v0, double v1, const std::vector<double>& m) {
            return h00 * v0 + h10 * h * m[i] + h01 * v1 + h11 * h * m[i + 1];
        };
        return {y, mix(s0.a, s1.a, m_slopeA), mix(s0.b, s1.b, m_slopeB),
                mix(s0.zc, s1.zc, m_slopeZ), mix(s0.p, s1.p, m_slopeP)};
    }

    double torso(const Vec3& p) const {
        const Section s = sectionAt(p.y());
        const double ux = std::abs(p.x()) / s.a;
        const double uz = std::abs(p.z() - s.zc) / s.b;
        const double q = std::pow(std::pow(ux, s.p) + std::pow(uz, s.p), 1.0 / s.p);
        double d;
        if (q < 1e-9) {
            d = -std::min(s.a, s.b);
        } else {
            // (q − 1)/|∇q|: first-order distance to the section's outline.
            const double gx = std::pow(ux / q, s.p - 1) / s.a;
            const double gz = std::pow(uz / q, s.p - 1) / s.b;
            d = (q - 1) / std::max(std::hypot(gx, gz), 1e-9);
        }
        // Cut flat at the top (inside the head) and, with a rounded edge, at the crotch.
        const double bottom = m_sections.front().y - p.y();
        const double top = p.y() - m_sections.back().y;
        return std::max(-smin(-d, -bottom, 0.05), top);
    }

    double core(const Vec3& p) const {
        double f = torso(p);
        f = smin(
            f, ellipsoid(p, m_headCentre, Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), m_headRadii),
            0.03);
        if (m_female) {
            for (const Vec3& c : m_breastCentre) {
                f = smin(
                    f, ellipsoid(p, c, Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), m_breastRadii),
                    0.035);
            }
        }
        return f;
    }

    bool m_female;
    MannequinLandmarks m_landmarks;
    std::vector<Section> m_sections;
    std::vector<double> m_slopeA, m_slopeB, m_slopeZ, m_slopeP;
    Vec3 m_headCentre, m_headRadii;
    std::array<Vec3, 2> m_breastCentre{};
    Vec3 m_breastRadii = Vec3::Zero();
    std::array<Limb, 2> m_arms, m_legs;
    Vec3 m_boxMin, m_boxMax;
};

double targetGirth(const BodyMeasurements& m, int g) {
    switch (g) {
    case Bust:
        return m.bust;
    case UnderBust:
        return m.underBust;
    case Waist:
        return m.waist;
    case Hip:
        return m.hip;
    case Neck:
        return m.neck;
    case UpperArm:
        return m.upperArm;
    default:
        return m.thigh;
    }
}

/// First crossing of the vertical line through (x, z) with the mesh, from below [m].
double lowestCrossing(const sim::MatX3& v, const sim::MatX3i& f, double x, double z) {
    double best = std::numeric_limits<double>::infinity();
    for (Eigen::Index t = 0; t < f.rows(); ++t) {
        const Vec3 a = v.row(f(t, 0));
        const Vec3 b = v.row(f(t, 1));
        const Vec3 c = v.row(f(t, 2));
        // Barycentric coordinates of (x, z) in the triangle's xz projection.
        const double det = (b.x() - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (b.z() - a.z());
        if (std::abs(det) < 1e-18) {
            continue;
        }
        const double l1 = ((x - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (z - a.z())) / det;
        const double l2 = ((b.x() - a.x()) * (z - a.z()) - (x - a.x()) * (b.z() - a.z())) / det;
        if (l1 < 0 || l2 < 0 || l1 + l2 > 1) {
            continue;
        }
        best = std::min(best, a.y() + l1 * (b.y() - a.y()) + l2 * (c.y() - a.y()));
    }
    return best;
}

/// Where the slots go: axes and ranges from landmarks; radii enclose the parts' vertices.
struct SlotFrame {
    Vec3 torsoOrigin;
    double shoulderHalfWidth = 0; ///< torso slots also enclose the shoulders up to here
    double crotchY = 0, shoulderY = 0, neckY = 0;
    std::array<Vec3, 2> shoulderJoint, armAxis, armTop, hipJoint;
    std::array<double, 2> armLength{};
};

/// The 1 cm profile bin (of `bins` from alongMin) nearest to `along`, clamped to the ends.
std::size_t profileBin(const ArrangementSlot& slot, double along, std::size_t bins) {
    const long k = std::lround((along - slot.alongMin) / 0.01);
    return static_cast<std::size_t>(std::clamp(k, 0L, static_cast<long>(bins) - 1));
}

/// Which vertices a slot encloses: (vertex, its part label) → in or not.
using VertexSelection = std::function<bool(Eigen::Index, int)>;

/// The section centres of the selected vertices along a slot's axis, in 1 cm bins from
/// alongMin (as its profile), as offsets ⟂ axis from it [m]: each bin's bounding-box centre
/// in the plane ⟂ axis, an empty bin taking the nearest filled bin's (the lower one on a tie;
/// none filled: the axis), then averaged over ±5 bins so the surface bends smoothly (on a leg
/// slot, from the half pelvis to the thigh).
std::vector<Vec3> sectionCentres(const sim::MatX3& x, const std::vector<int>& part,
                                 const ArrangementSlot& slot, std::size_t bins,
                                 const VertexSelection& in) {
    const Vec3 right = slot.right();
    std::vector<Vec3> lo(bins, Vec3::Constant(std::numeric_limits<double>::infinity()));
    std::vector<Vec3> hi(bins, Vec3::Constant(-std::numeric_limits<double>::infinity()));
    for (Eigen::Index v = 0; v < x.rows(); ++v) {
        if (!in(v, part[static_cast<std::size_t>(v)])) {
            continue;
        }
        const Vec3 d = Vec3(x.row(v)) - slot.origin;
        const double along = d.dot(slot.axis);
        if (along < slot.alongMin || along > slot.alongMax) {
            continue;
        }
        const std::size_t k = profileBin(slot, along, bins);
        const Vec3 q(d.dot(right), d.dot(slot.facing), 0);
        lo[k] = lo[k].cwiseMin(q);
        hi[k] = hi[k].cwiseMax(q);
    }
    auto filled = [&](std::size_t k) { return lo[k].x() <= hi[k].x(); };
    std::vector<long> source(bins, -1); // the filled bin each bin takes its centre from
    for (std::size_t k = 0, last = bins; k < bins; ++k) {
        last = filled(k) ? k : last;
        source[k] = last < bins ? static_cast<long>(last) : -1;
    }
    for (std::size_t k = bins, next = bins; k-- > 0;) {
        next = filled(k) ? k : next;
        const long from = source[k];
        if (next < bins &&
            (from < 0 || static_cast<long>(next - k) < static_cast<long>(k) - from)) {
            source[k] = static_cast<long>(next);
        }
    }
    std::vector<Vec3> mid(bins, Vec3::Zero());
    for (std::size_t k = 0; k < bins; ++k) {
        if (source[k] >= 0) {
            const auto from = static_cast<std::size_t>(source[k]);
            mid[k] = 0.5 * (lo[from] + hi[from]);
        }
    }
    std::vector<Vec3> centres(bins);
    for (std::size_t k = 0; k < bins; ++k) {
        Vec3 acc = Vec3::Zero();
        int count = 0;
        for (std::size_t j = k >= 5 ? k - 5 : 0; j <= std::min(bins - 1, k + 5); ++j) {
            acc += mid[j];
            ++count;
        }
        acc /= count;
        centres[k] = acc.x() * right + acc.y() * slot.facing;
    }
    return centres;
}

/// Part labels: 0 torso (head, neck), 1–2 arms (left, right), 3–4 legs, −1 none.
std::vector<ArrangementSlot> computeSlots(const sim::MatX3& x, const std::vector<int>& part,
                                          const SlotFrame& f) {
    std::vector<ArrangementSlot> slots;
    // Aggregate initialisation would leave the newer members to -Wmissing-field-initializers.
    auto slotOf = [](std::string name, const Vec3& origin, const Vec3& axis, const Vec3& facing,
                     double radius, double alongMin, double alongMax) {
        ArrangementSlot s;
        s.name = std::move(name);
        s.origin = origin;
        s.axis = axis;
        s.facing = facing;
        s.radius = radius;
        s.alongMin = alongMin;
        s.alongMax = alongMax;
        return s;
    };
    auto parts = [&](std::initializer_list<int> labels) -> VertexSelection {
        return [labels = std::vector<int>(labels)](Eigen::Index, int pv) {
            return std::find(labels.begin(), labels.end(), pv) != labels.end();
        };
    };
    bool paired = true; // front/back (or left/right) panels share the slot's circumference
    // The radius encloses the selected vertices in the slot's range, and those of `nearParts`
    // closer to the axis than `nearRadius` (the shoulders, labelled arm, around the torso);
    // a centred slot (a leg) measures them from its sections' centres, not from the axis.
    auto enclose = [&](ArrangementSlot slot, const VertexSelection& in, bool centred,
                       std::initializer_list<int> nearParts = {}, double nearRadius = 0) {
        // The radius, and its profile along the axis in 1 cm bins (each bin later also
        // covering its neighbours), from the same vertices.
        const int bins = static_cast<int>(std::ceil((slot.alongMax - slot.alongMin) / 0.01)) + 1;
        slot.profileStep = 0.01;
        if (centred) {
            slot.profileCentre = sectionCentres(x, part, slot, static_cast<std::size_t>(bins), in);
        }
        std::vector<double> prof(static_cast<std::size_t>(bins), 0.0);
        double r = 0;
        for (Eigen::Index v = 0; v < x.rows(); ++v) {
            const int pv = part[static_cast<std::size_t>(v)];
            const bool inside = in(v, pv);
            const bool near = std::find(nearParts.begin(), nearParts.end(), pv) != nearParts.end();
            if (!inside && !near) {
                continue;
            }
            Vec3 d = Vec3(x.row(v)) - slot.origin;
            const double along = d.dot(slot.axis);
            if (along < slot.alongMin || along > slot.alongMax) {
                continue;
            }
            if (centred) {
                d -= slot.centreAt(along); // where wrapOnSlot puts the surface's centre
            }
            const double radial = (d - along * slot.axis).norm();
            if (inside || radial <= nearRadius) {
                r = std::max(r, radial);
                const std::size_t k = profileBin(slot, along, static_cast<std::size_t>(bins));
                prof[k] = std::max(prof[k], radial);
            }
        }
        slot.radius = r;
        slot.profile.assign(prof.size(), 0.0);
        for (int k = 0; k < bins; ++k) {
            double m = 0;
            for (int j = std::max(0, k - 2); j <= std::min(bins - 1, k + 2); ++j) {
                m = std::max(m, prof[static_cast<std::size_t>(j)]);
            }
            slot.profile[static_cast<std::size_t>(k)] = m > 0 ? m : r;
        }
        slot.profileStep = 0.01;
        slot.maxAngle = paired ? 0.49 * std::numbers::pi : 0.97 * std::numbers::pi;
        slots.push_back(slot);
    };
    const double waistY = f.torsoOrigin.y();
    const std::array<std::pair<const char*, Vec3>, 4> facings = {{
        {"front", Vec3::UnitZ()},
        {"back", -Vec3::UnitZ()},
        {"left", Vec3::UnitX()},
        {"right", -Vec3::UnitX()},
    }};
    for (const auto& [name, facing] : facings) {
        enclose(slotOf(std::string("torso_") + name, f.torsoOrigin, Vec3::UnitY(), facing, 0,
                       f.crotchY - waistY, f.shoulderY - waistY + 0.01),
                parts({0}), false, {1, 2}, f.shoulderHalfWidth + 0.005);
        // A torso panel hugging the bust would wrap its sides into the arms: the torso slots
        // stay cylinders of the whole torso's radius.
        slots.back().profile.clear();
    }
    for (const auto& [name, facing] : facings) {
        enclose(slotOf(std::string("waist_") + name, f.torsoOrigin, Vec3::UnitY(), facing, 0,
                       f.crotchY - 0.02 - waistY, 0.06),
                parts({0, 3, 4}), false);
    }
    paired = false;
    enclose(slotOf("neck", Vec3(f.torsoOrigin.x(), f.neckY, f.torsoOrigin.z()), Vec3::UnitY(),
                   Vec3::UnitZ(), 0, -0.03, 0.03),
            parts({0}), false);
    for (std::size_t i = 0; i < 2; ++i) {
        const std::string lr = i == 0 ? "left" : "right";
        const int side = static_cast<int>(i);
        // Arm: +axis toward the shoulder, facing the top of the arm.
        paired = false;
        enclose(slotOf("arm_" + lr, f.shoulderJoint[i], f.armAxis[i], f.armTop[i], 0,
                       -f.armLength[i], 0.0),
                parts({1 + side}), false);
        paired = true;
        // Leg: from the ankle up to the waist band's top (as the waist slots), following the
        // leg's sections and the pelvis on its side (torso vertices on that side of the
        // torso's axis): a trouser panel placed here starts around its own leg, its
        // inseam beside the other panel's. The back slot is the front one facing back (the
        // same centres, radius and profile).
        const Vec3 legOrigin(f.hipJoint[i].x(), f.crotchY, f.hipJoint[i].z());
        const double sx = i == 0 ? 1.0 : -1.0;
        const int leg = 3 + side;
        const VertexSelection legSide = [&, sx, leg](Eigen::Index v, int pv) {
            return pv == leg || (pv == 0 && sx * (x(v, 0) - f.torsoOrigin.x()) > 0);
        };
        enclose(slotOf("leg_" + lr + "_front", legOrigin, Vec3::UnitY(), Vec3::UnitZ(), 0,
                       -f.crotchY + 0.09, waistY + 0.06 - f.crotchY),
                legSide, true);
        ArrangementSlot back = slots.back();
        back.name = "leg_" + lr + "_back";
        back.facing = -Vec3::UnitZ();
        slots.push_back(back);
    }
    return slots;
}

} // namespace

std::optional<std::string> estimateSlots(Body& body) {
    auto found = findLandmarks(body.vertices, body.triangles);
    if (const auto* problem = std::get_if<std::string>(&found)) {
        return *problem;
    }
    const auto& [L, part] = std::get<FoundLandmarks>(found);
    // The slots are made in the body's own frame (facing +z, its left +x, as the mannequin's)
    // and turned back into the mesh's.
    sim::MatX3 local(body.vertices.rows(), 3);
    for (Eigen::Index v = 0; v < local.rows(); ++v) {
        local.row(v) = L.toLocal(body.vertices.row(v)).transpose();
    }
    SlotFrame frame;
    frame.torsoOrigin = Vec3(0, L.waistY, 0);
    frame.shoulderHalfWidth = L.shoulderHalfWidth + 0.025 * L.height;
    frame.crotchY = L.crotchY;
    frame.shoulderY = L.shoulderY;
    frame.neckY = L.neckY;
    for (std::size_t i = 0; i < 2; ++i) {
        frame.shoulderJoint[i] = L.toLocal(L.shoulderJoint[i]);
        const Vec3 axis(L.armAxis[i].dot(L.left), L.armAxis[i].y(), L.armAxis[i].dot(L.facing));
        frame.armAxis[i] = axis;
        frame.armLength[i] = (L.shoulderJoint[i] - L.wrist[i]).norm();
        const Vec3 up = Vec3::UnitY() - axis * axis.y();
        frame.armTop[i] = up.norm() > 1e-6 ? Vec3(up.normalized()) : Vec3(Vec3::UnitX());
        frame.hipJoint[i] = L.toLocal(L.hipJoint[i]);
    }
    body.slots = computeSlots(local, part, frame);
    for (ArrangementSlot& s : body.slots) {
        s.origin = L.toWorld(s.origin);
        s.axis = L.directionToWorld(s.axis);
        s.facing = L.directionToWorld(s.facing);
        for (Vec3& c : s.profileCentre) {
            c = L.directionToWorld(c);
        }
    }
    return std::nullopt;
}

std::vector<std::pair<std::string_view, double BodyMeasurements::*>> measurementFields() {
    return {{"height", &BodyMeasurements::height},
            {"bust", &BodyMeasurements::bust},
            {"under_bust", &BodyMeasurements::underBust},
            {"waist", &BodyMeasurements::waist},
            {"hip", &BodyMeasurements::hip},
            {"neck", &BodyMeasurements::neck},
            {"shoulder_width", &BodyMeasurements::shoulderWidth},
            {"arm_length", &BodyMeasurements::armLength},
            {"upper_arm", &BodyMeasurements::upperArm},
            {"inseam", &BodyMeasurements::inseam},
            {"thigh", &BodyMeasurements::thigh}};
}

bool baseMeasurements(std::string_view base, BodyMeasurements& out) {
    if (base == "female") {
        out = BodyMeasurements{};
        return true;
    }
    if (base == "male") {
        out = BodyMeasurements{1.78, 1.00, 0.92, 0.86, 0.99, 0.39, 0.46, 0.62, 0.31, 0.82, 0.56};
        return true;
    }
    return false;
}

std::vector<std::pair<std::string, std::string>> checkMeasurements(const BodyMeasurements& m) {
    std::vector<std::pair<std::string, std::string>> issues;
    auto range = [&](std::string_view field, double v, double lo, double hi) {
        if (!(v >= lo && v <= hi)) {
            issues.emplace_back(std::string(field), "must be in [" +
                                                        std::to_string(lo).substr(0, 5) + ", " +
                                                        std::to_string(hi).substr(0, 5) +
                                                        "] m (found " + std::to_string(v) + ")");
        }
    };
    range("height", m.height, 1.4, 2.1);
    const double H = m.height;
    range("bust", m.bust, 0.45 * H, 0.85 * H);
    range("under_bust", m.underBust, 0.38 * H, std::min(m.bust, 0.8 * H));
    range("waist", m.waist, 0.33 * H, 0.8 * H);
    range("hip", m.hip, 0.45 * H, 0.85 * H);
    range("neck", m.neck, 0.16 * H, 0.28 * H);
    range("shoulder_width", m.shoulderWidth, 0.19 * H, 0.3 * H);
    range("arm_length", m.armLength, 0.3 * H, 0.4 * H);
    range("upper_arm", m.upperArm, 0.12 * H, 0.26 * H);
    range("inseam", m.inseam, 0.40 * H, 0.5 * H);
    range("thigh", m.thigh, 0.26 * H, std::min(0.42 * H, 0.6 * m.hip));
    if (m.waist > 1.25 * std::min(m.hip, m.bust)) {
        issues.emplace_back("waist", "is more than 1.25 times the smaller of hip and bust");
    }
    return issues;
}

BodyMeasurements measureMannequin(const sim::MatX3& vertices, const sim::MatX3i& triangles,
                                  const MannequinLandmarks& L) {
    BodyMeasurements out;
    out.height = vertices.col(1).maxCoeff() - vertices.col(1).minCoeff();
    const Vec3 up = Vec3::UnitY();
    auto girth = [&](const Vec3& point, const Vec3& normal) {
        return tapeGirth(vertices, triangles, point, normal).value_or(0.0);
    };
    out.bust = girth(Vec3(0, L.bustY, L.torsoZ), up);
    out.underBust = girth(Vec3(0, L.underBustY, L.torsoZ), up);
    out.waist = girth(Vec3(0, L.waistY, L.torsoZ), up);
    out.hip = girth(Vec3(0, L.hipY, L.torsoZ), up);
    out.neck = girth(Vec3(0, L.neckY, L.torsoZ), up);
    out.upperArm = girth(L.upperArmPoint[0], (L.elbow[0] - L.shoulderJoint[0]).normalized());
    out.thigh = girth(L.thighPoint[0], up);
    out.inseam = lowestCrossing(vertices, triangles, 0, L.torsoZ) - vertices.col(1).minCoeff();
    out.shoulderWidth = (L.shoulderPoint[0] - L.shoulderPoint[1]).norm();
    out.armLength = (L.wrist[0] - L.shoulderPoint[0]).norm();
    return out;
}

Mannequin makeMannequin(std::string_view base, const BodyMeasurements& m,
                        const MannequinOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const bool female = base != "male";
    Fit scale;
    scale.fill(1.0);
    scale[Crotch] = 0;
    Mannequin out;
    out.requested = m;
    for (int round = 0;; ++round) {
        const Shape shape(female, m, scale);
        IsosurfaceOptions iso;
        iso.boxMin = shape.boxMin();
        iso.boxMax = shape.boxMax();
        iso.cell = options.cell;
        const bool last = round >= options.fitIterations;
        // Fitting rounds relax less: the girths hardly depend on it.
        iso.relaxIterations = last ? 6 : 2;
        const Isosurface surface =
            extractIsosurface([&shape](const Vec3& p) { return shape(p); }, iso);
        const BodyMeasurements measured =
            measureMannequin(surface.vertices, surface.triangles, shape.landmarks());
        double worst = 0;
        for (int g = 0; g < GIRTHS; ++g) {
            worst = std::max(worst, std::abs(targetGirth(measured, g) - targetGirth(m, g)));
        }
        worst = std::max(worst, std::abs(measured.inseam - m.inseam));
        if (!last && worst < options.fitTolerance) {
            round = options.fitIterations - 1; // one more, final round with full relaxation
        } else if (last) {
            out.body.vertices = surface.vertices;
            out.body.triangles = surface.triangles;
            out.normals = surface.normals;
            out.landmarks = shape.landmarks();
            out.measured = measured;
            std::vector<int> part(static_cast<std::size_t>(surface.vertices.rows()));
            for (Eigen::Index v = 0; v < surface.vertices.rows(); ++v) {
                part[static_cast<std::size_t>(v)] = shape.part(surface.vertices.row(v));
            }
            const MannequinLandmarks& L = out.landmarks;
            SlotFrame frame;
            frame.torsoOrigin = Vec3(0, L.waistY, L.torsoZ);
            frame.shoulderHalfWidth = 0.5 * m.shoulderWidth;
            frame.crotchY = L.crotchY;
            frame.shoulderY = L.shoulderY;
            frame.neckY = L.neckY;
            for (std::size_t i = 0; i < 2; ++i) {
                const double sx = i == 0 ? 1.0 : -1.0;
                frame.shoulderJoint[i] = L.shoulderJoint[i];
                frame.armAxis[i] = (L.shoulderJoint[i] - L.wrist[i]).normalized();
                frame.armLength[i] = (L.wrist[i] - L.shoulderJoint[i]).norm();
                frame.armTop[i] = Vec3(sx * std::cos(L.armAngle), std::sin(L.armAngle), 0);
                frame.hipJoint[i] = L.hipJoint[i];
            }
            out.body.slots = computeSlots(surface.vertices, part, frame);
            break;
        }
        for (int g = 0; g < GIRTHS; ++g) {
            const double got = targetGirth(measured, g);
            // Damped: a section that merges with a neighbour for a round must not throw
            // the fit off.
            if (got > 0) {
                scale[static_cast<std::size_t>(g)] *= std::clamp(targetGirth(m, g) / got, 0.9, 1.1);
            }
        }
        scale[Crotch] += std::clamp(m.inseam - measured.inseam, -0.03, 0.03);
    }
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return out;
}

} // namespace atelier::patterns
