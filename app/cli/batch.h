#pragma once
/// What `atelier-cli batch` (batch_command.cpp) and `atelier-cli batch-summary`
/// (batch_summary.cpp) share: the layout of a batch's output folder.
///
/// DIR/JOB/ holds the job's project as draped (JOB.atelier), its meshes (JOB.obj,
/// JOB.body.obj), its drape report (JOB.report.json), its pictures (JOB-VIEW.png), the log of
/// its processes (JOB.log) and, written last and atomically, its result (job.json): status
/// "done" or "failed", the error, the time, the drape's quality figures and a fingerprint of
/// what was asked. A job whose job.json says done, with the same fingerprint and every output
/// present, is complete: a re-run skips it.

namespace atelier::app {

inline constexpr const char* JOB_RESULT_FILE = "job.json";
inline constexpr const char* SUMMARY_FILE = "summary.json";

} // namespace atelier::app
