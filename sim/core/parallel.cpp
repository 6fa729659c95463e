#include "sim/core/parallel.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#if defined(__linux__)
#include <sched.h>
#endif

namespace atelier::sim {

namespace {

using Clock = std::chrono::steady_clock;

/// Default spin before sleeping [µs]: see spinMicroseconds() and
/// docs/decisions/017-engine-thread-pool.md.
constexpr int DEFAULT_SPIN_US = 50;
/// Threads a loop can use (the helper count is packed in 8 bits).
constexpr int MAX_THREADS = 256;
/// Bits of a loop's task index in the words that tag it with the loop's generation.
constexpr int INDEX_BITS = 40;
constexpr std::uint64_t INDEX_MASK = (std::uint64_t{1} << INDEX_BITS) - 1;
/// Loops this long run serially: late claims must never carry the index into the generation.
constexpr std::int64_t MAX_TASKS = std::int64_t{1} << (INDEX_BITS - 1);

/// Set on pool threads for good, and on a caller while its loop runs: loops inside loops run
/// serially.
thread_local bool t_inLoop = false;

int availableCores() {
#if defined(__linux__)
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(0, sizeof set, &set) == 0) {
        return std::max(1, CPU_COUNT(&set));
    }
#endif
    return std::max(1u, std::thread::hardware_concurrency());
}

inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#elif defined(__aarch64__)
    asm volatile("yield");
#endif
}

/// Spins until done() or `us` microseconds have passed; returns done().
template <class Done> bool spinUntil(int us, Done&& done) {
    if (us <= 0) {
        return done();
    }
    const auto deadline = Clock::now() + std::chrono::microseconds(us);
    for (int i = 1;; ++i) {
        if (done()) {
            return true;
        }
        cpuRelax();
        if ((i & 63) == 0 && Clock::now() >= deadline) {
            return done();
        }
    }
}

/// The engine's threads. One loop at a time runs on it; the thread that starts a loop takes
/// part in it, and pool thread w (1-based) takes part when w < the loop's thread count.
class Pool {
  public:
    static Pool& instance() {
        static Pool pool;
        return pool;
    }

    Pool()
        : m_threads(std::min(availableCores(), MAX_THREADS)), m_defaultThreads(m_threads.load()) {}

    ~Pool() {
        {
            const std::lock_guard lock(m_mutex);
            m_stop = true;
        }
        m_wake.notify_all();
        for (std::thread& t : m_workers) {
            t.join();
        }
    }

    Pool(const Pool&) = delete;
    Pool& operator=(const Pool&) = delete;

    int threads() const { return m_threads.load(std::memory_order_relaxed); }
    void setThreads(int n) { m_threads.store(n < 1 ? m_defaultThreads : std::min(n, MAX_THREADS)); }
    int spin() const { return m_spinUs.load(std::memory_order_relaxed); }
    void setSpin(int us) { m_spinUs.store(us < 0 ? DEFAULT_SPIN_US : us); }

    void run(std::int64_t tasks, void (*task)(void*, std::int64_t), void* context) {
        const auto serial = [&] {
            for (std::int64_t k = 0; k < tasks; ++k) {
                task(context, k);
            }
        };
        int helpers = static_cast<int>(std::min<std::int64_t>(threads() - 1, tasks - 1));
        if (t_inLoop || helpers < 1 || tasks >= MAX_TASKS) {
            serial(); // checked before the lock: this thread may hold it already
            return;
        }
        std::unique_lock region(m_region, std::try_to_lock);
        if (!region.owns_lock()) {
            serial(); // another thread's loop has the pool
            return;
        }
        try {
            while (static_cast<int>(m_workers.size()) < helpers) {
                const int index = static_cast<int>(m_workers.size()) + 1;
                m_workers.emplace_back([this, index] { workerLoop(index); });
            }
        } catch (const std::system_error&) {
            // No more threads to be had: run with those there are.
            helpers = static_cast<int>(m_workers.size());
            if (helpers < 1) {
                region.unlock();
                serial();
                return;
            }
        }
        m_task = task;
        m_context = context;
        m_completed.store(0, std::memory_order_relaxed);
        m_aborted.store(false, std::memory_order_relaxed);
        bool wake = false;
        {
            const std::lock_guard lock(m_mutex);
            const std::uint64_t generation = (m_state.load(std::memory_order_relaxed) >> 8) + 1;
            // The loop's task count, then its claim counter, both tagged with the generation:
            // a helper that wakes late claims from whichever loop is current and can tell
            // whether its claim is a task of the loop whose fields it reads.
            m_loop.store(generation << INDEX_BITS | static_cast<std::uint64_t>(tasks),
                         std::memory_order_release);
            m_claim.store(generation << INDEX_BITS, std::memory_order_release);
            m_state.store(generation << 8 | static_cast<std::uint64_t>(helpers),
                          std::memory_order_release);
            wake = m_sleepers > 0;
        }
        if (wake) {
            m_wake.notify_all();
        }
        t_inLoop = true;
        work();
        t_inLoop = false;
        // The loop ends when its tasks are done, not when every helper has checked in: a helper
        // the scheduler has not run yet (the cores busy with a window's drawing) costs nothing.
        const auto finished = [this, tasks] {
            return m_completed.load(std::memory_order_acquire) == tasks;
        };
        if (!spinUntil(spin(), finished)) {
            std::unique_lock lock(m_mutex);
            m_done.wait(lock, finished);
        }
        if (m_failure) {
            std::exception_ptr failure;
            std::swap(failure, m_failure);
            std::rethrow_exception(failure);
        }
    }

