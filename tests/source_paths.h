#pragma once
// Paths into the source tree that tests read (ATELIER_SOURCE_DIR, set by tests/CMakeLists.txt).

#include <filesystem>
#include <string>

namespace atelier::test {

/// The bundled sample garments (assets/garments/*.atelier).
inline const std::filesystem::path GARMENTS_DIR =
    std::filesystem::path(ATELIER_SOURCE_DIR) / "assets/garments";

/// The skirt sample's project file.
inline const std::string SKIRT_PROJECT = (GARMENTS_DIR / "skirt.atelier").string();

} // namespace atelier::test
