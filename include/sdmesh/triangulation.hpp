#pragma once
// Connectivity plus one length per edge: all that the operators and solvers need. Built from a
// TriangleMesh (lengths from positions) or from faces and lengths (intrinsic triangulations), so
// extrinsic and intrinsic meshes share every operator.
//
// Conventions (as in topology.hpp): halfedge h = 3f + k is the side of face f opposite corner k,
// running from F(f,(k+1)%3) to F(f,(k+2)%3). A Δ-complex is allowed: two edges may join the same
// vertices, and an edge may join a vertex to itself, which is why edges are stored explicitly
// instead of being looked up by their endpoints.

#include <Eigen/Core>

#include "sdmesh/mesh.hpp"

namespace sdmesh {

struct Triangulation {
    int num_vertices = 0;
    /// |F| x 3 vertex indices per face, counter-clockwise.
    Eigen::MatrixX3i F;
    /// |E| x 2 endpoints, E(e,0) <= E(e,1); edge e is oriented E(e,0) -> E(e,1) (DEC's d0).
    Eigen::MatrixX2i E;
    /// |F| x 3: the edge opposite corner k of face f.
    Eigen::MatrixX3i face_edge;
    /// |F| x 3: +1 if face f runs along face_edge(f,k) in the edge's direction, else -1.
    Eigen::Matrix<signed char, Eigen::Dynamic, 3> face_edge_sign;
    /// |E| x 2: the halfedges (3f + k) on each edge; column 1 is -1 on a boundary edge.
    Eigen::MatrixX2i edge_halfedges;
    /// |E| edge lengths, > 0.
    Eigen::VectorXd length;

    [[nodiscard]] int num_faces() const { return static_cast<int>(F.rows()); }
    [[nodiscard]] int num_edges() const { return static_cast<int>(E.rows()); }
    [[nodiscard]] bool is_boundary(int e) const { return edge_halfedges(e, 1) < 0; }
    /// Length of the side of face f opposite corner k.
    [[nodiscard]] double side(int f, int k) const { return length[face_edge(f, k)]; }

    /// From a mesh: edges numbered as in build_edge_table (lexicographic), lengths from V.
    /// \throws InvalidMeshError a non-manifold edge, a face with a repeated index, a non-finite
    ///         coordinate, an index out of range or a zero-length edge (naming the element).
    static Triangulation from_mesh(const TriangleMesh& mesh);

    /// From faces and the length of each face side, side_length(f,k) opposite corner k; edges are
    /// identified by their endpoints, as in from_mesh.
    /// \throws InvalidMeshError as from_mesh, or when the two faces of an edge disagree on its
    ///         length (relative 1e-12), or when a face violates the triangle inequality.
    static Triangulation from_side_lengths(const Eigen::MatrixX3i& F, const Eigen::MatrixX3d& side_length,
                                           int num_vertices);

    /// Checks the invariants above (sizes, index ranges, halfedge/edge agreement, positive finite
    /// lengths, triangle inequality up to rounding); for triangulations assembled by hand.
    /// \throws InvalidMeshError naming the first violation.
    void check() const;
};

}  // namespace sdmesh
