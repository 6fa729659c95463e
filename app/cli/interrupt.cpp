#include "app/cli/interrupt.h"

#include <atomic>
#include <csignal>

namespace atelier::app {

namespace {

std::atomic<int> g_signal{0};

extern "C" void onInterrupt(int sig) {
    g_signal.store(sig);
    std::signal(SIGINT, SIG_DFL);
    std::signal(SIGTERM, SIG_DFL);
}

} // namespace

InterruptGuard::InterruptGuard() {
    g_signal.store(0);
    m_previousInt = std::signal(SIGINT, onInterrupt);
    m_previousTerm = std::signal(SIGTERM, onInterrupt);
}

InterruptGuard::~InterruptGuard() {
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
