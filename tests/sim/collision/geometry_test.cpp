#include "sim/collision/geometry.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <vector>

namespace atelier::sim {
namespace {

using Rng = std::mt19937;

double uniform(Rng& rng, double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
}

Vec3 randomVec(Rng& rng, double lo, double hi) {
    return {uniform(rng, lo, hi), uniform(rng, lo, hi), uniform(rng, lo, hi)};
}

Vec3 unitVec(Rng& rng) {
    for (;;) {
        const Vec3 v = randomVec(rng, -1, 1);
        const double n = v.norm();
        if (n > 0.1 && n <= 1) {
            return v / n;
        }
    }
}

/// Barycentric weights with each weight >= margin.
std::array<double, 3> randomBary(Rng& rng, double margin) {
    const double a = uniform(rng, 0, 1);
    const double b = uniform(rng, 0, 1);
    const double lo = std::min(a, b);
    const double hi = std::max(a, b);
    const double free = 1 - 3 * margin;
    return {margin + free * lo, margin + free * (hi - lo), margin + free * (1 - hi)};
}

Vec3 baryPoint(const std::array<double, 3>& w, const Vec3& a, const Vec3& b, const Vec3& c) {
    return w[0] * a + w[1] * b + w[2] * c;
}

double triangleArea(const Vec3& a, const Vec3& b, const Vec3& c) {
    return 0.5 * (b - a).cross(c - a).norm();
}

Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
    return (1 - t) * a + t * b;
}

void expectValidBary(const std::array<double, 3>& w) {
    for (double x : w) {
        EXPECT_TRUE(std::isfinite(x));
        EXPECT_GE(x, 0.0);
        EXPECT_LE(x, 1.0);
    }
    EXPECT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-14);
}

// =============================================================================================
// closestPointOnTriangle
// =============================================================================================

/// Smallest distance from p to points of the triangle on a barycentric grid of n subdivisions
/// (the grid includes the vertices and points along the edges).
double sampledTriangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int n) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i) {
        for (int j = 0; i + j <= n; ++j) {
            const double v = double(i) / n;
            const double w = double(j) / n;
            best = std::min(best, (p - ((1 - v - w) * a + v * b + w * c)).norm());
        }
    }
    return best;
}

void checkTrianglePoint(const TrianglePoint& r, const Vec3& p, const Vec3& a, const Vec3& b,
                        const Vec3& c) {
    expectValidBary(r.bary);
    const double size = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm(), 1e-300});
    EXPECT_LE((r.point - baryPoint(r.bary, a, b, c)).norm(), 1e-14 * size);
    EXPECT_NEAR(r.distance, (p - r.point).norm(), 1e-14 * (size + r.distance));
}

TEST(ClosestPointOnTriangle, MatchesDenseSampling) {
    Rng rng(11);
    constexpr int GRID = 100;
    for (int trial = 0; trial < 150; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const Vec3 a = randomVec(rng, -1, 1);
        const Vec3 b = randomVec(rng, -1, 1);
        const Vec3 c = randomVec(rng, -1, 1);
        // Points near the triangle, in its plane, and far away.
        Vec3 p = randomVec(rng, -1.5, 1.5);
        if (trial % 3 == 1) {
            const Vec3 n = (b - a).cross(c - a).normalized();
            p -= n.dot(p - a) * n;
        } else if (trial % 3 == 2) {
            p *= 10;
        }
        const TrianglePoint r = closestPointOnTriangle(p, a, b, c);
        checkTrianglePoint(r, p, a, b, c);
        const double sampled = sampledTriangleDistance(p, a, b, c, GRID);
        const double longest = std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()});
        // Never worse than any sample, and the samples are within one grid cell of every point.
        EXPECT_LE(r.distance, sampled + 1e-12);
        EXPECT_GE(r.distance, sampled - longest / GRID);
    }
}

TEST(ClosestPointOnTriangle, VoronoiRegions) {
    const Vec3 a(0, 0, 0);
    const Vec3 b(2, 0, 0);
    const Vec3 c(0, 2, 0);
    struct Case {
        Vec3 p;
        Vec3 expected;
        std::array<double, 3> bary;
    };
    const std::vector<Case> cases = {
        {{-1, -1, 1}, a, {1, 0, 0}},                        // vertex a
        {{3, -1, -1}, b, {0, 1, 0}},                        // vertex b
        {{-1, 3, 2}, c, {0, 0, 1}},                         // vertex c
        {{0.5, -1, 1}, {0.5, 0, 0}, {0.75, 0.25, 0}},       // edge ab
        {{-1, 1.5, 0}, {0, 1.5, 0}, {0.25, 0, 0.75}},       // edge ca
        {{2, 2, 3}, {1, 1, 0}, {0, 0.5, 0.5}},              // edge bc
        {{0.5, 0.5, -4}, {0.5, 0.5, 0}, {0.5, 0.25, 0.25}}, // face
        {{0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, 0.25, 0.25}},  // on the face
    };
    for (const Case& k : cases) {
        const TrianglePoint r = closestPointOnTriangle(k.p, a, b, c);
        checkTrianglePoint(r, k.p, a, b, c);
        EXPECT_LE((r.point - k.expected).norm(), 1e-14);
        EXPECT_NEAR(r.distance, (k.p - k.expected).norm(), 1e-14);
        for (std::size_t i = 0; i < 3; ++i) {
            EXPECT_NEAR(r.bary[i], k.bary[i], 1e-14);
        }
    }
}

TEST(ClosestPointOnTriangle, DegenerateTrianglesUseTheirEdges) {
    const Vec3 p(0.3, 1.0, 0.5);
    // Collinear vertices (c between a and b): the segment from (0,0,0) to (1,0,0).
    {
        const TrianglePoint r =
            closestPointOnTriangle(p, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0));
        checkTrianglePoint(r, p, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 0, 0));
        EXPECT_LE((r.point - Vec3(0.3, 0, 0)).norm(), 1e-15);
        EXPECT_NEAR(r.distance, std::sqrt(1.25), 1e-15);
    }
    // Repeated vertex.
    {
        const Vec3 a(1, 1, 1);
        const TrianglePoint r = closestPointOnTriangle(p, a, a, Vec3(2, 1, 1));
        checkTrianglePoint(r, p, a, a, Vec3(2, 1, 1));
        EXPECT_LE((r.point - a).norm(), 1e-15);
    }
    // All three vertices equal.
    {
        const Vec3 a(-1, 2, 0);
        const TrianglePoint r = closestPointOnTriangle(p, a, a, a);
        checkTrianglePoint(r, p, a, a, a);
        EXPECT_EQ(r.point, a);
        EXPECT_NEAR(r.distance, (p - a).norm(), 1e-15);
    }
    // Needle triangles (tiny but nonzero area) against dense sampling.
    Rng rng(5);
    for (int trial = 0; trial < 100; ++trial) {
        const Vec3 a = randomVec(rng, -1, 1);
        const Vec3 b = randomVec(rng, -1, 1);
        const Vec3 c = lerp(a, b, uniform(rng, -0.5, 1.5)) +
                       std::pow(10.0, -uniform(rng, 2, 15)) * randomVec(rng, -1, 1);
        const Vec3 q = randomVec(rng, -1.5, 1.5);
        const TrianglePoint r = closestPointOnTriangle(q, a, b, c);
        checkTrianglePoint(r, q, a, b, c);
        EXPECT_LE(r.distance, sampledTriangleDistance(q, a, b, c, 60) + 1e-12);
    }
}

// =============================================================================================
// closestPointsOfSegments
// =============================================================================================

/// Distance from p to segment q0q1 by projection (clamped).
double pointSegmentDistance(const Vec3& p, const Vec3& q0, const Vec3& q1) {
    const Vec3 d = q1 - q0;
    const double len2 = d.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - q0).dot(d) / len2, 0.0, 1.0) : 0.0;
    return (p - lerp(q0, q1, t)).norm();
}

/// Smallest distance from n + 1 evenly spaced points of p0p1 to segment q0q1.
double sampledSegmentDistance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1,
                              int n) {
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= n; ++i) {
        best = std::min(best, pointSegmentDistance(lerp(p0, p1, double(i) / n), q0, q1));
    }
    return best;
}

void checkSegmentPoints(const SegmentPoints& r, const Vec3& p0, const Vec3& p1, const Vec3& q0,
                        const Vec3& q1) {
    EXPECT_TRUE(std::isfinite(r.s) && std::isfinite(r.t) && std::isfinite(r.distance));
    EXPECT_GE(r.s, 0.0);
    EXPECT_LE(r.s, 1.0);
    EXPECT_GE(r.t, 0.0);
    EXPECT_LE(r.t, 1.0);
    const double size = std::max({(p1 - p0).norm(), (q1 - q0).norm(), 1.0});
    EXPECT_LE((r.onP - lerp(p0, p1, r.s)).norm(), 1e-14 * size);
    EXPECT_LE((r.onQ - lerp(q0, q1, r.t)).norm(), 1e-14 * size);
    EXPECT_NEAR(r.distance, (r.onP - r.onQ).norm(), 1e-14 * size);
}