  private:
    /// Claims and runs tasks of the current loop until none is left. Each claimed task of the
    /// loop is counted as completed once run (or skipped after another task threw).
    void work() {
        for (;;) {
            const std::uint64_t claim = m_claim.fetch_add(1, std::memory_order_acq_rel);
            const std::uint64_t loop = m_loop.load(std::memory_order_acquire);
            const auto k = static_cast<std::int64_t>(claim & INDEX_MASK);
            if ((claim >> INDEX_BITS) != (loop >> INDEX_BITS) ||
                k >= static_cast<std::int64_t>(loop & INDEX_MASK)) {
                return; // that loop has no task left (or has ended and another begun)
            }
            // The loop cannot end before this task is counted, so its fields stay.
            if (!m_aborted.load(std::memory_order_relaxed)) {
                try {
                    m_task(m_context, k);
                } catch (...) {
                    const std::lock_guard lock(m_failureMutex);
                    if (!m_failure) {
                        m_failure = std::current_exception();
                    }
                    m_aborted.store(true, std::memory_order_relaxed);
                }
            }
            const std::int64_t tasks = static_cast<std::int64_t>(loop & INDEX_MASK);
            if (m_completed.fetch_add(1, std::memory_order_acq_rel) + 1 == tasks) {
                const std::lock_guard lock(m_mutex); // so the caller cannot miss the wake-up
                m_done.notify_one();
            }
        }
    }

    void workerLoop(int index) {
        t_inLoop = true;
        std::uint64_t seen = 0;
        for (;;) {
            const auto published = [&] { return m_state.load(std::memory_order_acquire) != seen; };
            if (!spinUntil(spin(), published)) {
                std::unique_lock lock(m_mutex);
                ++m_sleepers;
                m_wake.wait(lock, [&] { return m_stop || published(); });
                --m_sleepers;
                if (m_stop) {
                    return;
                }
            }
            // One load gives the loop and its helper count together.
            seen = m_state.load(std::memory_order_acquire);
            if (static_cast<std::uint64_t>(index) > (seen & 0xff)) {
                continue; // not asked to take part in this loop
            }
            work();
        }
    }

    std::atomic<int> m_threads;
    int m_defaultThreads;
    std::atomic<int> m_spinUs{DEFAULT_SPIN_US};

    std::mutex m_region; ///< held by the thread whose loop runs
    std::vector<std::thread> m_workers;

    // The loop being run: written before m_state is published, read by the helpers after.
    void (*m_task)(void*, std::int64_t) = nullptr;
    void* m_context = nullptr;
    /// The loop's generation << INDEX_BITS | its task count.
    std::atomic<std::uint64_t> m_loop{0};
    /// The loop's generation << INDEX_BITS | the next task to claim.
    std::atomic<std::uint64_t> m_claim{0};
    std::atomic<std::int64_t> m_completed{0}; ///< tasks of the loop run (or skipped)
    std::atomic<bool> m_aborted{false};       ///< a task threw: the rest are skipped
    std::mutex m_failureMutex;
    std::exception_ptr m_failure; ///< the loop's first exception (read once helpers are done)

    std::mutex m_mutex;
    std::condition_variable m_wake; ///< a loop is published (or the pool stops)
    std::condition_variable m_done; ///< the last helper finished
    /// The published loop: its generation (counting loops) << 8 | its helper count.
    std::atomic<std::uint64_t> m_state{0};
    int m_sleepers = 0;  ///< guarded by m_mutex
    bool m_stop = false; ///< guarded by m_mutex
};

} // namespace

int threadCount() {
#if defined(ATELIER_HAVE_THREADS)
    return Pool::instance().threads();
#else
    return 1;
#endif
}

void setThreadCount(int n) {
#if defined(ATELIER_HAVE_THREADS)
    Pool::instance().setThreads(n);
#else
    (void)n;
#endif
}

int spinMicroseconds() {
    return Pool::instance().spin();
}
void setSpinMicroseconds(int us) {
    Pool::instance().setSpin(us);
}

namespace detail {
void runTasks(std::int64_t tasks, void (*task)(void*, std::int64_t), void* context) {
#if defined(ATELIER_HAVE_THREADS)
    Pool::instance().run(tasks, task, context);
#else
    for (std::int64_t k = 0; k < tasks; ++k) {
        task(context, k);
    }
#endif
}
} // namespace detail

} // namespace atelier::sim
