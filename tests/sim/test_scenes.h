#pragma once
// Small generated scenes shared by the engine tests.

#include "sim/collision/collision_stage.h"
#include "sim/simulation.h"

namespace atelier::test {

/// A square sheet of `cells`×`cells` in the vertical plane z = 0 (pattern x → world x,
/// pattern y → world y) or, when `horizontal`, in the plane y = 0 (pattern y → world −z),
/// optionally pinned at its two "top" corners (pattern y = size).
inline sim::SceneSpec smallSheet(sim::StretchModel model, int cells = 4, double size = 1.0,
                                 bool pinTopCorners = true, bool horizontal = false) {
    sim::SceneSpec s;
    sim::ClothSpec c;
    sim::RectangleOptions r;
    r.width = size;
    r.height = size;
    r.cellsX = cells;
    r.cellsY = cells;
    sim::MatX2 rest;
    sim::MatX3i tris;
    sim::makeRectangle(r, rest, tris);
    (void)sim::buildClothMesh(rest, tris, c.mesh);
    c.position.resize(rest.rows(), 3);
    for (int i = 0; i < rest.rows(); ++i) {
        if (horizontal) {
            c.position.row(i) << rest(i, 0), 0.0, -rest(i, 1);
        } else {
            c.position.row(i) << rest(i, 0), rest(i, 1), 0.0;
        }
    }
    c.model = model;
    s.cloths.push_back(c);
    if (pinTopCorners) {
        s.pins = {cells * (cells + 1), (cells + 1) * (cells + 1) - 1};
    }
    return s;
}

/// Exact triangle–triangle intersections at the simulation's current positions: all of them,
/// and in `withObstacles` (if given) those between cloth and obstacles.
inline long intersections(const sim::Simulation& simulation, long* withObstacles = nullptr) {
    return simulation.intersectingTrianglePairs(withObstacles);
}

} // namespace atelier::test
