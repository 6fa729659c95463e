#include "io/batch_manifest.h"

#include "io/atomic_file.h"
#include "io/json_reader.h"
#include "io/materials.h"
#include "io/project_json.h"

#include <map>

namespace atelier::io {

namespace {

using detail::JsonError;
using detail::ObjectReader;
using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;

constexpr int MAX_PICTURE_SIDE = 4096;
constexpr int MAX_THREADS = 256;
constexpr std::size_t MAX_JOBS = 1'000'000;

/// What a job may set, and `defaults` too; unset fields keep the defaults'.
struct JobOptions {
    std::optional<std::string> bodyName;
    std::optional<patterns::BodySource> body;
    std::optional<std::string> fabric;
    std::optional<double> particleDistance;
    std::optional<double> timeLimit;
    std::optional<std::vector<std::string>> views;
    std::optional<std::pair<int, int>> size;
    std::optional<int> threads;
    std::optional<std::vector<std::string>> exports;
};

/// The manifest's named bodies: `"bodies": {"M": {"base": "female", ...}, ...}`.
using NamedBodies = std::map<std::string, patterns::BodySource, std::less<>>;

bool validJobName(std::string_view name) {
    if (name.empty() || name.size() > 200 || name == "." || name == "..") {
        return false;
    }
    for (const char c : name) {
        const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
                        (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
        if (!ok) {
            return false;
        }
    }
    return true;
}

std::vector<std::string> stringList(ObjectReader& r, std::string_view key) {
    const std::string ptr = r.pointerOf(key);
    const json& array = detail::arrayAt(r.require(key), ptr);
    std::vector<std::string> out;
    for (std::size_t i = 0; i < array.size(); ++i) {
        if (!array[i].is_string() || array[i].get<std::string>().empty()) {
            throw JsonError{detail::childPointer(ptr, i),
                            "must be a non-empty string, found " + detail::typeName(array[i])};
        }
        out.push_back(array[i].get<std::string>());
    }
    return out;
}

/// A body in a manifest, its mesh path made absolute against `baseDir`.
patterns::BodySource readBodyAt(const json& value, const ordered_json& ordered,
                                const std::string& pointer, const std::filesystem::path& baseDir) {
    patterns::BodySource body = detail::readBody(value, ordered, pointer);
    if (!body.meshPath.empty()) {
        const std::filesystem::path mesh = baseDir / body.meshPath;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(mesh, ec)) {
            throw JsonError{pointer + "/mesh", "body mesh not found: " + mesh.string()};
        }
        body.meshPath = std::filesystem::absolute(mesh).lexically_normal().string();
    }
    return body;
}

/// The job options of object `r` (a job, `defaults` or `matrix`); `body` may name one of
/// `bodies` or be a body object.
JobOptions readJobOptions(ObjectReader& r, const ordered_json& ordered, const NamedBodies& bodies,
                          const std::filesystem::path& baseDir) {
    JobOptions o;
    if (const json* body = r.find("body")) {
        const std::string ptr = r.pointerOf("body");
        if (body->is_string()) {
            const auto named = bodies.find(body->get<std::string>());
            if (named == bodies.end()) {
                throw JsonError{ptr, "no body named " + detail::inQuotes(body->get<std::string>()) +
                                         " in /bodies"};
            }
            o.bodyName = named->first;
            o.body = named->second;
        } else {
            o.body = readBodyAt(*body, ordered.at("body"), ptr, baseDir);
        }
    }
    if (const auto fabric = r.optionalString("fabric")) {
        if (!builtinMaterialPresets().contains(*fabric)) {
            std::string names;
            for (const auto& [name, material] : builtinMaterialPresets()) {
                names += (names.empty() ? "" : ", ") + detail::inQuotes(name);
            }
            r.fail("fabric", "unknown fabric preset " + detail::inQuotes(*fabric) +
                                 " (built-in presets: " + names + ")");
        }
        o.fabric = *fabric;
    }
    if (r.has("particle_distance_mm")) {
        const double mm = r.positive("particle_distance_mm");
        if (mm < 1 || mm > 1000) {
            r.fail("particle_distance_mm", "must be between 1 and 1000 mm");
        }
        o.particleDistance = mm / 1000;
    }
    if (r.has("time_limit_s")) {
        const double s = r.positive("time_limit_s");
        if (s > 3600) {
            r.fail("time_limit_s", "must be at most 3600 s");
        }
        o.timeLimit = s;
    }
    if (r.has("views")) {
        o.views = stringList(r, "views");
    }
    if (const json* size = r.find("size")) {
        const std::string ptr = r.pointerOf("size");
        const json& array = detail::arrayAt(*size, ptr);
        if (array.size() != 2) {
            throw JsonError{ptr, "must be [width, height] in pixels"};
        }
        const long long w = detail::integerAt(array[0], ptr + "/0");
        const long long h = detail::integerAt(array[1], ptr + "/1");
        if (w < 1 || h < 1 || w > MAX_PICTURE_SIDE || h > MAX_PICTURE_SIDE) {
            throw JsonError{ptr, "each side must be between 1 and " +
                                     std::to_string(MAX_PICTURE_SIDE) + " pixels"};
        }
        o.size = {static_cast<int>(w), static_cast<int>(h)};
    }
    if (r.has("threads")) {
        const long long threads = r.integer("threads");
        if (threads < 1 || threads > MAX_THREADS) {
            r.fail("threads", "must be between 1 and " + std::to_string(MAX_THREADS));
        }
        o.threads = static_cast<int>(threads);
    }
    if (r.has("exports")) {
        auto exports = stringList(r, "exports");
        for (std::size_t i = 0; i < exports.size(); ++i) {
            const std::string& e = exports[i];
            if (e != "obj" && e != "glb" && e != "fbx" && e != "ply") {
                throw JsonError{detail::childPointer(r.pointerOf("exports"), i),
                                "unknown export format " + detail::inQuotes(e) +
                                    " (formats: \"obj\", \"glb\", \"fbx\", \"ply\")"};
            }
        }
        o.exports = std::move(exports);
    }
    return o;
}

/// `over`'s fields where set, `base`'s otherwise.
JobOptions merged(const JobOptions& base, const JobOptions& over) {
    JobOptions o = base;
    if (over.body) {
        o.body = over.body;
        o.bodyName = over.bodyName;
    }
    const auto take = [](auto& into, const auto& from) {
        if (from) {
            into = from;
        }
    };
    take(o.fabric, over.fabric);
    take(o.particleDistance, over.particleDistance);
    take(o.timeLimit, over.timeLimit);
    take(o.views, over.views);
    take(o.size, over.size);
    take(o.threads, over.threads);
    take(o.exports, over.exports);
    return o;
}

std::filesystem::path projectPath(const std::string& text, const std::string& pointer,
                                  const std::filesystem::path& baseDir) {
    const std::filesystem::path path = baseDir / text;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        throw JsonError{pointer, "project not found: " + path.string()};
    }
    return std::filesystem::absolute(path).lexically_normal();
}

BatchJob makeJob(std::string name, std::filesystem::path project, const JobOptions& o,
                 std::string pointer) {
    BatchJob job;
    job.name = std::move(name);
    job.project = std::move(project);
    job.body = o.body;
    job.bodyLabel = o.bodyName.value_or(o.body ? "body" : "");
    job.fabric = o.fabric.value_or("");
    job.particleDistance = o.particleDistance;
    job.timeLimit = o.timeLimit;
    job.views = o.views.value_or(std::vector<std::string>{"three-quarter"});
    if (o.size) {
        job.width = o.size->first;
        job.height = o.size->second;
    }
    job.threads = o.threads.value_or(1);
    if (o.exports) {
        job.exports = *o.exports;
    }
    job.pointer = std::move(pointer);
    return job;
}

BatchManifest readManifest(const json& root, const ordered_json& ordered,
                           const std::filesystem::path& baseDir) {
    ObjectReader r(root, "");
    r.allow({"comment"});
    const std::string format = r.string("format");
    if (format != "atelier-batch") {
        r.fail("format", "expected \"atelier-batch\", found " + detail::inQuotes(format));
    }
    if (const long long version = r.integer("version"); version != 1) {
        r.fail("version",
               "unsupported version " + std::to_string(version) + " (this build reads version 1)");
    }
    NamedBodies bodies;
    if (const json* named = r.find("bodies")) {
        ObjectReader b(*named, r.pointerOf("bodies"));
        for (const auto& [name, value] : named->items()) {
            b.find(name);
            bodies.emplace(
                name, readBodyAt(value, ordered.at("bodies").at(name), b.pointerOf(name), baseDir));
        }
    }
    JobOptions defaults;
    if (const json* d = r.find("defaults")) {
        ObjectReader dr(*d, r.pointerOf("defaults"));
        defaults = readJobOptions(dr, ordered.at("defaults"), bodies, baseDir);
        dr.finish();
    }

    BatchManifest manifest;
    std::map<std::string, std::string> names; // name → pointer of the job that has it
    const auto add = [&](BatchJob job) {
        if (const auto [it, fresh] = names.emplace(job.name, job.pointer); !fresh) {
            throw JsonError{job.pointer, "job name " + detail::inQuotes(job.name) +
                                             " is already used at " + it->second};
        }
        if (manifest.jobs.size() >= MAX_JOBS) {
            throw JsonError{job.pointer, "more than " + std::to_string(MAX_JOBS) + " jobs"};
        }
        manifest.jobs.push_back(std::move(job));
    };

    detail::forEachIn(r, "jobs", [&](const json& value, const std::string& pointer) {
        ObjectReader jr(value, pointer);
        const std::string name = jr.string("name");
        if (!validJobName(name)) {
            jr.fail("name", "job name " + detail::inQuotes(name) +
                                " must be 1-200 letters, digits, '.', '_' or '-' (it names a "
                                "folder)");
        }
        const std::filesystem::path project =
            projectPath(jr.string("project"), jr.pointerOf("project"), baseDir);
        const std::size_t index = std::stoul(pointer.substr(pointer.rfind('/') + 1));
        const JobOptions o =
            merged(defaults, readJobOptions(jr, ordered.at("jobs").at(index), bodies, baseDir));
        jr.finish();
        add(makeJob(name, project, o, pointer));
    });

    if (const json* matrix = r.find("matrix")) {
        const std::string ptr = r.pointerOf("matrix");
        ObjectReader mr(*matrix, ptr);
        const std::vector<std::string> projects = stringList(mr, "projects");
        std::vector<std::string> bodyNames = {""};
        if (mr.has("bodies")) {
            bodyNames = stringList(mr, "bodies");
            for (std::size_t i = 0; i < bodyNames.size(); ++i) {
                if (!bodies.contains(bodyNames[i])) {
                    throw JsonError{detail::childPointer(mr.pointerOf("bodies"), i),
                                    "no body named " + detail::inQuotes(bodyNames[i]) +
                                        " in /bodies"};
                }
            }
        }
        std::vector<std::string> fabrics = {""};
        if (mr.has("fabrics")) {
            fabrics = stringList(mr, "fabrics");
            for (std::size_t i = 0; i < fabrics.size(); ++i) {
                if (!builtinMaterialPresets().contains(fabrics[i])) {
                    throw JsonError{detail::childPointer(mr.pointerOf("fabrics"), i),
                                    "unknown fabric preset " + detail::inQuotes(fabrics[i])};
                }
            }
        }
        const JobOptions common =
            merged(defaults, readJobOptions(mr, ordered.at("matrix"), bodies, baseDir));
        mr.finish();
        for (std::size_t p = 0; p < projects.size(); ++p) {
            const std::string pp = detail::childPointer(mr.pointerOf("projects"), p);
            const std::filesystem::path project = projectPath(projects[p], pp, baseDir);
            for (const std::string& bodyName : bodyNames) {
                for (const std::string& fabric : fabrics) {
                    JobOptions o = common;
                    std::string name = project.stem().string();
                    if (!bodyName.empty()) {
                        o.body = bodies.at(bodyName);
                        o.bodyName = bodyName;
                        name += "-" + bodyName;
                    }
                    if (!fabric.empty()) {
                        o.fabric = fabric;
                        name += "-" + fabric;
                    }
                    if (!validJobName(name)) {
                        throw JsonError{pp, "the job name " + detail::inQuotes(name) +
                                                " made from this project, body and fabric is "
                                                "not a valid folder name"};
                    }
                    add(makeJob(name, project, o, pp));
                }
            }
        }
    }
    r.finish();
    if (manifest.jobs.empty()) {
        r.fail("jobs", "no jobs: give \"jobs\" or \"matrix\"");
    }
    return manifest;
}

} // namespace

