#pragma once
// The shared corpus of real meshes (../shared/data/meshes) and its MANIFEST.md, read so that
// tests compare against numbers nobody in this project computed.

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace sdmesh::test {

inline std::filesystem::path corpus_dir() { return SDMESH_CORPUS_DIR; }

inline bool corpus_available() { return std::filesystem::exists(corpus_dir() / "MANIFEST.md"); }

/// The cells of every manifest table row whose first cell is a `file name`, keyed by file name;
/// rows of both tables are concatenated (first table's cells first). Numbers keep their commas.
inline std::map<std::string, std::vector<std::string>> read_manifest() {
    std::map<std::string, std::vector<std::string>> rows;
    std::ifstream in(corpus_dir() / "MANIFEST.md");
    for (std::string line; std::getline(in, line);) {
        if (!line.starts_with("| `")) continue;
        std::vector<std::string> cells;
        std::stringstream ss(line.substr(1));
        for (std::string cell; std::getline(ss, cell, '|');) {
            const auto first = cell.find_first_not_of(' '), last = cell.find_last_not_of(' ');
            cells.push_back(first == std::string::npos ? "" : cell.substr(first, last - first + 1));
        }
        const std::string name = cells[0].substr(1, cells[0].size() - 2);
        auto& row = rows[name];
        row.insert(row.end(), cells.begin() + 1, cells.end());
    }
    return rows;
}

/// "1,234" -> 1234; "-16" -> -16.
inline long long manifest_number(std::string cell) {
    std::erase(cell, ',');
    return std::stoll(cell);
}

}  // namespace sdmesh::test
