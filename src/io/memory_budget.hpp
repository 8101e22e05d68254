#pragma once
// How much memory reading a mesh may take. Files are parsed from one buffer holding their whole
// text, and the text then grows into arrays of vertices and triangles (a line "f 1 1 1 ... 1" of
// one-digit corners becomes 12 bytes per corner). Both are capped, so that input that cannot fit
// (a gzip bomb, a link to /dev/zero, millions of degenerate polygons) is refused with an IoError
// instead of running the machine out of memory. Reading peaks at about half the usable memory.

#include <cstddef>
#include <filesystem>
#include <string_view>

namespace sdmesh::io {

/// The memory this process may use: the least of the machine's physical memory, the address
/// space and data limits (ulimit -v, -d) and the memory limits of its control groups.
std::size_t usable_memory();

/// The least memory limit of the control groups that `self_cgroup` (the text of /proc/self/cgroup)
/// names and of their ancestors, whose limits hold too, read below `cgroup_root` (/sys/fs/cgroup):
/// memory.max under cgroup v2 ("0::/path"), memory.limit_in_bytes under v1's memory controller
/// ("4:memory:/path"). SIZE_MAX where none is set or readable.
std::size_t cgroup_memory_limit(std::string_view self_cgroup, const std::filesystem::path& cgroup_root);

enum class MemoryUse { text, mesh };

/// The largest text read into memory: a quarter of usable_memory(). Its buffer grows by doubling,
/// so reading peaks at about twice the text.
std::size_t max_text_bytes();

/// The largest mesh parsed from a text, its vertices and triangles as read: a sixteenth of
/// usable_memory(). Converting a mesh takes about ten times that (the skull: 38 MB as read,
/// 403 MB at the peak of `sdmesh convert`).
std::size_t max_mesh_bytes();

/// \throws IoError "<file>: <what> more than <max_bytes>, the most ... (a quarter of the memory
/// this process may use)", the budget of `use` named.
[[noreturn]] void throw_too_large(std::string_view file, std::string_view what, MemoryUse use,
                                  std::size_t max_bytes);

}  // namespace sdmesh::io