TEST(ClosestPointsOfSegments, MatchesDenseSampling) {
    Rng rng(12);
    constexpr int GRID = 1000;
    for (int trial = 0; trial < 200; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const Vec3 p0 = randomVec(rng, -1, 1);
        const Vec3 p1 = randomVec(rng, -1, 1);
        Vec3 q0 = randomVec(rng, -1, 1);
        Vec3 q1 = randomVec(rng, -1, 1);
        switch (trial % 5) {
        case 1: // parallel
            q1 = q0 + uniform(rng, -2, 2) * (p1 - p0);
            break;
        case 2: // nearly parallel
            q1 = q0 + uniform(rng, -2, 2) * (p1 - p0) +
                 std::pow(10.0, -uniform(rng, 3, 14)) * randomVec(rng, -1, 1);
            break;
        case 3: // zero-length second segment
            q1 = q0;
            break;
        case 4: // collinear
            q0 = lerp(p0, p1, uniform(rng, -1, 2));
            q1 = lerp(p0, p1, uniform(rng, -1, 2));
            break;
        default:
            break;
        }
        const SegmentPoints r = closestPointsOfSegments(p0, p1, q0, q1);
        checkSegmentPoints(r, p0, p1, q0, q1);
        const double sampled = sampledSegmentDistance(p0, p1, q0, q1, GRID);
        EXPECT_LE(r.distance, sampled + 1e-12);
        EXPECT_GE(r.distance, sampled - (p1 - p0).norm() / GRID);
    }
}

TEST(ClosestPointsOfSegments, KnownConfigurations) {
    // Crossing at right angles, 0.5 apart.
    {
        const SegmentPoints r = closestPointsOfSegments(Vec3(-1, 0, 0), Vec3(1, 0, 0),
                                                        Vec3(0, -1, 0.5), Vec3(0, 1, 0.5));
        EXPECT_NEAR(r.s, 0.5, 1e-15);
        EXPECT_NEAR(r.t, 0.5, 1e-15);
        EXPECT_NEAR(r.distance, 0.5, 1e-15);
    }
    // Intersecting.
    {
        const SegmentPoints r =
            closestPointsOfSegments(Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(1, -1, 0), Vec3(1, 3, 0));
        EXPECT_NEAR(r.s, 0.25, 1e-15);
        EXPECT_NEAR(r.t, 0.25, 1e-15);
        EXPECT_NEAR(r.distance, 0.0, 1e-15);
    }
    // Parallel and overlapping: any pair on the overlap, at the offset.
    {
        const Vec3 p0(0, 0, 0), p1(2, 0, 0), q0(1, 0.3, 0), q1(3, 0.3, 0);
        const SegmentPoints r = closestPointsOfSegments(p0, p1, q0, q1);
        checkSegmentPoints(r, p0, p1, q0, q1);
        EXPECT_NEAR(r.distance, 0.3, 1e-15);
        EXPECT_GE(r.onP.x(), 1.0 - 1e-15);
        EXPECT_NEAR(r.onP.x(), r.onQ.x(), 1e-15);
    }
    // Collinear and disjoint: the facing endpoints.
    {
        const SegmentPoints r =
            closestPointsOfSegments(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(3, 3, 3), Vec3(2, 2, 2));
        EXPECT_NEAR(r.s, 1.0, 1e-15);
        EXPECT_NEAR(r.t, 1.0, 1e-15);
        EXPECT_NEAR(r.distance, std::sqrt(3.0), 1e-15);
    }
    // Endpoint against interior (T shape).
    {
        const SegmentPoints r =
            closestPointsOfSegments(Vec3(0, 1, 0), Vec3(0, 5, 0), Vec3(-1, 0, 0), Vec3(1, 0, 0));
        EXPECT_NEAR(r.s, 0.0, 1e-15);
        EXPECT_NEAR(r.t, 0.5, 1e-15);
        EXPECT_NEAR(r.distance, 1.0, 1e-15);
    }
    // Zero-length segments.
    {
        const Vec3 a(1, 2, 3);
        const SegmentPoints r = closestPointsOfSegments(a, a, Vec3(0, 0, 0), Vec3(2, 0, 0));
        checkSegmentPoints(r, a, a, Vec3(0, 0, 0), Vec3(2, 0, 0));
        EXPECT_NEAR(r.t, 0.5, 1e-15);
        EXPECT_NEAR(r.distance, std::sqrt(13.0), 1e-14);
        const SegmentPoints rr = closestPointsOfSegments(a, a, Vec3(0, 0, 0), Vec3(0, 0, 0));
        EXPECT_NEAR(rr.distance, a.norm(), 1e-14);
        const SegmentPoints same = closestPointsOfSegments(a, a, a, a);
        EXPECT_EQ(same.distance, 0.0);
    }
}

// =============================================================================================
// sweptVertexTriangle
// =============================================================================================

/// A vertex and a triangle, each vertex moving linearly from x0 to x1 over the step.
struct VertexTriangleMotion {
    Vec3 p0, p1, a0, a1, b0, b1, c0, c1;

    std::optional<SweptHit> sweep(double distance) const {
        return sweptVertexTriangle(p0, p1, a0, a1, b0, b1, c0, c1, distance);
    }
    TrianglePoint closestAt(double t) const {
        return closestPointOnTriangle(lerp(p0, p1, t), lerp(a0, a1, t), lerp(b0, b1, t),
                                      lerp(c0, c1, t));
    }
    /// Signed volume x·(e₁×e₂) at t, computed directly.
    double volumeAt(double t) const {
        const Vec3 a = lerp(a0, a1, t);
        return (lerp(p0, p1, t) - a).dot((lerp(b0, b1, t) - a).cross(lerp(c0, c1, t) - a));
    }
    /// Scale of the tolerances of sweptVertexTriangle: the largest offset from a or its motion.
    double scale() const {
        const Vec3 x0 = p0 - a0, x1 = p1 - a1, e10 = b0 - a0, e11 = b1 - a1, e20 = c0 - a0,
                   e21 = c1 - a1;
        double s = 0;
        for (const Vec3& v :
             std::array<Vec3, 9>{x0, x1, e10, e11, e20, e21, x1 - x0, e11 - e10, e21 - e20}) {
            s = std::max(s, v.norm());
        }
        return s;
    }
};

/// Given two positions at time tau and a velocity (per step), the start and end positions.
void placeMotion(const Vec3& atTau, const Vec3& velocity, double tau, Vec3& start, Vec3& end) {
    start = atTau - tau * velocity;
    end = atTau + (1 - tau) * velocity;
}

/// A vertex crossing the interior of a slowly moving random triangle at time tau, at the
/// triangle point with weights `bary`, coming from the side the normal points to.
VertexTriangleMotion vertexThroughTriangle(Rng& rng, double tau, std::array<double, 3>& bary) {
    Vec3 a, b, c;
    do {
        a = randomVec(rng, -1, 1);
        b = randomVec(rng, -1, 1);
        c = randomVec(rng, -1, 1);
    } while (triangleArea(a, b, c) < 0.2);
    bary = randomBary(rng, 0.02);
    const Vec3 x = baryPoint(bary, a, b, c);
    const Vec3 n = (b - a).cross(c - a).normalized();
    VertexTriangleMotion m;
    placeMotion(a, randomVec(rng, -0.05, 0.05), tau, m.a0, m.a1);
    placeMotion(b, randomVec(rng, -0.05, 0.05), tau, m.b0, m.b1);
    placeMotion(c, randomVec(rng, -0.05, 0.05), tau, m.c0, m.c1);
    const Vec3 vp = -uniform(rng, 0.5, 2.0) * n + randomVec(rng, -0.2, 0.2);
    placeMotion(x, vp, tau, m.p0, m.p1);
    return m;
}

TEST(SweptVertexTriangle, FindsTheCrossingTime) {
    Rng rng(21);
    int checked = 0;
    for (int trial = 0; trial < 500; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const double tau = trial < 10 ? (trial < 5 ? 0.0 : 1.0) : uniform(rng, 0, 1);
        std::array<double, 3> bary{};
        const VertexTriangleMotion m = vertexThroughTriangle(rng, tau, bary);
        // The construction makes the vertex stay on the positive side before tau.
        bool clean = true;
        for (int k = 0; k < 200 && clean; ++k) {
            const double t = tau * k / 200.0;
            clean = t >= tau - 1e-3 || m.volumeAt(t) > 0;
        }
        if (!clean) {
            continue;
        }
        ++checked;
        const auto hit = m.sweep(0.0);
        ASSERT_TRUE(hit.has_value());
        EXPECT_NEAR(hit->time, tau, 1e-6);
        EXPECT_LE(hit->time, tau + 1e-12);
        expectValidBary(hit->coords);
        for (std::size_t i = 0; i < 3; ++i) {
            EXPECT_NEAR(hit->coords[i], bary[i], 1e-6);
        }
        EXPECT_LE(m.closestAt(hit->time).distance, 1e-8 * m.scale());
    }
    EXPECT_GT(checked, 450);
}

TEST(SweptVertexTriangle, WithDistanceHitsNoLaterThanTheCrossing) {
    Rng rng(22);
    for (int trial = 0; trial < 300; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const double tau = uniform(rng, 0, 1);
        std::array<double, 3> bary{};
        const VertexTriangleMotion m = vertexThroughTriangle(rng, tau, bary);
        const double d = std::pow(10.0, -uniform(rng, 1, 4));
        const auto hit = m.sweep(d);
        ASSERT_TRUE(hit.has_value());
        EXPECT_LE(hit->time, tau + 1e-12);
        EXPECT_GE(hit->time, 0.0);
        expectValidBary(hit->coords);
        // Within the distance up to the search resolution (1e-6 of the scale), and the first
        // such time: farther than the distance before.
        EXPECT_LE(m.closestAt(hit->time).distance, d + 1.01e-6 * m.scale());
        for (int k = 0; k < 100 && hit->time > 0; ++k) {
            EXPECT_GT(m.closestAt(hit->time * k / 100.0).distance, d);
        }
    }
}

