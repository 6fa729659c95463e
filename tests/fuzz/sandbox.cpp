#include "sandbox.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <thread>

namespace atelier::fuzz {

namespace fs = std::filesystem;

namespace {

/// The child's side: never returns.
[[noreturn]] void child(const FuzzCase& c, const fs::path& dir, const BodyCache& bodies,
                        const RunLimits& runLimits, const SandboxLimits& limits) {
    const std::string log = (dir / "log.txt").string();
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fd >= 0) {
        ::dup2(fd, STDOUT_FILENO);
        ::dup2(fd, STDERR_FILENO);
        ::close(fd);
    }
    if (!ATELIER_FUZZ_ASAN) {
        // ASan reserves terabytes of address space for its shadow: only without it.
        const rlim_t bytes = static_cast<rlim_t>(limits.memoryMb) << 20;
        const rlimit limit{bytes, bytes};
        ::setrlimit(RLIMIT_AS, &limit);
    }
    std::string message;
    const int code = runCase(c.kind, dir / c.mainName(), bodies, runLimits, message);
    std::ofstream(dir / "result.txt", std::ios::binary) << message;
    std::fflush(nullptr);
    ::_exit(code); // not exit(): the parent's atexit handlers and buffers are not the child's
}

/// Resident memory of process `pid` [MiB], or 0.
long residentMb(pid_t pid) {
    std::ifstream statm("/proc/" + std::to_string(pid) + "/statm");
    long pages = 0;
    long resident = 0;
    statm >> pages >> resident;
    return resident * (::sysconf(_SC_PAGESIZE) / 1024) / 1024;
}

std::string tail(const std::string& text, std::size_t bytes) {
    return text.size() <= bytes ? text : "..." + text.substr(text.size() - bytes);
}

} // namespace

bool CaseResult::ok() const {
    return !timedOut && !overMemory && signal == 0 && passed(exitStatus);
}

std::string CaseResult::summary() const {
    if (timedOut) {
        return "hang: killed after " + std::to_string(static_cast<int>(seconds)) + " s";
    }
    if (overMemory) {
        return "memory: killed above its limit";
    }
    if (signal != 0) {
        return "signal " + std::to_string(signal) + " (" + ::strsignal(signal) + ")";
    }
    switch (static_cast<CaseEnd>(exitStatus)) {
    case CaseEnd::Ran:
        return "ran: " + message;
    case CaseEnd::Refused:
        return "refused: " + message;
    case CaseEnd::TooLarge:
        return "too large: " + message;
    case CaseEnd::EmptyError:
        return "refused with an empty message: \"" + message + "\"";
    case CaseEnd::Exception:
    case CaseEnd::Stalled:
        return message;
    }
    return "exit status " + std::to_string(exitStatus) + " (a sanitizer report?)";
}

CaseResult runForked(const FuzzCase& c, const fs::path& dir, const BodyCache& bodies,
                     const RunLimits& runLimits, const SandboxLimits& limits) {
    fs::remove_all(dir);
    writeCase(c, dir);
    if (c.files.count(FIFO_NAME) == 0) {
        ::mkfifo((dir / FIFO_NAME).c_str(), 0600);
    }
    std::fflush(nullptr);
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = ::fork();
    if (pid == 0) {
        child(c, dir, bodies, runLimits, limits);
    }
    CaseResult result;
    int wstatus = 0;
    for (int poll = 0;; ++poll) {
        const pid_t done = ::waitpid(pid, &wstatus, WNOHANG);
        result.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (done == pid || pid < 0) {
            break;
        }
        result.timedOut = result.seconds > limits.seconds;
        result.overMemory = poll % 10 == 0 && residentMb(pid) > limits.memoryMb;
        if (result.timedOut || result.overMemory) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &wstatus, 0);
            break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    if (pid < 0) {
        result.message = std::string("fork failed: ") + std::strerror(errno);
    } else if (!result.timedOut && !result.overMemory) {
        result.exitStatus = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
        result.signal = WIFSIGNALED(wstatus) ? WTERMSIG(wstatus) : 0;
        result.message = readText(dir / "result.txt");
    }
    result.log = tail(readText(dir / "log.txt"), 6000);
    fs::remove_all(dir);
    return result;
}

} // namespace atelier::fuzz
