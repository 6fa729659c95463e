#pragma once
/// The body of a project: the parametric mannequin from a base and measurements, or a mesh
/// file; and measurement files for `atelier-cli body`.

#include "io/result.h"

#include "patterns/mannequin.h"
#include "patterns/project.h"

#include <filesystem>

namespace atelier::io {

/// The base's measurements with the source's overrides applied. Errors name `file` and the
/// JSON path (`/body/measurements/waist`): an unknown measurement, a value out of range or
/// measurements that do not fit together.
Result<patterns::BodyMeasurements> bodyMeasurements(const patterns::BodySource& source,
                                                    const std::string& file);

/// The mannequin of the source (meshPath empty).
Result<patterns::Mannequin> makeBody(const patterns::BodySource& source, const std::string& file);

/// The body a project drapes on: the mannequin, or the mesh at meshPath (relative to
/// projectDir; slots estimated from its proportions, see patterns::estimateSlots).
Result<patterns::Body> loadBody(const patterns::BodySource& source,
                                const std::filesystem::path& projectDir,
                                const std::filesystem::path& projectFile);

/// A measurements file: `{"base": "female", "height": 1.70, "waist": 0.72, ...}` (metres; every
/// key but `base` optional).
Result<patterns::BodySource> readMeasurementsFile(const std::filesystem::path& path);

} // namespace atelier::io
