#include "fuzz_case.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <fstream>
#include <sstream>
#include <utility>

namespace atelier::fuzz {

namespace fs = std::filesystem;

namespace {

constexpr std::array<std::pair<InputKind, std::string_view>, 6> SUFFIXES = {{
    {InputKind::Scene, ".scene.json"},
    {InputKind::Project, ".atelier"},
    {InputKind::Fabrics, ".fabrics.json"},
    {InputKind::Measurements, ".measurements.json"},
    {InputKind::GarmentCode, ".garmentcode.json"},
    {InputKind::Dxf, ".dxf"},
}};

/// The kind of a bundled asset from its `"format"` key (assets name scenes `NAME.json`).
std::optional<InputKind> kindOfContent(const std::string& text) {
    const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
    if (!doc.is_object() || !doc.contains("format") || !doc["format"].is_string()) {
        return std::nullopt;
    }
    const std::string format = doc["format"].get<std::string>();
    if (format == "atelier-scene") {
        return InputKind::Scene;
    }
    if (format == "atelier-project") {
        return InputKind::Project;
    }
    if (format == "atelier-fabrics") {
        return InputKind::Fabrics;
    }
    return std::nullopt;
}

std::optional<InputKind> kindOfFile(const fs::path& path, const std::string& text) {
    if (auto kind = kindOfName(path.filename().string())) {
        return kind;
    }
    return path.extension() == ".json" ? kindOfContent(text) : std::nullopt;
}

/// The case of a folder holding `case.<suffix>`, if it is one.
std::optional<FuzzCase> folderCase(const fs::path& dir) {
    for (const auto& [kind, suffix] : SUFFIXES) {
        if (fs::is_regular_file(dir / ("case" + std::string(suffix)))) {
            FuzzCase c;
            c.kind = kind;
            c.origin = dir.string();
            for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
                if (e.is_regular_file()) {
                    c.files[e.path().filename().string()] = readText(e.path());
                }
            }
            return c;
        }
    }
    return std::nullopt;
}

void collect(const fs::path& path, std::vector<FuzzCase>& out) {
    if (fs::is_directory(path)) {
        if (auto c = folderCase(path)) {
            out.push_back(std::move(*c));
            return;
        }
        std::vector<fs::path> entries;
        for (const fs::directory_entry& e : fs::directory_iterator(path)) {
            entries.push_back(e.path());
        }
        std::sort(entries.begin(), entries.end());
        for (const fs::path& entry : entries) {
            collect(entry, out);
        }
        return;
    }
    if (!fs::is_regular_file(path)) {
        return;
    }
    std::string text = readText(path);
    if (const auto kind = kindOfFile(path, text)) {
        FuzzCase c;
        c.kind = *kind;
        c.origin = path.string();
        c.files[c.mainName()] = std::move(text);
        out.push_back(std::move(c));
    }
}

} // namespace

std::string_view kindSuffix(InputKind kind) {
    for (const auto& [k, suffix] : SUFFIXES) {
        if (k == kind) {
            return suffix;
        }
    }
    return "";
}

std::optional<InputKind> kindOfName(std::string_view fileName) {
    for (const auto& [kind, suffix] : SUFFIXES) {
        if (fileName.size() > suffix.size() && fileName.ends_with(suffix)) {
            return kind;
        }
    }
    return std::nullopt;
}

std::string FuzzCase::mainName() const {
    return "case" + std::string(kindSuffix(kind));
}

std::vector<FuzzCase> readCases(const fs::path& root) {
    std::vector<FuzzCase> out;
    collect(root, out);
    return out;
}

void writeCase(const FuzzCase& c, const fs::path& dir) {
    fs::create_directories(dir);
    for (const auto& [name, text] : c.files) {
        std::ofstream(dir / name, std::ios::binary) << text;
    }
}

std::string readText(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

} // namespace atelier::fuzz
