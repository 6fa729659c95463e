#include "app/cli/interrupt.h"

#include <atomic>
#include <csignal>

namespace atelier::app {

namespace {

std::atomic<int> g_signal{0};
int g_depth = 0; // guards alive; only the main thread makes them

extern "C" void onInterrupt(int sig) {
    g_signal.store(sig);
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
}

} // namespace

InterruptGuard::InterruptGuard() {
    if (g_depth++ == 0) {
        g_signal.store(0);
    }
    if (g_signal.load() == 0) {
        m_previousInt = std::signal(SIGINT, onInterrupt);
        m_previousTerm = std::signal(SIGTERM, onInterrupt);
        m_installed = true;
    }
    // else: a signal already came under an outer guard; the handlers are the default ones
    // again, so that a second signal ends the program at once.
}

InterruptGuard::~InterruptGuard() {
    --g_depth;
    if (m_installed) {
        std::signal(SIGINT, g_signal.load() != 0 && g_depth > 0 ? SIG_DFL : m_previousInt);
        std::signal(SIGTERM, g_signal.load() != 0 && g_depth > 0 ? SIG_DFL : m_previousTerm);
    }
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
