/// atelier: the desktop application (ui/widgets over the drape session and the renderer).
///
///   atelier [PROJECT.atelier | SPEC.json | PATTERN.dxf] [--recovery-dir DIR]
///           [--autosave-seconds N]
///   atelier PROJECT.atelier --screenshot OUT.png [--drape-seconds S]   (tests, documentation)

#include "ui/widgets/main_window.h"
#include "ui/widgets/viewport.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QMessageBox>
#include <QSaveFile>
#include <QTimer>

#include <cstdio>

namespace {

/// The sample garments: beside the program when installed, else in the source tree.
QString samplesDir() {
    const QString app = QCoreApplication::applicationDirPath();
    for (const QString& candidate :
         {app + "/../share/atelier/garments", QString(ATELIER_SOURCE_DIR "/assets/garments")}) {
        if (QFileInfo(candidate).isDir()) {
            return QDir(candidate).canonicalPath();
        }
    }
    return {};
}

} // namespace

int main(int argc, char** argv) {
    QApplication app(argc, argv);
    QApplication::setApplicationName("atelier");
    QApplication::setOrganizationName("Atelier");
    QApplication::setApplicationVersion("0.1.0");

    QCommandLineParser parser;
    parser.setApplicationDescription("Atelier: design, sew and drape garments");
    parser.addHelpOption();
    parser.addVersionOption();
    parser.addPositionalArgument(
        "file", "A garment project (.atelier), a GarmentCode specification (.json) or a DXF-AAMA "
                "pattern (.dxf) to open");
    const QCommandLineOption screenshot(
        "screenshot",
        "Open the project, drape it for --drape-seconds, save the window as PNG "
        "and quit",
        "png");
    const QCommandLineOption seconds("drape-seconds", "Simulated seconds before --screenshot", "s",
                                     "0");
    const QCommandLineOption recoveryDir(
        "recovery-dir",
        "Where autosaved recovery files go (default: the application's data folder)", "dir");
    const QCommandLineOption autosaveSeconds(
        "autosave-seconds", "Autosave period while modified (default: the setting, 60)", "s");
    parser.addOption(screenshot);
    parser.addOption(seconds);
    parser.addOption(recoveryDir);
    parser.addOption(autosaveSeconds);
    parser.process(app);

    atelier::ui::MainWindow window(samplesDir());
    if (parser.isSet(recoveryDir)) {
        window.setRecoveryDirectory(parser.value(recoveryDir));
    }
    if (parser.isSet(autosaveSeconds)) {
        bool ok = false;
        const int period = parser.value(autosaveSeconds).toInt(&ok);
        if (!ok || period < 0) {
            std::fputs("error: --autosave-seconds must be a whole number >= 0\n", stderr);
            return 2;
        }
        window.setAutosaveSeconds(period);
    }
    window.show();
    const QStringList projects = parser.positionalArguments();
    if (!parser.isSet(screenshot)) {
        // Unsaved changes from a run that did not close cleanly come first; on the very first
        // start, the tshirt sample.
        if (!window.offerRecovery()) {
            if (!projects.isEmpty()) {
                window.openFile(projects.front());
            } else {
                window.openFirstRunSample();
            }
        }
        return QApplication::exec();
    }
    // Screenshot mode: no dialogs; errors go to stderr.
    atelier::ui::Prompts quiet;
    quiet.error = [](const QString& message) {
        std::fprintf(stderr, "error: %s\n", qPrintable(message));
    };
    quiet.saveChanges = [](const QString&) { return QMessageBox::Discard; };
    window.setPrompts(quiet);
    if (!projects.isEmpty() && !window.openProject(projects.front())) {
        return 1;
    }

    // Screenshot mode: drape to the time asked for, then grab the window and quit.
    if (projects.isEmpty()) {
        std::fputs("error: --screenshot needs a project\n", stderr);
        return 2;
    }
    bool ok = false;
    const double until = parser.value(seconds).toDouble(&ok);
    if (!ok || until < 0) {
        std::fputs("error: --drape-seconds must be a number >= 0\n", stderr);
        return 2;
    }
    const QString out = parser.value(screenshot);
    int code = 1;
    QObject::connect(&window.drape(), &atelier::ui::DrapeController::failed,
                     [&](const QString& message) {
                         std::fprintf(stderr, "error: %s\n", qPrintable(message));
                         code = 1;
                         QApplication::exit(1);
                     });
    QObject::connect(&window, &atelier::ui::MainWindow::projectReady, [&] {
        window.drape().start();
        auto* timer = new QTimer(&window);
        QObject::connect(timer, &QTimer::timeout, [&, timer] {
            const atelier::ui::DrapeProgress p = window.drape().progress();
            if (p.time < until && (p.running || p.steps == 0) && until > 0) {
                return;
            }
            timer->stop();
            window.drape().pause();
            // Two more frames so that the last snapshot is drawn, then the picture.
            QTimer::singleShot(300, [&] {
                // The cost of a frame at full quality with the drape paused: ten redraws.
                QElapsedTimer clock;
                clock.start();
                for (int k = 0; k < 10; ++k) {
                    window.viewport().repaint();
                }
                const double pausedMs = double(clock.nsecsElapsed()) * 1e-6 / 10;
                QSaveFile file(out);
                const QImage picture = window.grab().toImage();
                if (file.open(QIODevice::WriteOnly) && picture.save(&file, "PNG") &&
                    file.commit()) {
                    std::printf("atelier: t = %.2f s, %ld steps; 3D view: %.0f frames/s while "
                                "draping, %.1f ms per frame paused (full quality); wrote %s\n",
                                window.drape().progress().time, window.drape().progress().steps,
                                window.viewport().framesPerSecond(), pausedMs, qPrintable(out));
                    code = window.viewport().rendererError().isEmpty() ? 0 : 1;
                } else {
                    std::fprintf(stderr, "error: %s: %s\n", qPrintable(out),
                                 qPrintable(file.errorString()));
                }
                QApplication::exit(code);
            });
        });
        timer->start(50);
    });
    const int exitCode = QApplication::exec();
    return exitCode != 0 ? exitCode : code;
}