Result<BatchManifest> parseBatchManifest(std::string_view text, const std::string& file,
                                         const std::filesystem::path& baseDir,
                                         const Limits& limits) {
    const std::string textCopy(text);
    auto parsed = detail::parseJson(textCopy, file, limits.maxJsonDepth);
    if (!parsed.ok()) {
        return parsed.error();
    }
    // The same document keeping key order (a body's measurements are an ordered list).
    const ordered_json ordered = ordered_json::parse(textCopy);
    try {
        return readManifest(parsed.value(), ordered, baseDir);
    } catch (const JsonError& e) {
        return Error{file, e.where, e.message};
    }
}

Result<BatchManifest> loadBatchManifest(const std::filesystem::path& path, const Limits& limits) {
    auto text = readFile(path, limits.maxJsonBytes);
    if (!text.ok()) {
        return text.error();
    }
    return parseBatchManifest(text.value(), path.string(), path.parent_path(), limits);
}

std::vector<std::size_t> shardJobs(std::size_t jobCount, int index, int count) {
    std::vector<std::size_t> out;
    if (count < 1 || index < 0 || index >= count) {
        return out;
    }
    for (std::size_t k = static_cast<std::size_t>(index); k < jobCount;
         k += static_cast<std::size_t>(count)) {
        out.push_back(k);
    }
    return out;
}

std::uint64_t fingerprint(std::string_view text) {
    std::uint64_t h = 14695981039346656037ULL;
    for (const char c : text) {
        h ^= static_cast<unsigned char>(c);
        h *= 1099511628211ULL;
    }
    return h;
}

} // namespace atelier::io
