#pragma once
/// `--limit NAME=VALUE` on every command that reads files, and `atelier-cli limits`, which
/// lists them: the bounds of io::Limits that a user can read and raise or lower.

#include "io/limits.h"

#include "sim/core/result.h"
#include "sim/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace atelier::app {

/// Adds the repeatable `--limit NAME=VALUE` option to `cmd`, collected into `raw`.
void addLimitOption(CLI::App* cmd, std::vector<std::string>* raw);

/// io::Limits with the user's `--limit` values; an unknown name, a malformed pair or a value
/// that is not a positive number is an error naming it and the names there are.
Result<io::Limits> limitsFrom(const std::vector<std::string>& raw);

/// limitsFrom(), or nullopt after printing the error (`error: --limit: ...`) on stderr.
std::optional<io::Limits> limitsOrReport(const std::vector<std::string>& raw);

/// An input error as printed: "error: " + the error, and, when it is a limit that refused the
/// input, how to see and change the limits.
std::string inputErrorText(const Error& error);

/// Loads a scene held to the user's `--limit` values; nullopt after printing the error.
std::optional<sim::SceneSpec> loadSceneOrReport(const std::string& path,
                                                const std::vector<std::string>& rawLimits);

/// `atelier-cli limits`: each limit's name, default and what it bounds.
void addLimitsCommand(CLI::App& app);

} // namespace atelier::app
