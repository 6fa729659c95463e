#include "app/cli/run_loop.h"

#include "app/cli/commands.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace atelier::app {

std::string_view runEndName(RunEnd end) {
    switch (end) {
    case RunEnd::Done:
        return "done";
    case RunEnd::Cancelled:
        return "cancelled";
    case RunEnd::Failed:
        return "failed";
    }
    return "?";
}

RunLoop::RunLoop(std::string command, double endTime, std::string framesDir)
    : m_command(std::move(command)), m_endTime(endTime), m_framesDir(std::move(framesDir)),
      m_tty(::isatty(STDERR_FILENO) != 0) {}

RunLoop::~RunLoop() {
    if (m_lineOpen) {
        std::cerr << "\n";
    }
}

bool RunLoop::prepare() {
    if (m_framesDir.empty()) {
        return true;
    }
    std::error_code ec;
    std::filesystem::create_directories(m_framesDir, ec);
    if (ec) {
        std::cerr << "error: " << m_framesDir << ": " << ec.message() << "\n";
        return false;
    }
    return true;
}

RunEnd RunLoop::run(const std::function<StepState()>& step) {
    RunEnd end = RunEnd::Done;
    for (;;) {
        if (InterruptGuard::interrupted()) {
            end = RunEnd::Cancelled;
            break;
        }
        const StepState state = step();
        if (state == StepState::Done) {
            break;
        }
        if (state == StepState::Failed) {
            end = RunEnd::Failed;
            break;
        }
    }
    if (m_lineOpen) {
        std::cerr << "\n";
        m_lineOpen = false;
    }
    return end;
}

void RunLoop::progress(double time, const std::string& figures) {
    const int mark = m_endTime > 0 ? static_cast<int>(10 * time / m_endTime) : 10;
    if (!m_tty && mark == m_lastMark) {
        return;
    }
    m_lastMark = mark;
    std::cerr << (m_tty ? "\r\033[K" : "") << m_command << ": t = ";
    char t[32];
    std::snprintf(t, sizeof t, "%.3f s", time);
    std::cerr << t << "  " << figures << (m_tty ? "" : "\n") << std::flush;
    m_lineOpen = m_tty;
}

void RunLoop::frame(long index, double time, const std::string& figures,
                    const std::function<Result<void>(const std::filesystem::path& stem)>& write) {
    progress(time, figures);
    if (m_framesDir.empty() || !m_frameError.empty() || !write) {
        return;
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05ld", index);
    const auto written = write(std::filesystem::path(m_framesDir) / name);
    if (written.ok()) {
        ++m_framesWritten;
    } else {
        m_frameError = written.error().toString();
    }
}

int RunLoop::exitCode(RunEnd end) const {
    int code = end == RunEnd::Cancelled ? EXIT_CANCELLED
               : end == RunEnd::Failed  ? EXIT_RUN_FAILED
                                        : EXIT_OK;
    if (!m_frameError.empty()) {
        std::cerr << "error: " << m_frameError << "\n";
        code = code == EXIT_OK ? EXIT_RUN_FAILED : code;
    }
    return code;
}

int RunLoop::writeFailed(const Error& error, int code) {
    std::cerr << "error: " << error.toString() << "\n";
    return code == EXIT_OK ? EXIT_RUN_FAILED : code;
}

} // namespace atelier::app