TEST(SweptVertexTriangle, StartingOrEndingWithinTheDistance) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    // Starts 0.005 above the face, moves away: hit at 0 with d = 0.01, none with d = 0.001.
    const VertexTriangleMotion away{{0.2, 0.2, 0.005}, {0.2, 0.2, 1}, a, a, b, b, c, c};
    const auto h0 = away.sweep(0.01);
    ASSERT_TRUE(h0.has_value());
    EXPECT_EQ(h0->time, 0.0);
    EXPECT_NEAR(h0->coords[1], 0.2, 1e-12);
    EXPECT_FALSE(away.sweep(0.001).has_value());
    // Approaches and stops 0.005 above the face without crossing: hit at the end (or before).
    const VertexTriangleMotion toward{{0.2, 0.2, 1}, {0.2, 0.2, 0.005}, a, a, b, b, c, c};
    const auto h1 = toward.sweep(0.01);
    ASSERT_TRUE(h1.has_value());
    EXPECT_LE(toward.closestAt(h1->time).distance, 0.01 + 1e-8);
    EXPECT_FALSE(toward.sweep(0.0).has_value());
    // Touching at the start with distance 0.
    const VertexTriangleMotion touching{{0.2, 0.2, 0}, {0.2, 0.2, 1}, a, a, b, b, c, c};
    const auto h2 = touching.sweep(0.0);
    ASSERT_TRUE(h2.has_value());
    EXPECT_EQ(h2->time, 0.0);
}

TEST(SweptVertexTriangle, DistantMotionsReportNothing) {
    Rng rng(23);
    for (int trial = 0; trial < 500; ++trial) {
        // Triangle and its motion inside the unit ball; the vertex stays beyond x = 3.
        VertexTriangleMotion m;
        m.a0 = randomVec(rng, -0.5, 0.5);
        m.a1 = randomVec(rng, -0.5, 0.5);
        m.b0 = randomVec(rng, -0.5, 0.5);
        m.b1 = randomVec(rng, -0.5, 0.5);
        m.c0 = randomVec(rng, -0.5, 0.5);
        m.c1 = randomVec(rng, -0.5, 0.5);
        m.p0 = randomVec(rng, -3, 3) + Vec3(6, 0, 0);
        m.p1 = randomVec(rng, -3, 3) + Vec3(6, 0, 0);
        EXPECT_FALSE(m.sweep(0.0).has_value());
        EXPECT_FALSE(m.sweep(0.5).has_value());
    }
}

TEST(SweptVertexTriangle, CrossingThePlaneOutsideTheTriangleIsNoHit) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    const VertexTriangleMotion m{{0.8, 0.8, 1}, {0.8, 0.8, -1}, a, a, b, b, c, c};
    EXPECT_FALSE(m.sweep(0.0).has_value());
    EXPECT_FALSE(m.sweep(0.1).has_value()); // 0.6 / √2 ≈ 0.42 from the edge
    EXPECT_TRUE(m.sweep(0.5).has_value());
}

/// First time at which the vertex is inside the triangle, found by sampling the signed volume
/// for sign changes and bisecting them; only crossings clearly inside the triangle (weights
/// >= 1e-6) count.
std::optional<double> bruteForceCrossing(const VertexTriangleMotion& m) {
    constexpr int SAMPLES = 500;
    double fPrev = m.volumeAt(0);
    for (int k = 1; k <= SAMPLES; ++k) {
        double lo = double(k - 1) / SAMPLES;
        double hi = double(k) / SAMPLES;
        const double fHi = m.volumeAt(hi);
        if ((fPrev < 0) != (fHi < 0)) {
            const bool loNegative = fPrev < 0;
            for (int i = 0; i < 60; ++i) {
                const double mid = 0.5 * (lo + hi);
                ((m.volumeAt(mid) < 0) == loNegative ? lo : hi) = mid;
            }
            const TrianglePoint cp = m.closestAt(hi);
            const double minWeight = std::min({cp.bary[0], cp.bary[1], cp.bary[2]});
            if (cp.distance <= 1e-10 * m.scale() && minWeight >= 1e-6) {
                return hi;
            }
        }
        fPrev = fHi;
    }
    return std::nullopt;
}

TEST(SweptVertexTriangle, NeverMissesABruteForceCrossing) {
    Rng rng(24);
    int crossings = 0;
    for (int trial = 0; trial < 700; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        VertexTriangleMotion m;
        m.a0 = randomVec(rng, -1, 1);
        m.b0 = randomVec(rng, -1, 1);
        m.c0 = randomVec(rng, -1, 1);
        m.a1 = m.a0 + randomVec(rng, -1, 1);
        m.b1 = m.b0 + randomVec(rng, -1, 1);
        m.c1 = m.c0 + randomVec(rng, -1, 1);
        // The vertex moves between points near the triangle's centroid at both ends: it
        // crosses the moving triangle often.
        m.p0 = (m.a0 + m.b0 + m.c0) / 3 + randomVec(rng, -0.7, 0.7);
        m.p1 = (m.a1 + m.b1 + m.c1) / 3 + randomVec(rng, -0.7, 0.7);
        const auto hit = m.sweep(0.0);
        if (hit) {
            EXPECT_GE(hit->time, 0.0);
            EXPECT_LE(hit->time, 1.0);
            expectValidBary(hit->coords);
            // A hit is a real contact (up to the tolerances).
            EXPECT_LE(m.closestAt(hit->time).distance, 1.01e-6 * m.scale());
        }
        if (const auto crossing = bruteForceCrossing(m)) {
            ++crossings;
            ASSERT_TRUE(hit.has_value()) << "missed a crossing at t = " << *crossing;
            EXPECT_LE(hit->time, *crossing + 1e-9);
        }
    }
    EXPECT_GT(crossings, 150);
}

/// Checks a continuous test with a distance against dense sampling of the distance: a time
/// sampled within the distance is never before the hit, the hit is within the distance up to
/// the resolution, and nothing before the hit is within the distance.
template <class Motion> void checkFirstProximity(const Motion& m, double d, int& episodes) {
    constexpr int SAMPLES = 200;
    const auto hit = m.sweep(d);
    std::optional<double> firstSample;
    for (int k = 0; k <= SAMPLES && !firstSample; ++k) {
        if (m.closestAt(double(k) / SAMPLES).distance <= d) {
            firstSample = double(k) / SAMPLES;
        }
    }
    if (firstSample) {
        ++episodes;
        ASSERT_TRUE(hit.has_value());
        EXPECT_LE(hit->time, *firstSample);
    }
    if (hit) {
        EXPECT_LE(m.closestAt(hit->time).distance, d + 1.01e-6 * m.scale());
        for (int k = 0; k < SAMPLES && double(k) / SAMPLES < hit->time; ++k) {
            EXPECT_GT(m.closestAt(double(k) / SAMPLES).distance, d);
        }
    }
}

TEST(SweptVertexTriangle, WithDistanceFindsTheFirstProximity) {
    Rng rng(26);
    int episodes = 0;
    for (int trial = 0; trial < 400; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        VertexTriangleMotion m{randomVec(rng, -1, 1), randomVec(rng, -1, 1), randomVec(rng, -1, 1),
                               randomVec(rng, -1, 1), randomVec(rng, -1, 1), randomVec(rng, -1, 1),
                               randomVec(rng, -1, 1), randomVec(rng, -1, 1)};
        if (trial % 3 == 0) { // everything in one plane: a flat sheet
            for (Vec3* v : {&m.p0, &m.p1, &m.a0, &m.a1, &m.b0, &m.b1, &m.c0, &m.c1}) {
                v->z() = 0;
            }
        }
        checkFirstProximity(m, std::pow(10.0, -uniform(rng, 0.5, 3)), episodes);
    }
    EXPECT_GT(episodes, 100);
}

TEST(SweptVertexTriangle, MotionInThePlane) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    // Sliding in the plane into the triangle through edge ca at t = 0.5.
    const VertexTriangleMotion into{{-1, 0.25, 0}, {1, 0.25, 0}, a, a, b, b, c, c};
    const auto hit = into.sweep(0.0);
    ASSERT_TRUE(hit.has_value());
    EXPECT_LE(hit->time, 0.5 + 1e-12);
    EXPECT_GE(hit->time, 0.5 - 1e-5);
    expectValidBary(hit->coords);
    EXPECT_LE(into.closestAt(hit->time).distance, 1e-5);
    // With a distance: reached when 0.1 from the edge, at t = 0.45.
    const auto near = into.sweep(0.1);
    ASSERT_TRUE(near.has_value());
    EXPECT_NEAR(near->time, 0.45, 1e-5);
    // Sliding in the plane alongside edge ab, 0.01 outside it: no contact, proximity 0.01.
    const VertexTriangleMotion along{{-1, -0.01, 0}, {2, -0.01, 0}, a, a, b, b, c, c};
    EXPECT_FALSE(along.sweep(0.0).has_value());
    EXPECT_FALSE(along.sweep(0.005).has_value());
    const auto alongHit = along.sweep(0.02);
    ASSERT_TRUE(alongHit.has_value());
    EXPECT_LE(along.closestAt(alongHit->time).distance, 0.02 + 1e-6);
    // A flat sheet: a coplanar vertex moving far from the triangle.
    const VertexTriangleMotion far{{3, 3, 0}, {3.5, 3.2, 0}, a, a, b, b, c, c};
    EXPECT_FALSE(far.sweep(0.0).has_value());
    EXPECT_FALSE(far.sweep(0.1).has_value());
    // The whole configuration moving in a tilted plane.
    const Vec3 u = Vec3(1, 2, 3).normalized();
    const Vec3 v = u.cross(Vec3(0, 0, 1)).normalized();
    const auto inPlane = [&](double x, double y) { return Vec3(x * u + y * v + Vec3(5, -2, 1)); };
    const VertexTriangleMotion tilted{inPlane(-1, 0.25), inPlane(1, 0.25), inPlane(0, 0),
                                      inPlane(0.1, 0),   inPlane(1, 0),    inPlane(1.1, 0),
                                      inPlane(0, 1),     inPlane(0.1, 1)};
    const auto tiltedHit = tilted.sweep(0.0);
    ASSERT_TRUE(tiltedHit.has_value()); // enters at x = 0.1 t, i.e. t = 1/1.9
    EXPECT_LE(tiltedHit->time, 1 / 1.9 + 1e-9);
    EXPECT_GE(tiltedHit->time, 1 / 1.9 - 1e-5);
}

