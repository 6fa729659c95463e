#include "patterns/seam_allowance.h"

#include "patterns/curve.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <unordered_map>
#include <utility>

namespace atelier::patterns {

namespace {

double distanceToSegment(const Vec2& p, const Vec2& a, const Vec2& b) {
    const Vec2 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
    return (a + t * ab - p).norm();
}

/// The closed polyline without repeated points (consecutive, or the last equal to the first).
std::vector<Vec2> withoutRepeats(const std::vector<Vec2>& loop) {
    std::vector<Vec2> out;
    out.reserve(loop.size());
    for (const Vec2& p : loop) {
        if (out.empty() || (p - out.back()).norm() > 1e-12) {
            out.push_back(p);
        }
    }
    while (out.size() > 1 && (out.back() - out.front()).norm() <= 1e-12) {
        out.pop_back();
    }
    return out;
}

/// The untrimmed offset to the right of `loop` (each edge moved by `distance` along its right
/// normal), with a circumscribed arc polygon around each corner that turns away from the
/// offset side. Every point is at least `distance` from the corner or edge it comes from.
std::vector<Vec2> rawOffset(const std::vector<Vec2>& loop, double distance, double tolerance) {
    const std::size_t n = loop.size();
    std::vector<Vec2> normals(n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2 d = (loop[(i + 1) % n] - loop[i]).normalized();
        normals[i] = Vec2(d.y(), -d.x());
    }
    // Arc pieces turning at most this much keep the circumscribed polygon within `tolerance`:
    // distance / cos(step / 2) − distance ≤ tolerance.
    const double maxStep = 2.0 * std::acos(distance / (distance + tolerance));
    std::vector<Vec2> raw;
    raw.reserve(2 * n);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec2& p = loop[i];
        const Vec2& n0 = normals[(i + n - 1) % n];
        const Vec2& n1 = normals[i];
        // Turning left (counter-clockwise), the right-hand offsets of the two edges part: fill
        // the gap with the arc around the corner.
        const double turn = std::atan2(sim::cross2d(n0, n1), n0.dot(n1));
        raw.push_back(p + distance * n0);
        if (turn > 0) {
            const int pieces = std::max(1, static_cast<int>(std::ceil(turn / maxStep)));
            const double step = turn / pieces;
            const double a0 = std::atan2(n0.y(), n0.x());
            const double r = distance / std::cos(0.5 * step);
            for (int k = 0; k < pieces; ++k) {
                const double a = a0 + (k + 0.5) * step;
                raw.push_back(p + r * Vec2(std::cos(a), std::sin(a)));
            }
        }
        raw.push_back(p + distance * n1);
    }
    return withoutRepeats(raw);
}

/// Drops the points that lie within `tolerance` of the chord joining their neighbours (the
/// offsets of nearly straight stretches come as three nearly collinear points per vertex).
std::vector<Vec2> withoutCollinear(const std::vector<Vec2>& loop, double tolerance) {
    std::vector<Vec2> out;
    out.reserve(loop.size());
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const Vec2& next = loop[(i + 1) % loop.size()];
        if (out.empty() || distanceToSegment(loop[i], out.back(), next) > tolerance) {
            out.push_back(loop[i]);
        }
    }
    return out.size() >= 3 ? out : loop;
}

