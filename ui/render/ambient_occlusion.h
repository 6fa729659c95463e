#pragma once
/// A cheap ambient-occlusion approximation from distances, computed per vertex on the CPU.

#include "ui/render/scene.h"

#include <vector>

namespace atelier::render {

struct AmbientOcclusionOptions {
    double radius = 0.08;  ///< the farthest sample from the surface [m] (a hand's breadth)
    int samples = 4;       ///< samples along the normal, at radius/2^(samples−1) ... radius
    double strength = 1.0; ///< visibility = 1 − strength · occlusion, clamped to [0, 1]
};

/// For each mesh of the scene, each vertex's visibility in [0, 1] (1 = open sky): at points
/// q_k = p + r_k n along the vertex normal, the distance d_k to the nearest surface of any mesh
/// of the scene (itself included) is compared with r_k; a flat or convex neighbourhood gives
/// d_k = r_k, a crease, an armpit or cloth close to the body gives less. The occlusion is the
/// mean of (r_k − d_k)/r_k (Evans, "Fast approximations for global illumination on dynamic
/// scenes", SIGGRAPH 2006 course; sampled distances as in distance-field AO).
///
/// \f$v = 1 - s\,\frac{1}{K}\sum_k \max(0, r_k - d_k)/r_k\f$
std::vector<std::vector<float>> ambientOcclusion(const Scene& scene,
                                                 const AmbientOcclusionOptions& options = {});

} // namespace atelier::render