TEST(SweptVertexTriangle, GrazingMotion) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    for (double slope : {1e-3, 1e-7, 1e-10, 1e-13, 1e-16}) {
        SCOPED_TRACE(::testing::Message() << "slope " << slope);
        // Crosses z = 0 at t = 0.5 at (0.5, 0.3): inside.
        const VertexTriangleMotion inside{{-1, 0.3, slope}, {2, 0.3, -slope}, a, a, b, b, c, c};
        const auto hit = inside.sweep(0.0);
        ASSERT_TRUE(hit.has_value());
        EXPECT_LE(hit->time, 0.5 + 1e-9);
        EXPECT_LE(inside.closestAt(hit->time).distance, 1e-5);
        // Crosses z = 0 at t = 0.5 near the hypotenuse, just inside (x + y = 1 − 1e-7).
        const VertexTriangleMotion edge{
            {-1, 0.5 - 1e-7, slope}, {2, 0.5 - 1e-7, -slope}, a, a, b, b, c, c};
        const auto edgeHit = edge.sweep(0.0);
        ASSERT_TRUE(edgeHit.has_value());
        EXPECT_LE(edgeHit->time, 0.5 + 1e-9);
        // Crosses z = 0 at (0.5, 1.2), outside, and never passes over the triangle (its
        // closest approach is 0.2 from vertex c): no contact. (A path over the triangle at a
        // height below the tolerance, 1e-9 of the size, would count as a contact.)
        const VertexTriangleMotion outside{{-1, 1.2, slope}, {2, 1.2, -slope}, a, a, b, b, c, c};
        EXPECT_FALSE(outside.sweep(0.0).has_value());
    }
}

TEST(SweptVertexTriangle, DegenerateInputsStayFinite) {
    const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    // No motion at all, vertex above the face: nothing; with a large distance: at once.
    const VertexTriangleMotion still{{0.2, 0.2, 0.5}, {0.2, 0.2, 0.5}, a, a, b, b, c, c};
    EXPECT_FALSE(still.sweep(0.0).has_value());
    const auto stillHit = still.sweep(1.0);
    ASSERT_TRUE(stillHit.has_value());
    EXPECT_EQ(stillHit->time, 0.0);
    // No motion, vertex on the face.
    const VertexTriangleMotion on{{0.2, 0.2, 0}, {0.2, 0.2, 0}, a, a, b, b, c, c};
    const auto onHit = on.sweep(0.0);
    ASSERT_TRUE(onHit.has_value());
    EXPECT_EQ(onHit->time, 0.0);
    // Everything at one point.
    const Vec3 o(1, 2, 3);
    const VertexTriangleMotion point{o, o, o, o, o, o, o, o};
    const auto pointHit = point.sweep(0.0);
    ASSERT_TRUE(pointHit.has_value());
    EXPECT_EQ(pointHit->time, 0.0);
    expectValidBary(pointHit->coords);
    // A triangle collapsed to a segment (collinear vertices), the vertex passing through its
    // middle at t = 0.25, and beside it.
    const Vec3 m(0.5, 0, 0);
    const VertexTriangleMotion segment{{0.5, 0, 0.25}, {0.5, 0, -0.75}, a, a, b, b, m, m};
    const auto segmentHit = segment.sweep(0.0);
    ASSERT_TRUE(segmentHit.has_value());
    EXPECT_LE(segmentHit->time, 0.25 + 1e-9);
    EXPECT_GE(segmentHit->time, 0.25 - 1e-5);
    expectValidBary(segmentHit->coords);
    const VertexTriangleMotion beside{{0.5, 0.1, 0.25}, {0.5, 0.1, -0.75}, a, a, b, b, m, m};
    EXPECT_FALSE(beside.sweep(0.0).has_value());
    // A triangle that collapses during the step.
    const VertexTriangleMotion collapsing{{0.2, 0.2, 0.1}, {0.2, 0.2, 0.1}, a, a, b, b,
                                          {0, 1, 1},       {1, 0, -1}};
    const auto collapsingHit = collapsing.sweep(0.0);
    if (collapsingHit) {
        EXPECT_TRUE(std::isfinite(collapsingHit->time));
        expectValidBary(collapsingHit->coords);
    }
    // Non-finite input: no hit rather than NaN.
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const VertexTriangleMotion broken{{nan, 0, 0}, {0, 0, 0}, a, a, b, b, c, c};
    EXPECT_FALSE(broken.sweep(0.0).has_value());
}

TEST(SweptVertexTriangle, RandomInputsNeverGiveNaN) {
    Rng rng(25);
    for (int trial = 0; trial < 2000; ++trial) {
        const double size = std::pow(10.0, uniform(rng, -6, 3));
        const auto pick = [&]() {
            // Reuse coordinates to produce coincident and collinear points often.
            const int kind = std::uniform_int_distribution<int>(0, 3)(rng);
            return kind == 0 ? Vec3::Zero().eval()
                             : Vec3(size * randomVec(rng, -1, 1) * (kind == 1 ? 1e-9 : 1.0));
        };
        VertexTriangleMotion m{pick(), pick(), pick(), pick(), pick(), pick(), pick(), pick()};
        if (trial % 4 == 0) {
            m.c0 = lerp(m.a0, m.b0, 0.5);
            m.c1 = lerp(m.a1, m.b1, 0.5);
        }
        for (double d : {0.0, 0.1 * size}) {
            const auto hit = m.sweep(d);
            if (hit) {
                EXPECT_TRUE(std::isfinite(hit->time));
                EXPECT_GE(hit->time, 0.0);
                EXPECT_LE(hit->time, 1.0);
                expectValidBary(hit->coords);
            }
        }
    }
}

// =============================================================================================
// sweptEdgeEdge
// =============================================================================================

struct EdgeEdgeMotion {
    Vec3 pa0, pa1, pb0, pb1, qa0, qa1, qb0, qb1;

    std::optional<SweptHit> sweep(double distance) const {
        return sweptEdgeEdge(pa0, pa1, pb0, pb1, qa0, qa1, qb0, qb1, distance);
    }
    SegmentPoints closestAt(double t) const {
        return closestPointsOfSegments(lerp(pa0, pa1, t), lerp(pb0, pb1, t), lerp(qa0, qa1, t),
                                       lerp(qb0, qb1, t));
    }
    double volumeAt(double t) const {
        const Vec3 pa = lerp(pa0, pa1, t);
        const Vec3 qa = lerp(qa0, qa1, t);
        return (qa - pa).dot((lerp(pb0, pb1, t) - pa).cross(lerp(qb0, qb1, t) - qa));
    }
    /// Scale of the tolerances of sweptEdgeEdge: the largest offset from pa or its motion.
    double scale() const {
        const Vec3 x0 = qa0 - pa0, x1 = qa1 - pa1, e10 = pb0 - pa0, e11 = pb1 - pa1,
                   e20 = qb0 - qa0, e21 = qb1 - qa1;
        double s = 0;
        for (const Vec3& v :
             std::array<Vec3, 9>{x0, x1, e10, e11, e20, e21, x1 - x0, e11 - e10, e21 - e20}) {
            s = std::max(s, v.norm());
        }
        return s;
    }
};

/// Edge p slowly moving, edge q passing through it at time tau (the points at s on p and u on q
/// meet), coming from the side of the normal p × q.
EdgeEdgeMotion edgeThroughEdge(Rng& rng, double tau, double& s, double& u) {
    Vec3 pa, pb, dirQ;
    do {
        pa = randomVec(rng, -1, 1);
        pb = randomVec(rng, -1, 1);
        dirQ = unitVec(rng);
    } while ((pb - pa).norm() < 0.5 || (pb - pa).normalized().cross(dirQ).norm() < 0.3);
    s = uniform(rng, 0.02, 0.98);
    u = uniform(rng, 0.02, 0.98);
    const double lengthQ = uniform(rng, 0.5, 2);
    const Vec3 x = lerp(pa, pb, s);
    const Vec3 qa = x - u * lengthQ * dirQ;
    const Vec3 qb = x + (1 - u) * lengthQ * dirQ;
    const Vec3 n = (pb - pa).cross(qb - qa).normalized();
    EdgeEdgeMotion m;
    placeMotion(pa, randomVec(rng, -0.05, 0.05), tau, m.pa0, m.pa1);
    placeMotion(pb, randomVec(rng, -0.05, 0.05), tau, m.pb0, m.pb1);
    const Vec3 vq = -uniform(rng, 0.5, 2.0) * n;
    placeMotion(qa, vq + randomVec(rng, -0.05, 0.05), tau, m.qa0, m.qa1);
    placeMotion(qb, vq + randomVec(rng, -0.05, 0.05), tau, m.qb0, m.qb1);
    return m;
}

