#pragma once
/// `atelier-cli bench cusick`: the Cusick drape test of a fabric (patterns/cusick.h) from a few
/// perturbed starts, since a real fabric's drape coefficient varies by several points from one
/// test to the next: each start's coefficient and nodes, their mean and spread, and a picture
/// of the first start seen from above. Plain C++ (no CLI11): the parsing is in
/// bench_command.cpp.

#include "patterns/cusick.h"

#include <string>

namespace atelier::app {

struct CusickBenchOptions {
    std::string fabric = "cotton"; ///< a built-in fabric preset
    int starts = 3;                ///< perturbed starts (seeds 1 … starts)
    std::string out;               ///< folder for cusick.csv, cusick.json and cusick.svg
    patterns::CusickOptions test;
};

/// Runs the starts, prints a table, writes the files atomically. Returns an exit code
/// (app/cli/commands.h).
int runCusickBench(const CusickBenchOptions& options);

} // namespace atelier::app
