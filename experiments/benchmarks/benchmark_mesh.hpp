#pragma once
// The mesh a benchmark runs on: the file named by $SDMESH_BENCH_MESH, or a corpus mesh by default.
// Read once per process; benchmarks time what comes after reading.

#include <cstdlib>
#include <string>

#include "sdmesh/io.hpp"

namespace sdmesh::bench {

inline std::string mesh_path(const char* default_corpus_file) {
    if (const char* path = std::getenv("SDMESH_BENCH_MESH")) return path;
    return std::string(SDMESH_CORPUS_DIR) + "/" + default_corpus_file;
}

/// \pre every call in one program passes the same default (the mesh is cached on the first call).
inline const TriangleMesh& mesh(const char* default_corpus_file) {
    static const TriangleMesh loaded = read_mesh(mesh_path(default_corpus_file));
    return loaded;
}

}  // namespace sdmesh::bench
