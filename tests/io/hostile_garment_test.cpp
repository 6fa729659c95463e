// Garments that the mesher could not take: panels at absurd coordinates and outline ranges
// sewn twice, refused by patterns::validateGarment and reported at their JSON pointer.
#include "io/project_file.h"

#include <gtest/gtest.h>

#include <string>

namespace atelier::io {
namespace {

/// A version-1 project with two 400 × 500 mm panels, `front` having `farCorner` as its second
/// corner, and `seams` (the array's content).
std::string projectV1(const std::string& seams, const std::string& farCorner = "400") {
    return R"({"format": "atelier-project", "version": 1,
  "materials": [{"name": "m", "fabric": "cotton"}],
  "panels": [
    {"name": "front", "material": "m", "outline": [{"line": {"from": [0, 0]}},
      {"line": {"from": [)" +
           farCorner + R"(, 0]}}, {"line": {"from": [400, 500]}}, {"line": {"from": [0, 500]}}]},
    {"name": "back", "material": "m", "outline": [{"line": {"from": [0, 0]}},
      {"line": {"from": [400, 0]}}, {"line": {"from": [400, 500]}}, {"line": {"from": [0, 500]}}],
     "darts": []}
  ],
  "seams": [)" +
           seams + "]}";
}

std::string seam(const std::string& name, const std::string& a, const std::string& b) {
    return R"({"name": ")" + name + R"(", "a": [)" + a + R"(], "b": [)" + b + "]}";
}

std::string range(const std::string& panel, int segment, double t0 = 0, double t1 = 1) {
    return R"({"panel": ")" + panel + R"(", "segment": )" + std::to_string(segment) +
           R"(, "t0": )" + std::to_string(t0) + R"(, "t1": )" + std::to_string(t1) + "}";
}

std::string errorOf(const Result<patterns::Project>& result) {
    return result.ok() ? std::string("(no error)") : result.error().toString();
}

TEST(HostileProject, ContactThicknessIsBounded) {
    std::string text = projectV1("");
    text.insert(text.size() - 1, R"(, "simulation": {"cloth_thickness_mm": 1e18})");
    EXPECT_EQ(errorOf(parseProject(text, "p.atelier")),
              "p.atelier: /simulation/cloth_thickness_mm: must be at most 50.0 mm (the limit "
              "thickness-m; found 1e+18)");
    text = projectV1("");
    text.insert(text.size() - 1, R"(, "simulation": {"body_thickness_mm": 60})");
    EXPECT_EQ(errorOf(parseProject(text, "p.atelier")),
              "p.atelier: /simulation/body_thickness_mm: must be at most 50.0 mm (the limit "
              "thickness-m; found 60.0)");
}

TEST(HostileGarment, PanelsBeyondGarmentScaleAreRefused) {
    // 1e300 mm aborted the mesher with std::length_error; 1e9 mm meshed for ever.
    EXPECT_EQ(errorOf(parseProject(projectV1("", "1e300"), "p.atelier")),
              "p.atelier: /panels/0/outline: panel \"front\" is 1e+297 m across, more than the "
              "10 m a panel may span (outline points are millimetres)");
    EXPECT_EQ(errorOf(parseProject(projectV1("", "1e9"), "p.atelier")),
              "p.atelier: /panels/0/outline: panel \"front\" is 1e+06 m across, more than the "
              "10 m a panel may span (outline points are millimetres)");
    EXPECT_TRUE(parseProject(projectV1("", "9000"), "p.atelier").ok());
}

TEST(HostileGarment, APlacementOffsetOffEveryBodyIsRefused) {
    // 9.2e18 mm (a fuzz case) made the drape's placement run past the fuzzer's 20 s.
    const auto placed = [](const std::string& offset) {
        std::string text = projectV1("");
        const std::string front = R"({"name": "front", "material": "m",)";
        text.replace(text.find(front), front.size(),
                     front + R"( "placement": {"slot": "torso_front", "offset_mm": )" + offset +
                         "},");
        return parseProject(text, "p.atelier");
    };
    EXPECT_EQ(errorOf(placed("[0, 9.2e18]")),
              "p.atelier: /panels/0/placement/offset_mm: an offset beyond 10000 mm is off the "
              "body");
    EXPECT_TRUE(placed("[-300, 120]").ok()) << errorOf(placed("[-300, 120]"));
}

TEST(HostileGarment, ASeamSewingAnEdgeToItselfIsAnError) {
    EXPECT_EQ(
        errorOf(parseProject(projectV1(seam("side", range("front", 1), range("front", 1, 1, 0))),
                             "p.atelier")),
        "p.atelier: /seams/0/b/0: seam \"side\" sews an edge to itself: this range "
        "overlaps /seams/0/a/0");
    EXPECT_EQ(errorOf(parseProject(
                  projectV1(seam("", range("front", 1, 0, 0.6) + ", " + range("front", 1, 0.4, 1),
                                 range("back", 3))),
                  "p.atelier")),
              "p.atelier: /seams/0/a/1: seam 0 uses the same edge range twice: this range "
              "overlaps /seams/0/a/0");
}

TEST(HostileGarment, TheSameSeamTwiceIsAnError) {
    const std::string side = seam("side", range("front", 1), range("back", 3, 1, 0));
    const std::string again = seam("side again", range("back", 3, 1, 0), range("front", 1));
    EXPECT_EQ(errorOf(parseProject(projectV1(side + ", " + again), "p.atelier")),
              "p.atelier: /seams/1: seam \"side again\" repeats seam \"side\" (/seams/0): the "
              "same ranges sewn together again");
}

TEST(HostileGarment, AnEdgeRangeInTwoSeamsIsAnError) {
    const std::string side = seam("side", range("front", 1), range("back", 3, 1, 0));
    const std::string other = seam("other", range("back", 1), range("front", 1, 0.5, 1));
    EXPECT_EQ(errorOf(parseProject(projectV1(side + ", " + other), "p.atelier")),
              "p.atelier: /seams/1/b/0: this range is also sewn by seam \"side\" "
              "(/seams/0/a/0): an edge range takes part in one seam or dart only");
    // Ranges that only meet at a point are fine: an edge split between two seams.
    const std::string half = seam("half", range("front", 1, 0, 0.5), range("back", 3, 1, 0.5));
    const std::string rest = seam("rest", range("front", 1, 0.5, 1), range("back", 1));
    EXPECT_TRUE(parseProject(projectV1(half + ", " + rest), "p.atelier").ok());
}

TEST(HostileGarment, ADartLegInASeamIsAnError) {
    std::string text = projectV1(seam("side", range("back", 1), range("front", 3)));
    text.replace(text.find(R"("darts": [])"), 11, R"("darts": [{"leg": 0}])");
    EXPECT_EQ(errorOf(parseProject(text, "p.atelier")),
              "p.atelier: /seams/0/a/0: this range is also sewn by dart 0 of panel \"back\" "
              "(/panels/1/darts/0): an edge range takes part in one seam or dart only");
}

TEST(HostileGarment, Version2ReportsSeamIssuesAtItsPointers) {
    const std::string corners = R"([{"point": 2, "at": [0, 0], "edge": 3},
        {"point": 4, "at": [400, 0], "edge": 5}, {"point": 6, "at": [400, 500], "edge": 7},
        {"point": 8, "at": [0, 500], "edge": 9}])";
    const std::string text = R"({"format": "atelier-project", "version": 2,
      "materials": [{"name": "m", "fabric": "cotton"}],
      "panels": [{"id": 1, "name": "front", "material": "m", "outline": )" +
                             corners + R"(}],
      "seams": [{"id": 10, "a": [{"panel": 1, "edge": 5}],
                 "b": [{"panel": 1, "edge": 5, "t0": 1, "t1": 0}]}]})";
    EXPECT_EQ(errorOf(parseProject(text, "p.atelier")),
              "p.atelier: /seams/0/b/0: seam 0 sews an edge to itself: this range overlaps "
              "/seams/0/a/0");
}

} // namespace
} // namespace atelier::io
