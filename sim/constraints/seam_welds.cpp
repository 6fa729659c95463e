#include "sim/constraints/seam_welds.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace atelier::sim {

SeamWelds::SeamWelds(const std::vector<SeamPair>& seams, int vertexCount)
    : m_seams(&seams), m_vertexCount(vertexCount), m_parent(static_cast<std::size_t>(vertexCount)),
      m_pairWelded(seams.size(), 0) {
    std::iota(m_parent.begin(), m_parent.end(), 0);
}

int SeamWelds::root(int v) {
    while (m_parent[static_cast<std::size_t>(v)] != v) {
        v = m_parent[static_cast<std::size_t>(v)] =
            m_parent[static_cast<std::size_t>(m_parent[static_cast<std::size_t>(v)])];
    }
    return v;
}

bool SeamWelds::join(const SeamPair& p) {
    const int ra = root(p.a), rb = root(p.b);
    if (ra == rb) {
        return false;
    }
    m_parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    return true;
}

bool SeamWelds::weldClosed(const MatX3& x, double distance, bool all, WeldFigures& figures) {
    const std::vector<SeamPair>& seams = *m_seams;
    const double d2 = distance * distance;
    bool changed = false;
    m_new.clear();
    for (std::size_t k = 0; k < seams.size(); ++k) {
        const SeamPair& p = seams[k];
        if (m_pairWelded[k]) {
            continue;
        }
        const double gap2 = (x.row(p.a) - x.row(p.b)).squaredNorm();
        if (gap2 > d2) {
            if (!all) {
                continue;
            }
            figures.largestForced = std::max(figures.largestForced, std::sqrt(gap2));
            figures.forcedGaps.resize(seams.size(), 0.0);
            figures.forcedGaps[k] = std::sqrt(gap2);
        }
        m_pairWelded[k] = 1;
        ++figures.weldedPairs;
        m_new.push_back(k);
        changed = join(p) || changed;
    }
    if (changed) {
        rebuildGroups();
    }
    return changed;
}

void SeamWelds::rebuildGroups() {
    std::map<int, std::vector<int>> groups;
    for (const SeamPair& p : *m_seams) {
        for (int v : {p.a, p.b}) {
            groups[root(v)].push_back(v);
        }
    }
    m_groups.clear();
    for (auto& [r, members] : groups) {
        std::sort(members.begin(), members.end());
        members.erase(std::unique(members.begin(), members.end()), members.end());
        if (members.size() >= 2) {
            m_groups.push_back(std::move(members));
        }
    }
}

void SeamWelds::merge(MatX3* x, MatX3& v, const VecX& mass, const VecX& invMass) const {
    for (const std::vector<int>& g : m_groups) {
        double m = 0;
        Vec3 px = Vec3::Zero(), pv = Vec3::Zero();
        int heldVertex = -1;
        for (int i : g) {
            if (invMass[i] == 0) {
                heldVertex = i;
            }
            m += mass[i];
            if (x != nullptr) {
                px += mass[i] * x->row(i).transpose();
            }
            pv += mass[i] * v.row(i).transpose();
        }
        if (heldVertex >= 0) {
            if (x != nullptr) {
                px = x->row(heldVertex).transpose();
            }
            pv = v.row(heldVertex).transpose();
        } else if (m > 0) {
            px /= m;
            pv /= m;
        } else {
            continue;
        }
        for (int i : g) {
            if (x != nullptr) {
                x->row(i) = px.transpose();
            }
            v.row(i) = pv.transpose();
        }
    }
}

void SeamWelds::shareAccelerations(MatX3& a, const VecX& mass, const VecX& invMass) const {
    for (const std::vector<int>& g : m_groups) {
        double m = 0;
        Vec3 pa = Vec3::Zero();
        int heldVertex = -1;
        for (int i : g) {
            if (invMass[i] == 0) {
                heldVertex = i;
            }
            m += mass[i];
            pa += mass[i] * a.row(i).transpose();
        }
        if (heldVertex >= 0) {
            pa = a.row(heldVertex).transpose();
        } else if (m > 0) {
            pa /= m;
        } else {
            continue;
        }
        for (int i : g) {
            a.row(i) = pa.transpose();
        }
    }
}