/// Answers "is any edge of a closed polyline nearer than r to p?" for one fixed r by looking
/// only at the edges filed in the grid cells around p: the edges are cut into pieces no longer
/// than a cell, each filed under the cells its bounding box touches.
class NearEdges {
  public:
    NearEdges(const std::vector<Vec2>& loop, double r) : m_r(r) {
        Vec2 lo = loop.front(), hi = loop.front();
        for (const Vec2& p : loop) {
            lo = lo.cwiseMin(p);
            hi = hi.cwiseMax(p);
        }
        // At least r, so that a query looks at 3 × 3 cells; at most 1024 cells across.
        m_cell = std::max({r, (hi - lo).maxCoeff() / 1024, 1e-9});
        m_origin = lo;
        for (std::size_t i = 0; i < loop.size(); ++i) {
            const Vec2 a = loop[i], b = loop[(i + 1) % loop.size()];
            const int pieces = std::max(1, static_cast<int>(std::ceil((b - a).norm() / m_cell)));
            for (int k = 0; k < pieces; ++k) {
                const Vec2 p0 = a + (b - a) * (static_cast<double>(k) / pieces);
                const Vec2 p1 = a + (b - a) * (static_cast<double>(k + 1) / pieces);
                const int edge = static_cast<int>(m_edges.size());
                m_edges.push_back({p0, p1});
                const auto [x0, y0] = cellOf(p0.cwiseMin(p1));
                const auto [x1, y1] = cellOf(p0.cwiseMax(p1));
                for (long long x = x0; x <= x1; ++x) {
                    for (long long y = y0; y <= y1; ++y) {
                        m_cells[key(x, y)].push_back(edge);
                    }
                }
            }
        }
    }

    /// Whether an edge lies nearer than r to p.
    bool anyNearer(const Vec2& p) const {
        const auto [x0, y0] = cellOf(p - Vec2(m_r, m_r));
        const auto [x1, y1] = cellOf(p + Vec2(m_r, m_r));
        for (long long x = x0; x <= x1; ++x) {
            for (long long y = y0; y <= y1; ++y) {
                const auto it = m_cells.find(key(x, y));
                if (it == m_cells.end()) {
                    continue;
                }
                for (int e : it->second) {
                    const auto& [a, b] = m_edges[static_cast<std::size_t>(e)];
                    if (distanceToSegment(p, a, b) < m_r) {
                        return true;
                    }
                }
            }
        }
        return false;
    }

  private:
    std::pair<long long, long long> cellOf(const Vec2& p) const {
        return {static_cast<long long>(std::floor((p.x() - m_origin.x()) / m_cell)),
                static_cast<long long>(std::floor((p.y() - m_origin.y()) / m_cell))};
    }
    static long long key(long long x, long long y) {
        return (x + (1LL << 20)) << 32 | (y + (1LL << 20));
    }

    double m_r, m_cell = 1;
    Vec2 m_origin = Vec2::Zero();
    std::vector<std::pair<Vec2, Vec2>> m_edges;
    std::unordered_map<long long, std::vector<int>> m_cells;
};

/// A piece of the raw offset between two of its vertices or crossings.
struct Piece {
    Vec2 from, to;
    int startNode = 0, endNode = 0;
    bool keep = false;
    bool visited = false;
};

