#include "patterns/triangulation_cache.h"

#include <algorithm>
#include <bit>

namespace atelier::patterns {

namespace {

/// Entries kept at most (a garment has tens of panels; a session edits a few at a time).
constexpr std::size_t MAX_ENTRIES = 512;

/// FNV-1a over raw bytes.
void mix(std::uint64_t& h, const void* data, std::size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < bytes; ++i) {
        h = (h ^ p[i]) * 1099511628211ull;
    }
}

std::uint64_t hashOf(const TriangulationInput& in) {
    std::uint64_t h = 14695981039346656037ull;
    for (const sim::Vec2& p : in.points) {
        mix(h, p.data(), 2 * sizeof(double));
    }
    for (const auto& c : in.constraints) {
        mix(h, c.data(), sizeof c);
    }
    for (const sim::Vec2& p : in.holeSeeds) {
        mix(h, p.data(), 2 * sizeof(double));
    }
    mix(h, &in.maxEdge, sizeof in.maxEdge);
    mix(h, &in.minAngleDeg, sizeof in.minAngleDeg);
    mix(h, &in.lloydIterations, sizeof in.lloydIterations);
    return h;
}

/// The same bits (a point moved by one ulp is another input; -0 and +0 differ).
bool sameBits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

bool same(const TriangulationInput& a, const TriangulationInput& b) {
    const auto samePoints = [](const std::vector<sim::Vec2>& x, const std::vector<sim::Vec2>& y) {
        return x.size() == y.size() && std::equal(x.begin(), x.end(), y.begin(),
                                                  [](const sim::Vec2& p, const sim::Vec2& q) {
                                                      return sameBits(p.x(), q.x()) &&
                                                             sameBits(p.y(), q.y());
                                                  });
    };
    return samePoints(a.points, b.points) && samePoints(a.holeSeeds, b.holeSeeds) &&
           a.constraints == b.constraints && sameBits(a.maxEdge, b.maxEdge) &&
           sameBits(a.minAngleDeg, b.minAngleDeg) && a.lloydIterations == b.lloydIterations;
}

} // namespace

std::optional<std::string> TriangulationCache::triangulate(const TriangulationInput& input,
                                                           TriangulationOutput& out) {
    const std::uint64_t key = hashOf(input);
    auto& bucket = m_entries[key];
    for (const Entry& e : bucket) {
        if (same(e.input, input)) {
            out = e.output;
            return std::nullopt;
        }
    }
    ++m_computed;
    if (auto err = patterns::triangulate(input, out)) {
        return err;
    }
    if (m_size >= MAX_ENTRIES) {
        clear();
    }
    m_entries[key].push_back({input, out});
    ++m_size;
    return std::nullopt;
}

void TriangulationCache::clear() {
    m_entries.clear();
    m_size = 0;
}

} // namespace atelier::patterns
