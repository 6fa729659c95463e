#pragma once
/// Narrow-phase geometry of collisions: closest points, continuous (swept) tests, exact
/// triangle–triangle intersection. Free functions over points; no state. One header per
/// concept, all included here:
///  - distance/: closest points of a point and a triangle, of two segments;
///  - ccd/: continuous vertex–triangle and edge–edge tests (root finding on the coplanarity
///    cubic, conservative advancement, branch and bound);
///  - predicates/: the exact orientation predicate;
///  - intersection/: the exact triangle–triangle test;
///  - triangle_normal.h: the unit normal of a triangle.

#include "sim/collision/ccd/edge_edge_ccd.h"
#include "sim/collision/ccd/point_triangle_ccd.h"
#include "sim/collision/ccd/swept_hit.h"
#include "sim/collision/distance/edge_edge.h"
#include "sim/collision/distance/point_triangle.h"
#include "sim/collision/intersection/triangle_triangle.h"
#include "sim/collision/predicates/orient3d.h"
#include "sim/collision/triangle_normal.h"
#include "sim/core/types.h"

#include <Eigen/Geometry>

#include <array>
#include <optional>