TEST(SweptEdgeEdge, FindsTheCrossingTime) {
    Rng rng(31);
    int checked = 0;
    for (int trial = 0; trial < 500; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const double tau = trial < 10 ? (trial < 5 ? 0.0 : 1.0) : uniform(rng, 0, 1);
        double s = 0, u = 0;
        const EdgeEdgeMotion m = edgeThroughEdge(rng, tau, s, u);
        bool clean = true;
        for (int k = 0; k < 200 && clean; ++k) {
            const double t = tau * k / 200.0;
            clean = t >= tau - 1e-3 || m.volumeAt(t) > 0;
        }
        if (!clean) {
            continue;
        }
        ++checked;
        const auto hit = m.sweep(0.0);
        ASSERT_TRUE(hit.has_value());
        EXPECT_NEAR(hit->time, tau, 1e-6);
        EXPECT_LE(hit->time, tau + 1e-12);
        EXPECT_NEAR(hit->coords[0], s, 1e-6);
        EXPECT_NEAR(hit->coords[1], u, 1e-6);
        EXPECT_EQ(hit->coords[2], 0.0);
        EXPECT_LE(m.closestAt(hit->time).distance, 1e-8 * m.scale());
    }
    EXPECT_GT(checked, 450);
}

TEST(SweptEdgeEdge, WithDistanceHitsNoLaterThanTheCrossing) {
    Rng rng(32);
    for (int trial = 0; trial < 300; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const double tau = uniform(rng, 0, 1);
        double s = 0, u = 0;
        const EdgeEdgeMotion m = edgeThroughEdge(rng, tau, s, u);
        const double d = std::pow(10.0, -uniform(rng, 1, 4));
        const auto hit = m.sweep(d);
        ASSERT_TRUE(hit.has_value());
        EXPECT_LE(hit->time, tau + 1e-12);
        EXPECT_GE(hit->coords[0], 0.0);
        EXPECT_LE(hit->coords[0], 1.0);
        EXPECT_GE(hit->coords[1], 0.0);
        EXPECT_LE(hit->coords[1], 1.0);
        EXPECT_LE(m.closestAt(hit->time).distance, d + 1.01e-6 * m.scale());
        for (int k = 0; k < 100 && hit->time > 0; ++k) {
            EXPECT_GT(m.closestAt(hit->time * k / 100.0).distance, d);
        }
    }
}

TEST(SweptEdgeEdge, DistantMotionsReportNothing) {
    Rng rng(33);
    for (int trial = 0; trial < 500; ++trial) {
        EdgeEdgeMotion m;
        m.pa0 = randomVec(rng, -0.5, 0.5);
        m.pa1 = randomVec(rng, -0.5, 0.5);
        m.pb0 = randomVec(rng, -0.5, 0.5);
        m.pb1 = randomVec(rng, -0.5, 0.5);
        m.qa0 = randomVec(rng, -3, 3) + Vec3(0, 6, 0);
        m.qa1 = randomVec(rng, -3, 3) + Vec3(0, 6, 0);
        m.qb0 = randomVec(rng, -3, 3) + Vec3(0, 6, 0);
        m.qb1 = randomVec(rng, -3, 3) + Vec3(0, 6, 0);
        EXPECT_FALSE(m.sweep(0.0).has_value());
        EXPECT_FALSE(m.sweep(0.5).has_value());
    }
}

std::optional<double> bruteForceCrossing(const EdgeEdgeMotion& m) {
    constexpr int SAMPLES = 500;
    double fPrev = m.volumeAt(0);
    for (int k = 1; k <= SAMPLES; ++k) {
        double lo = double(k - 1) / SAMPLES;
        double hi = double(k) / SAMPLES;
        const double fHi = m.volumeAt(hi);
        if ((fPrev < 0) != (fHi < 0)) {
            const bool loNegative = fPrev < 0;
            for (int i = 0; i < 60; ++i) {
                const double mid = 0.5 * (lo + hi);
                ((m.volumeAt(mid) < 0) == loNegative ? lo : hi) = mid;
            }
            const SegmentPoints sp = m.closestAt(hi);
            const bool interior = std::min({sp.s, sp.t, 1 - sp.s, 1 - sp.t}) >= 1e-6;
            if (sp.distance <= 1e-10 * m.scale() && interior) {
                return hi;
            }
        }
        fPrev = fHi;
    }
    return std::nullopt;
}

TEST(SweptEdgeEdge, NeverMissesABruteForceCrossing) {
    Rng rng(34);
    int crossings = 0;
    for (int trial = 0; trial < 700; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        EdgeEdgeMotion m;
        m.pa0 = randomVec(rng, -1, 1);
        m.pb0 = randomVec(rng, -1, 1);
        m.pa1 = m.pa0 + randomVec(rng, -1, 1);
        m.pb1 = m.pb0 + randomVec(rng, -1, 1);
        // Edge q is centred near edge p's middle at both ends: the edges cross often.
        const Vec3 mid0 = lerp(m.pa0, m.pb0, 0.5) + randomVec(rng, -0.5, 0.5);
        const Vec3 mid1 = lerp(m.pa1, m.pb1, 0.5) + randomVec(rng, -0.5, 0.5);
        const Vec3 half0 = randomVec(rng, -1, 1);
        const Vec3 half1 = randomVec(rng, -1, 1);
        m.qa0 = mid0 - half0;
        m.qb0 = mid0 + half0;
        m.qa1 = mid1 - half1;
        m.qb1 = mid1 + half1;
        const auto hit = m.sweep(0.0);
        if (hit) {
            EXPECT_GE(hit->time, 0.0);
            EXPECT_LE(hit->time, 1.0);
            EXPECT_LE(m.closestAt(hit->time).distance, 1.01e-6 * m.scale());
        }
        if (const auto crossing = bruteForceCrossing(m)) {
            ++crossings;
            ASSERT_TRUE(hit.has_value()) << "missed a crossing at t = " << *crossing;
            EXPECT_LE(hit->time, *crossing + 1e-9);
        }
    }
    EXPECT_GT(crossings, 150);
}

TEST(SweptEdgeEdge, WithDistanceFindsTheFirstProximity) {
    Rng rng(36);
    int episodes = 0;
    for (int trial = 0; trial < 400; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        EdgeEdgeMotion m{randomVec(rng, -1, 1), randomVec(rng, -1, 1), randomVec(rng, -1, 1),
                         randomVec(rng, -1, 1), randomVec(rng, -1, 1), randomVec(rng, -1, 1),
                         randomVec(rng, -1, 1), randomVec(rng, -1, 1)};
        if (trial % 3 == 0) {
            for (Vec3* v : {&m.pa0, &m.pa1, &m.pb0, &m.pb1, &m.qa0, &m.qa1, &m.qb0, &m.qb1}) {
                v->z() = 0;
            }
        }
        checkFirstProximity(m, std::pow(10.0, -uniform(rng, 0.5, 3)), episodes);
    }
    EXPECT_GT(episodes, 100);
}

TEST(SweptEdgeEdge, ParallelEdges) {
    const Vec3 p0(0, 0, 0), p1(1, 0, 0);
    // Parallel, overlapping along x, passing through each other at t = 0.5 (the coplanarity
    // function vanishes identically).
    const EdgeEdgeMotion through{p0,          p0,           p1,          p1,
                                 {0.5, 0, 1}, {0.5, 0, -1}, {1.5, 0, 1}, {1.5, 0, -1}};
    const auto hit = through.sweep(0.0);
    ASSERT_TRUE(hit.has_value());
    EXPECT_LE(hit->time, 0.5 + 1e-12);
    EXPECT_GE(hit->time, 0.5 - 1e-5);
    EXPECT_LE(through.closestAt(hit->time).distance, 1e-5);
    // Same, but not overlapping along x.
    const EdgeEdgeMotion past{p0, p0, p1, p1, {2, 0, 1}, {2, 0, -1}, {3, 0, 1}, {3, 0, -1}};
    EXPECT_FALSE(past.sweep(0.0).has_value());
    // Parallel, 0.1 apart sideways at the closest.
    const EdgeEdgeMotion beside{
        p0, p0, p1, p1, {0.5, 0.1, 1}, {0.5, 0.1, -1}, {1.5, 0.1, 1}, {1.5, 0.1, -1}};
    EXPECT_FALSE(beside.sweep(0.0).has_value());
    EXPECT_FALSE(beside.sweep(0.05).has_value());
    const auto besideHit = beside.sweep(0.2);
    ASSERT_TRUE(besideHit.has_value());
    // Found by the conservative search (the coplanarity cubic vanishes identically): within
    // its resolution, 1e-6 of the scale.
    EXPECT_LE(beside.closestAt(besideHit->time).distance, 0.2 + 1e-6 * beside.scale());
}

TEST(SweptEdgeEdge, NearlyParallelCrossing) {
    // Two long edges at a tiny angle crossing each other at their middles at t = 0.5: the
    // coplanarity cubic is tiny and its root ill-conditioned.
    for (double angle : {1e-4, 1e-8, 1e-12, 1e-15}) {
        SCOPED_TRACE(::testing::Message() << "angle " << angle);
        const EdgeEdgeMotion m{{-1, 0, 0},      {-1, 0, 0},       {1, 0, 0},     {1, 0, 0},
                               {-1, -angle, 1}, {-1, -angle, -1}, {1, angle, 1}, {1, angle, -1}};
        const auto hit = m.sweep(0.0);
        ASSERT_TRUE(hit.has_value());
        EXPECT_LE(hit->time, 0.5 + 1e-9);
        EXPECT_GE(hit->time, 0.5 - 1e-4);
        EXPECT_LE(m.closestAt(hit->time).distance, 1e-5);
    }
}

