#pragma once
// The cotan Laplacian, mass matrices and discrete exterior calculus (DEC) on circumcentric duals,
// built from a Triangulation's connectivity and edge lengths alone (never positions), so that
// extrinsic meshes and intrinsic triangulations share them. Formulas: ALGORITHMS.md §6.
//
// Conventions (DESIGN.md):
//  - L = d0ᵀ·⋆1·d0 is positive semidefinite: L_ij = -(cot α_ij + cot β_ij)/2 summed over the
//    edges joining i ≠ j, rows sum to 0. Eigenproblem: L φ = λ M φ.
//  - Edge e runs E(e,0) -> E(e,1); face f runs counter-clockwise F(f,0) -> F(f,1) -> F(f,2).
//  - Hodge stars are diagonals, returned as vectors: ⋆0 (|V|) signed circumcentric dual areas,
//    ⋆1 (|E|) signed dual/primal length ratios, ⋆2 (|F|) inverse face areas. Signed quantities are
//    computed honestly: on a self-Delaunay mesh (strict boundary policy) ⋆0 > 0 and ⋆1 >= 0; on
//    other meshes entries can be negative, and inverse_star() refuses them.
//  - A Δ-complex is handled: edges joining the same two vertices add up in L and M; a self-loop
//    (E(e,0) == E(e,1)) has an empty d0 row and contributes nothing to L.
//  - Matrices are Eigen::SparseMatrix<double>, column-major, compressed, with sorted indices.
//
// Precondition of every function taking a Triangulation: it satisfies Triangulation::check()
// (its constructors guarantee this). Only the array sizes are verified here, since a full check
// costs as much as the assembly; a mismatch throws InvalidMeshError.
//
// Assembly runs in parallel with OpenMP and gives bit-identical results for any thread count.
//
// Example:
//   const auto t = sdmesh::Triangulation::from_mesh(sdmesh::read_mesh("bunny.obj"));
//   const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t);
//   const Eigen::SparseMatrix<double> M = sdmesh::mass_matrix(t, sdmesh::MassType::mixed_voronoi);

#include <string_view>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "sdmesh/triangulation.hpp"

namespace sdmesh {

/// Exterior derivative on 0-forms, |E| x |V|: row e is -1 at E(e,0) and +1 at E(e,1) (empty for
/// a self-loop). Integer-valued, so d1·d0 = 0 holds exactly.
Eigen::SparseMatrix<double> d0(const Triangulation& t);

/// Exterior derivative on 1-forms, |F| x |E|: row f holds face_edge_sign(f,k) at column
/// face_edge(f,k), k = 0..2 (the boundary of the counter-clockwise face); an edge that a face
/// meets twice gets the sum of its signs, and zero sums are not stored.
Eigen::SparseMatrix<double> d1(const Triangulation& t);

/// |F| face areas, by Kahan's formula from the three lengths.
Eigen::VectorXd face_areas(const Triangulation& t);

/// ⋆0, |V|: signed circumcentric dual area of each vertex, Σ over its edges of
/// (l²/8)(cot α + cot β) (one cotangent on a boundary edge); a self-loop counts at both ends.
/// Sums to the total area. 0 for a vertex without faces.
Eigen::VectorXd star0(const Triangulation& t);

/// ⋆1, |E|: (cot α + cot β)/2 per edge, cot α / 2 on a boundary edge; negative on an edge that is
/// not locally Delaunay (or whose boundary angle is obtuse).
Eigen::VectorXd star1(const Triangulation& t);

/// ⋆2, |F|: 1 / face area.
Eigen::VectorXd star2(const Triangulation& t);

/// Entrywise inverse of a diagonal Hodge star (or any positive diagonal); `name` ("star0") is used
/// in the message.
/// \throws NumericalError an entry is <= 0 or not finite; the message names the first one, its
///         value and how many there are.
Eigen::VectorXd inverse_star(const Eigen::VectorXd& star, std::string_view name);

/// The n x n sparse matrix with `diagonal` on its diagonal; every diagonal entry is stored, zeros
/// included (so a file written from it shows the full diagonal).
Eigen::SparseMatrix<double> diagonal_matrix(const Eigen::VectorXd& diagonal);

/// Cotan Laplacian L = d0ᵀ·⋆1·d0, |V| x |V|, positive semidefinite on a self-Delaunay mesh (its
/// off-diagonal entries are then <= 0); symmetric, rows sum to 0, exactly symmetric in floating
/// point. Pattern: the diagonal (always stored) plus both directions of every edge that is not a
/// self-loop; parallel edges share one entry.
Eigen::SparseMatrix<double> cotan_laplacian(const Triangulation& t);

/// The vertex mass matrices. Each sums (over all entries) to the total area.
enum class MassType {
    barycentric,    ///< lumped: a third of the area of each incident face (diagonal)
    circumcentric,  ///< lumped: ⋆0, signed, can be negative on a non-Delaunay mesh (diagonal)
    mixed_voronoi,  ///< lumped, Meyer et al. 2003: Voronoi areas in non-obtuse faces; in an obtuse
                    ///< face area/2 to the obtuse corner and area/4 to the others (diagonal, > 0)
    galerkin,       ///< consistent P1 mass: per face area/6 on the diagonal, area/12 off it;
                    ///< same pattern as cotan_laplacian
};

/// Mass matrix, |V| x |V|, symmetric; diagonal types store the full diagonal.
Eigen::SparseMatrix<double> mass_matrix(const Triangulation& t, MassType type = MassType::barycentric);

/// |V| angle defects: 2π - Σ corner angles at an interior vertex, π - Σ at a vertex on a boundary
/// edge, 2π at a vertex without faces. Discrete Gauss–Bonnet: they sum to 2π·(|V| - |E| + |F|).
Eigen::VectorXd angle_defects(const Triangulation& t);

/// Per-face gradient of piecewise-linear vertex functions, 2|F| x |V|: rows 2f and 2f+1 are the x
/// and y components of the gradient in face f's own frame, laid out from its lengths with corner 0
/// at the origin, corner 1 on the +x axis and corner 2 at y > 0. ∇φ_k = J·e_k / (2·area), e_k the
/// side opposite corner k (counter-clockwise), J the rotation by +90°. Each face row pair has a
/// structural entry per vertex of the face.
Eigen::SparseMatrix<double> gradient(const Triangulation& t);

/// Integrated (weak) divergence of per-face vectors in the frames of gradient(), |V| x 2|F|:
/// div = -Gᵀ·A with A the face areas repeated per component, so that div·grad = -L exactly in
/// exact arithmetic (to rounding in floating point). (div X)_i is the integral over the surface
/// of the divergence tested against the hat function of vertex i; divide by a lumped mass for
/// pointwise values: M⁻¹·div·grad = -M⁻¹L is the (negative semidefinite) Laplace–Beltrami.
Eigen::SparseMatrix<double> divergence(const Triangulation& t);

}  // namespace sdmesh
