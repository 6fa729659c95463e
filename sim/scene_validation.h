#pragma once
/// Checking a scene before it is built.

#include "sim/scene.h"

#include <optional>
#include <string>

namespace atelier::sim {

/// What is wrong with the scene, naming the cloth, obstacle, pin, drive or seam pair and the
/// vertex or triangle where it applies; nullopt when it can be simulated.
std::optional<std::string> validateScene(const SceneSpec& scene);

} // namespace atelier::sim