TEST(SweptEdgeEdge, DegenerateInputsStayFinite) {
    // A zero-length edge (a point) passing through the other edge at t = 0.5.
    const Vec3 q(0.3, 0, 1), qEnd(0.3, 0, -1);
    const EdgeEdgeMotion pointThrough{{0, 0, 0}, {0, 0, 0}, {1, 0, 0}, {1, 0, 0}, q, qEnd, q, qEnd};
    const auto hit = pointThrough.sweep(0.0);
    ASSERT_TRUE(hit.has_value());
    EXPECT_LE(hit->time, 0.5 + 1e-12);
    EXPECT_GE(hit->time, 0.5 - 1e-5);
    EXPECT_NEAR(hit->coords[0], 0.3, 1e-5);
    // Two points meeting at t = 0.25 (o + (t − ¼) v and o + (¼ − t) v), and two points
    // passing 0.1 apart.
    const Vec3 o(1, 1, 1);
    const Vec3 v(2, -1, 0.5);
    const EdgeEdgeMotion points{o - 0.25 * v, o + 0.75 * v, o - 0.25 * v, o + 0.75 * v,
                                o + 0.25 * v, o - 0.75 * v, o + 0.25 * v, o - 0.75 * v};
    const auto pointsHit = points.sweep(0.0);
    ASSERT_TRUE(pointsHit.has_value());
    EXPECT_LE(pointsHit->time, 0.25 + 1e-12);
    EXPECT_GE(pointsHit->time, 0.25 - 1e-5);
    const Vec3 side(0, 0.1, 0);
    const EdgeEdgeMotion missing{o - 0.25 * v,        o + 0.75 * v,        o - 0.25 * v,
                                 o + 0.75 * v,        o + 0.25 * v + side, o - 0.75 * v + side,
                                 o + 0.25 * v + side, o - 0.75 * v + side};
    EXPECT_FALSE(missing.sweep(0.0).has_value());
    // No motion: crossing edges hit at once; separated ones never.
    const EdgeEdgeMotion crossing{{-1, 0, 0}, {-1, 0, 0}, {1, 0, 0}, {1, 0, 0},
                                  {0, -1, 0}, {0, -1, 0}, {0, 1, 0}, {0, 1, 0}};
    const auto crossingHit = crossing.sweep(0.0);
    ASSERT_TRUE(crossingHit.has_value());
    EXPECT_EQ(crossingHit->time, 0.0);
    EXPECT_NEAR(crossingHit->coords[0], 0.5, 1e-15);
    const EdgeEdgeMotion apart{{-1, 0, 0},   {-1, 0, 0},   {1, 0, 0},   {1, 0, 0},
                               {0, -1, 0.1}, {0, -1, 0.1}, {0, 1, 0.1}, {0, 1, 0.1}};
    EXPECT_FALSE(apart.sweep(0.0).has_value());
    EXPECT_TRUE(apart.sweep(0.1).has_value());
    // Everything at one point.
    const EdgeEdgeMotion one{o, o, o, o, o, o, o, o};
    const auto oneHit = one.sweep(0.0);
    ASSERT_TRUE(oneHit.has_value());
    EXPECT_EQ(oneHit->time, 0.0);
    EXPECT_TRUE(std::isfinite(oneHit->coords[0]) && std::isfinite(oneHit->coords[1]));
}

TEST(SweptEdgeEdge, RandomInputsNeverGiveNaN) {
    Rng rng(35);
    for (int trial = 0; trial < 2000; ++trial) {
        const double size = std::pow(10.0, uniform(rng, -6, 3));
        const auto pick = [&]() {
            const int kind = std::uniform_int_distribution<int>(0, 3)(rng);
            return kind == 0 ? Vec3::Zero().eval()
                             : Vec3(size * randomVec(rng, -1, 1) * (kind == 1 ? 1e-9 : 1.0));
        };
        EdgeEdgeMotion m{pick(), pick(), pick(), pick(), pick(), pick(), pick(), pick()};
        if (trial % 4 == 0) { // parallel edges
            m.qb0 = m.qa0 + 0.5 * (m.pb0 - m.pa0);
            m.qb1 = m.qa1 + 0.5 * (m.pb1 - m.pa1);
        }
        for (double d : {0.0, 0.1 * size}) {
            const auto hit = m.sweep(d);
            if (hit) {
                EXPECT_TRUE(std::isfinite(hit->time));
                EXPECT_GE(hit->time, 0.0);
                EXPECT_LE(hit->time, 1.0);
                for (double x : hit->coords) {
                    EXPECT_TRUE(std::isfinite(x));
                    EXPECT_GE(x, 0.0);
                    EXPECT_LE(x, 1.0);
                }
            }
        }
    }
}

// =============================================================================================
// orient3d
// =============================================================================================

/// Minimal signed big integer (sign and magnitude in base 2³²) for exact reference values.
class BigInt {
  public:
    BigInt() = default;

    /// x / 2^unitExponent, which must be an integer.
    static BigInt fromDouble(double x, int unitExponent) {
        BigInt r;
        if (x == 0) {
            return r;
        }
        int e = 0;
        const double m = std::frexp(x, &e); // x = m · 2^e, 0.5 <= |m| < 1
        const auto mantissa = static_cast<std::int64_t>(std::ldexp(m, 53));
        r.m_negative = mantissa < 0;
        const auto magnitude = static_cast<std::uint64_t>(mantissa < 0 ? -mantissa : mantissa);
        r.m_limbs = {static_cast<std::uint32_t>(magnitude & 0xffffffffu),
                     static_cast<std::uint32_t>(magnitude >> 32)};
        r.shiftLeft(e - 53 - unitExponent);
        r.trim();
        return r;
    }

    int sign() const { return m_limbs.empty() ? 0 : (m_negative ? -1 : 1); }

    friend BigInt operator+(const BigInt& a, const BigInt& b) {
        BigInt r;
        if (a.m_negative == b.m_negative) {
            r.m_limbs = addMagnitudes(a.m_limbs, b.m_limbs);
            r.m_negative = a.m_negative;
        } else if (compareMagnitudes(a.m_limbs, b.m_limbs) >= 0) {
            r.m_limbs = subtractMagnitudes(a.m_limbs, b.m_limbs);
            r.m_negative = a.m_negative;
        } else {
            r.m_limbs = subtractMagnitudes(b.m_limbs, a.m_limbs);
            r.m_negative = b.m_negative;
        }
        r.trim();
        return r;
    }
    friend BigInt operator-(const BigInt& a, const BigInt& b) {
        BigInt nb = b;
        nb.m_negative = !nb.m_negative;
        return a + nb;
    }
    friend BigInt operator*(const BigInt& a, const BigInt& b) {
        BigInt r;
        if (a.m_limbs.empty() || b.m_limbs.empty()) {
            return r;
        }
        std::vector<std::uint64_t> acc(a.m_limbs.size() + b.m_limbs.size() + 1, 0);
        for (std::size_t i = 0; i < a.m_limbs.size(); ++i) {
            std::uint64_t carry = 0;
            for (std::size_t j = 0; j < b.m_limbs.size(); ++j) {
                const std::uint64_t cur =
                    acc[i + j] + std::uint64_t(a.m_limbs[i]) * b.m_limbs[j] + carry;
                acc[i + j] = cur & 0xffffffffu;
                carry = cur >> 32;
            }
            acc[i + b.m_limbs.size()] += carry;
        }
        r.m_limbs.resize(acc.size());
        for (std::size_t i = 0; i < acc.size(); ++i) {
            r.m_limbs[i] = static_cast<std::uint32_t>(acc[i]);
        }
        r.m_negative = a.m_negative != b.m_negative;
        r.trim();
        return r;
    }

  private:
    using Limbs = std::vector<std::uint32_t>;

    void shiftLeft(int bits) {
        const auto words = static_cast<std::size_t>(bits / 32);
        const int rest = bits % 32;
        Limbs out(m_limbs.size() + words + 1, 0);
        for (std::size_t i = 0; i < m_limbs.size(); ++i) {
            const std::uint64_t v = std::uint64_t(m_limbs[i]) << rest;
            out[i + words] |= static_cast<std::uint32_t>(v & 0xffffffffu);
            out[i + words + 1] |= static_cast<std::uint32_t>(v >> 32);
        }
        m_limbs = out;
    }
    void trim() {
        while (!m_limbs.empty() && m_limbs.back() == 0) {
            m_limbs.pop_back();
        }
    }
    static int compareMagnitudes(const Limbs& a, const Limbs& b) {
        if (a.size() != b.size()) {
            return a.size() < b.size() ? -1 : 1;
        }
        for (std::size_t i = a.size(); i-- > 0;) {
            if (a[i] != b[i]) {
                return a[i] < b[i] ? -1 : 1;
            }
        }
        return 0;
    }
    static Limbs addMagnitudes(const Limbs& a, const Limbs& b) {
        Limbs r(std::max(a.size(), b.size()) + 1, 0);
        std::uint64_t carry = 0;
        for (std::size_t i = 0; i < r.size(); ++i) {
            const std::uint64_t cur =
                carry + (i < a.size() ? a[i] : 0u) + (i < b.size() ? b[i] : 0u);
            r[i] = static_cast<std::uint32_t>(cur & 0xffffffffu);
            carry = cur >> 32;
        }
        return r;
    }
    static Limbs subtractMagnitudes(const Limbs& a, const Limbs& b) { // |a| >= |b|
        Limbs r(a.size(), 0);
        std::int64_t borrow = 0;
        for (std::size_t i = 0; i < a.size(); ++i) {
            std::int64_t cur =
                std::int64_t(a[i]) - (i < b.size() ? std::int64_t(b[i]) : 0) - borrow;
            borrow = cur < 0 ? 1 : 0;
            if (cur < 0) {
                cur += std::int64_t(1) << 32;
            }
            r[i] = static_cast<std::uint32_t>(cur);
        }
        return r;
    }

