#include "sdmesh/mesh.hpp"

#include <string>

#include "sdmesh/error.hpp"

namespace sdmesh {

void require_indices_in_range(const TriangleMesh& mesh) {
    const int n = mesh.num_vertices();
    for (int f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k)
            if (mesh.F(f, k) < 0 || mesh.F(f, k) >= n)
                throw InvalidMeshError("face " + std::to_string(f) + " references vertex " +
                                       std::to_string(mesh.F(f, k)) + ", but the mesh has " +
                                       std::to_string(n) + " vertices");
}

void require_finite_positions(const TriangleMesh& mesh) {
    for (int v = 0; v < mesh.num_vertices(); ++v)
        if (!mesh.V.row(v).allFinite())
            throw InvalidMeshError("vertex " + std::to_string(v) +
                                   " has a coordinate that is not finite");
}

}  // namespace sdmesh
