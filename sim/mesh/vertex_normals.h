#pragma once
/// Vertex normals of a triangle mesh, for drawing and export.

#include "sim/core/types.h"

namespace atelier::sim {

/// Unit vertex normals (|V|×3) of the mesh at positions x (|V|×3): the sum of the incident
/// triangles' normals weighted by their area, normalised; (0, 0, 1) for a vertex with none (or
/// only degenerate ones). Counter-clockwise triangles give outward normals.
void vertexNormals(const MatX3& x, const MatX3i& triangles, MatX3& normals);

} // namespace atelier::sim