/// Splits `raw` at its self-crossings, keeps the pieces at least `minDistance` from `loop`, and
/// chains them into closed loops; nullopt when a chain does not close (a crossing exactly at a
/// vertex or along a shared line).
std::optional<std::vector<std::vector<Vec2>>>
trimOffset(const std::vector<Vec2>& loop, const std::vector<Vec2>& raw, double minDistance) {
    const std::size_t m = raw.size();
    const NearEdges near(loop, minDistance);
    struct Cut {
        double s;
        int node;
    };
    std::vector<std::vector<Cut>> cuts(m);
    // Crossings: sweep the segments in order of their lowest x.
    std::vector<std::size_t> order(m);
    std::vector<double> minX(m), maxX(m), minY(m), maxY(m);
    for (std::size_t j = 0; j < m; ++j) {
        const Vec2 &a = raw[j], &b = raw[(j + 1) % m];
        minX[j] = std::min(a.x(), b.x());
        maxX[j] = std::max(a.x(), b.x());
        minY[j] = std::min(a.y(), b.y());
        maxY[j] = std::max(a.y(), b.y());
        order[j] = j;
    }
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return minX[a] < minX[b]; });
    int nextNode = static_cast<int>(m);
    std::vector<std::vector<int>> startsAt(m); // node → pieces starting there (grows)
    for (std::size_t oi = 0; oi < m; ++oi) {
        const std::size_t j = order[oi];
        for (std::size_t ok = oi + 1; ok < m && minX[order[ok]] <= maxX[j]; ++ok) {
            const std::size_t k = order[ok];
            if (k == (j + 1) % m || j == (k + 1) % m || minY[k] > maxY[j] || minY[j] > maxY[k]) {
                continue;
            }
            const Vec2 d1 = raw[(j + 1) % m] - raw[j];
            const Vec2 d2 = raw[(k + 1) % m] - raw[k];
            const double denom = sim::cross2d(d1, d2);
            if (denom == 0) {
                continue;
            }
            const Vec2 w = raw[k] - raw[j];
            const double s = sim::cross2d(w, d2) / denom;
            const double t = sim::cross2d(w, d1) / denom;
            if (s > 0 && s < 1 && t > 0 && t < 1) {
                cuts[j].push_back({s, nextNode});
                cuts[k].push_back({t, nextNode});
                ++nextNode;
            }
        }
    }
    startsAt.resize(static_cast<std::size_t>(nextNode));

    std::vector<Piece> pieces;
    pieces.reserve(m + 2 * static_cast<std::size_t>(nextNode - static_cast<int>(m)));
    for (std::size_t j = 0; j < m; ++j) {
        std::sort(cuts[j].begin(), cuts[j].end(),
                  [](const Cut& a, const Cut& b) { return a.s < b.s; });
        const Vec2 a = raw[j], d = raw[(j + 1) % m] - raw[j];
        double s0 = 0;
        int node0 = static_cast<int>(j);
        for (std::size_t c = 0; c <= cuts[j].size(); ++c) {
            const bool last = c == cuts[j].size();
            const double s1 = last ? 1.0 : cuts[j][c].s;
            const int node1 = last ? static_cast<int>((j + 1) % m) : cuts[j][c].node;
            Piece piece{a + s0 * d, a + s1 * d, node0, node1};
            const Vec2 mid = 0.5 * (piece.from + piece.to);
            // No side test is needed: a point of the raw offset that is at least the distance
            // from every edge lies on the offset side, for the straight line to the edge or
            // corner it comes from leaves that edge or corner to that side and does not cross
            // the loop (a crossing would be nearer).
            piece.keep = !near.anyNearer(mid);
            startsAt[static_cast<std::size_t>(node0)].push_back(static_cast<int>(pieces.size()));
            pieces.push_back(piece);
            s0 = s1;
            node0 = node1;
        }
    }

    std::vector<std::vector<Vec2>> loops;
    for (std::size_t first = 0; first < pieces.size(); ++first) {
        if (!pieces[first].keep || pieces[first].visited) {
            continue;
        }
        std::vector<Vec2> chain;
        int current = static_cast<int>(first);
        for (std::size_t steps = 0;; ++steps) {
            Piece& piece = pieces[static_cast<std::size_t>(current)];
            piece.visited = true;
            chain.push_back(piece.from);
            // At a crossing two pieces start: the one on the same segment and the one on the
            // other; the boundary switches strands there, so take the other when it is kept.
            const std::vector<int>& next = startsAt[static_cast<std::size_t>(piece.endNode)];
            int chosen = -1;
            for (int candidate : next) {
                if (pieces[static_cast<std::size_t>(candidate)].keep &&
                    (chosen < 0 || candidate != current + 1)) {
                    chosen = candidate;
                }
            }
            if (chosen == static_cast<int>(first)) {
                break;
            }
            if (chosen < 0 || pieces[static_cast<std::size_t>(chosen)].visited ||
                steps > pieces.size()) {
                return std::nullopt;
            }
            current = chosen;
        }
        chain = withoutRepeats(chain);
        if (chain.size() >= 3) {
            loops.push_back(std::move(chain));
        }
    }
    return loops;
}

} // namespace

