#pragma once
/// Ctrl-C (SIGINT) and SIGTERM while a command runs: the first signal asks the command to stop
/// after its current step, write what it has (marked interrupted) and exit 130; a second one,
/// 0.3 s or more after the first, ends the program at once (the default action), for a
/// preparation or a write that takes too long. The same signal again within 0.3 s is the same
/// request (`timeout` sends its signal to the command and then to its process group).

namespace atelier::app {

/// Catches SIGINT and SIGTERM from construction to destruction (then the previous handlers
/// are back). Guards nest: main() holds the outermost one, so that a signal while the program
/// starts or parses its arguments is kept for the command, which stops before its first step.
/// Only the outermost guard clears an earlier interruption. Main thread only.
class InterruptGuard {
  public:
    InterruptGuard();
    ~InterruptGuard();
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

    /// Whether a signal has come since the guard was made.
    static bool interrupted();
    /// The signal that came (SIGINT or SIGTERM), or 0.
    static int signal();
    /// "SIGINT", "SIGTERM" or "" for the report and the messages.
    static const char* signalName();

  private:
    void (*m_previousInt)(int) = nullptr;
    void (*m_previousTerm)(int) = nullptr;
};

} // namespace atelier::app
