#include "patterns/curve.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace atelier::patterns {

namespace {

// 8-point Gauss–Legendre nodes and weights on [−1, 1].
constexpr std::array<double, 8> GL_X = {
    -0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
    0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
constexpr std::array<double, 8> GL_W = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                        0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                        0.2223810344533745, 0.1012285362903763};

template <class F> double integrate(double a, double b, int pieces, F f) {
    double sum = 0;
    const double step = (b - a) / pieces;
    for (int p = 0; p < pieces; ++p) {
        const double lo = a + p * step;
        const double mid = lo + 0.5 * step, half = 0.5 * step;
        for (std::size_t k = 0; k < GL_X.size(); ++k) {
            sum += GL_W[k] * half * f(mid + half * GL_X[k]);
        }
    }
    return sum;
}

} // namespace

bool arcGeometry(const Segment& s, Vec2& centre, double& radius, double& startAngle,
                 double& sweep) {
    const Vec2 chord = s.end - s.start;
    const double c = chord.norm();
    if (s.kind != SegmentKind::Arc || s.bulge == 0 || c == 0) {
        return false;
    }
    sweep = 4.0 * std::atan(s.bulge);
    const double half = 0.5 * sweep;
    radius = 0.5 * c / std::abs(std::sin(half));
    const Vec2 left(-chord.y() / c, chord.x() / c);
    centre = 0.5 * (s.start + s.end) + left * (0.5 * c / std::tan(half));
    startAngle = std::atan2(s.start.y() - centre.y(), s.start.x() - centre.x());
    return true;
}

Vec2 pointAt(const Segment& s, double t) {
    const double u = 1 - t;
    switch (s.kind) {
    case SegmentKind::Line:
        return u * s.start + t * s.end;
    case SegmentKind::Quadratic:
        return u * u * s.start + 2 * u * t * s.control1 + t * t * s.end;
    case SegmentKind::Cubic:
        return u * u * u * s.start + 3 * u * u * t * s.control1 + 3 * u * t * t * s.control2 +
               t * t * t * s.end;
    case SegmentKind::Arc: {
        Vec2 centre;
        double r, a0, sweep;
        if (!arcGeometry(s, centre, r, a0, sweep)) {
            return u * s.start + t * s.end;
        }
        if (t <= 0) {
            return s.start;
        }
        if (t >= 1) {
            return s.end;
        }
        const double a = a0 + sweep * t;
        return centre + r * Vec2(std::cos(a), std::sin(a));
    }
    }
    return s.start;
}

Vec2 tangentAt(const Segment& s, double t) {
    const double u = 1 - t;
    switch (s.kind) {
    case SegmentKind::Line:
        return s.end - s.start;
    case SegmentKind::Quadratic:
        return 2 * u * (s.control1 - s.start) + 2 * t * (s.end - s.control1);
    case SegmentKind::Cubic:
        return 3 * u * u * (s.control1 - s.start) + 6 * u * t * (s.control2 - s.control1) +
               3 * t * t * (s.end - s.control2);
    case SegmentKind::Arc: {
        Vec2 centre;
        double r, a0, sweep;
        if (!arcGeometry(s, centre, r, a0, sweep)) {
            return s.end - s.start;
        }
        const double a = a0 + sweep * t;
        return r * sweep * Vec2(-std::sin(a), std::cos(a));
    }
    }
    return s.end - s.start;
}

double arcLength(const Segment& s, double t0, double t1) {
    if (t1 < t0) {
        std::swap(t0, t1);
    }
    if (s.kind == SegmentKind::Line) {
        return (s.end - s.start).norm() * (t1 - t0);
    }
    if (s.kind == SegmentKind::Arc) {
        Vec2 centre;
        double r, a0, sweep;
        if (arcGeometry(s, centre, r, a0, sweep)) {
            return r * std::abs(sweep) * (t1 - t0);
        }
        return (s.end - s.start).norm() * (t1 - t0);
    }
    return integrate(t0, t1, 16, [&](double t) { return tangentAt(s, t).norm(); });
}

double parameterAtLength(const Segment& s, double t0, double t1, double length) {
    const double total = arcLength(s, t0, t1);
    if (total <= 0 || length <= 0) {
        return t0;
    }
    if (length >= total) {
        return t1;
    }
    // Bisection on the monotone arc length, refined by Newton steps.
    double lo = std::min(t0, t1), hi = std::max(t0, t1);
    const bool forward = t1 >= t0;
    auto lengthTo = [&](double t) { return arcLength(s, t0, t); };
    double t = t0 + (t1 - t0) * (length / total);
    for (int it = 0; it < 60; ++it) {
        const double f = lengthTo(t) - length;
        if (std::abs(f) < 1e-13) {
            break;
        }
        // Keep the bracket: along the walking direction, f grows.
        if ((f > 0) == forward) {
            hi = t;
        } else {
            lo = t;
        }
        const double speed = tangentAt(s, t).norm();
        double next = speed > 0 ? t - (forward ? f : -f) / speed : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) {
            next = 0.5 * (lo + hi);
        }
        t = next;
    }
    return t;
}

double loopArea(const Loop& loop) {
    double area = 0;
    for (const Segment& s : loop) {
        if (s.kind == SegmentKind::Line) {
            area += 0.5 * (s.start.x() * s.end.y() - s.end.x() * s.start.y());
            continue;
        }
        area += integrate(0.0, 1.0, 16, [&](double t) {
            const Vec2 p = pointAt(s, t), d = tangentAt(s, t);
            return 0.5 * (p.x() * d.y() - p.y() * d.x());
        });
    }
    return area;
}

double chordDeviation(const Segment& s, double t0, double t1) {
    if (s.kind == SegmentKind::Line) {
        return 0;
    }
    const Vec2 a = pointAt(s, t0), b = pointAt(s, t1);
    const Vec2 ab = b - a;
    const double len = ab.norm();
    double worst = 0;
    for (int k = 1; k <= 9; ++k) {
        const Vec2 p = pointAt(s, t0 + (t1 - t0) * k / 10.0);
        const double d =
            len > 0 ? std::abs(ab.x() * (p - a).y() - ab.y() * (p - a).x()) / len : (p - a).norm();
        worst = std::max(worst, d);
    }
    return worst;
}

std::vector<double> equalLengthParameters(const Segment& s, double t0, double t1, int n) {
    std::vector<double> ts(static_cast<std::size_t>(n) + 1);
    const double total = arcLength(s, t0, t1);
    ts.front() = t0;
    ts.back() = t1;
    for (int i = 1; i < n; ++i) {
        ts[static_cast<std::size_t>(i)] = parameterAtLength(s, t0, t1, total * i / n);
    }
    return ts;
}

bool insidePolygon(const std::vector<Vec2>& poly, const Vec2& p) {
    bool inside = false;
    for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        const Vec2& a = poly[i];
        const Vec2& b = poly[j];
        if ((a.y() > p.y()) != (b.y() > p.y()) &&
            p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
            inside = !inside;
        }
    }
    return inside;
}

} // namespace atelier::patterns
