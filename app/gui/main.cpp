/// atelier: the desktop application (ui/widgets over the drape session and the renderer).
///
///   atelier [PROJECT.atelier | SPEC.json | PATTERN.dxf] [--recovery-dir DIR]
///           [--autosave-seconds N]
///   atelier PROJECT.atelier --screenshot OUT.png [--drape-seconds S]   (tests, documentation)
///   atelier PROJECT.atelier --measure-ui OUT.json [--drape-seconds S]  (responsiveness)

#include "ui/widgets/main_window.h"
#include "ui/widgets/viewport.h"

#include "sim/core/parallel.h"

#include <QApplication>
#include <QCommandLineParser>
#include <QDir>
#include <QElapsedTimer>
#include <QFileInfo>
#include <QJsonDocument>
#include <QJsonObject>
#include <QMessageBox>
#include <QSaveFile>
#include <QTimer>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <thread>
#include <vector>

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

using atelier::ui::MainWindow;

/// Screenshot mode: drapes to `until` simulated seconds (or rest), then saves the window as PNG
/// and quits with `code` (0 when written).
void takeScreenshot(MainWindow& window, double until, const QString& out, int& code) {
    QObject::connect(&window, &MainWindow::projectReady, [&window, until, out, &code] {
        window.drape().start();
        auto* timer = new QTimer(&window);
        QObject::connect(timer, &QTimer::timeout, [&window, until, out, &code, timer] {
            const atelier::ui::DrapeProgress p = window.drape().progress();
            if (p.time < until && (p.running || p.steps == 0) && until > 0) {
                return;
            }
            timer->stop();
            window.drape().pause();
            // Two more frames so that the last snapshot is drawn, then the picture.
            QTimer::singleShot(300, [&window, out, &code] {
                // The cost of a frame at full quality with the drape paused: ten redraws.
                QElapsedTimer clock;
                clock.start();
                for (int k = 0; k < 10; ++k) {
                    window.viewport().drawNow();
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
}

/// What the responsiveness measure records while the drape runs.
struct UiMeasure {
    static constexpr int TICK_MS = 5;
    QElapsedTimer clock;
    qint64 lastTick = -1;     ///< [ns] on `clock`; -1 before the first tick
    double firstTick = 0;     ///< from the drape's start to the first tick [ms]
    std::vector<double> gaps; ///< between ticks of a 5 ms precise timer [ms]
    double longestGap = 0;    ///< [ms]
    double longestGapAt = 0;  ///< when it ended, from the drape's start [s]
    long firstFrame = 0;
};

/// Writes the figures of a finished measure as JSON (atomically) and prints them.
bool writeUiMeasure(MainWindow& window, UiMeasure& m, const QString& out) {
    const double wall = double(m.clock.nsecsElapsed()) * 1e-9;
    std::sort(m.gaps.begin(), m.gaps.end());
    const auto quantile = [&](double q) {
        return m.gaps.empty()
                   ? 0.0
                   : m.gaps[std::min(m.gaps.size() - 1, std::size_t(q * double(m.gaps.size())))];
    };
    const double longest = m.gaps.empty() ? 0.0 : m.gaps.back();
    const atelier::ui::DrapeProgress p = window.drape().progress();
    const long frames = window.viewport().framesDrawn() - m.firstFrame;
    QJsonObject o;
    o["wall_s"] = wall;
    o["simulated_s"] = p.time;
    o["steps"] = static_cast<qint64>(p.steps);
    o["simulated_per_wall"] = wall > 0 ? p.time / wall : 0.0;
    o["frames"] = static_cast<qint64>(frames);
    o["frames_per_second"] = wall > 0 ? double(frames) / wall : 0.0;
    o["draw_ms_mean"] = window.viewport().drawMilliseconds();
    o["event_loop_tick_ms"] = UiMeasure::TICK_MS;
    o["event_loop_longest_block_ms"] = std::max(0.0, longest - UiMeasure::TICK_MS);
    o["event_loop_longest_block_at_s"] = m.longestGapAt;
    o["event_loop_first_tick_ms"] = m.firstTick;
    o["event_loop_gap_p99_ms"] = quantile(0.99);
    o["event_loop_gap_median_ms"] = quantile(0.5);
    o["viewport_width"] = window.viewport().width();
    o["viewport_height"] = window.viewport().height();
    std::printf("atelier: %.2f s simulated in %.1f s wall (%.2f); 3D view %.1f frames/s "
                "(%ld frames, %.1f ms per draw); event loop blocked at most %.1f ms "
                "(99th percentile gap %.1f ms)\n",
                p.time, wall, wall > 0 ? p.time / wall : 0.0,
                wall > 0 ? double(frames) / wall : 0.0, frames,
                window.viewport().drawMilliseconds(), std::max(0.0, longest - UiMeasure::TICK_MS),
                quantile(0.99));
    QSaveFile file(out);
    if (!file.open(QIODevice::WriteOnly) || file.write(QJsonDocument(o).toJson()) < 0 ||
        !file.commit()) {
        std::fprintf(stderr, "error: %s: %s\n", qPrintable(out), qPrintable(file.errorString()));
        return false;
    }
    return true;
}

/// Measure mode (issue 23's responsiveness benchmark): drapes to `until` simulated seconds (or
/// rest) as the window does, measuring the longest time the event loop did not run (the
/// lateness of a 5 ms precise timer) and the 3D view's frames per second; writes JSON to `out`.
void measureResponsiveness(MainWindow& window, double until, const QString& out, int& code) {
    auto m = std::make_shared<UiMeasure>();
    QObject::connect(&window, &MainWindow::projectReady, [&window, until, out, &code, m] {
        window.drape().start();
        m->clock.start();
        m->firstFrame = window.viewport().framesDrawn();
        auto* tick = new QTimer(&window);
        tick->setTimerType(Qt::PreciseTimer);
        QObject::connect(tick, &QTimer::timeout, [m] {
            const qint64 now = m->clock.nsecsElapsed();
            if (m->lastTick < 0) {
                // The rest of the project's opening (the pattern view, the docks) runs first.
                m->firstTick = double(now) * 1e-6;
                m->lastTick = now;
                return;
            }
            const double gap = double(now - m->lastTick) * 1e-6;
            m->gaps.push_back(gap);
            if (gap > m->longestGap) {
                m->longestGap = gap;
                m->longestGapAt = double(now) * 1e-9;
            }
            m->lastTick = now;
        });
        tick->start(UiMeasure::TICK_MS);
        auto* watch = new QTimer(&window);
        QObject::connect(watch, &QTimer::timeout, [&window, until, out, &code, m, tick, watch] {
            const atelier::ui::DrapeProgress p = window.drape().progress();
            if (p.time < until && (p.running || p.steps == 0) && until > 0) {
                return;
            }
            watch->stop();
            tick->stop();
            window.drape().pause();
            code = writeUiMeasure(window, *m, out) && window.viewport().rendererError().isEmpty()
                       ? 0
                       : 1;
            QApplication::exit(code);
        });
        watch->start(50);
    });
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
    const QCommandLineOption seconds(
        "drape-seconds", "Simulated seconds before --screenshot or --measure-ui", "s", "0");
    const QCommandLineOption recoveryDir(
        "recovery-dir",
        "Where autosaved recovery files go (default: the application's data folder)", "dir");
    const QCommandLineOption autosaveSeconds(
        "autosave-seconds", "Autosave period while modified (default: the setting, 60)", "s");
    const QCommandLineOption measure(
        "measure-ui",
        "Open the project, drape it for --drape-seconds (or to rest) as the window does, write "
        "the 3D view's frames per second and the event loop's longest block as JSON and quit",
        "json");
    const QCommandLineOption threads(
        QStringList{"j", "threads"},
        "Engine threads (default: all cores but one, which the window and its 3D view keep)", "n");
    parser.addOption(screenshot);
    parser.addOption(measure);
    parser.addOption(threads);
    parser.addOption(seconds);
    parser.addOption(recoveryDir);
    parser.addOption(autosaveSeconds);
    parser.process(app);

    if (parser.isSet(threads)) {
        bool ok = false;
        const int n = parser.value(threads).toInt(&ok);
        if (!ok || n < 1) {
            std::fputs("error: --threads must be a whole number >= 1\n", stderr);
            return 2;
        }
        atelier::sim::setThreadCount(n);
    } else {
        // The 3D view draws on its own thread: an engine on every core makes the two fight
        // (the 20 mm skirt on 2 cores: 22-25 frames per second with two engine threads, 28
        // with one; docs/benchmarks.md, "Responsiveness while draping").
        atelier::sim::setThreadCount(
            std::max(1, static_cast<int>(std::thread::hardware_concurrency()) - 1));
    }
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
    if (!parser.isSet(screenshot) && !parser.isSet(measure)) {
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
    // Screenshot and measure modes: no dialogs; errors go to stderr.
    atelier::ui::Prompts quiet;
    quiet.error = [](const QString& message) {
        std::fprintf(stderr, "error: %s\n", qPrintable(message));
    };
    quiet.saveChanges = [](const QString&) { return QMessageBox::Discard; };
    window.setPrompts(quiet);
    if (projects.isEmpty()) {
        std::fprintf(stderr, "error: --%s needs a project\n",
                     parser.isSet(screenshot) ? "screenshot" : "measure-ui");
        return 2;
    }
    bool ok = false;
    const double until = parser.value(seconds).toDouble(&ok);
    if (!ok || until < 0) {
        std::fputs("error: --drape-seconds must be a number >= 0\n", stderr);
        return 2;
    }
    if (!window.openProject(projects.front())) {
        return 1;
    }
    int code = 1;
    QObject::connect(&window.drape(), &atelier::ui::DrapeController::failed,
                     [&](const QString& message) {
                         std::fprintf(stderr, "error: %s\n", qPrintable(message));
                         code = 1;
                         QApplication::exit(1);
                     });
    if (parser.isSet(measure)) {
        measureResponsiveness(window, until, parser.value(measure), code);
    } else {
        takeScreenshot(window, until, parser.value(screenshot), code);
    }
    const int exitCode = QApplication::exec();
    return exitCode != 0 ? exitCode : code;
}
