#pragma once
// The mesh users hold, read and write: vertex positions and triangles, nothing else.

#include <vector>

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

/// By vertex: 1 where a face uses it (indices outside [0, |V|) are skipped).
[[nodiscard]] std::vector<char> referenced_vertices(const TriangleMesh& mesh);

/// The length of the diagonal of the bounding box of the vertices that faces use (of all the
/// vertices when there are no faces): 0 without any, +inf if it overflows, NaN if one of them is
/// not finite.
[[nodiscard]] double bounding_box_diagonal(const TriangleMesh& mesh);

/// The bounding-box diagonals that operators, solvers, conversion and decimation accept: from
/// 2^-500 to 2^500 (about 3e-151 to 3e150), where squared lengths, hence areas and masses, are
/// normal doubles. The Delaunay certificate (sdmesh check) holds at any scale.
inline constexpr int kMaxExtentExponent = 500;

/// \returns the bounding-box diagonal (bounding_box_diagonal), for callers that need it too.
/// \throws InvalidMeshError naming the diagonal, when it lies outside the supported range (a
///         mesh whose vertices all coincide has diagonal 0 and passes, for the checks of its
///         faces; so does a NaN coordinate, for require_finite_positions).
double require_supported_extent(const TriangleMesh& mesh);

/// The mesh with its coordinates multiplied by 2^exponent, exactly (barring overflow and
/// underflow): algorithms whose tests multiply several lengths run at the scale of a unit
/// diagonal (see unit_exponent in geometry.hpp) and give back results in the input's units.
[[nodiscard]] TriangleMesh scaled_by_power_of_two(const TriangleMesh& mesh, int exponent);

}  // namespace sdmesh
