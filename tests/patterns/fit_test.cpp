#include "patterns/fit.h"

#include <gtest/gtest.h>

#include <cmath>

namespace atelier::patterns {
namespace {

/// One panel: a 10 cm square of two triangles, and a second one beside it in the scene.
AssembledGarment twoSquares() {
    AssembledGarment g;
    sim::MatX2 rest(4, 2);
    rest << 0, 0, 0.1, 0, 0.1, 0.1, 0, 0.1;
    sim::MatX3i triangles(2, 3);
    triangles << 0, 1, 2, 0, 2, 3;
    for (const char* name : {"front", "back"}) {
        sim::ClothSpec c;
        c.name = name;
        EXPECT_FALSE(sim::buildClothMesh(rest, triangles, c.mesh).has_value());
        g.scene.cloths.push_back(c);
    }
    g.panelOffsets = {0, 4, 8};
    return g;
}

/// The squares' rest shapes mapped by F (3×2) and placed at height `y`.
sim::MatX3 mapped(const AssembledGarment& g, const Eigen::Matrix<double, 3, 2>& front,
                  const Eigen::Matrix<double, 3, 2>& back) {
    sim::MatX3 x(8, 3);
    for (int c = 0; c < 2; ++c) {
        const auto& f = c == 0 ? front : back;
        for (int v = 0; v < 4; ++v) {
            const sim::Vec2 u = g.scene.cloths[static_cast<std::size_t>(c)].mesh.rest.row(v);
            x.row(4 * c + v) = (f * u).transpose() + sim::Vec3(0, 1.0 + c, 0).transpose();
        }
    }
    return x;
}

TEST(PanelStrains, ReadTheLargestPrincipalStretchWhateverTheRotation) {
    const AssembledGarment g = twoSquares();
    // Front: stretched 12% along x, then turned about z by 30°; back: a simple shear γ = 0.1.
    const double c = std::cos(0.5236), s = std::sin(0.5236);
    Eigen::Matrix<double, 3, 2> front;
    front << 1.12 * c, -s, 1.12 * s, c, 0, 0;
    Eigen::Matrix<double, 3, 2> back;
    back << 1, 0.1, 0, 1, 0, 0;
    const auto strains = panelStrains(g, mapped(g, front, back));
    ASSERT_EQ(strains.size(), 2u);
    EXPECT_EQ(strains[0].panel, "front");
    EXPECT_NEAR(strains[0].maxStrain, 0.12, 1e-12);
    EXPECT_DOUBLE_EQ(strains[0].over5, 1.0);
    EXPECT_DOUBLE_EQ(strains[0].over10, 1.0);
    EXPECT_NEAR(strains[0].maxHeight, 1.0, 0.1);
    // Simple shear: λ = γ/2 + √(1 + γ²/4).
    EXPECT_NEAR(strains[1].maxStrain, 0.05 + std::sqrt(1 + 0.0025) - 1, 1e-12);
    EXPECT_DOUBLE_EQ(strains[1].over5, 1.0); // 5.1%
    EXPECT_DOUBLE_EQ(strains[1].over10, 0.0);
    EXPECT_NEAR(strains[1].maxHeight, 2.0, 0.1);

    const GarmentFit fit{strains, {}};
    EXPECT_DOUBLE_EQ(fit.largestStrain(), strains[0].maxStrain);
    EXPECT_DOUBLE_EQ(fit.largestShareBeyond10(), 1.0);
}

TEST(PanelStrains, ACompressedPanelIsNotStretched) {
    const AssembledGarment g = twoSquares();
    Eigen::Matrix<double, 3, 2> half;
    half << 0.5, 0, 0, 0.9, 0, 0;
    const auto strains = panelStrains(g, mapped(g, half, half));
    EXPECT_DOUBLE_EQ(strains[0].maxStrain, 0.0);
    EXPECT_DOUBLE_EQ(strains[0].over5, 0.0);
}

TEST(FitVerdict, NamesThePanelsAndSeamsThatDoNotFit) {
    PanelStrain easy{"front", 0.15, 1.2, 0.01, 0.001};
    EXPECT_EQ(fitVerdict({easy}, {}, 0, 0).fit, FitLevel::Fits);
    EXPECT_TRUE(fitVerdict({easy}, {}, 0, 0).message.empty());

    PanelStrain tight{"back", 0.08, 1.3, 0.2, 0.0};
    const FitVerdict t = fitVerdict({easy, tight}, {}, 0, 0);
    EXPECT_EQ(t.fit, FitLevel::Tight);
    EXPECT_NE(t.message.find("back: 20.0% of its area stretched beyond 5%"), std::string::npos)
        << t.message;
    EXPECT_EQ(t.message.find("front"), std::string::npos) << t.message;

    PanelStrain torn{"sleeve_right", 2.68, 1.31, 0.87, 0.55};
    const FitVerdict d = fitVerdict({easy, tight, torn}, {{"shoulder_left", 0.0234, 5}}, 44, 0);
    EXPECT_EQ(d.fit, FitLevel::DoesNotFit);
    EXPECT_EQ(d.message.rfind("sleeve_right: 55.0% of its area stretched beyond 10% (up to 268% "
                              "at 1.31 m height)",
                              0),
              0u)
        << d.message; // the worst first
    EXPECT_NE(d.message.find("seam shoulder_left left open (5 pairs, widest 23.4 mm)"),
              std::string::npos);
    EXPECT_NE(d.message.find("44 intersecting triangle pairs (cloth through cloth)"),
              std::string::npos);
    EXPECT_EQ(fitName(d.fit), "does not fit");

    EXPECT_EQ(fitVerdict({easy}, {{"side", 0.01, 1}}, 0, 0).fit, FitLevel::DoesNotFit);
    EXPECT_EQ(fitVerdict({easy}, {}, 1, 0).fit, FitLevel::DoesNotFit);
    // Pairs with the body are named as such, apart from the cloth's own.
    const FitVerdict body = fitVerdict({easy}, {}, 14, 14);
    EXPECT_EQ(body.fit, FitLevel::DoesNotFit);
    EXPECT_EQ(body.message, "14 cloth triangles intersecting the body's (cloth through the body)");
    const FitVerdict both = fitVerdict({easy}, {}, 5, 2);
    EXPECT_EQ(both.message, "3 intersecting triangle pairs (cloth through cloth); 2 cloth "
                            "triangles intersecting the body's (cloth through the body)");
}

} // namespace
} // namespace atelier::patterns
