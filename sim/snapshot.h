#pragma once
/// Snapshots of a running simulation for other threads (a window's viewport, a status bar, a
/// plot): the stepping thread publishes after a step, readers copy the latest at any moment.

#include "sim/core/types.h"

#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

namespace atelier::sim {

/// The state a viewer draws and the figures it shows, at one step.
struct Snapshot {
    std::uint64_t version = 0; ///< publications so far, this one included (0: none yet)
    double time = 0;           ///< simulated time [s]
    long steps = 0;            ///< accepted steps
    double wallTime = 0;       ///< wall time spent in steps [s]
    double kineticEnergy = 0;  ///< [J]
    long contacts = 0;         ///< active contacts after the step
    MatX3 clothPositions;      ///< (|V|×3) over all cloths [m]
    MatX3 clothNormals;        ///< (|V|×3) unit, area-weighted over the vertex's triangles
    std::vector<MatX3> obstaclePositions; ///< per obstacle (|V_k|×3) [m]
    std::vector<MatX3> obstacleNormals;   ///< per obstacle (|V_k|×3), unit
    /// Per obstacle: changes whenever its positions do (a static body keeps one version, so a
    /// viewer uploads it once).
    std::vector<std::uint64_t> obstacleVersions;
};

/// A triple buffer: the writer fills one slot while the latest published one waits in the
/// middle and readers copy from a third, so the writer never waits for a reader and a reader
/// never sees a slot being written (no tearing). Publishing is one atomic exchange; readers
/// take a mutex among themselves only, never one the writer holds.
class SnapshotBuffer {
  public:
    /// Writer: the slot to fill before publish() (its previous contents are an older snapshot,
    /// so arrays of the same size are overwritten without allocating).
    Snapshot& back() { return m_slots[m_back]; }
    /// Writer: makes back() the latest snapshot; back() is then another slot.
    void publish() {
        m_slots[m_back].version = ++m_published;
        m_back = m_middle.exchange(m_back | FRESH, std::memory_order_acq_rel) & INDEX;
    }

    /// Reader (any thread): copies the latest published snapshot into `out` (reusing its
    /// arrays); returns false, leaving `out` alone, when nothing has been published yet.
    bool read(Snapshot& out) {
        const std::lock_guard lock(m_readers);
        if ((m_middle.load(std::memory_order_acquire) & FRESH) != 0) {
            m_front = m_middle.exchange(m_front, std::memory_order_acq_rel) & INDEX;
        }
        const Snapshot& s = m_slots[m_front];
        if (s.version == 0) {
            return false;
        }
        out = s;
        return true;
    }

  private:
    static constexpr unsigned INDEX = 3;
    static constexpr unsigned FRESH = 4;
    Snapshot m_slots[3];
    unsigned m_back = 0;               ///< the writer's slot
    unsigned m_front = 2;              ///< the readers' slot (guarded by m_readers)
    std::atomic<unsigned> m_middle{1}; ///< the slot between them, FRESH when newly published
    std::uint64_t m_published = 0;     ///< the writer's count
    std::mutex m_readers;
};

} // namespace atelier::sim
