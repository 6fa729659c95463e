#include "app/cli/preflight.h"

#include <unistd.h>

#include <system_error>

namespace atelier::app {

namespace {

namespace fs = std::filesystem;

/// The path as compared: absolute, with `.`, `..` and the links of its existing part resolved.
fs::path canonicalOf(const fs::path& path) {
    std::error_code ec;
    fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
    return ec ? fs::absolute(path).lexically_normal() : p;
}

std::string where(const NamedPath& p) {
    return p.flag + ": " + p.path.string() + ": ";
}

std::optional<std::string> checkFolderOf(const NamedPath& out) {
    std::error_code ec;
    if (fs::is_directory(out.path, ec)) {
        return where(out) + "is a folder, not a file";
    }
    fs::path dir = fs::absolute(out.path, ec).parent_path();
    if (!fs::exists(dir, ec)) {
        return where(out) + "the folder " + dir.string() + " does not exist";
    }
    if (!fs::is_directory(dir, ec)) {
        return where(out) + dir.string() + " is not a folder";
    }
    if (::access(dir.c_str(), W_OK | X_OK) != 0) {
        return where(out) + "the folder " + dir.string() + " is not writable";
    }
    return std::nullopt;
}

} // namespace

std::optional<std::string> checkOutputs(const std::vector<NamedPath>& inputs,
                                        const std::vector<NamedPath>& outputs) {
    std::vector<std::pair<fs::path, const NamedPath*>> seen;
    for (const NamedPath& in : inputs) {
        if (!in.path.empty()) {
            seen.emplace_back(canonicalOf(in.path), &in);
        }
    }
    const std::size_t inputCount = seen.size();
    for (const NamedPath& out : outputs) {
        if (out.path.empty()) {
            continue;
        }
        if (auto problem = checkFolderOf(out)) {
            return problem;
        }
        const fs::path c = canonicalOf(out.path);
        for (std::size_t k = 0; k < seen.size(); ++k) {
            if (seen[k].first == c) {
                const NamedPath& other = *seen[k].second;
                return where(out) + (k < inputCount ? "is the input " : "is also the output of ") +
                       other.flag + " (" + other.path.string() + ")";
            }
        }
        seen.emplace_back(c, &out);
    }
    return std::nullopt;
}

std::optional<std::string> checkOutputFolder(const NamedPath& folder,
                                             const std::vector<NamedPath>& files) {
    if (folder.path.empty()) {
        return std::nullopt;
    }
    std::error_code ec;
    if (fs::exists(folder.path, ec) && !fs::is_directory(folder.path, ec)) {
        return where(folder) + "exists and is not a folder";
    }
    const fs::path c = canonicalOf(folder.path);
    for (const NamedPath& f : files) {
        if (!f.path.empty() && canonicalOf(f.path) == c) {
            return where(folder) + "is also " + f.flag;
        }
    }
    return std::nullopt;
}

std::optional<std::string> checkVertexLimit(const std::string& what, long estimate, long limit) {
    if (estimate <= limit) {
        return std::nullopt;
    }
    return what + " would have about " + std::to_string(estimate) +
           " vertices, above the limit of " + std::to_string(limit) +
           " (--max-vertices N raises it)";
}

} // namespace atelier::app
