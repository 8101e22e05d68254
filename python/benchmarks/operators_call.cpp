// The C++ side of python_overhead.py: the calls sdmesh.operators() makes (Triangulation, L, M, d0,
// d1 and the three stars as diagonal matrices), timed on a mesh read beforehand, after one untimed call.
//   python_overhead_cpp MESH REPEATS   ->   one JSON line {"faces": ..., "seconds": [...]}

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: python_overhead_cpp MESH REPEATS\n");
        return 2;
    }
    const sdmesh::TriangleMesh mesh = sdmesh::read_mesh(argv[1]);
    const int repeats = std::atoi(argv[2]);
    std::string seconds;
    for (int r = -1; r < repeats; ++r) {  // r = -1: an untimed warm-up (thread pool, first page faults)
        const auto start = std::chrono::steady_clock::now();
        const sdmesh::Triangulation t = sdmesh::Triangulation::from_mesh(mesh);
        const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t), M = sdmesh::mass_matrix(t),
                                          d0 = sdmesh::d0(t), d1 = sdmesh::d1(t),
                                          star0 = sdmesh::diagonal_matrix(sdmesh::star0(t)),
                                          star1 = sdmesh::diagonal_matrix(sdmesh::star1(t)),
                                          star2 = sdmesh::diagonal_matrix(sdmesh::star2(t));
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // Use every result so that nothing is optimized away.
        if (L.nonZeros() + M.nonZeros() + d0.nonZeros() + d1.nonZeros() + star0.nonZeros() + star1.nonZeros() +
                star2.nonZeros() == 0)
            return 1;
        if (r >= 0) seconds += (seconds.empty() ? "" : ", ") + std::to_string(elapsed);
    }
    std::printf("{\"faces\": %d, \"seconds\": [%s]}\n", mesh.num_faces(), seconds.c_str());
    return 0;
}