    bool m_negative = false;
    Limbs m_limbs;
};

/// Exact sign of det[b − a, c − a, d − a] with big integers (differences first, unlike the
/// implementation).
int orient3dReference(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    int unit = std::numeric_limits<int>::max();
    for (const Vec3* v : {&a, &b, &c, &d}) {
        for (int i = 0; i < 3; ++i) {
            if ((*v)[i] != 0) {
                int e = 0;
                std::frexp((*v)[i], &e);
                unit = std::min(unit, e - 53);
            }
        }
    }
    if (unit == std::numeric_limits<int>::max()) {
        return 0;
    }
    const auto big = [&](const Vec3& v) {
        return std::array<BigInt, 3>{BigInt::fromDouble(v.x(), unit),
                                     BigInt::fromDouble(v.y(), unit),
                                     BigInt::fromDouble(v.z(), unit)};
    };
    const auto A = big(a), B = big(b), C = big(c), D = big(d);
    std::array<BigInt, 3> u, v, w;
    for (std::size_t i = 0; i < 3; ++i) {
        u[i] = B[i] - A[i];
        v[i] = C[i] - A[i];
        w[i] = D[i] - A[i];
    }
    const BigInt det = u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
                       u[2] * (v[0] * w[1] - v[1] * w[0]);
    return det.sign();
}

int naiveSign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const double det = (b - a).dot((c - a).cross(d - a));
    return (det > 0) - (det < 0);
}

TEST(Orient3d, BasicOrientations) {
    const Vec3 o(0, 0, 0), x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
    EXPECT_EQ(orient3d(o, x, y, z), 1);
    EXPECT_EQ(orient3d(o, y, x, z), -1);
    EXPECT_EQ(orient3d(o, x, y, -z), -1);
    EXPECT_EQ(orient3d(o, x, y, Vec3(0.3, 0.7, 0)), 0);
    EXPECT_EQ(orient3d(o, x, x, z), 0);
    EXPECT_EQ(orient3d(z, z, z, z), 0);
    // Exactly coplanar points with inexact products: the plane x + y + z = 1.
    EXPECT_EQ(orient3d(Vec3(0.5, 0.25, 0.25), Vec3(0.125, 0.375, 0.5), Vec3(0.75, 0.0625, 0.1875),
                       Vec3(0.3125, 0.3125, 0.375)),
              0);
}

TEST(Orient3d, MatchesBigIntegerReferenceOnNearlyCoplanarPoints) {
    Rng rng(41);
    int naiveWrong = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        const double size = std::pow(10.0, uniform(rng, -3, 3));
        const Vec3 offset = std::pow(10.0, uniform(rng, 0, 6)) * randomVec(rng, -1, 1);
        Vec3 a = offset + size * randomVec(rng, -1, 1);
        Vec3 b = offset + size * randomVec(rng, -1, 1);
        Vec3 c = offset + size * randomVec(rng, -1, 1);
        if (trial % 4 == 3) { // nearly collinear a, b, c
            c = lerp(a, b, uniform(rng, -1, 2));
        }
        // d on the plane up to rounding, then moved by a few ulps in one coordinate.
        Vec3 d = lerp(lerp(a, b, uniform(rng, -1, 2)), c, uniform(rng, -1, 2));
        const int axis = std::uniform_int_distribution<int>(0, 2)(rng);
        const int ulps = std::uniform_int_distribution<int>(-2, 2)(rng);
        for (int k = 0; k < std::abs(ulps); ++k) {
            d[axis] = std::nextafter(d[axis], ulps > 0 ? 1e300 : -1e300);
        }
        const int expected = orient3dReference(a, b, c, d);
        ASSERT_EQ(orient3d(a, b, c, d), expected);
        // Antisymmetric under swaps, invariant under even permutations.
        EXPECT_EQ(orient3d(b, a, c, d), -expected);
        EXPECT_EQ(orient3d(a, b, d, c), -expected);
        EXPECT_EQ(orient3d(b, c, a, d), expected);
        EXPECT_EQ(orient3d(d, c, b, a), expected);
        EXPECT_EQ(orient3d(c, d, a, b), expected);
        naiveWrong += naiveSign(a, b, c, d) != expected;
    }
    // The inputs are hard: the rounded determinant gets many of them wrong.
    EXPECT_GT(naiveWrong, 500);
}

TEST(Orient3d, MatchesBigIntegerReferenceOnGenericPoints) {
    Rng rng(42);
    for (int trial = 0; trial < 2000; ++trial) {
        const Vec3 a = randomVec(rng, -1, 1), b = randomVec(rng, -1, 1);
        const Vec3 c = randomVec(rng, -1, 1), d = randomVec(rng, -1, 1);
        ASSERT_EQ(orient3d(a, b, c, d), orient3dReference(a, b, c, d));
    }
}

TEST(Orient3d, UlpGridAgainstAPlane) {
    // The plane x = y through (12, 12, 0), (24, 24, 0), (24, 24, 5); d on a grid of ulps around
    // (0.5, 0.5, 0.25): the exact sign is that of x − y (Shewchuk's classic orient2d example,
    // lifted to 3D), which the rounded determinant cannot see after the subtractions.
    const Vec3 a(12, 12, 0), b(24, 24, 0), c(24, 24, 5);
    const int positive = orient3d(a, b, c, Vec3(1, 0, 0.25));
    ASSERT_NE(positive, 0);
    const double ulp = std::ldexp(1.0, -53);
    int naiveWrong = 0;
    for (int i = 0; i < 64; ++i) {
        for (int j = 0; j < 64; ++j) {
            const Vec3 d(0.5 + i * ulp, 0.5 + j * ulp, 0.25);
            const int expected = i == j ? 0 : (i > j ? positive : -positive);
            ASSERT_EQ(orient3d(a, b, c, d), expected) << i << " " << j;
            naiveWrong += naiveSign(a, b, c, d) != expected;
        }
    }
    EXPECT_GT(naiveWrong, 500);
}

// =============================================================================================
// trianglesIntersect
// =============================================================================================

using Tri = std::array<Vec3, 3>;

bool intersect(const Tri& t, const Tri& u) {
    return trianglesIntersect(t[0], t[1], t[2], u[0], u[1], u[2]);
}

/// trianglesIntersect agrees under swapping the triangles and permuting their vertices.
void expectIntersect(const Tri& t, const Tri& u, bool expected) {
    std::array<int, 3> pt = {0, 1, 2};
    do {
        std::array<int, 3> pu = {0, 1, 2};
        do {
            const Tri tt = {t[pt[0]], t[pt[1]], t[pt[2]]};
            const Tri uu = {u[pu[0]], u[pu[1]], u[pu[2]]};
            EXPECT_EQ(intersect(tt, uu), expected);
            EXPECT_EQ(intersect(uu, tt), expected);
        } while (std::next_permutation(pu.begin(), pu.end()));
    } while (std::next_permutation(pt.begin(), pt.end()));
}

TEST(TrianglesIntersect, ConstructedCases) {
    const Tri a = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    const double above = std::nextafter(1.0, 2.0);
    const Tri a1 = {Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(0, 1, 1)}; // a lifted to z = 1
    // Crossing: b pierces a's interior.
    expectIntersect(a, {Vec3(0.25, 0.25, -1), Vec3(0.25, 0.25, 1), Vec3(2, 2, 0)}, true);
    // The same, but b's cut line misses a.
    expectIntersect(a, {Vec3(0.75, 0.75, -1), Vec3(0.75, 0.75, 1), Vec3(2, 2, 0)}, false);
    // Touching at a vertex of b on a's interior; at a vertex of a; 1 ulp away.
    expectIntersect(a, {Vec3(0.25, 0.25, 0), Vec3(0, 0, 1), Vec3(1, 1, 1)}, true);
    expectIntersect(a, {Vec3(1, 0, 0), Vec3(2, 0, 1), Vec3(2, 1, 1)}, true);
    expectIntersect(a1, {Vec3(0.25, 0.25, 1), Vec3(0, 0, 2), Vec3(1, 1, 2)}, true);
    expectIntersect(a1, {Vec3(0.25, 0.25, above), Vec3(0, 0, 2), Vec3(1, 1, 2)}, false);
    // Touching along a segment: b's edge lies in a's plane across a; b's edge overlaps a's edge.
    expectIntersect(a, {Vec3(-0.5, 0.25, 0), Vec3(1.5, 0.25, 0), Vec3(0.5, 0.25, 1)}, true);
    expectIntersect(a, {Vec3(0.5, 0, 0), Vec3(2, 0, 0), Vec3(1, 0, 1)}, true);
    // Sharing an edge (folded and flat), sharing a vertex only.
    expectIntersect(a, {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 1)}, true);
    expectIntersect(a, {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)}, true);
    expectIntersect(a, {Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)}, true);
    // Coplanar: overlapping, containing, disjoint, touching at a point of the hypotenuse.
    expectIntersect(a, {Vec3(0.2, 0.2, 0), Vec3(2, 0.2, 0), Vec3(0.2, 2, 0)}, true);
    expectIntersect(a, {Vec3(0.1, 0.1, 0), Vec3(0.2, 0.1, 0), Vec3(0.1, 0.2, 0)}, true);
    expectIntersect(a, {Vec3(0.6, 0.6, 0), Vec3(2, 0.6, 0), Vec3(0.6, 2, 0)}, false);
    expectIntersect(a, {Vec3(0.5, 0.5, 0), Vec3(1, 1, 0), Vec3(0.5, 1, 0)}, true);
    // Parallel planes 1 ulp apart, and the same triangle.
    expectIntersect(a1, {Vec3(0, 0, above), Vec3(1, 0, above), Vec3(0, 1, above)}, false);
    expectIntersect(a1, a1, true);
    // b's cut line through a's hypotenuse point (0.5, 0.5), and 1 ulp beyond it.
    const double y = std::nextafter(0.5, 1.0);
    expectIntersect(a, {Vec3(0.5, 0.5, -1), Vec3(0.5, 0.5, 1), Vec3(1.5, 1.5, 0)}, true);
    expectIntersect(a, {Vec3(0.5, y, -1), Vec3(0.5, y, 1), Vec3(1.5, y + 1, 0)}, false);
    // Far apart.
    expectIntersect(a, {Vec3(10, 10, 10), Vec3(11, 10, 10), Vec3(10, 11, 10)}, false);
}

