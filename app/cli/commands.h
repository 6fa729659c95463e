#pragma once
/// Subcommands of atelier-cli. Each registers itself on the application with a callback that
/// does the work; a callback reports a non-zero exit status by throwing
/// `CLI::RuntimeError(code)` (main returns the code without printing anything more).
///
/// Exit codes shared by all commands: 0 success, 1 the command ran but failed (e.g. the
/// simulation blew up), 2 bad input (unreadable or invalid file, bad arguments),
/// 130 cancelled (Ctrl-C).

namespace CLI {
class App;
}

namespace atelier::app {

inline constexpr int EXIT_OK = 0;
inline constexpr int EXIT_RUN_FAILED = 1;
inline constexpr int EXIT_BAD_INPUT = 2;
inline constexpr int EXIT_CANCELLED = 130;

/// `atelier-cli simulate SCENE.json --out OUT.obj --report REPORT.json [--threads N]
/// [--frames-dir DIR]` (app/cli/simulate_command.cpp).
void addSimulateCommand(CLI::App& app);

// ---- Further subcommands register here (one function per file in app/cli/) ----
/// `atelier-cli bench work-precision SCENE.json --out WP.csv [--plot WP.svg]` and
/// `atelier-cli bench material --model M --mesh T --out M.json` (app/cli/bench_command.cpp).
void addBenchCommand(CLI::App& app);

/// `atelier-cli drape PROJECT.atelier --out OUT.obj --report REPORT.json [--thumbnail T.png]`
/// (drape_command.cpp).
void addDrapeCommand(CLI::App& app);

/// `atelier-cli render INPUT --out PICTURE.png [--size WxH] [--view V|all] [--overlay
/// wireframe|strain|seams|contact] [--background COLOUR]` and `atelier-cli render --frames-dir
/// DIR --out OUTDIR` (render_command.cpp).
void addRenderCommand(CLI::App& app);

/// `atelier-cli render-batch LIST|FOLDER --out DIR [--views V,...] [--size WxH]
/// [--sheet-columns N]` (render_batch_command.cpp).
void addRenderBatchCommand(CLI::App& app);

/// `atelier-cli body [--measurements M.json | --base B] --out BODY.obj` (body_command.cpp).
void addBodyCommand(CLI::App& app);

/// `atelier-cli batch MANIFEST.json --out DIR [--shard I/N]` (batch_command.cpp).
void addBatchCommand(CLI::App& app);

/// `atelier-cli batch-summary DIR [--manifest M]` (batch_summary.cpp).
void addBatchSummaryCommand(CLI::App& app);

/// `atelier-cli export-pattern PROJECT.atelier --out PATTERN.svg [--seam-allowance MM]`
/// (export_pattern_command.cpp).
void addExportPatternCommand(CLI::App& app);

/// `atelier-cli animate PROJECT.atelier --body-frames FRAMES... --out SEQUENCE.glb`
/// (animate_command.cpp).
void addAnimateCommand(CLI::App& app);

/// `atelier-cli import garmentcode SPEC.json --out PROJECT.atelier [--fabric NAME]`
/// (import_command.cpp).
void addImportCommand(CLI::App& app);
/// `atelier-cli fabric fit --density G_M2 --bending-length-weft MM ... --out PRESET.json`
/// (fabric_command.cpp).
void addFabricCommand(CLI::App& app);

} // namespace atelier::app
