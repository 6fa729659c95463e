#pragma once
/// Parallel loops on the engine's own thread pool.
///
/// The pool's threads wait for work by spinning for a few microseconds and then sleeping on a
/// futex, so an engine that shares its cores with a window, a compositor or another job never
/// keeps them busy while it has nothing to do (OpenMP's default waiting spins for about a
/// millisecond per loop, which on a loaded 2-core machine made the 10 mm tshirt drape 7× slower:
/// docs/decisions/017-engine-thread-pool.md). Loops write per index or per chunk, so results
/// are the same bits for any number of threads. With ATELIER_THREADS=OFF everything runs
/// serially.

#include <algorithm>
#include <cstdint>
#include <utility>

namespace atelier::sim {

/// Number of threads the engine uses for parallel loops (the calling thread included).
int threadCount();
/// Sets the number of threads (1 = serial). Values < 1 restore the default (all cores).
void setThreadCount(int n);

/// How long a pool thread (and the caller waiting for a loop's end) spins before it sleeps [µs].
/// Short enough that a loaded machine loses almost nothing to spinning, long enough to catch
/// the next loop of a conjugate-gradient iteration without a wake-up.
int spinMicroseconds();
/// Sets the spin (0 = sleep at once, as OMP_WAIT_POLICY=passive); < 0 restores the default.
void setSpinMicroseconds(int us);

/// Minimum loop length for which parallel loops are worth their fork/join cost.
inline constexpr std::int64_t PARALLEL_GRAIN = 2048;

namespace detail {
/// Runs task(context, k) for every k in [0, tasks) on the pool (the caller takes part), each
/// task exactly once, in any order and on any thread; returns when all are done. Serial when
/// called from inside a parallel loop, or while another thread's loop holds the pool.
void runTasks(std::int64_t tasks, void (*task)(void*, std::int64_t), void* context);
} // namespace detail

/// Contiguous blocks a flat parallel loop is cut into per thread: a few, so that a thread the
/// scheduler runs late (cores shared with a window's drawing) leaves its blocks to the others.
inline constexpr std::int64_t BLOCKS_PER_THREAD = 4;

/// Calls body(i) for every i in [0, n): in parallel (a few contiguous blocks per thread) when
/// n >= PARALLEL_GRAIN, else serially. body(i) must only write what belongs to i.
template <class Body> void parallelFor(std::int64_t n, Body&& body) {
    const int threads = threadCount();
    if (n < PARALLEL_GRAIN || threads <= 1) {
        for (std::int64_t i = 0; i < n; ++i) {
            body(i);
        }
        return;
    }
    struct Context {
        Body* body;
        std::int64_t n;
        std::int64_t blocks;
    } context{&body, n, std::min<std::int64_t>(threads * BLOCKS_PER_THREAD, n / 256)};
    detail::runTasks(
        context.blocks,
        [](void* c, std::int64_t k) {
            const auto& ctx = *static_cast<Context*>(c);
            const std::int64_t end = ctx.n * (k + 1) / ctx.blocks;
            for (std::int64_t i = ctx.n * k / ctx.blocks; i < end; ++i) {
                (*ctx.body)(i);
            }
        },
        &context);
}

/// Calls body(i) for every i in [0, n), iterations of uneven cost handed out one at a time,
/// in parallel only when `parallel`.
template <class Body> void parallelForEach(std::int64_t n, bool parallel, Body&& body) {
    if (!parallel || n <= 1 || threadCount() <= 1) {
        for (std::int64_t i = 0; i < n; ++i) {
            body(i);
        }
        return;
    }
    detail::runTasks(
        n, [](void* b, std::int64_t i) { (*static_cast<Body*>(b))(i); }, &body);
}

/// Number of contiguous pieces parallelChunks splits a loop of n uneven iterations into: enough
/// for the threads to balance, few enough that each piece's output buffer stays large.
inline std::int64_t chunkCount(std::int64_t n) {
    return std::clamp<std::int64_t>(n / 256, 1, 64);
}

/// Calls body(chunk, begin, end) for the chunkCount(n) contiguous pieces [begin, end) of [0, n),
/// in parallel, in any order. A caller that gives each chunk its own output and concatenates
/// the outputs in chunk order gets exactly what one serial pass would give, for any number of
/// threads (so results stay deterministic).
template <class Body> void parallelChunks(std::int64_t n, Body&& body) {
    const std::int64_t chunks = chunkCount(n);
    parallelForEach(chunks, n >= PARALLEL_GRAIN,
                    [&](std::int64_t c) { body(c, n * c / chunks, n * (c + 1) / chunks); });
}

} // namespace atelier::sim
