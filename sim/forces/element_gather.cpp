#include "sim/forces/element_gather.h"

#include "sim/core/parallel.h"

#include <algorithm>

namespace atelier::sim {

ElementGather::ElementGather(const Eigen::MatrixXi& elements, int offset)
    : m_offset(offset), m_k(static_cast<int>(elements.cols())),
      m_elementCount(static_cast<int>(elements.rows())) {
    m_elements.resize(static_cast<std::size_t>(m_elementCount) * static_cast<std::size_t>(m_k));
    int maxIndex = -1;
    for (int e = 0; e < m_elementCount; ++e) {
        for (int a = 0; a < m_k; ++a) {
            m_elements[static_cast<std::size_t>(e * m_k + a)] = elements(e, a);
            maxIndex = std::max(maxIndex, elements(e, a));
        }
    }
    const auto nv = static_cast<std::size_t>(maxIndex + 1);
    m_start.assign(nv + 1, 0);
    for (int v : m_elements) {
        if (v >= 0) {
            ++m_start[static_cast<std::size_t>(v) + 1];
        }
    }
    for (std::size_t i = 0; i < nv; ++i) {
        m_start[i + 1] += m_start[i];
    }
    m_incidence.resize(static_cast<std::size_t>(m_start[nv]));
    std::vector<int> fill(m_start.begin(), m_start.end() - 1);
    // Increasing slot order per vertex, so sums are deterministic.
    for (std::size_t s = 0; s < m_elements.size(); ++s) {
        const int v = m_elements[s];
        if (v >= 0) {
            m_incidence[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] =
                static_cast<int>(s);
        }
    }
}

void ElementGather::gather(const MatX3& buffer, MatX3& f) const {
    const std::int64_t nv = vertexCount();
    parallelFor(nv, [&](std::int64_t v) {
        const auto i = static_cast<std::size_t>(v);
        Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
        for (int s = m_start[i]; s < m_start[i + 1]; ++s) {
            sum += buffer.row(m_incidence[static_cast<std::size_t>(s)]);
        }
        f.row(m_offset + v) += sum;
    });
}

void ElementGather::gatherJacobian(const std::vector<Mat3>& blocks, BlockSparseMatrix& J) const {
    const std::int64_t nv = vertexCount();
    if (m_slotsFor != J.patternId() || J.patternId() == 0) {
        m_slots.assign(m_incidence.size() * static_cast<std::size_t>(m_k), -1);
        for (std::size_t v = 0; v + 1 < m_start.size(); ++v) {
            const int row = m_offset + static_cast<int>(v);
            for (int s = m_start[v]; s < m_start[v + 1]; ++s) {
                const int e = m_incidence[static_cast<std::size_t>(s)] / m_k;
                for (int b = 0; b < m_k; ++b) {
                    const int local = m_elements[static_cast<std::size_t>(e * m_k + b)];
                    m_slots[static_cast<std::size_t>(s * m_k + b)] =
                        local < 0 ? -1 : J.slot(row, m_offset + local);
                }
            }
        }
        m_slotsFor = J.patternId();
    }
    parallelFor(nv, [&](std::int64_t v) {
        const auto i = static_cast<std::size_t>(v);
        for (int s = m_start[i]; s < m_start[i + 1]; ++s) {
            const int slotIndex = m_incidence[static_cast<std::size_t>(s)]; // e·k + a
            for (int b = 0; b < m_k; ++b) {
                const int slot = m_slots[static_cast<std::size_t>(s * m_k + b)];
                if (slot >= 0) {
                    J.addAt(slot, blocks[static_cast<std::size_t>(slotIndex * m_k + b)]);
                }
            }
        }
    });
}

void ElementGather::addPattern(std::vector<std::pair<int, int>>& pairs) const {
    for (int e = 0; e < m_elementCount; ++e) {
        for (int a = 0; a < m_k; ++a) {
            for (int b = a + 1; b < m_k; ++b) {
                const int la = m_elements[static_cast<std::size_t>(e * m_k + a)];
                const int lb = m_elements[static_cast<std::size_t>(e * m_k + b)];
                if (la >= 0 && lb >= 0 && la != lb) {
                    pairs.emplace_back(m_offset + la, m_offset + lb);
                }
            }
        }
    }
}

} // namespace atelier::sim
