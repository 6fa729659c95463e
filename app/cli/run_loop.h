#pragma once
/// The run loop shared by `atelier-cli drape` and `atelier-cli simulate`: steps until the run
/// ends, fails or is interrupted (SIGINT or SIGTERM, between steps: what was computed is still
/// written), a progress line, output frames as DIR/frame_NNNNN.obj, and the exit codes of
/// commands.h.

#include "app/cli/interrupt.h"

#include "sim/core/result.h"

#include <filesystem>
#include <functional>
#include <string>

namespace atelier::app {

/// What one call of a run's step function says.
enum class StepState { Continue, Done, Failed };
/// How a run ended.
enum class RunEnd { Done, Cancelled, Failed };
std::string_view runEndName(RunEnd end); ///< "done", "cancelled", "failed"

class RunLoop {
  public:
    /// `command` starts the progress line; `endTime` is the simulated time the run goes to at
    /// most [s] (for the progress marks when stderr is not a terminal); `framesDir` may be
    /// empty (no frames written). SIGINT and SIGTERM are caught from here on (a signal while
    /// the run is being prepared stops it before its first step) until the loop is destroyed.
    RunLoop(std::string command, double endTime, std::string framesDir);
    ~RunLoop();
    RunLoop(const RunLoop&) = delete;
    RunLoop& operator=(const RunLoop&) = delete;

    void setEndTime(double endTime) { m_endTime = endTime; }
    /// Creates the frames folder if there is one; prints the error and returns false if it
    /// cannot.
    bool prepare();
    /// Calls step() until it returns Done or Failed, or a signal has come (checked before
    /// every step).
    RunEnd run(const std::function<StepState()>& step);

    /// At an output frame: the progress line (`figures` after the time), and, with a frames
    /// folder, write(DIR/frame_NNNNN) to write the frame's files (the writer adds ".obj" and
    /// whatever else it writes). The first write error stops further frames and is reported
    /// at the end.
    void frame(long index, double time, const std::string& figures,
               const std::function<Result<void>(const std::filesystem::path& stem)>& write);
    const std::string& framesDir() const { return m_framesDir; }
    int framesWritten() const { return m_framesWritten; }

    /// The exit code for the way the run ended, counting a frame write error as a failure.
    int exitCode(RunEnd end) const;
    /// Prints a write error and turns a successful exit code into a failed one.
    static int writeFailed(const Error& error, int code);

  private:
    void progress(double time, const std::string& figures);

    InterruptGuard m_interrupts;
    std::string m_command;
    double m_endTime;
    std::string m_framesDir;
    bool m_tty;
    int m_lastMark = -1;
    bool m_lineOpen = false;
    int m_framesWritten = 0;
    std::string m_frameError;
};

} // namespace atelier::app
