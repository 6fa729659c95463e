#pragma once
// What the window's tests share: waiting on the event loop, prompts that never block, opening a
// project and waiting until it is placed.

#include "ui/widgets/main_window.h"

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QSignalSpy>

namespace atelier::ui::test {

/// The bundled sample garments (assets/garments).
inline const QString GARMENTS = QStringLiteral(ATELIER_SOURCE_DIR "/assets/garments");

/// Runs the event loop until `done` or `seconds` have passed; returns done().
template <class Done> bool waitFor(Done done, double seconds) {
    QElapsedTimer clock;
    clock.start();
    while (!done()) {
        if (clock.elapsed() > seconds * 1000) {
            return false;
        }
        QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
    }
    return true;
}

/// Prompts that never block: errors are collected, unsaved changes are discarded, recovery
/// files declined, no file name given.
struct QuietPrompts {
    QStringList errors;

    void install(MainWindow& window) {
        Prompts p;
        p.error = [this](const QString& message) { errors << message; };
        p.saveChanges = [](const QString&) { return QMessageBox::Discard; };
        p.restore = [](const QString&, const QString&) { return false; };
        p.saveFileName = [] { return QString(); };
        window.setPrompts(std::move(p));
    }
};

/// Opens `file` in `window` and waits until it is placed.
inline bool openAndWait(MainWindow& window, const QString& file) {
    QSignalSpy ready(&window, &MainWindow::projectReady);
    if (!window.openProject(file)) {
        return false;
    }
    return waitFor([&] { return ready.count() >= 1; }, 120) &&
           window.drape().staticScene() != nullptr;
}

} // namespace atelier::ui::test
