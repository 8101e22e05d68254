// The memory budgets of reading, from what the machine and the system let this process use.

#include "io/memory_budget.hpp"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include <sys/resource.h>
#include <unistd.h>

#include "sdmesh/error.hpp"

namespace sdmesh::io {
namespace {

// The number a cgroup file holds ("max" or anything else unreadable: no limit).
std::size_t read_limit(const std::filesystem::path& file) {
    std::ifstream in(file);
    std::string text;
    std::size_t limit = SIZE_MAX;
    if (in >> text) std::from_chars(text.data(), text.data() + text.size(), limit);
    return limit;
}

std::string self_cgroup() {
    std::ifstream in("/proc/self/cgroup");
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::size_t resource_limit(int resource) {
    rlimit limit{};
    if (::getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return SIZE_MAX;
    return static_cast<std::size_t>(limit.rlim_cur);
}

}  // namespace

std::size_t cgroup_memory_limit(std::string_view self_cgroup, const std::filesystem::path& cgroup_root) {
    std::size_t limit = SIZE_MAX;
    std::istringstream lines{std::string(self_cgroup)};
    for (std::string line; std::getline(lines, line);) {
        const auto first = line.find(':'), second = line.find(':', first + 1);
        if (first == std::string::npos || second == std::string::npos) continue;
        const std::string controllers = line.substr(first + 1, second - first - 1);
        std::filesystem::path root, file;
        if (line.compare(0, first, "0") == 0 && controllers.empty()) {
            root = cgroup_root;
            file = "memory.max";
        } else if (("," + controllers + ",").find(",memory,") != std::string::npos) {
            root = cgroup_root / "memory";
            file = "memory.limit_in_bytes";
        } else {
            continue;
        }
        // Inside a cgroup namespace the path may not exist below the mount: its files are missed.
        for (std::filesystem::path group = line.substr(second + 1);; group = group.parent_path()) {
            limit = std::min(limit, read_limit(root / group.relative_path() / file));
            if (!group.has_relative_path()) break;
        }
    }
    return limit;
}

std::size_t usable_memory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page_size = ::sysconf(_SC_PAGE_SIZE);
    const std::size_t physical = pages > 0 && page_size > 0
                                     ? static_cast<std::size_t>(pages) * static_cast<std::size_t>(page_size)
                                     : std::size_t{4} << 30;
    return std::min({physical, resource_limit(RLIMIT_AS), resource_limit(RLIMIT_DATA),
                     cgroup_memory_limit(self_cgroup(), "/sys/fs/cgroup")});
}

std::size_t max_text_bytes() { return usable_memory() / 4; }

std::size_t max_mesh_bytes() { return usable_memory() / 16; }

void throw_too_large(std::string_view file, std::string_view what, MemoryUse use, std::size_t max_bytes) {
    const std::string size = max_bytes >= (std::size_t{1} << 20) ? std::to_string(max_bytes >> 20) + " MiB"
                                                                  : std::to_string(max_bytes) + " bytes";
    const std::string budget = use == MemoryUse::text
                                   ? "the most text read into memory (a quarter of the memory this process may use)"
                                   : "the most a mesh read may take (a sixteenth of the memory this process may use)";
    throw IoError(std::string(file) + ": " + std::string(what) + " more than " + size + ", " + budget);
}

}  // namespace sdmesh::io
