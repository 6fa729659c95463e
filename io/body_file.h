#pragma once
/// The body of a project: the parametric mannequin from a base and measurements, or a mesh
/// file; and measurement files for `atelier-cli body`.

#include "io/limits.h"
#include "io/mesh_import.h"
#include "io/result.h"

#include "patterns/mannequin.h"
#include "patterns/project.h"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace atelier::io {

/// The base's measurements with the source's overrides applied. Errors name `file` and the
/// JSON path (`/body/measurements/waist`): an unknown measurement, a value out of range or
/// measurements that do not fit together.
Result<patterns::BodyMeasurements> bodyMeasurements(const patterns::BodySource& source,
                                                    const std::string& file);

/// The import options of the source's mesh: its unit and up axis, detected where not given.
BodyImportOptions bodyImportOptions(const patterns::BodySource& source);

/// The mannequin of the source (meshPath empty).
Result<patterns::Mannequin> makeBody(const patterns::BodySource& source, const std::string& file);

/// The body a project drapes on: the mannequin, or the mesh at meshPath (relative to
/// projectDir; imported and normalised by importBody with the source's unit and up axis;
/// slots fitted to landmarks found from its shape, see patterns::estimateSlots). The mesh must
/// be a regular file of at most `limits.maxMeshBytes`, and no side of its normalised bounding
/// box longer than `limits.maxBodyExtent`. The import's warnings (holes, non-manifold edges),
/// each prefixed with the mesh file, are appended to `warnings` when given.
Result<patterns::Body> loadBody(const patterns::BodySource& source,
                                const std::filesystem::path& projectDir,
                                const std::filesystem::path& projectFile, const Limits& limits = {},
                                std::vector<std::string>* warnings = nullptr);

/// What is wrong when a body (or obstacle) mesh has a bounding-box side longer than `maxExtent`
/// [m], naming the length and the axis; nullopt when it fits.
std::optional<std::string> checkBodyExtent(const sim::MatX3& vertices, double maxExtent);

/// A measurements file: `{"base": "female", "height": 1.70, "waist": 0.72, ...}` (metres; every
/// key but `base` optional).
Result<patterns::BodySource> readMeasurementsFile(const std::filesystem::path& path,
                                                  const Limits& limits = {});

} // namespace atelier::io
