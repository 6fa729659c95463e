#pragma once
/// Checks that every outline range is sewn at most once: no seam sews an edge to itself, no
/// seam repeats another, and no range takes part in two seams or in a seam and a dart (the
/// mesher pairs each boundary vertex with one partner; a range sewn twice would get points
/// from both seams, paired with neither one to one).

#include "patterns/garment.h"
#include "patterns/mesh.h"

#include <vector>

namespace atelier::patterns {

/// Appends an issue for each range that overlaps another one on the same outline segment (by
/// more than a point), at the later range's pointer (`/seams/4/b/0`, `/panels/1/darts/0`)
/// and naming the earlier one. Precondition: every seam range names an existing panel and
/// segment, and every dart's legs are in its outline (validateGarment checks this first).
void checkSewnRanges(const Garment& garment, std::vector<GarmentIssue>& issues);

} // namespace atelier::patterns
