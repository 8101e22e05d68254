#pragma once
// The mesh users hold, read and write: vertex positions and triangles, nothing else.

#include <Eigen/Core>

namespace sdmesh {

/// A triangle mesh as two arrays.
///   V: |V| x 3 vertex positions.
///   F: |F| x 3 vertex indices per triangle, counter-clockwise seen from outside.
/// Nothing is assumed about validity; see validate.hpp for what can be checked and repaired.
struct TriangleMesh {
    Eigen::MatrixX3d V;
    Eigen::MatrixX3i F;

    [[nodiscard]] int num_vertices() const { return static_cast<int>(V.rows()); }
    [[nodiscard]] int num_faces() const { return static_cast<int>(F.rows()); }
};

}  // namespace sdmesh

namespace sdmesh {

/// \throws InvalidMeshError naming the first face with an index outside [0, |V|).
void require_indices_in_range(const TriangleMesh& mesh);

/// \throws InvalidMeshError naming the first vertex with a NaN or infinite coordinate.
void require_finite_positions(const TriangleMesh& mesh);

}  // namespace sdmesh
