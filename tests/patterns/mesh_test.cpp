// Meshing panels: good triangles (min angle ≥ 25°), pattern area kept, seams matched one to
// one at equal arc-length fractions, internal lines as edges, holes, darts, notches, mirrored
// and grain-rotated rest shapes; and validation naming each bad case.

#include "patterns/curve.h"
#include "patterns/loops.h"
#include "patterns/mesh.h"

#include "sim/mesh/cloth_mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace atelier::patterns {
namespace {

using test::arc;
using test::line;

Segment cubic(Vec2 a, Vec2 c1, Vec2 c2, Vec2 b) {
    Segment s = line(a, b);
    s.kind = SegmentKind::Cubic;
    s.control1 = c1;
    s.control2 = c2;
    return s;
}

Loop polygon(const std::vector<Vec2>& p) {
    Loop l;
    for (std::size_t i = 0; i < p.size(); ++i) {
        l.push_back(line(p[i], p[(i + 1) % p.size()]));
    }
    return l;
}

Panel panel(const std::string& name, Loop outline) {
    Panel p;
    p.name = name;
    p.outline = std::move(outline);
    p.material = "m";
    return p;
}

/// A bodice front: hem, sides, cubic armholes, shoulders, an arc neckline.
Panel bodice() {
    const double w = 0.26, ay = 0.41, sx = 0.185, sy = 0.585, nx = 0.085, ny = 0.62;
    return panel("front",
                 {line({-w, 0}, {w, 0}), line({w, 0}, {w, ay}),
                  cubic({w, ay}, {w - 0.04, ay + 0.02}, {sx + 0.005, ay + 0.11}, {sx, sy}),
                  line({sx, sy}, {nx, ny}), arc({nx, ny}, {-nx, ny}, -0.5),
                  line({-nx, ny}, {-sx, sy}),
                  cubic({-sx, sy}, {-sx - 0.005, ay + 0.11}, {-w + 0.04, ay + 0.02}, {-w, ay}),
                  line({-w, ay}, {-w, 0})});
}

double meshArea(const PanelMesh& m) {
    double a = 0;
    for (int t = 0; t < m.triangles.rows(); ++t) {
        a += sim::signedArea(m.rest.row(m.triangles(t, 0)).transpose(),
                             m.rest.row(m.triangles(t, 1)).transpose(),
                             m.rest.row(m.triangles(t, 2)).transpose());
    }
    return a;
}

void expectGoodMesh(const GarmentMesh& m, const Garment& g) {
    EXPECT_GE(m.minAngleDeg, 25.0);
    for (std::size_t p = 0; p < m.panels.size(); ++p) {
        SCOPED_TRACE(g.panels[p].name);
        const PanelMesh& pm = m.panels[p];
        sim::ClothMesh cloth;
        const auto err = sim::buildClothMesh(pm.rest, pm.triangles, cloth);
        EXPECT_FALSE(err.has_value()) << *err;
        double exact = loopArea(g.panels[p].outline);
        for (const Loop& h : g.panels[p].holes) {
            exact -= std::abs(loopArea(h));
        }
        EXPECT_NEAR(meshArea(pm) / exact, 1.0, 0.005); // every triangle counter-clockwise too
        EXPECT_GE(minTriangleAngleDeg(pm.rest, pm.triangles), 25.0);
        // Every vertex is used.
        std::vector<char> used(static_cast<std::size_t>(pm.rest.rows()), 0);
        for (int t = 0; t < pm.triangles.rows(); ++t)
            for (int k = 0; k < 3; ++k)
                used[static_cast<std::size_t>(pm.triangles(t, k))] = 1;
        EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
    }
}

TEST(Mesh, APanelAtItsOwnParticleDistanceIsSewnAtTheFinerOne) {
    // Two 0.4 × 0.6 m panels sewn along their long sides; the first meshed at 10 mm, the second
    // at the garment's 20 mm.
    Garment g;
    g.materials.push_back({"m", {}});
    g.panels.push_back(panel("fine", polygon({{0, 0}, {0.4, 0}, {0.4, 0.6}, {0, 0.6}})));
    g.panels.push_back(panel("coarse", polygon({{0, 0}, {0.4, 0}, {0.4, 0.6}, {0, 0.6}})));
    g.panels[0].particleDistance = 0.01;
    Seam seam;
    seam.name = "side";
    seam.a = {{"fine", 1, 0, 1}};
    seam.b = {{"coarse", 3, 1, 0}};
    g.seams.push_back(seam);
    GarmentMesh m;
    MeshOptions options;
    options.particleDistance = 0.02;
    ASSERT_FALSE(meshGarment(g, options, m).has_value());
    expectGoodMesh(m, g);
    const double ratio = static_cast<double>(m.panels[0].triangles.rows()) /
                         static_cast<double>(m.panels[1].triangles.rows());
    EXPECT_GT(ratio, 3.0) << "a quarter of the area per triangle";
    EXPECT_LT(ratio, 5.0);
    // The seam takes the finer spacing on both sides: about 0.6 m / 10 mm pairs.
    EXPECT_GE(m.seamPairs.size(), 59U);
    EXPECT_LE(m.seamPairs.size(), 62U);
    // The estimate follows each panel's distance too.
    const MeshEstimate estimate = estimateGarmentMesh(g, 0.02);
    EXPECT_NEAR(static_cast<double>(estimate.triangles) / static_cast<double>(m.triangleCount), 1.0,
                0.2);
    // Out of bounds: refused with the panel named.
    g.panels[1].particleDistance = 0.0001;
    const auto issues = validateGarment(g);
    ASSERT_FALSE(issues.empty());
    EXPECT_NE(issues.front().where.find("particle_distance_mm"), std::string::npos);
}

TEST(Mesh, SameGarmentSameMeshWhateverTheHeap) {
    // Meshing must not follow memory addresses: the same garment meshed again after the heap
    // has changed gives the same triangles (CGAL's Lloyd smoothing did not, so it is off).
    Garment g;
    g.panels.push_back(bodice());
    MeshOptions o;
    o.particleDistance = 0.01;
    GarmentMesh first;
    ASSERT_FALSE(meshGarment(g, o, first).has_value());
    std::vector<std::vector<double>> clutter;
    for (int i = 0; i < 1000; ++i) {
        clutter.emplace_back(static_cast<std::size_t>(17 + i % 50), 1.0);
    }
    GarmentMesh second;
    ASSERT_FALSE(meshGarment(g, o, second).has_value());
    ASSERT_EQ(first.panels.size(), second.panels.size());
    EXPECT_EQ(first.panels[0].triangles, second.panels[0].triangles);
    EXPECT_EQ(first.panels[0].pattern, second.panels[0].pattern);
}

TEST(Mesh, BodiceHasGoodTrianglesAndKeepsItsArea) {
    Garment g;
    g.panels.push_back(bodice());
    for (double h : {0.02, 0.01, 0.005}) {
        SCOPED_TRACE(h);
        GarmentMesh m;
        MeshOptions o;
        o.particleDistance = h;
        ASSERT_FALSE(meshGarment(g, o, m).has_value());
        expectGoodMesh(m, g);
        // Triangle count scales like 1/h² (mean edge ≈ h: about area / (0.43 h²) triangles).
        const double expected = loopArea(g.panels[0].outline) / (0.433 * h * h);
        EXPECT_GT(m.triangleCount, 0.6 * expected);
        EXPECT_LT(m.triangleCount, 1.6 * expected);
    }
}

TEST(Mesh, HoleStaysEmpty) {
    Garment g;
    Panel p = panel("p", polygon({{0, 0}, {0.3, 0}, {0.3, 0.3}, {0, 0.3}}));
    p.holes.push_back({arc({0.2, 0.15}, {0.1, 0.15}, 1.0), arc({0.1, 0.15}, {0.2, 0.15}, 1.0)});
    g.panels.push_back(p);
    GarmentMesh m;
    ASSERT_FALSE(meshGarment(g, {}, m).has_value());
    expectGoodMesh(m, g);
    const PanelMesh& pm = m.panels[0];
    for (int t = 0; t < pm.triangles.rows(); ++t) {
        const Vec2 c = (pm.pattern.row(pm.triangles(t, 0)) + pm.pattern.row(pm.triangles(t, 1)) +
                        pm.pattern.row(pm.triangles(t, 2)))
                           .transpose() /
                       3.0;
        EXPECT_GT((c - Vec2(0.15, 0.15)).norm(), 0.05 - 0.002) << "triangle " << t;
    }
}

TEST(Mesh, InternalLinesAreEdgesWithTheirFold) {
    Garment g;
    Panel p = panel("p", polygon({{0, 0}, {0.3, 0}, {0.3, 0.2}, {0, 0.2}}));
    InternalLine fold;
    fold.path = {line({0.05, 0.1}, {0.25, 0.1})};
    fold.foldAngle = 0.4;
    p.internalLines.push_back(fold);
    g.panels.push_back(p);
    GarmentMesh m;
    ASSERT_FALSE(meshGarment(g, {}, m).has_value());
    expectGoodMesh(m, g);
    const PanelMesh& pm = m.panels[0];
    ASSERT_EQ(pm.lineEdges.size(), 20u); // 0.2 m at 0.01 m
    std::set<std::pair<int, int>> edges;
    for (int t = 0; t < pm.triangles.rows(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int a = pm.triangles(t, k), b = pm.triangles(t, (k + 1) % 3);
            edges.insert({std::min(a, b), std::max(a, b)});
        }
    for (std::size_t e = 0; e < pm.lineEdges.size(); ++e) {
        const auto [a, b] = pm.lineEdges[e];
        EXPECT_TRUE(edges.count({std::min(a, b), std::max(a, b)})) << "line edge " << e;
        EXPECT_NEAR(pm.pattern(a, 1), 0.1, 1e-12);
        EXPECT_EQ(pm.lineFoldAngles[e], 0.4);
    }
}

/// Positions on each side of a seam chain, at the arc-length fraction of each pair.
double fractionAlong(const Garment& g, const std::vector<SeamEdge>& chain, int panel,
                     const Vec2& q) {
    double total = 0, before = 0, found = -1;
    for (const SeamEdge& e : chain) {
        const Segment& s = g.panels[static_cast<std::size_t>(g.panelIndex(e.panel))]
                               .outline[static_cast<std::size_t>(e.segment)];
        const double len = arcLength(s, e.t0, e.t1);
        if (found < 0 && g.panelIndex(e.panel) == panel) {
            // Closest sample on this range.
            // Closest parameter: sampled, then refined by ternary search.
            double best = 1e9, bestT = e.t0;
            const double step = (e.t1 - e.t0) / 1000.0;
            for (int i = 0; i <= 1000; ++i) {
                const double t = e.t0 + step * i;
                const double d = (pointAt(s, t) - q).norm();
                if (d < best) {
                    best = d;
                    bestT = t;
                }
            }
            double lo = std::clamp(bestT - std::abs(step), 0.0, 1.0),
                   hi = std::clamp(bestT + std::abs(step), 0.0, 1.0);
            for (int it = 0; it < 100; ++it) {
                const double m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
                if ((pointAt(s, m1) - q).norm() < (pointAt(s, m2) - q).norm()) {
                    hi = m2;
                } else {
                    lo = m1;
                }
            }
            const double t = 0.5 * (lo + hi);
            if ((pointAt(s, t) - q).norm() < 1e-9) {
                found = before + arcLength(s, e.t0, t);
            }
        }
        before += len;
        total += len;
    }
    return found / total;
}

TEST(Mesh, OneToManySeamMatchesOneToOneByLengthFraction) {
    // A's curved top (0.4 m chord) is sewn to B's top and C's top (0.25 + 0.15 m).
    Garment g;
    Panel a =
        panel("a", {line({0, 0}, {0.4, 0}), line({0.4, 0}, {0.4, 0.2}),
                    cubic({0.4, 0.2}, {0.3, 0.26}, {0.1, 0.26}, {0, 0.2}), line({0, 0.2}, {0, 0})});
    Panel b = panel("b", polygon({{0, 0}, {0.25, 0}, {0.25, 0.1}, {0, 0.1}}));
    Panel c = panel("c", polygon({{0, 0}, {0.15, 0}, {0.15, 0.1}, {0, 0.1}}));
    g.panels = {a, b, c};
    Seam s;
    s.name = "top";
    s.a = {{"a", 2, 0, 1}};
    s.b = {{"b", 2, 0, 1}, {"c", 2, 0, 1}};
    g.seams.push_back(s);
    GarmentMesh m;
    ASSERT_FALSE(meshGarment(g, {}, m).has_value());
    expectGoodMesh(m, g);
    ASSERT_FALSE(m.warnings.empty()); // 0.43 m against 0.40 m: ease beyond 5 mm
    EXPECT_NE(m.warnings[0].find("seam \"top\""), std::string::npos);
    std::set<int> onA;
    int junction = 0;
    for (std::size_t k = 0; k < m.seamPairs.size(); ++k) {
        const auto& [pa, pb] = m.seamPairs[k];
        ASSERT_EQ(pa.panel, 0);
        onA.insert(pa.vertex);
        const Vec2 qa = m.panels[0].pattern.row(pa.vertex).transpose();
        const Vec2 qb =
            m.panels[static_cast<std::size_t>(pb.panel)].pattern.row(pb.vertex).transpose();
        const double fa = fractionAlong(g, s.a, 0, qa), fb = fractionAlong(g, s.b, pb.panel, qb);
        ASSERT_GE(fa, 0) << "pair " << k << ": A's vertex is not on its curve";
        ASSERT_GE(fb, 0) << "pair " << k << ": B's vertex is not on its curve";
        EXPECT_NEAR(fa, fb, 1e-7) << "pair " << k;
        junction += std::abs(fa - 0.25 / 0.4) < 1e-3 ? 1 : 0;
    }
    // One A vertex per fraction; the junction fraction pairs with both B's end and C's start.
    EXPECT_EQ(m.seamPairs.size(), onA.size() + 1);
    EXPECT_EQ(junction, 2);
}

TEST(Mesh, DartLegsArePairedTipToMouth) {
    // A rectangle with a V dart cut into its top edge, tip at (0.15, 0.12).
    Garment g;
    Panel p = panel(
        "p",
        polygon({{0, 0}, {0.3, 0}, {0.3, 0.2}, {0.17, 0.2}, {0.15, 0.12}, {0.13, 0.2}, {0, 0.2}}));
    p.darts.push_back({3}); // legs 3 ((0.17,0.2)→tip) and 4 (tip→(0.13,0.2))
    g.panels.push_back(p);
    GarmentMesh m;
    ASSERT_FALSE(meshGarment(g, {}, m).has_value());
    expectGoodMesh(m, g);
    ASSERT_GE(m.seamPairs.size(), 8u);
    for (std::size_t k = 0; k < m.seamPairs.size(); ++k) {
        EXPECT_EQ(m.seamOfPair[k], -1);
        const Vec2 a = m.panels[0].pattern.row(m.seamPairs[k][0].vertex).transpose();
        const Vec2 b = m.panels[0].pattern.row(m.seamPairs[k][1].vertex).transpose();
        // Mirror images about the dart's centre line x = 0.15, at the same height.
        EXPECT_NEAR(a.y(), b.y(), 1e-9);
        EXPECT_NEAR(a.x() + b.x(), 0.3, 1e-9);
    }
}

TEST(Mesh, NotchesBackPanelsAndGrain) {
    Garment g;
    Panel p = panel("p", polygon({{0, 0}, {0.2, 0}, {0.2, 0.1}, {0, 0.1}}));
    p.notches.push_back({0, 0.37});
    p.side = PanelSide::Back;
    p.grainAngle = 0; // warp along the pattern's x
    g.panels.push_back(p);
    GarmentMesh m;
    ASSERT_FALSE(meshGarment(g, {}, m).has_value());
    expectGoodMesh(m, g);
    const PanelMesh& pm = m.panels[0];
    ASSERT_EQ(pm.notchVertices.size(), 1u);
    EXPECT_NEAR((pm.pattern.row(pm.notchVertices[0]) -
                 sim::MatX2::Map(std::array<double, 2>{0.074, 0.0}.data(), 1, 2))
                    .norm(),
                0.0, 1e-12);
    // Mirrored (x → −x), then the grain (now along −x) turned to +y: pattern (x, y) → (y, −x)?
    // Rest lengths are kept, and the pattern's x extent becomes the rest's y extent.
    EXPECT_NEAR(pm.rest.col(1).maxCoeff() - pm.rest.col(1).minCoeff(), 0.2, 1e-12);
    EXPECT_NEAR(pm.rest.col(0).maxCoeff() - pm.rest.col(0).minCoeff(), 0.1, 1e-12);
}

TEST(Mesh, ValidationNamesEachProblem) {
    auto firstIssue = [](const Garment& g) {
        const auto issues = validateGarment(g);
        return issues.empty() ? std::string("none") : issues[0].where + ": " + issues[0].message;
    };
    Garment ok;
    ok.panels.push_back(panel("front", polygon({{0, 0}, {0.2, 0}, {0.2, 0.1}, {0, 0.1}})));
    EXPECT_EQ(firstIssue(ok), "none");

    Garment zero = ok;
    zero.panels[0].outline = polygon({{0, 0}, {0.2, 0}, {0.2, 0}, {0, 0.1}});
    EXPECT_EQ(firstIssue(zero), "/panels/0/outline/1: segment has zero length");

    Garment bowtie = ok;
    bowtie.panels[0].outline = polygon({{0, 0}, {0.2, 0.1}, {0.2, 0}, {0, 0.1}});
    EXPECT_NE(firstIssue(bowtie).find("/panels/0/outline: outline intersects itself"),
              std::string::npos)
        << firstIssue(bowtie);

    Garment gap = ok;
    gap.panels[0].outline[2].end = Vec2(0.05, 0.11);
    EXPECT_EQ(firstIssue(gap),
              "/panels/0/outline/2: segment does not end where the next one starts");

    Garment missing = ok;
    missing.seams.push_back({"side", {{"front", 1, 0, 1}}, {{"sleeve", 0, 0, 1}}});
    EXPECT_EQ(firstIssue(missing), "/seams/0/b/0/panel: seam names missing panel \"sleeve\"");

    Garment badSegment = ok;
    badSegment.seams.push_back({"side", {{"front", 9, 0, 1}}, {{"front", 3, 0, 1}}});
    EXPECT_EQ(firstIssue(badSegment), "/seams/0/a/0/segment: panel \"front\" has no segment 9");

    Garment empty = ok;
    empty.seams.push_back({"side", {{"front", 1, 0.5, 0.5}}, {{"front", 3, 0, 1}}});
    EXPECT_EQ(firstIssue(empty), "/seams/0/a/0: seam range is empty (t0 = t1)");

    Garment outside = ok;
    outside.panels[0].internalLines.push_back({{line({0.1, 0.05}, {0.3, 0.05})}, 0});
    EXPECT_EQ(firstIssue(outside), "/panels/0/internal_lines/0/segments/0: internal line leaves "
                                   "the panel (it must lie inside)");

    Garment clockwise = ok;
    clockwise.panels[0].outline = polygon({{0, 0}, {0, 0.1}, {0.2, 0.1}, {0.2, 0}});
    EXPECT_NE(firstIssue(clockwise).find("counter-clockwise"), std::string::npos);

    Garment dart = ok;
    dart.panels[0].darts.push_back({3});
    EXPECT_EQ(firstIssue(dart), "/panels/0/darts/0/leg: dart legs 3 and 4 are not in the outline");

    Garment nan = ok;
    nan.panels[0].outline[1].start.x() = std::nan("");
    EXPECT_EQ(firstIssue(nan), "/panels/0/outline/1: coordinates must be finite");

    // meshGarment refuses an invalid garment with the same message.
    GarmentMesh m;
    const auto err = meshGarment(missing, {}, m);
    ASSERT_TRUE(err.has_value());
    EXPECT_EQ(*err, "/seams/0/b/0/panel: seam names missing panel \"sleeve\"");
}

} // namespace
} // namespace atelier::patterns
