#include "io/body_file.h"

#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/mesh_import.h"

#include <nlohmann/json.hpp>

namespace atelier::io {

namespace {

const std::string MEASUREMENTS_POINTER = "/body/measurements";

/// The error for the first problem checkMeasurements finds, at `pointer`/field.
std::optional<Error> checkAll(const patterns::BodyMeasurements& m, const std::string& file,
                              const std::string& pointer) {
    const auto issues = patterns::checkMeasurements(m);
    if (issues.empty()) {
        return std::nullopt;
    }
    return Error{file, detail::childPointer(pointer, issues.front().first), issues.front().second};
}

} // namespace

Result<patterns::BodyMeasurements> bodyMeasurements(const patterns::BodySource& source,
                                                    const std::string& file) {
    patterns::BodyMeasurements m;
    if (!patterns::baseMeasurements(source.base, m)) {
        return Error{file, "/body/base",
                     "unknown body base \"" + source.base + "\" (expected female or male)"};
    }
    const auto fields = patterns::measurementFields();
    for (const auto& [name, value] : source.measurements) {
        bool known = false;
        for (const auto& [fieldName, member] : fields) {
            if (fieldName == name) {
                m.*member = value;
                known = true;
            }
        }
        if (!known) {
            std::string list;
            for (const auto& [fieldName, member] : fields) {
                list += (list.empty() ? "" : ", ") + std::string(fieldName);
            }
            return Error{file, detail::childPointer(MEASUREMENTS_POINTER, name),
                         "unknown measurement \"" + name + "\" (known: " + list + ")"};
        }
    }
    if (auto error = checkAll(m, file, MEASUREMENTS_POINTER)) {
        return *error;
    }
    return m;
}

Result<patterns::Mannequin> makeBody(const patterns::BodySource& source, const std::string& file) {
    auto m = bodyMeasurements(source, file);
    if (!m.ok()) {
        return m.error();
    }
    return patterns::makeMannequin(source.base, m.value());
}

std::optional<std::string> checkBodyExtent(const sim::MatX3& vertices, double maxExtent) {
    if (vertices.rows() == 0) {
        return std::nullopt;
    }
    const sim::Vec3 extent = vertices.colwise().maxCoeff() - vertices.colwise().minCoeff();
    Eigen::Index axis = 0;
    if (!(extent.maxCoeff(&axis) <= maxExtent)) {
        return "the mesh is " + nlohmann::json(extent[axis]).dump() + " m along " +
               std::string(1, static_cast<char>('x' + axis)) + ", more than the " +
               nlohmann::json(maxExtent).dump() +
               " m a body may measure (a body mesh is in metres, Y up)";
    }
    return std::nullopt;
}

Result<patterns::Body> loadBody(const patterns::BodySource& source,
                                const std::filesystem::path& projectDir,
                                const std::filesystem::path& projectFile, const Limits& limits,
                                std::vector<std::string>* warnings) {
    if (source.meshPath.empty()) {
        auto mannequin = makeBody(source, projectFile.string());
        if (!mannequin.ok()) {
            return mannequin.error();
        }
        return std::move(mannequin).value().body;
    }
    const std::filesystem::path path = projectDir / source.meshPath;
    if (!std::filesystem::exists(path)) {
        return Error{projectFile.string(), "/body/mesh", "body mesh not found: " + path.string()};
    }
    auto imported = importBody(path, bodyImportOptions(source), limits);
    if (!imported.ok()) {
        return imported.error();
    }
    if (warnings != nullptr) {
        for (const std::string& w : imported.value().report.warnings) {
            warnings->push_back(path.string() + ": " + w);
        }
    }
    patterns::Body body;
    body.vertices = std::move(imported.value().vertices);
    body.triangles = std::move(imported.value().triangles);
    if (auto problem = patterns::estimateSlots(body)) {
        return Error{path.string(), "", *problem};
    }
    return body;
}

BodyImportOptions bodyImportOptions(const patterns::BodySource& source) {
    BodyImportOptions options;
    // The project reader checked the spellings.
    options.units = parseLengthUnit(source.meshUnits.empty() ? "auto" : source.meshUnits)
                        .value_or(LengthUnit::Auto);
    options.up = parseUpAxis(source.meshUp.empty() ? "auto" : source.meshUp).value_or(UpAxis::Auto);
    return options;
}

Result<patterns::BodySource> readMeasurementsFile(const std::filesystem::path& path,
                                                  const Limits& limits) {
    const std::string file = path.string();
    auto text = readFile(path, limits.maxJsonBytes);
    if (!text.ok()) {
        return text.error();
    }
    auto parsed = detail::parseJson(text.value(), file, limits.maxJsonDepth);
    if (!parsed.ok()) {
        return parsed.error();
    }
    patterns::BodySource source;
    try {
        detail::ObjectReader r(parsed.value(), "");
        source.base = r.string("base", source.base);
        for (const auto& [name, member] : patterns::measurementFields()) {
            if (const auto v = r.optionalNumber(name)) {
                source.measurements.emplace_back(std::string(name), *v);
            }
        }
        r.allow({"comment", "format"});
        r.finish();
    } catch (const detail::JsonError& e) {
        return Error{file, e.where, e.message};
    }
    patterns::BodyMeasurements m;
    if (!patterns::baseMeasurements(source.base, m)) {
        return Error{file, "/base",
                     "unknown body base \"" + source.base + "\" (expected female or male)"};
    }
    for (const auto& [name, value] : source.measurements) {
        for (const auto& [fieldName, member] : patterns::measurementFields()) {
            if (fieldName == name) {
                m.*member = value;
            }
        }
    }
    if (auto error = checkAll(m, file, "")) {
        return *error;
    }
    return source;
}

} // namespace atelier::io
