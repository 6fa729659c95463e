#pragma once
/// Collision obstacles: generated shapes (plane, sphere, box, capsule) and the motion of an
/// obstacle (rigid keyframes or per-vertex frames) evaluated at a time.

#include "sim/scene.h"

namespace atelier::sim {

/// A square of side `size` [m] in the XZ plane centred at the origin, normal +Y, split into
/// cells×cells squares (two triangles each). Open (two-sided).
void makePlaneMesh(double size, int cells, MatX3& vertices, MatX3i& triangles);
/// Icosphere of `radius` [m] centred at the origin, `subdivisions` times refined
/// (20·4^s triangles). Closed, outward normals.
void makeSphereMesh(double radius, int subdivisions, MatX3& vertices, MatX3i& triangles);
/// Box of full extents `size` [m] centred at the origin, each face split into cells×cells
/// squares. Closed, outward normals.
void makeBoxMesh(const Vec3& size, int cells, MatX3& vertices, MatX3i& triangles);
/// Capsule along Y: a cylinder of `radius` and `length` [m] (between the hemisphere centres)
/// capped by hemispheres, centred at the origin, `segments` around. Closed, outward normals.
/// Length 0 gives a latitude–longitude sphere (`segments` around, `segments`/2 from pole to pole).
void makeCapsuleMesh(double radius, double length, int segments, MatX3& vertices,
                     MatX3i& triangles);

/// Whether every edge of the mesh has exactly two triangles that traverse it in opposite
/// directions (watertight and consistently oriented).
bool isClosedOriented(const MatX3i& triangles, int vertexCount);

/// World positions of the obstacle's vertices at time t [s] (|V|×3).
void obstaclePositionsAt(const ObstacleSpec& obstacle, double t, MatX3& out);

/// Whether the obstacle moves at all (keys with different poses, or animation frames).
bool obstacleMoves(const ObstacleSpec& obstacle);

/// Next time after t at which the obstacle's motion has a kink (a key or frame), or +inf.
double nextObstacleEvent(const ObstacleSpec& obstacle, double t);

} // namespace atelier::sim