std::vector<int> SeamWelds::crossings(const MatX3& xBefore, const MatX3& x,
                                      const CrossingTest& test) {
    m_moved.clear();
    for (const std::vector<int>& g : m_groups) {
        for (int i : g) {
            if (x.row(i) != xBefore.row(i)) {
                m_moved.push_back(i);
            }
        }
    }
    return test(xBefore, x, m_moved);
}

void SeamWelds::unweldCrossing(const MatX3& xBefore, const MatX3& vBefore, MatX3& x, MatX3& v,
                               const VecX& mass, const VecX& invMass, const CrossingTest& crossing,
                               WeldFigures& figures) {
    const std::vector<SeamPair>& seams = *m_seams;
    for (int round = 0; round < 8; ++round) {
        const std::vector<int> crossed = crossings(xBefore, x, crossing);
        if (crossed.empty()) {
            return;
        }
        std::vector<char> rootCrosses(static_cast<std::size_t>(m_vertexCount), 0);
        for (int i : crossed) {
            rootCrosses[static_cast<std::size_t>(root(i))] = 1;
        }
        std::vector<std::size_t> kept;
        bool undone = false;
        for (std::size_t k : m_new) {
            if (!rootCrosses[static_cast<std::size_t>(root(seams[k].a))]) {
                kept.push_back(k);
                continue;
            }
            m_pairWelded[k] = 0;
            --figures.weldedPairs;
            ++figures.deferred;
            if (k < figures.forcedGaps.size()) {
                figures.forcedGaps[k] = 0;
            }
            undone = true;
        }
        if (!undone) {
            // Older groups brought back together after the collision corrections moved their
            // members apart: where that crosses, those members stay where the corrections put
            // them (the group keeps one velocity and is merged again at a later step).
            for (int i : crossed) {
                x.row(i) = xBefore.row(i);
            }
            continue;
        }
        m_new = std::move(kept);
        std::iota(m_parent.begin(), m_parent.end(), 0);
        for (std::size_t k = 0; k < seams.size(); ++k) {
            if (m_pairWelded[k]) {
                join(seams[k]);
            }
        }
        rebuildGroups();
        figures.largestForced =
            figures.forcedGaps.empty()
                ? 0.0
                : *std::max_element(figures.forcedGaps.begin(), figures.forcedGaps.end());
        x = xBefore;
        v = vBefore;
        merge(&x, v, mass, invMass);
    }
    // Rounds exhausted (or the last one merged again): whatever still crosses stays where it
    // was before the merge.
    for (int i : crossings(xBefore, x, crossing)) {
        x.row(i) = xBefore.row(i);
    }
}

void SeamWelds::putBackCrossing(const MatX3& xBefore, MatX3& x, const std::vector<int>& candidates,
                                const CrossingTest& test) {
    std::vector<int> moved = candidates;
    for (int round = 0; round < 8 && !moved.empty(); ++round) {
        const std::vector<int> crossed = test(xBefore, x, moved);
        if (crossed.empty()) {
            return;
        }
        for (int i : crossed) {
            x.row(i) = xBefore.row(i);
        }
        // What is left to test: the candidates still away from where they were.
        std::erase_if(moved, [&](int i) { return x.row(i) == xBefore.row(i); });
    }
    for (int i : test(xBefore, x, moved)) {
        x.row(i) = xBefore.row(i);
    }
}

void SeamWelds::mergeWithoutCrossing(MatX3& x, MatX3& v, const VecX& mass, const VecX& invMass,
                                     const CrossingTest& crossing, double unchecked) {
    m_moved.clear();
    for (const std::vector<int>& g : m_groups) {
        const bool apart = std::any_of(g.begin() + 1, g.end(), [&](int i) {
            return (x.row(i) - x.row(g.front())).norm() > unchecked;
        });
        if (apart) {
            m_moved.insert(m_moved.end(), g.begin(), g.end());
        }
    }
    if (m_moved.empty()) {
        merge(&x, v, mass, invMass);
        return;
    }
    m_xBefore = x;
    merge(&x, v, mass, invMass);
    putBackCrossing(m_xBefore, x, m_moved, crossing);
}

} // namespace atelier::sim
