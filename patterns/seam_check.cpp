#include "patterns/seam_check.h"

#include <algorithm>
#include <map>
#include <string>
#include <utility>

namespace atelier::patterns {

namespace {

constexpr double TOUCH_EPS = 1e-9; ///< ranges sharing less than this in parameter only touch [-]

/// One sewn range of an outline segment: a seam's range or a dart's leg.
struct SewnRange {
    double lo = 0; ///< smaller curve parameter
    double hi = 0; ///< larger curve parameter
    int order = 0; ///< position in file order (darts with their panels, then seams)
    int seam = -1; ///< seam index, or −1 for a dart leg
    int side = 0;  ///< seams: 0 = a, 1 = b
    std::string where;
    std::string what; ///< how a message names it
};

std::string seamName(const Garment& garment, int s) {
    const std::string& name = garment.seams[static_cast<std::size_t>(s)].name;
    return name.empty() ? "seam " + std::to_string(s) : "seam \"" + name + "\"";
}

bool sameSide(const std::vector<SeamEdge>& x, const std::vector<SeamEdge>& y) {
    return std::equal(
        x.begin(), x.end(), y.begin(), y.end(), [](const SeamEdge& a, const SeamEdge& b) {
            return a.panel == b.panel && a.segment == b.segment && a.t0 == b.t0 && a.t1 == b.t1;
        });
}

/// Whether two seams sew the same ranges together (either way round).
bool sameSeam(const Seam& x, const Seam& y) {
    return (sameSide(x.a, y.a) && sameSide(x.b, y.b)) || (sameSide(x.a, y.b) && sameSide(x.b, y.a));
}

/// The issue for `later` overlapping `earlier`, at the later one's pointer.
GarmentIssue overlapIssue(const Garment& garment, const SewnRange& earlier,
                          const SewnRange& later) {
    if (later.seam >= 0 && later.seam == earlier.seam) {
        const std::string how = later.side == earlier.side ? "uses the same edge range twice"
                                                           : "sews an edge to itself";
        return {later.where, seamName(garment, later.seam) + " " + how + ": this range overlaps " +
                                 earlier.where};
    }
    if (later.seam >= 0 && earlier.seam >= 0 &&
        sameSeam(garment.seams[static_cast<std::size_t>(later.seam)],
                 garment.seams[static_cast<std::size_t>(earlier.seam)])) {
        return {"/seams/" + std::to_string(later.seam),
                seamName(garment, later.seam) + " repeats " + earlier.what + " (/seams/" +
                    std::to_string(earlier.seam) + "): the same ranges sewn together again"};
    }
    return {later.where, "this range is also sewn by " + earlier.what + " (" + earlier.where +
                             "): an edge range takes part in one seam or dart only"};
}

} // namespace

void checkSewnRanges(const Garment& garment, std::vector<GarmentIssue>& issues) {
    // Ranges grouped by (panel, outline segment), in file order: panels (with their darts)
    // come before seams.
    std::map<std::pair<int, int>, std::vector<SewnRange>> bySegment;
    int order = 0;
    for (std::size_t p = 0; p < garment.panels.size(); ++p) {
        const Panel& panel = garment.panels[p];
        for (std::size_t d = 0; d < panel.darts.size(); ++d) {
            const std::string where =
                "/panels/" + std::to_string(p) + "/darts/" + std::to_string(d);
            const std::string what =
                "dart " + std::to_string(d) + " of panel \"" + panel.name + "\"";
            for (const int leg : {panel.darts[d].leg, panel.darts[d].leg + 1}) {
                bySegment[{static_cast<int>(p), leg}].push_back(
                    {0, 1, order++, -1, 0, where, what});
            }
        }
    }
    for (std::size_t s = 0; s < garment.seams.size(); ++s) {
        for (int side = 0; side < 2; ++side) {
            const auto& edges = side == 0 ? garment.seams[s].a : garment.seams[s].b;
            for (std::size_t e = 0; e < edges.size(); ++e) {
                const SeamEdge& edge = edges[e];
                const std::string where =
                    "/seams/" + std::to_string(s) + (side == 0 ? "/a/" : "/b/") + std::to_string(e);
                bySegment[{garment.panelIndex(edge.panel), edge.segment}].push_back(
                    {std::min(edge.t0, edge.t1), std::max(edge.t0, edge.t1), order++,
                     static_cast<int>(s), side, where, seamName(garment, static_cast<int>(s))});
            }
        }
    }
    for (auto& [segment, ranges] : bySegment) {
        std::sort(ranges.begin(), ranges.end(), [](const SewnRange& x, const SewnRange& y) {
            return x.lo != y.lo ? x.lo < y.lo : x.order < y.order;
        });
        // Sorted by start, a range overlaps an earlier one if it starts before the farthest
        // end so far.
        const SewnRange* reach = nullptr;
        for (const SewnRange& r : ranges) {
            if (reach != nullptr && r.lo < reach->hi - TOUCH_EPS) {
                const bool rLater = r.order > reach->order;
                GarmentIssue issue =
                    overlapIssue(garment, rLater ? *reach : r, rLater ? r : *reach);
                // A repeated seam overlaps on each of its ranges: say so once.
                if (std::none_of(issues.begin(), issues.end(), [&](const GarmentIssue& i) {
                        return i.where == issue.where && i.message == issue.message;
                    })) {
                    issues.push_back(std::move(issue));
                }
            }
            if (reach == nullptr || r.hi > reach->hi) {
                reach = &r;
            }
        }
    }
}

} // namespace atelier::patterns
