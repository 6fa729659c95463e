#pragma once
/// Thin wrappers over OpenMP so the rest of the engine does not spell pragmas.
/// Without OpenMP (ATELIER_OPENMP=OFF, the sanitizer build) everything runs serially.

#include <algorithm>
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
/// `ATELIER_PARALLEL_FOR_DYNAMIC(n, on) for (std::int64_t i = 0; i < n; ++i)`: iterations of
/// uneven cost handed out one at a time, in parallel only when `on`.
#define ATELIER_PARALLEL_FOR_DYNAMIC(n, on) ATELIER_PRAGMA(omp parallel for schedule(dynamic, 1) if (on))
#else
#define ATELIER_PARALLEL_FOR(n)
#define ATELIER_PARALLEL_FOR_DYNAMIC(n, on)
#endif

namespace atelier::sim {

/// Number of contiguous pieces parallelChunks splits a loop of n uneven iterations into: enough
/// for the threads to balance, few enough that each piece's output buffer stays large.
inline std::int64_t chunkCount(std::int64_t n) {
    return std::clamp<std::int64_t>(n / 256, 1, 64);
}

/// Calls body(chunk, begin, end) for the chunkCount(n) contiguous pieces [begin, end) of [0, n),
/// in parallel, in any order. A caller that gives each chunk its own output and concatenates
/// the outputs in chunk order gets exactly what one serial pass would give, for any number of
/// threads (so results stay deterministic).
template <class Body>
void parallelChunks(std::int64_t n, Body&& body) {
    const std::int64_t chunks = chunkCount(n);
    ATELIER_PARALLEL_FOR_DYNAMIC(chunks, n >= PARALLEL_GRAIN)
    for (std::int64_t c = 0; c < chunks; ++c) {
        body(c, n * c / chunks, n * (c + 1) / chunks);
    }
}

} // namespace atelier::sim
