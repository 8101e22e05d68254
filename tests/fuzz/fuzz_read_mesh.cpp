// libFuzzer target: the mesh readers (OBJ, OFF, PLY, STL, optionally gzip) on arbitrary bytes.
// A reader may only return a mesh or throw sdmesh::Error; anything else (another exception, a
// sanitizer report, a hang) is a bug. A returned mesh must hold what the reader promises.

#include <cstdlib>

#include "fuzz_input.hpp"
#include "sdmesh/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const sdmesh::TriangleMesh mesh = sdmesh::fuzz::parse_fuzz_input(data, size);
        // Readers check every index against the vertices they read (io.hpp).
        sdmesh::require_indices_in_range(mesh);
    } catch (const sdmesh::ParseError&) {
    } catch (const sdmesh::UnsupportedFormatError&) {
    } catch (const sdmesh::InvalidMeshError&) {
        std::abort();  // a reader returned an index out of range
    }
    return 0;
}
