#pragma once
/// A skinned, animated body (glTF 2.0, FBX, COLLADA through assimp) sampled frame by frame into
/// a body motion: the skeleton's node animation evaluated at each sample time, the meshes
/// skinned on the CPU (linear blend), the frames normalised as importBodyMotion does.

#include "io/limits.h"
#include "io/mesh_import.h"
#include "io/result.h"

#include <filesystem>
#include <string>

namespace atelier::io {

struct BodyAnimationOptions {
    BodyImportOptions import; ///< unit, up axis and weld of the first frame (as importBody)
    /// The animation sampled: its name, or its index in the file when no animation has that
    /// name; empty = the first (a warning lists the others when there are several).
    std::string animation;
    double fps = 30;      ///< frames sampled per second [1/s]
    double start = 0;     ///< start of the window sampled, from the animation's time 0 [s]
    double duration = -1; ///< length of the window sampled [s]; < 0 = to the animation's end
};

/// Samples an animation of a skinned body at `options.fps` over its duration (or the window
/// `start`, `duration`): frame k at t = start + k / fps, as many frames as fit the window.
///
/// At each time every node's local transform is T·R·S from its channel's keys (linear between
/// keys, rotations by spherical interpolation; before the first key the first, after the last
/// the last; a node without a channel keeps its own transform), times in the animation's ticks
/// (its ticks per second; 25 when the file gives none, as assimp's viewer assumes). A skinned
/// vertex is \f$ x = \sum_b w_b\, G_b(t)\, O_b\, x_0 / \sum_b w_b \f$ with \f$ G_b \f$ the bone
/// node's global transform and \f$ O_b \f$ its offset (inverse bind) matrix: that is already in
/// scene coordinates, so the mesh node's own transform is not applied (glTF 2.0, "Skins"); a
/// mesh without bones, or a vertex without weights, follows its node's global transform.
///
/// The first frame is normalised as importBody does (unit and up axis detected or given, the
/// weld, standing on y = 0); every frame gets its unit, up axis, floor offset and weld
/// (placeAsFirstFrame), so the motion is kept. `files` holds the path once per frame;
/// warnings (several animations, morph channels not applied) go to `first.report.warnings`.
///
/// Errors name the file: no animation, no skinned or animated mesh, an unknown animation name
/// or an index out of range (the message lists the file's animations), a duration of zero, a
/// non-finite key, offset matrix or weight, a bone naming no node, a window outside the
/// animation or under two frames, more frames than `limits.maxFrames`, or more vertices over
/// all frames than `limits.maxBodyVertices`.
Result<BodyMotion> importBodyAnimation(const std::filesystem::path& path,
                                       const BodyAnimationOptions& options = {},
                                       const Limits& limits = {});

} // namespace atelier::io
