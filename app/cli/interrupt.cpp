#include "app/cli/interrupt.h"

#include <atomic>
#include <csignal>
#include <ctime>

namespace atelier::app {

namespace {

std::atomic<int> g_signal{0};
std::atomic<long long> g_firstSignalNs{0}; // CLOCK_MONOTONIC time of the first signal
int g_depth = 0;                           // guards alive; only the main thread makes them

/// A signal this soon after the first is the same request sent twice: `timeout` sends its
/// signal to the command and then to the command's process group, so the command gets it
/// twice within microseconds; a person pressing Ctrl-C again is much slower.
constexpr long long SAME_REQUEST_NS = 300'000'000;

long long monotonicNs() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t); // async-signal-safe
    return static_cast<long long>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

extern "C" void onInterrupt(int sig) {
    const long long now = monotonicNs();
    int none = 0;
    if (g_signal.compare_exchange_strong(none, sig)) {
        g_firstSignalNs.store(now);
        return;
    }
    if (now - g_firstSignalNs.load() >= SAME_REQUEST_NS) {
        // A second request: the default action, at once.
        std::signal(sig, SIG_DFL);
        std::raise(sig);
    }
}

} // namespace

InterruptGuard::InterruptGuard() {
    if (g_depth++ == 0) {
        g_signal.store(0);
    }
    m_previousInt = std::signal(SIGINT, onInterrupt);
    m_previousTerm = std::signal(SIGTERM, onInterrupt);
}

InterruptGuard::~InterruptGuard() {
    --g_depth;
    std::signal(SIGINT, m_previousInt);
    std::signal(SIGTERM, m_previousTerm);
}

bool InterruptGuard::interrupted() {
    return g_signal.load() != 0;
}

int InterruptGuard::signal() {
    return g_signal.load();
}

const char* InterruptGuard::signalName() {
    switch (g_signal.load()) {
    case SIGINT:
        return "SIGINT";
    case SIGTERM:
        return "SIGTERM";
    default:
        return "";
    }
}

} // namespace atelier::app
