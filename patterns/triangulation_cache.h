#pragma once
/// Triangulations remembered by their exact input, so that meshing a garment again after an
/// edit triangulates only the panels whose boundary, holes, lines or mesh size changed.

#include "patterns/triangulate.h"

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace atelier::patterns {

class TriangulationCache {
  public:
    /// triangulate(input, out), or the output of an earlier call with the same input (the
    /// triangulation is deterministic, so this is the same mesh to the bit).
    std::optional<std::string> triangulate(const TriangulationInput& input,
                                           TriangulationOutput& out);
    /// Triangulations computed (not found in the cache) so far.
    long computed() const { return m_computed; }
    std::size_t size() const { return m_size; }
    void clear();

  private:
    struct Entry {
        TriangulationInput input;
        TriangulationOutput output;
    };
    std::unordered_map<std::uint64_t, std::vector<Entry>> m_entries;
    std::size_t m_size = 0;
    long m_computed = 0;
};

} // namespace atelier::patterns
