#pragma once
// Mesh files are parsed from one buffer holding the whole text, read within a cap
// (memory_budget.hpp), so that a link to /dev/zero or an endless pipe is refused, not read.

#include <cstddef>
#include <filesystem>
#include <string>

namespace sdmesh::io {

/// The whole file; reads in a loop rather than trusting the size up front (pipes, files that
/// grow while read).
/// \throws IoError "<file>: ..." if it cannot be read or holds more than max_bytes.
std::string read_file(const std::filesystem::path& path, std::size_t max_bytes);

}  // namespace sdmesh::io
