// Welded groups brought together at a step's start: never through the cloth.

#include "sim/constraints/seam_welds.h"

#include <gtest/gtest.h>

#include <vector>

namespace atelier::sim {
namespace {

/// Two pairs (0, 1) and (2, 3) welded, then their members pulled apart as collision
/// corrections leave them: 1 mm for the first group, 10 mm for the second.
struct TwoGroups {
    std::vector<SeamPair> seams{{0, 1}, {2, 3}};
    SeamWelds welds{seams, 4};
    MatX3 x = MatX3::Zero(4, 3);
    MatX3 v = MatX3::Zero(4, 3);
    VecX mass = VecX::Ones(4);
    VecX invMass = VecX::Ones(4);

    TwoGroups() {
        WeldFigures figures;
        welds.weldClosed(x, 0.001, true, figures);
        x.row(1) << 0.001, 0, 0;
        x.row(2) << 0, 1, 0;
        x.row(3) << 0.01, 1, 0;
        v.row(1) << 2, 0, 0;
    }
};

TEST(SeamWelds, StartMergeKeepsApartTheMembersThatWouldCross) {
    TwoGroups s;
    std::vector<std::vector<int>> asked;
    // The cloth between vertices 2 and 3: moving 3 crosses it, moving 2 does not.
    const SeamWelds::CrossingTest crossing = [&](const MatX3&, const MatX3&,
                                                 const std::vector<int>& moved) {
        asked.push_back(moved);
        std::vector<int> crossed;
        for (int i : moved) {
            if (i == 3) {
                crossed.push_back(i);
            }
        }
        return crossed;
    };
    const MatX3 before = s.x;
    s.welds.mergeWithoutCrossing(s.x, s.v, s.mass, s.invMass, crossing, 0.002);
    // Within 2 mm: merged without asking; the 10 mm group was tested.
    ASSERT_FALSE(asked.empty());
    for (const std::vector<int>& moved : asked) {
        for (int i : moved) {
            EXPECT_TRUE(i == 2 || i == 3) << i;
        }
    }
    EXPECT_EQ((s.x.row(0) - s.x.row(1)).norm(), 0.0);
    EXPECT_NEAR(s.x(0, 0), 0.0005, 1e-15);
    // Vertex 3 stays where it was, vertex 2 goes to the group's point; both share a velocity.
    EXPECT_EQ(s.x.row(3), before.row(3));
    EXPECT_NEAR(s.x(2, 0), 0.005, 1e-15);
    EXPECT_EQ(s.v.row(0), s.v.row(1));
    EXPECT_NEAR(s.v(0, 0), 1.0, 1e-15);
}

TEST(SeamWelds, StartMergeWithNothingInTheWayIsTheMerge) {
    TwoGroups checked, plain;
    int calls = 0;
    const SeamWelds::CrossingTest none = [&](const MatX3&, const MatX3&, const std::vector<int>&) {
        ++calls;
        return std::vector<int>{};
    };
    checked.welds.mergeWithoutCrossing(checked.x, checked.v, checked.mass, checked.invMass, none,
                                       0.0);
    plain.welds.merge(&plain.x, plain.v, plain.mass, plain.invMass);
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(checked.x, plain.x); // to the bit
    EXPECT_EQ(checked.v, plain.v);
}

} // namespace
} // namespace atelier::sim
