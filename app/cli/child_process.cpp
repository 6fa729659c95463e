#include "app/cli/child_process.h"

#include "app/cli/interrupt.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <thread>

extern char** environ; // NOLINT: POSIX

namespace atelier::app {

std::string ChildResult::describe(double timeLimit) const {
    if (!started) {
        return "could not start: " + error;
    }
    if (timedOut) {
        return "timed out after " + std::to_string(static_cast<long>(timeLimit)) + " s";
    }
    if (interrupted) {
        return "interrupted";
    }
    if (signal != 0) {
        const char* name = sigabbrev_np(signal);
        return "killed by signal " + std::to_string(signal) +
               (name != nullptr ? " (SIG" + std::string(name) + ")" : "");
    }
    return "exit " + std::to_string(exitCode);
}

std::filesystem::path selfExecutable() {
    std::error_code ec;
    auto path = std::filesystem::read_symlink("/proc/self/exe", ec);
    return ec ? std::filesystem::path("atelier-cli") : path;
}

ChildResult runChild(const std::vector<std::string>& arguments, const std::filesystem::path& log,
                     double timeLimit) {
    using Clock = std::chrono::steady_clock;
    ChildResult result;
    std::vector<char*> argv;
    argv.reserve(arguments.size() + 1);
    for (const std::string& a : arguments) {
        argv.push_back(const_cast<char*>(a.c_str())); // NOLINT: posix_spawn's signature
    }
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    // The child starts with default signal handling, whatever this process has installed.
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    sigset_t defaults;
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGINT);
    sigaddset(&defaults, SIGTERM);
    posix_spawnattr_setsigdefault(&attributes, &defaults);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);

    const auto start = Clock::now();
    pid_t pid = 0;
    const int spawned = posix_spawn(&pid, argv[0], &actions, &attributes, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attributes);
    if (spawned != 0) {
        result.error = std::string(argv[0]) + ": " + std::strerror(spawned);
        return result;
    }
    result.started = true;

    bool termSent = false;
    Clock::time_point termAt;
    int status = 0;
    for (;;) {
        const pid_t done = waitpid(pid, &status, WNOHANG);
        if (done == pid) {
            break;
        }
        if (done < 0 && errno != EINTR) {
            result.error = std::strerror(errno);
            break;
        }
        const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
        if (!termSent) {
            if (InterruptGuard::interrupted()) {
                result.interrupted = true;
            } else if (timeLimit > 0 && elapsed > timeLimit) {
                result.timedOut = true;
            }
            if (result.interrupted || result.timedOut) {
                kill(pid, SIGTERM);
                termSent = true;
                termAt = Clock::now();
            }
        } else if (Clock::now() - termAt > std::chrono::seconds(10)) {
            kill(pid, SIGKILL);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    result.wallSeconds = std::chrono::duration<double>(Clock::now() - start).count();
    if (WIFEXITED(status)) {
        result.exitCode = WEXITSTATUS(status);
    } else if (WIFSIGNALED(status)) {
        result.signal = WTERMSIG(status);
    }
    return result;
}

} // namespace atelier::app
