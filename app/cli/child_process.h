#pragma once
/// Running atelier-cli again as a child process (a batch job's drape and pictures): a crash,
/// a hang or a blow-up in one job cannot take the others with it, and the job's output goes to
/// its own log file.

#include <filesystem>
#include <string>
#include <vector>

namespace atelier::app {

struct ChildResult {
    bool started = false;     ///< false: the process could not be started (`error` says why)
    int exitCode = -1;        ///< its exit status when it exited
    int signal = 0;           ///< the signal that ended it, or 0
    bool timedOut = false;    ///< ended by us after the time limit
    bool interrupted = false; ///< ended by us because this program got SIGINT or SIGTERM
    double wallSeconds = 0;
    std::string error;

    bool succeeded() const { return started && signal == 0 && exitCode == 0; }
    /// "exit 2", "killed by signal 11 (SIGSEGV)", "timed out after 600 s", ...
    std::string describe(double timeLimit) const;
};

/// This program's own executable (`/proc/self/exe`), to run its subcommands as children.
std::filesystem::path selfExecutable();

/// Runs `arguments` (argv[0] first, a path: no PATH search) with stdin from /dev/null and
/// stdout and stderr appended to `log`. Waits until it ends; after `timeLimit` seconds (> 0)
/// it is sent SIGTERM, and SIGKILL 10 s later. An InterruptGuard's signal (checked every 20 ms)
/// is passed on to it the same way.
ChildResult runChild(const std::vector<std::string>& arguments, const std::filesystem::path& log,
                     double timeLimit);

} // namespace atelier::app
