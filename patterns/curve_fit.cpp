#include "patterns/curve_fit.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>

namespace atelier::patterns {

namespace {

Vec2 bezier(const std::array<Vec2, 4>& c, double t) {
    const double u = 1 - t;
    return u * u * u * c[0] + 3 * u * u * t * c[1] + 3 * u * t * t * c[2] + t * t * t * c[3];
}

Vec2 bezierDerivative(const std::array<Vec2, 4>& c, double t) {
    const double u = 1 - t;
    return 3 * u * u * (c[1] - c[0]) + 6 * u * t * (c[2] - c[1]) + 3 * t * t * (c[3] - c[2]);
}

Vec2 bezierSecond(const std::array<Vec2, 4>& c, double t) {
    return 6 * (1 - t) * (c[2] - 2 * c[1] + c[0]) + 6 * t * (c[3] - 2 * c[2] + c[1]);
}

} // namespace

void fitPolyline(const std::vector<Vec2>& p, std::size_t first, std::size_t last, double tol,
                 Loop& out, double& error, int depth) {
    const Vec2 a = p[first];
    const Vec2 b = p[last];
    const Vec2 chord = b - a;
    const double chordLength = chord.norm();
    double lineError = 0;
    std::size_t worst = first;
    for (std::size_t i = first + 1; i < last; ++i) {
        const double d = chordLength > 0 ? std::abs(sim::cross2d(chord, p[i] - a)) / chordLength
                                         : (p[i] - a).norm();
        if (d > lineError) {
            lineError = d;
            worst = i;
        }
    }
    if (last - first == 1 || lineError <= tol) {
        Segment s;
        s.start = a;
        s.end = b;
        out.push_back(s);
        error = std::max(error, lineError);
        return;
    }
    const std::size_t n = last - first + 1;
    std::vector<double> t(n, 0.0);
    double polyLength = 0;
    for (std::size_t i = 1; i < n; ++i) {
        polyLength += (p[first + i] - p[first + i - 1]).norm();
        t[i] = polyLength;
    }
    for (double& ti : t) {
        ti /= polyLength;
    }
    std::array<Vec2, 4> c{a, a, b, b};
    double fitError = std::numeric_limits<double>::infinity();
    std::size_t fitWorst = worst;
    bool solved = false;
    if (n >= 4) {
        for (int iteration = 0; iteration < 4; ++iteration) {
            double m11 = 0, m12 = 0, m22 = 0;
            Vec2 r1 = Vec2::Zero(), r2 = Vec2::Zero();
            for (std::size_t i = 0; i < n; ++i) {
                const double u = 1 - t[i];
                const double b0 = u * u * u, b1 = 3 * u * u * t[i], b2 = 3 * u * t[i] * t[i],
                             b3 = t[i] * t[i] * t[i];
                const Vec2 r = p[first + i] - b0 * a - b3 * b;
                m11 += b1 * b1;
                m12 += b1 * b2;
                m22 += b2 * b2;
                r1 += b1 * r;
                r2 += b2 * r;
            }
            const double det = m11 * m22 - m12 * m12;
            if (!(std::abs(det) > 1e-12 * (m11 * m22 + 1e-300))) {
                break;
            }
            c[1] = (m22 * r1 - m12 * r2) / det;
            c[2] = (m11 * r2 - m12 * r1) / det;
            solved = true;
            // Newton steps on each parameter towards the nearest point of the curve.
            for (std::size_t i = 1; i + 1 < n; ++i) {
                const Vec2 d = bezier(c, t[i]) - p[first + i];
                const Vec2 d1 = bezierDerivative(c, t[i]);
                const double den = d1.squaredNorm() + d.dot(bezierSecond(c, t[i]));
                if (den > 0) {
                    t[i] = std::clamp(t[i] - d.dot(d1) / den, 0.0, 1.0);
                }
            }
        }
    }
    if (solved) {
        fitError = 0;
        for (std::size_t i = 1; i + 1 < n; ++i) {
            const double d = (bezier(c, t[i]) - p[first + i]).norm();
            if (d > fitError) {
                fitError = d;
                fitWorst = first + i;
            }
        }
        // A fit that loops or wanders between the points is no fit.
        Segment s;
        s.kind = SegmentKind::Cubic;
        s.start = c[0];
        s.control1 = c[1];
        s.control2 = c[2];
        s.end = c[3];
        if (fitError <= tol && arcLength(s) <= 1.02 * polyLength + tol) {
            out.push_back(s);
            error = std::max(error, fitError);
            return;
        }
    }
    if (depth > 60) { // cannot happen with splits inside the middle half; a guard all the same
        for (std::size_t i = first; i < last; ++i) {
            Segment s;
            s.start = p[i];
            s.end = p[i + 1];
            out.push_back(s);
        }
        return;
    }
    // Split at the worst point, kept inside the middle half so that the depth stays logarithmic.
    const std::size_t quarter = (last - first) / 4;
    const std::size_t split =
        std::clamp(solved ? fitWorst : worst, first + std::max<std::size_t>(quarter, 1),
                   last - std::max<std::size_t>(quarter, 1));
    fitPolyline(p, first, split, tol, out, error, depth + 1);
    fitPolyline(p, split, last, tol, out, error, depth + 1);
}

NearestPoint nearestPoint(const Loop& loop, const Vec2& q) {
    NearestPoint best;
    for (std::size_t s = 0; s < loop.size(); ++s) {
        // A Bézier lies in the box of its control points; an arc in its chord's box widened by
        // its sagitta |bulge|·chord/2 up to a half circle, by its circle's diameter beyond.
        const Segment& seg = loop[s];
        Eigen::AlignedBox2d box(seg.start);
        box.extend(seg.end);
        if (seg.kind == SegmentKind::Quadratic || seg.kind == SegmentKind::Cubic) {
            box.extend(seg.control1);
            box.extend(seg.kind == SegmentKind::Cubic ? seg.control2 : seg.control1);
        } else if (seg.kind == SegmentKind::Arc) {
            const double chord = (seg.end - seg.start).norm();
            const double b = std::abs(seg.bulge);
            const double reach = b <= 1 ? 0.5 * b * chord : chord * (1 + b * b) / (2 * b);
            box.extend(box.min() - Vec2::Constant(reach));
            box.extend(box.max() + Vec2::Constant(reach));
        }
        if (box.exteriorDistance(q) > best.distance) {
            continue;
        }
        constexpr int SAMPLES = 32;
        double bt = 0;
        double bd = std::numeric_limits<double>::infinity();
        for (int k = 0; k <= SAMPLES; ++k) {
            const double t = double(k) / SAMPLES;
            const double d = (pointAt(loop[s], t) - q).norm();
            if (d < bd) {
                bd = d;
                bt = t;
            }
        }
        double lo = std::max(0.0, bt - 1.0 / SAMPLES);
        double hi = std::min(1.0, bt + 1.0 / SAMPLES);
        for (int k = 0; k < 40; ++k) { // golden-section refinement
            const double m1 = lo + (hi - lo) * 0.381966;
            const double m2 = lo + (hi - lo) * 0.618034;
            if ((pointAt(loop[s], m1) - q).norm() < (pointAt(loop[s], m2) - q).norm()) {
                hi = m2;
            } else {
                lo = m1;
            }
        }
        const double t = 0.5 * (lo + hi);
        const double d = (pointAt(loop[s], t) - q).norm();
        if (d < best.distance) {
            best = NearestPoint{static_cast<int>(s), t, d};
        }
    }
    return best;
}

} // namespace atelier::patterns
