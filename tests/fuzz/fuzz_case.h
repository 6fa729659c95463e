#pragma once
/// A fuzz case: the main input (a scene, a project, a fabric preset file, a measurements
/// file or a GarmentCode specification) and the files beside it that it names (OBJ meshes, a
/// materials file), as text. Cases are read from the seed corpus and the regression folder and
/// written to a folder to run.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::fuzz {

/// The name of the FIFO written beside every case when it runs (a path in a case may name it).
inline constexpr const char* FIFO_NAME = "fifo";

/// What the main file is, and so which io loader reads it.
enum class InputKind { Scene, Project, Fabrics, Measurements, GarmentCode, Dxf };

/// The file name ending that says a file's kind: `.scene.json`, `.atelier`, `.fabrics.json`,
/// `.measurements.json`, `.garmentcode.json`.
std::string_view kindSuffix(InputKind kind);
/// The kind a file name ends with, if any.
std::optional<InputKind> kindOfName(std::string_view fileName);

struct FuzzCase {
    InputKind kind = InputKind::Scene;
    std::string origin; ///< where it was read from (a path), for reports
    /// File name → content; the main file is `mainName()`, the others sit beside it.
    std::map<std::string, std::string> files;

    /// `case` + the kind's suffix.
    std::string mainName() const;
    const std::string& main() const { return files.at(mainName()); }
    std::string& main() { return files.at(mainName()); }
};

/// Reads the cases under `root`:
/// - a file whose name ends with a kind suffix, or a bundled asset whose `"format"` is one of
///   ours (`atelier-scene`, `atelier-project`, `atelier-fabrics`), is a case alone;
/// - a folder holding a `case.<suffix>` file is one case with every file in it;
/// - any other folder is searched recursively; other files are left out.
/// Cases come sorted by path, so a seed names the same inputs on every machine.
std::vector<FuzzCase> readCases(const std::filesystem::path& root);

/// Writes the files of `c` into `dir` (created if needed).
void writeCase(const FuzzCase& c, const std::filesystem::path& dir);

/// The whole content of a file (empty when it cannot be read).
std::string readText(const std::filesystem::path& path);

} // namespace atelier::fuzz
