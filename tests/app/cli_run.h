#pragma once
/// Running the built atelier-cli (ATELIER_CLI) from the CLI tests: a tiny scene and a runner.

#include "io/temp_dir.h"

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace atelier::test {

inline const char* const TINY_SCENE = R"({
  "format": "atelier-scene",
  "version": 1,
  "cloths": [{
    "name": "tiny",
    "mesh": {"type": "rectangle", "width": 0.2, "height": 0.2, "cells": [3, 3]},
    "placement": {"origin": [0, 1, 0], "u_axis": [1, 0, 0], "v_axis": [0, 0, -1]},
    "material": "cotton"
  }],
  "pins": [{"cloth": "tiny", "edge": "top"}],
  "integrator": {"type": "implicit-euler", "dt": 0.01, "max_dt": 0.01},
  "duration": 0.05,
  "frame_rate": 100
})";

/// `p` in double quotes, for a shell command line (the test folders hold no quotes).
inline std::string inQuotes(const std::filesystem::path& p) {
    std::string text = p.string();
    text.insert(text.begin(), '"');
    text.push_back('"');
    return text;
}

struct CliRun {
    int exitCode = -1;
    std::string stderrText;
};

/// Runs `prefix "ATELIER_CLI" args` in the shell, stderr to a file.
inline CliRun runCli(const TempDir& dir, const std::string& args, const std::string& prefix = "") {
    const auto errPath = dir / "stderr.txt";
    const std::string command =
        prefix + "\"" + ATELIER_CLI + "\" " + args + " 2> \"" + errPath.string() + "\"";
    const int status = std::system(command.c_str());
    CliRun run;
    run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.stderrText = readText(errPath);
    return run;
}

} // namespace atelier::test
