#pragma once
// Mesh files are parsed from one buffer holding the whole text. Its size is capped, so that a
// file that cannot fit (a gzip bomb, a link to /dev/zero, an endless pipe) is refused with an
// IoError instead of running the machine out of memory.

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>

namespace sdmesh::io {

/// The largest text read into memory: a quarter of the machine's physical memory (1 GiB where
/// it cannot be told). The buffer grows by doubling, so reading peaks at about twice the text,
/// and the parsed mesh needs room beside it.
std::size_t max_text_bytes();

/// The whole file; reads in a loop rather than trusting the size up front (pipes, files that
/// grow while read).
/// \throws IoError "<file>: ..." if it cannot be read or holds more than max_bytes.
std::string read_file(const std::filesystem::path& path, std::size_t max_bytes);

/// \throws IoError "<file>: ... more than <size>, ..." for a text of more than max_bytes.
[[noreturn]] void throw_too_large(std::string_view file, std::string_view what, std::size_t max_bytes);

}  // namespace sdmesh::io
