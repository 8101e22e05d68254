// Whole files in memory, up to a size the caller gives.

#include "io/whole_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <system_error>

#include "io/errors.hpp"
#include "io/memory_budget.hpp"

namespace sdmesh::io {

std::string read_file(const std::filesystem::path& path, std::size_t max_bytes) {
    const std::string name = path.string();
    std::FILE* file = std::fopen(name.c_str(), "rb");
    if (file == nullptr) throw_io(name, "cannot open", errno);
    struct Closer {
        std::FILE* f;
        ~Closer() { std::fclose(f); }
    } closer{file};

    std::error_code ec;
    const std::uintmax_t size_hint = std::filesystem::file_size(path, ec);
    if (!ec && size_hint > max_bytes) throw_too_large(name, "holds", MemoryUse::text, max_bytes);
    // One byte more than allowed tells a file of exactly max_bytes from a larger one.
    const std::size_t cap = max_bytes + 1;
    std::string bytes(std::min<std::uintmax_t>(ec ? std::size_t{1} << 16 : size_hint + 1, cap), '\0');
    std::size_t used = 0;
    for (;;) {
        used += std::fread(bytes.data() + used, 1, bytes.size() - used, file);
        if (used > max_bytes) throw_too_large(name, "holds", MemoryUse::text, max_bytes);
        if (used < bytes.size()) break;  // end of file or error, told apart below
        bytes.resize(std::min(2 * bytes.size(), cap));
    }
    if (std::ferror(file) != 0) throw_io(name, "read failed", errno);
    bytes.resize(used);
    return bytes;
}

}  // namespace sdmesh::io
