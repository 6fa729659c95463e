#pragma once
/// Runs a fuzz case in a forked child so that a crash, a sanitizer report, a hang or a runaway
/// allocation is caught and reported instead of ending the fuzzer: the child writes the case to
/// its own folder and runs it (case_runner.h); the parent kills it past the time or memory
/// limit.

#include "case_runner.h"
#include "fuzz_case.h"

#include <filesystem>
#include <string>

#if defined(__SANITIZE_ADDRESS__)
#define ATELIER_FUZZ_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ATELIER_FUZZ_ASAN 1
#endif
#endif
#ifndef ATELIER_FUZZ_ASAN
#define ATELIER_FUZZ_ASAN 0
#endif

namespace atelier::fuzz {

/// Limits the parent enforces on each child.
struct SandboxLimits {
    /// Wall time after which the child is killed as hung [s]. The sanitizers make a case
    /// 10-50× slower.
    double seconds = ATELIER_FUZZ_ASAN ? 20.0 : 5.0;
    /// Resident memory above which the child is killed [MiB]; without ASan also its address
    /// space limit (RLIMIT_AS), so that a runaway allocation throws std::bad_alloc. ASan's own
    /// `max_allocation_size_mb` (set by the fuzzer's default options) catches one huge
    /// allocation.
    long memoryMb = 2048;
};

/// How a child ended.
struct CaseResult {
    int exitStatus = -1; ///< the child's exit status when it exited (CaseEnd or a sanitizer's)
    int signal = 0;      ///< the signal that ended it, 0 if none
    bool timedOut = false;
    bool overMemory = false;
    double seconds = 0;  ///< wall time of the child [s]
    std::string message; ///< the child's account (case_runner.h)
    std::string log;     ///< the tail of what the child printed (sanitizer reports)

    bool ok() const;
    /// What went wrong, or what happened (`signal 11 (SIGSEGV)`, `refused: ...`).
    std::string summary() const;
};

/// Writes `c` into a fresh folder `dir` with a FIFO named FIFO_NAME beside it (a path
/// mutation may name it), runs it in a child, and removes the folder.
CaseResult runForked(const FuzzCase& c, const std::filesystem::path& dir, const BodyCache& bodies,
                     const RunLimits& runLimits, const SandboxLimits& limits);

} // namespace atelier::fuzz
