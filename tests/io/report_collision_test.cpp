#include "io/report.h"
#include "io/scene_file.h"

#include "sim/simulation.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>

namespace atelier::io {
namespace {

/// A 0.2 m sheet 5 mm above a floor plane, dropped for 0.05 s (it falls ≈ 12 mm: it lands).
/// `obstacles` is the content of the obstacles array.
std::string dropScene(const std::string& obstacles) {
    return R"({
  "format": "atelier-scene",
  "version": 1,
  "cloths": [{
    "name": "sheet",
    "mesh": {"type": "rectangle", "width": 0.2, "height": 0.2, "cells": [4, 4]},
    "placement": {"origin": [-0.1, 0.005, 0.1], "u_axis": [1, 0, 0], "v_axis": [0, 0, -1]},
    "material": "cotton"
  }],
  "obstacles": [)" +
           obstacles + R"(],
  "integrator": {"type": "implicit-euler", "dt": 0.0025, "max_dt": 0.0025},
  "duration": 0.05,
  "frame_rate": 100
})";
}

nlohmann::json runCollisionReport(const std::string& text) {
    auto loaded = parseScene(text, "drop.json", ".");
    EXPECT_TRUE(loaded.ok()) << loaded.error().toString();
    if (!loaded.ok()) {
        return {};
    }
    sim::Simulation simulation(std::move(loaded).value());
    EXPECT_EQ(simulation.error(), "");
    EXPECT_EQ(simulation.run(simulation.scene().duration), sim::RunStatus::Finished)
        << simulation.stats().error;
    return nlohmann::json::parse(formatReport(simulation));
}

TEST(ReportCollision, SheetDroppedOnPlane) {
    const nlohmann::json report = runCollisionReport(
        dropScene(R"({"name": "floor", "shape": {"type": "plane", "size": 1}})"));
    ASSERT_TRUE(report.is_object());
    EXPECT_EQ(report.at("finite"), true);

    ASSERT_TRUE(report.at("max_penetration_m").is_number()); // null would be non-finite
    const double penetration = report.at("max_penetration_m").get<double>();
    EXPECT_TRUE(std::isfinite(penetration));
    EXPECT_GE(penetration, 0);
    EXPECT_LT(penetration, 0.002) << "the sheet stays on the floor";

    ASSERT_TRUE(report.at("intersecting_triangle_pairs").is_number_integer());
    EXPECT_GE(report.at("intersecting_triangle_pairs").get<long>(), 0);

    ASSERT_TRUE(report.at("collision_time_fraction").is_number());
    const double fraction = report.at("collision_time_fraction").get<double>();
    EXPECT_GE(fraction, 0);
    EXPECT_LE(fraction, 1);

    ASSERT_TRUE(report.at("contacts").is_number_integer());
    EXPECT_GE(report.at("contacts").get<long>(), 0);

    EXPECT_EQ(report.at("obstacles"), nlohmann::json::array({"floor"}));
    EXPECT_TRUE(report.at("stage_seconds").contains("collision"));
}

TEST(ReportCollision, KeysPresentWithoutCollisionStage) {
    const nlohmann::json report = runCollisionReport(dropScene(""));
    ASSERT_TRUE(report.is_object());
    EXPECT_EQ(report.at("max_penetration_m"), 0.0);
    EXPECT_EQ(report.at("intersecting_triangle_pairs"), 0);
    EXPECT_EQ(report.at("collision_time_fraction"), 0.0);
    EXPECT_EQ(report.at("contacts"), 0);
    EXPECT_EQ(report.at("obstacles"), nlohmann::json::array());
}

} // namespace
} // namespace atelier::io
