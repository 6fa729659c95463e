#pragma once
/// Scene files: the versioned JSON format of assets/scenes (documented in
/// assets/scenes/README.md) read into a sim::SceneSpec.

#include "io/limits.h"
#include "io/materials.h"
#include "io/result.h"

#include "sim/scene.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace atelier::io {

/// Options of `loadScene`.
struct SceneLoadOptions {
    /// Fabric presets for `"material": "name"`. Empty = the scene's `"materials_file"` when it
    /// has one, else the built-in copy of assets/materials/fabrics.json.
    MaterialPresets presets;
    /// Run sim::Simulation::validate on the result (an error there names no JSON path).
    bool validate = true;
    /// Bounds on sizes, counts, frames and files (docs/file-formats.md).
    Limits limits;
};

/// Reads a scene file (`"format": "atelier-scene"`, `"version": 1`). Every key is checked:
/// unknown keys, wrong types, out-of-range values, unknown names and vertex indices out of
/// range are errors naming the JSON pointer (`scene.json: /cloths/0/material: unknown preset
/// "demin"`). Paths inside (OBJ meshes, materials file) are relative to the scene file.
Result<sim::SceneSpec> loadScene(const std::filesystem::path& path,
                                 const SceneLoadOptions& options = {});

/// Same as `loadScene` for JSON text. `file` names it in errors; relative paths inside are
/// resolved against `baseDir`.
Result<sim::SceneSpec> parseScene(std::string_view text, const std::string& file,
                                  const std::filesystem::path& baseDir,
                                  const SceneLoadOptions& options = {});

/// The local vertex index of the rectangle corner named `corner` ("top-left", "top-right",
/// "bottom-left", "bottom-right"; top = max warp y, left = min weft x) of a grid of
/// cellsX × cellsY cells (see sim::makeRectangle for the indexing); -1 for an unknown name.
int rectangleCorner(std::string_view corner, int cellsX, int cellsY);

} // namespace atelier::io
