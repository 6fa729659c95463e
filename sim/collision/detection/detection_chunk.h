#pragma once
/// The parallel pieces of a detection pass: each piece of the candidate pairs writes its own
/// output, and the outputs concatenated in piece order give what a serial loop gives.

#include "sim/collision/contact.h"
#include "sim/core/parallel.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace atelier::sim {

/// What one piece of a parallel detection loop found (parallelChunks): concatenated in piece
/// order, the pieces give what a serial loop gives.
struct DetectionChunk {
    std::vector<Contact> contacts;
    std::vector<std::uint64_t> keys; ///< per contact: memory key (self vertex–face), else 0
    std::vector<signed char> sides;  ///< per contact: side of its face (self vertex–face)
    std::vector<char> reliable;      ///< per contact: side remembered or seen arriving (swept)
    std::vector<int> hits;           ///< fail-safe: vertices of crossing features
    std::vector<std::pair<int, int>> crossingPairs; ///< fail-safe: triangle pairs with a hit
    /// per obstacle contact: its features (ObstaclePass::First)
    std::vector<std::array<int, 2>> features;
    long continuousHits = 0;
    void clear() {
        contacts.clear();
        keys.clear();
        sides.clear();
        reliable.clear();
        hits.clear();
        crossingPairs.clear();
        features.clear();
        continuousHits = 0;
    }
};

/// What a detection pass leaves for its caller: how many pieces of the scratch hold its
/// findings (the first ones, to be gathered in order) and how many candidate pairs it tested.
struct DetectionResult {
    std::size_t pieces = 0;
    long candidatePairs = 0;
};

/// Scratch shared by the detection passes (and the fail-safe), kept between steps so that its
/// buffers are allocated once.
struct DetectionScratch {
    std::vector<std::pair<int, int>> pairs; ///< candidate triangle pairs of the current pass
    std::vector<DetectionChunk> chunks;     ///< one output per parallel piece
    std::vector<char> extracting;           ///< obstacle pass: per cloth, being carried out of it
    std::vector<char> movedTriangle; ///< ObstaclePass::Again: per triangle, moved since First

    /// Runs body(chunk, pair) over `pairs` in parallel pieces, each piece into its own cleared
    /// DetectionChunk; returns the number of pieces used (the first ones of `chunks`).
    template <class Body> std::size_t inChunks(Body&& body) {
        const std::int64_t n = static_cast<std::int64_t>(pairs.size());
        const std::size_t used = static_cast<std::size_t>(chunkCount(n));
        if (chunks.size() < used) {
            chunks.resize(used);
        }
        parallelChunks(n, [&](std::int64_t c, std::int64_t begin, std::int64_t end) {
            DetectionChunk& out = chunks[static_cast<std::size_t>(c)];
            out.clear();
            for (std::int64_t i = begin; i < end; ++i) {
                body(out, pairs[static_cast<std::size_t>(i)]);
            }
        });
        return used;
    }
};

} // namespace atelier::sim