std::vector<Vec2> loopPolyline(const Loop& loop, double tolerance) {
    std::vector<Vec2> points;
    for (const Segment& s : loop) {
        points.push_back(s.start);
        if (s.kind == SegmentKind::Line) {
            continue;
        }
        int pieces = 4;
        for (; pieces < 4096; pieces *= 2) {
            bool fine = true;
            for (int k = 0; k < pieces && fine; ++k) {
                fine = chordDeviation(s, static_cast<double>(k) / pieces,
                                      static_cast<double>(k + 1) / pieces) <= tolerance;
            }
            if (fine) {
                break;
            }
        }
        for (int k = 1; k < pieces; ++k) {
            points.push_back(pointAt(s, static_cast<double>(k) / pieces));
        }
    }
    return withoutRepeats(points);
}

double polylineArea(const std::vector<Vec2>& loop) {
    double area = 0;
    for (std::size_t i = 0; i < loop.size(); ++i) {
        area += 0.5 * sim::cross2d(loop[i], loop[(i + 1) % loop.size()]);
    }
    return area;
}

bool insidePolyline(const std::vector<Vec2>& loop, const Vec2& p) {
    bool inside = false;
    for (std::size_t i = 0, j = loop.size() - 1; i < loop.size(); j = i++) {
        const Vec2 &a = loop[i], &b = loop[j];
        if ((a.y() > p.y()) != (b.y() > p.y()) &&
            p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
            inside = !inside;
        }
    }
    return inside;
}

double distanceToPolyline(const std::vector<Vec2>& loop, const Vec2& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < loop.size(); ++i) {
        best = std::min(best, distanceToSegment(p, loop[i], loop[(i + 1) % loop.size()]));
    }
    return best;
}

std::vector<std::vector<Vec2>> offsetPolyline(const std::vector<Vec2>& loop, double distance,
                                              OffsetSide side, double tolerance) {
    std::vector<Vec2> clean = withoutRepeats(loop);
    if (clean.size() < 3 || !(distance > 0)) {
        return clean.size() < 3 ? std::vector<std::vector<Vec2>>{}
                                : std::vector<std::vector<Vec2>>{clean};
    }
    // Offset to the right: outside of a counter-clockwise loop, inside of a clockwise one.
    const bool counterClockwise = polylineArea(clean) > 0;
    const bool reversed = counterClockwise != (side == OffsetSide::Outside);
    if (reversed) {
        std::reverse(clean.begin(), clean.end());
    }
    std::vector<std::vector<Vec2>> loops;
    bool resolved = false;
    // A crossing exactly through a vertex cannot be told apart; a distance changed in its
    // ninth digit moves it off.
    for (double scale : {1.0, 1.0 + 1e-9, 1.0 - 1e-9}) {
        const double d = distance * scale;
        const auto trimmed = trimOffset(clean, rawOffset(clean, d, tolerance), d * (1 - 1e-9));
        if (trimmed) {
            loops = *trimmed;
            resolved = true;
            break;
        }
    }
    if (!resolved) {
        // Crossings that stay unresolved: the untrimmed offset, whose every point is at least
        // `distance` from the edge or corner it comes from.
        loops.push_back(rawOffset(clean, distance, tolerance));
    }
    // A loop smaller than the tolerance squared is a fold of the offset at an inner corner
    // turning so little that its depth is below the distance's rounding (a regular polygon of
    // 100,000 corners, offset inward, gave one per corner).
    std::erase_if(loops, [&](const std::vector<Vec2>& l) {
        return std::abs(polylineArea(l)) < tolerance * tolerance;
    });
    for (std::vector<Vec2>& l : loops) {
        l = withoutCollinear(l, 1e-3 * tolerance);
        if (reversed) {
            std::reverse(l.begin(), l.end());
        }
    }
    return loops;
}

} // namespace atelier::patterns
