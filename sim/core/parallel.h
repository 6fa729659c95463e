#pragma once
/// Thin wrappers over OpenMP so the rest of the engine does not spell pragmas.
/// Without OpenMP (ATELIER_OPENMP=OFF, the sanitizer build) everything runs serially.

#include <cstdint>

namespace atelier::sim {

/// Number of threads the engine uses for parallel loops.
int threadCount();
/// Sets the number of threads (1 = serial). Values < 1 restore the default (all cores).
void setThreadCount(int n);

/// Minimum loop length for which parallel loops are worth their fork/join cost.
inline constexpr std::int64_t PARALLEL_GRAIN = 2048;

} // namespace atelier::sim

#if defined(ATELIER_HAVE_OPENMP)
#define ATELIER_PRAGMA(x) _Pragma(#x)
/// `ATELIER_PARALLEL_FOR(n) for (std::int64_t i = 0; i < n; ++i)`
#define ATELIER_PARALLEL_FOR(n)                                                                    \
    ATELIER_PRAGMA(omp parallel for schedule(static) if ((n) >= ::atelier::sim::PARALLEL_GRAIN))
#else
#define ATELIER_PARALLEL_FOR(n)
#endif
