#include "sim/forces/seam_bending.h"

#include "sim/collision/indexing.h"
#include "sim/constraints/seam_welds.h"
#include "sim/forces/continuum_bending.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <set>
#include <unordered_map>
#include <utility>

namespace atelier::sim {

namespace {

/// A border edge of a cloth, as a seam hinge's wing sees it (global indices).
struct SeamWing {
    int from = 0;         ///< the edge's end it leaves from counter-clockwise in its triangle
    int to = 0;           ///< its other end
    int opposite = 0;     ///< the triangle's third corner
    double length = 0;    ///< rest length [m]
    double area = 0;      ///< the triangle's rest area [m²]
    double stiffness = 0; ///< k of the cloth across this edge [N·m] (see SeamBending)
    double damping = 0;   ///< τ [s]
};

/// k of a hinge along a border edge of cloth `c` at `angle` [rad] to the weft (SeamBending).
double borderStiffness(const ClothSpec& c, double angle) {
    if (!c.bending) {
        return 0.0;
    }
    if (c.bendingModel == BendingModel::Continuum) {
        BendingRigidity rigidity;
        if (bendingRigidity(c.material, rigidity) || !(rigidity.weft > 0) || !(rigidity.warp > 0) ||
            !(rigidity.twist > 0)) {
            return 0.0;
        }
        return stripRigidity(rigidity, angle + 0.5 * std::numbers::pi) / 3.0;
    }
    return std::max(c.material.bending, 0.0);
}

/// The key of the unordered edge (u, v).
std::uint64_t borderKey(int u, int v) {
    return pairKey(std::min(u, v), std::max(u, v));
}

/// Every border edge of the scene's cloths, and where each is found by its ends.
std::vector<SeamWing> borderWings(const SceneSpec& scene, const std::vector<int>& offsets,
                                  std::unordered_map<std::uint64_t, int>& byEnds) {
    std::vector<SeamWing> wings;
    for (std::size_t ci = 0; ci < scene.cloths.size(); ++ci) {
        const ClothSpec& c = scene.cloths[ci];
        const ClothMesh& mesh = c.mesh;
        const int off = offsets[ci];
        for (int e = 0; e < mesh.edges.rows(); ++e) {
            if (mesh.edgeTriangles(e, 1) >= 0 || mesh.edgeTriangles(e, 0) < 0) {
                continue; // interior
            }
            const int t = mesh.edgeTriangles(e, 0);
            int u = mesh.edges(e, 0);
            int v = mesh.edges(e, 1);
            int o = 0;
            bool backwards = false; // the triangle runs v→u
            for (int k = 0; k < 3; ++k) {
                const int a = mesh.triangles(t, k);
                backwards = backwards || (a == v && mesh.triangles(t, (k + 1) % 3) == u);
                if (a != u && a != v) {
                    o = a;
                }
            }
            if (backwards) {
                std::swap(u, v);
            }
            const Vec2 d = (mesh.rest.row(v) - mesh.rest.row(u)).transpose();
            const double k = borderStiffness(c, std::atan2(d.y(), d.x()));
            SeamWing w{u + off,
                       v + off,
                       o + off,
                       d.norm(),
                       mesh.restArea[t],
                       k,
                       std::max(c.material.damping, 0.0)};
            byEnds.emplace(borderKey(w.from, w.to), static_cast<int>(wings.size()));
            wings.push_back(w);
        }
    }
    return wings;
}

} // namespace

std::vector<SeamHinge> seamHinges(const SceneSpec& scene, const std::vector<int>& offsets) {
    std::unordered_map<std::uint64_t, int> byEnds;
    const std::vector<SeamWing> wings = borderWings(scene, offsets, byEnds);
    // Each vertex's partners across the seams, with the pair that sews them.
    std::unordered_map<int, std::vector<std::pair<int, std::size_t>>> partners;
    for (std::size_t k = 0; k < scene.seams.size(); ++k) {
        const SeamPair& p = scene.seams[k];
        partners[p.a].emplace_back(p.b, k);
        partners[p.b].emplace_back(p.a, k);
    }
    std::vector<SeamHinge> hinges;
    std::set<std::pair<int, int>> seen;
    const auto add = [&](const SeamWing& front, const SeamWing& back,
                         std::array<std::size_t, 2> pair) {
        SeamHinge h;
        h.corners = {front.from, front.to, front.opposite, back.opposite};
        h.pairs = pair;
        h.edgeLength = 0.5 * (front.length + back.length);
        h.areas = {front.area, back.area};
        h.stiffness = 0.5 * (front.stiffness + back.stiffness);
        h.damping = 0.5 * (front.damping + back.damping);
        hinges.push_back(h);
    };
    for (std::size_t i = 0; i < wings.size(); ++i) {
        const SeamWing& w = wings[i];
        const auto pu = partners.find(w.from);
        const auto pv = partners.find(w.to);
        if (pu == partners.end() || pv == partners.end()) {
            continue;
        }
        for (const auto& [u, ku] : pu->second) {
            for (const auto& [v, kv] : pv->second) {
                const auto j = byEnds.find(borderKey(u, v));
                if (u == v || j == byEnds.end() || j->second == static_cast<int>(i)) {
                    continue;
                }
                const int b = j->second;
                if (!seen.insert(
                             {std::min(static_cast<int>(i), b), std::max(static_cast<int>(i), b)})
                         .second) {
                    continue;
                }
                const SeamWing& other = wings[static_cast<std::size_t>(b)];
                // Wing 0 is the side holding the pair's `a` vertex (SeamPair::foldAngle).
                if (scene.seams[ku].a == w.from) {
                    add(w, other, {ku, kv});
                } else {
                    const bool atFrom = other.from == u; // other.from is sewn to w.from
                    add(other, w, atFrom ? std::array{ku, kv} : std::array{kv, ku});
                }
            }
        }
    }
    return hinges;
}

std::unique_ptr<SeamBending> SeamBending::build(const SceneSpec& scene,
                                                const std::vector<int>& offsets) {
    // k of each hinge; those with none (neither side bends) are left out.
    std::vector<SeamHinge> bending;
    for (SeamHinge& h : seamHinges(scene, offsets)) {
        h.stiffness *= 0.5 * (std::max(scene.seams[h.pairs[0]].bendingScale, 0.0) +
                              std::max(scene.seams[h.pairs[1]].bendingScale, 0.0));
        if (h.stiffness > 0) {
            bending.push_back(h);
        }
    }
    if (bending.empty()) {
        return nullptr;
    }
    HingeSet set;
    set.resize(static_cast<int>(bending.size()));
    std::vector<std::array<std::size_t, 2>> pairs;
    for (std::size_t i = 0; i < bending.size(); ++i) {
        const SeamHinge& s = bending[i];
        const int h = static_cast<int>(i);
        set.corners.row(h) << s.corners[0], s.corners[1], s.corners[2], s.corners[3];
        set.setRestShape(h, s.edgeLength * s.edgeLength, s.areas[0], s.areas[1]);
        set.restAngle[h] =
            0.5 * (scene.seams[s.pairs[0]].foldAngle + scene.seams[s.pairs[1]].foldAngle);
        set.stiffness[h] = s.stiffness;
        set.damping[h] = s.damping;
        pairs.push_back(s.pairs);
    }
    return std::unique_ptr<SeamBending>(new SeamBending(std::move(set), std::move(pairs)));
}

SeamBending::SeamBending(HingeSet hinges, std::vector<std::array<std::size_t, 2>> pairs)
    : DihedralBending(std::move(hinges), "bending.seams"), m_pairs(std::move(pairs)) {
    setActive(std::vector<char>(m_pairs.size(), 0));
    m_fullStiffness = stiffness();
}

void SeamBending::setStrength(double strength) {
    strength = std::clamp(strength, 0.0, 1.0);
    if (strength != m_strength) {
        m_strength = strength;
        stiffness() = m_fullStiffness * strength;
    }
}

bool SeamBending::switchOn(const std::vector<char>& on) {
    bool changed = false;
    for (std::size_t h = 0; h < on.size() && !changed; ++h) {
        changed = (on[h] != 0) != active(static_cast<int>(h));
    }
    if (changed) {
        setActive(on);
    }
    return changed;
}

bool SeamBending::switchOff() {
    return switchOn(std::vector<char>(m_pairs.size(), 0));
}

bool SeamBending::followWelds(const SeamWelds& welds) {
    std::vector<char> on(m_pairs.size(), 0);
    for (std::size_t h = 0; h < m_pairs.size(); ++h) {
        on[h] = welds.welded(m_pairs[h][0]) && welds.welded(m_pairs[h][1]) ? 1 : 0;
    }
    return switchOn(on);
}

} // namespace atelier::sim
