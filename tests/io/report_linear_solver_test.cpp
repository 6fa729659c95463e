// The run report tells which linear solver ran and whether its solves converged: a solve that
// stops at the iteration cap is counted with its residual, never silent.

#include "io/report.h"
#include "io/scene_file.h"

#include "sim/simulation.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

namespace atelier::io {
namespace {

/// A cotton sheet hanging from two corners for 0.05 s, with the given integrator keys.
std::string hangingScene(const std::string& solverKeys) {
    return R"({
  "format": "atelier-scene",
  "version": 1,
  "cloths": [{
    "name": "sheet",
    "mesh": {"type": "rectangle", "width": 0.5, "height": 0.5, "cells": [10, 10]},
    "placement": {"origin": [-0.25, 1.0, 0.25], "u_axis": [1, 0, 0], "v_axis": [0, 0, -1]},
    "material": "cotton"
  }],
  "pins": [{"cloth": "sheet", "corner": "top-left"}, {"cloth": "sheet", "corner": "top-right"}],
  "gravity": true,
  "integrator": {"type": "implicit-euler", "dt": 0.005, "max_dt": 0.005, )" +
           solverKeys + R"(},
  "duration": 0.05,
  "frame_rate": 20
})";
}

nlohmann::json runSolverReport(const std::string& solverKeys) {
    auto loaded = parseScene(hangingScene(solverKeys), "hanging.json", ".");
    EXPECT_TRUE(loaded.ok()) << loaded.error().toString();
    if (!loaded.ok()) {
        return {};
    }
    sim::Simulation simulation(std::move(loaded).value());
    EXPECT_EQ(simulation.run(0.05), sim::RunStatus::Finished) << simulation.error();
    return nlohmann::json::parse(formatReport(simulation));
}

TEST(ReportLinearSolver, CappedSolvesAreCountedWithTheirWorstResidual) {
    const nlohmann::json r = runSolverReport(
        R"("linear_solver": "block-jacobi", "cg_tolerance": 1e-9, "cg_max_iterations": 2)");
    ASSERT_FALSE(r.empty());
    EXPECT_EQ(r["linear_solver"], "block-jacobi");
    EXPECT_GT(r["linear_solves"].get<long>(), 0);
    EXPECT_EQ(r["linear_solves_capped"].get<long>(), r["linear_solves"].get<long>());
    EXPECT_EQ(r["linear_solves_unconverged"].get<long>(), r["linear_solves"].get<long>());
    EXPECT_GT(r["linear_solve_worst_residual"].get<double>(), 1e-9);
}

TEST(ReportLinearSolver, ConvergedSolvesReportNone) {
    const nlohmann::json r = runSolverReport(
        R"("linear_solver": "block-ic0", "cg_tolerance": 1e-9, "cg_max_iterations": 2000)");
    ASSERT_FALSE(r.empty());
    EXPECT_EQ(r["linear_solver"], "block-ic0");
    EXPECT_EQ(r["linear_solves_capped"].get<long>(), 0);
    EXPECT_EQ(r["linear_solves_unconverged"].get<long>(), 0);
    EXPECT_LE(r["linear_solve_worst_residual"].get<double>(), 1e-9);
}

TEST(ReportLinearSolver, AnUnknownSolverNamesTheKnownOnes) {
    const auto loaded = parseScene(hangingScene(R"("linear_solver": "cholesky")"), "h.json", ".");
    ASSERT_FALSE(loaded.ok());
    const std::string message = loaded.error().toString();
    EXPECT_NE(message.find("/integrator/linear_solver"), std::string::npos) << message;
    EXPECT_NE(message.find("block-ic0"), std::string::npos) << message;
}

} // namespace
} // namespace atelier::io