TEST(TrianglesIntersect, DegenerateTriangles) {
    const Tri a = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    // Segments (collinear vertices, in any order) through a, beside a, in a's plane.
    expectIntersect(a, {Vec3(0.25, 0.25, -1), Vec3(0.25, 0.25, 0.5), Vec3(0.25, 0.25, 1)}, true);
    expectIntersect(a, {Vec3(0.75, 0.75, -1), Vec3(0.75, 0.75, 0.5), Vec3(0.75, 0.75, 1)}, false);
    expectIntersect(a, {Vec3(-1, 0.5, 0), Vec3(2, 0.5, 0), Vec3(0, 0.5, 0)}, true);
    expectIntersect(a, {Vec3(0.1, 0.1, 0), Vec3(0.2, 0.2, 0), Vec3(0.2, 0.2, 0)}, true);
    expectIntersect(a, {Vec3(-1, -0.5, 0), Vec3(2, -0.5, 0), Vec3(0, -0.5, 0)}, false);
    expectIntersect(a, {Vec3(0.5, 0.5, 0), Vec3(2, 2, 0), Vec3(1, 1, 0)}, true); // touches
    // Points: on the face, on an edge, at a vertex, 1 ulp off.
    const auto point = [](const Vec3& p) { return Tri{p, p, p}; };
    expectIntersect(a, point(Vec3(0.25, 0.25, 0)), true);
    expectIntersect(a, point(Vec3(0.5, 0, 0)), true);
    expectIntersect(a, point(Vec3(0, 1, 0)), true);
    expectIntersect(a, point(Vec3(0.5, std::nextafter(0.5, 1.0), 0)), false);
    expectIntersect(a, point(Vec3(0.25, 0.25, 1e-200)), false);
    // Segment against segment: crossing, skew, collinear overlapping / touching / disjoint.
    const auto segment = [](const Vec3& p, const Vec3& q) { return Tri{p, q, lerp(p, q, 0.5)}; };
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(2, 2, 0)), segment(Vec3(0, 2, 0), Vec3(2, 0, 0)),
                    true);
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(2, 2, 0)), segment(Vec3(0, 2, 1), Vec3(2, 0, 1)),
                    false);
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(2, 2, 2)), segment(Vec3(1, 1, 1), Vec3(3, 3, 3)),
                    true);
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(2, 2, 2)), segment(Vec3(2, 2, 2), Vec3(3, 3, 3)),
                    true);
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(1, 1, 1)), segment(Vec3(2, 2, 2), Vec3(3, 3, 3)),
                    false);
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(2, 0, 0)), segment(Vec3(1, 0, 0), Vec3(1, 5, 0)),
                    true); // T junction
    // Segment against point; point against point.
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(2, 2, 2)), point(Vec3(0.5, 0.5, 0.5)), true);
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(2, 2, 2)), point(Vec3(0.5, 0.5, 0.6)), false);
    expectIntersect(segment(Vec3(0, 0, 0), Vec3(2, 2, 2)), point(Vec3(3, 3, 3)), false);
    expectIntersect(point(Vec3(1, 2, 3)), point(Vec3(1, 2, 3)), true);
    expectIntersect(point(Vec3(1, 2, 3)), point(Vec3(1, 2, std::nextafter(3.0, 4.0))), false);
}

/// Exact reference for small integer coordinates by the separating axis theorem: two compact
/// convex sets are disjoint iff some direction strictly separates their projections, and for
/// (possibly degenerate) triangles it can be found among the differences d of the six points,
/// their cross products d × d' and the products (d × d') × d'' (face normals, edge × edge,
/// in-plane edge normals, and the directions for segments and points).
bool satIntersect(const std::array<std::array<std::int64_t, 3>, 6>& pts) {
    using I3 = std::array<std::int64_t, 3>;
    const auto cross = [](const I3& u, const I3& v) {
        return I3{u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    };
    const auto dot = [](const I3& u, const I3& v) {
        return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    };
    std::vector<I3> diffs;
    for (std::size_t i = 0; i < 6; ++i) {
        for (std::size_t j = i + 1; j < 6; ++j) {
            diffs.push_back({pts[j][0] - pts[i][0], pts[j][1] - pts[i][1], pts[j][2] - pts[i][2]});
        }
    }
    std::vector<I3> axes = diffs;
    for (std::size_t i = 0; i < diffs.size(); ++i) {
        for (std::size_t j = i + 1; j < diffs.size(); ++j) {
            const I3 n = cross(diffs[i], diffs[j]);
            axes.push_back(n);
            for (const I3& d : diffs) {
                axes.push_back(cross(n, d));
            }
        }
    }
    for (const I3& axis : axes) {
        if (axis[0] == 0 && axis[1] == 0 && axis[2] == 0) {
            continue;
        }
        std::int64_t loA = dot(axis, pts[0]), hiA = loA, loB = dot(axis, pts[3]), hiB = loB;
        for (std::size_t i = 1; i < 3; ++i) {
            loA = std::min(loA, dot(axis, pts[i]));
            hiA = std::max(hiA, dot(axis, pts[i]));
            loB = std::min(loB, dot(axis, pts[i + 3]));
            hiB = std::max(hiB, dot(axis, pts[i + 3]));
        }
        if (hiA < loB || hiB < loA) {
            return false;
        }
    }
    return true;
}

TEST(TrianglesIntersect, MatchesSeparatingAxisReferenceOnIntegerGrids) {
    Rng rng(51);
    int hits = 0;
    int degenerate = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        SCOPED_TRACE("trial " + std::to_string(trial));
        // Small grids make touching, coplanar and degenerate configurations common.
        const int range = trial % 3 == 0 ? 2 : 4;
        const bool flat = trial % 5 == 0;
        std::uniform_int_distribution<int> coord(0, range);
        std::array<std::array<std::int64_t, 3>, 6> pts{};
        for (auto& p : pts) {
            for (std::size_t k = 0; k < 3; ++k) {
                p[k] = k == 2 && flat ? 1 : coord(rng);
            }
        }
        const bool expected = satIntersect(pts);
        // Exactly representable but inexact in products: scaled by 2⁻¹⁰ and moved far away.
        const double scale = trial % 2 == 0 ? 1.0 : std::ldexp(1.0, -10);
        const Vec3 offset = trial % 2 == 0 ? Vec3::Zero() : Vec3(1e6, -3e5, 7e5);
        std::array<Vec3, 6> v;
        for (std::size_t i = 0; i < 6; ++i) {
            v[i] = offset + scale * Vec3(double(pts[i][0]), double(pts[i][1]), double(pts[i][2]));
        }
        const Tri t = {v[0], v[1], v[2]};
        const Tri u = {v[3], v[4], v[5]};
        ASSERT_EQ(intersect(t, u), expected);
        hits += expected;
        degenerate += triangleArea(v[0], v[1], v[2]) == 0 || triangleArea(v[3], v[4], v[5]) == 0;
        if (trial % 10 == 0) {
            expectIntersect(t, u, expected);
        }
    }
    EXPECT_GT(hits, 500);
    EXPECT_LT(hits, 2500);
    EXPECT_GT(degenerate, 100);
}

TEST(TrianglesIntersect, SymmetricAndPermutationInvariantOnRandomTriangles) {
    Rng rng(52);
    for (int trial = 0; trial < 150; ++trial) {
        const Tri t = {randomVec(rng, -1, 1), randomVec(rng, -1, 1), randomVec(rng, -1, 1)};
        Tri u = {randomVec(rng, -1, 1), randomVec(rng, -1, 1), randomVec(rng, -1, 1)};
        if (trial % 3 == 0) { // nearly coplanar with t
            const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
            for (Vec3& p : u) {
                p -= n.dot(p - t[0]) * n;
            }
        }
        expectIntersect(t, u, intersect(t, u));
    }
}

// =============================================================================================
// triangleNormal
// =============================================================================================

TEST(TriangleNormal, UnitRightHandedOrZero) {
    EXPECT_LE((triangleNormal(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 3, 0)) - Vec3(0, 0, 1)).norm(),
              1e-15);
    EXPECT_LE((triangleNormal(Vec3(0, 0, 0), Vec3(0, 3, 0), Vec3(2, 0, 0)) - Vec3(0, 0, -1)).norm(),
              1e-15);
    EXPECT_EQ(triangleNormal(Vec3(0, 0, 0), Vec3(1, 1, 1), Vec3(2, 2, 2)), Vec3::Zero());
    EXPECT_EQ(triangleNormal(Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(1, 1, 1)), Vec3::Zero());
}

} // namespace
} // namespace atelier::sim
