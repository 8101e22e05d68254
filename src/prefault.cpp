#include "prefault.hpp"

#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

namespace sdmesh::detail {
namespace {

#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
// madvise on the whole pages inside the block; a refusal (old kernel, feature disabled) only
// leaves the default behaviour.
void advise_whole_pages(void* data, std::size_t bytes, int advice) {
    static const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
    const auto begin = (reinterpret_cast<std::uintptr_t>(data) + page - 1) & ~(page - 1);
    const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(page - 1);
    if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, advice);
}
#endif

}  // namespace

void prefault(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    constexpr std::size_t kWorthIt = std::size_t(1) << 20;  // below this, faults are cheap enough
    if (data != nullptr && bytes >= kWorthIt) advise_whole_pages(data, bytes, MADV_POPULATE_WRITE);
#else
    (void)data;
    (void)bytes;
#endif
}

}  // namespace sdmesh::detail
