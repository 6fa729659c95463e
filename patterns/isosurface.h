#pragma once
/// Closed triangle meshes of implicit surfaces: marching tetrahedra on a regular grid, then
/// tangential relaxation with projection back onto the surface.

#include "sim/core/types.h"

#include <functional>

namespace atelier::patterns {

/// f(p) < 0 inside, > 0 outside; smooth near the zero set.
using ImplicitFunction = std::function<double(const sim::Vec3&)>;

struct IsosurfaceOptions {
    sim::Vec3 boxMin = sim::Vec3::Constant(-1); ///< the surface must lie strictly inside [m]
    sim::Vec3 boxMax = sim::Vec3::Constant(1);
    double cell = 0.02;      ///< grid spacing [m]
    int relaxIterations = 6; ///< tangential smoothing + edge flips + projection rounds
};

struct Isosurface {
    sim::MatX3 vertices;   ///< on the zero set (within projection tolerance) [m]
    sim::MatX3 normals;    ///< unit gradients of f at the vertices
    sim::MatX3i triangles; ///< counter-clockwise seen from outside (f > 0)
};

/// The zero set of f inside the box. Marching tetrahedra (six Kuhn tetrahedra per cell) on a
/// piecewise-linear interpolant gives a closed, oriented 2-manifold wherever the surface stays
/// inside the box; grid values that are exactly zero are moved to the outside. The relaxation
/// moves vertices within their tangent planes toward their neighbours' centroid, flips edges
/// whose opposite angles sum beyond π where the surface is flat enough, and projects vertices
/// back onto f = 0 by Newton steps along the gradient: topology is never changed.
Isosurface extractIsosurface(const ImplicitFunction& f, const IsosurfaceOptions& options);

/// Unit gradient of f at p by central differences of step h.
sim::Vec3 implicitNormal(const ImplicitFunction& f, const sim::Vec3& p, double h);

} // namespace atelier::patterns
