#pragma once
/// The rows of a CSV the benches and tools write (no quoted cells), each split at its commas.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace atelier::test {

/// Every line of `path`, header included, as its comma-separated cells.
inline std::vector<std::vector<std::string>> csvRows(const std::filesystem::path& path) {
    std::ifstream in(path);
    std::vector<std::vector<std::string>> rows;
    std::string line;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream s(line);
        std::string cell;
        while (std::getline(s, cell, ',')) {
            cells.push_back(cell);
        }
        rows.push_back(std::move(cells));
    }
    return rows;
}

} // namespace atelier::test
