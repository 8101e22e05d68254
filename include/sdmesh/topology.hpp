#pragma once
// Combinatorics of a face list: unique edges, which faces meet at each edge, and which vertices
// are non-manifold. Positions are never looked at.
//
// Conventions used everywhere in sdmesh:
//  - corner k of face f is F(f,k); "halfedge" h = 3f + k is the side of face f OPPOSITE corner k,
//    running from F(f,(k+1)%3) to F(f,(k+2)%3) in the face's counter-clockwise order;
//  - edges are numbered in lexicographic order of their endpoints (lo, hi), lo < hi.
// Faces with a repeated vertex index have no valid sides: their halfedges get edge -1.

#include <vector>

#include <Eigen/Core>

namespace sdmesh {

/// Unique undirected edges of a face list.
struct EdgeTable {
    /// |E| x 2 endpoints, E(e,0) < E(e,1), rows in lexicographic order.
    Eigen::MatrixX2i E;
    /// |F| x 3: face_edge(f,k) is the edge opposite corner k of face f (-1 in a face with a
    /// repeated index).
    Eigen::MatrixX3i face_edge;
    /// Number of faces on each edge: 1 = boundary, 2 = manifold interior, >2 = non-manifold.
    std::vector<int> face_count;
    /// The first two halfedges (3f + k) on each edge, in increasing order; -1 where absent.
    Eigen::MatrixX2i edge_halfedges;
    /// Vertices whose incident faces form more than one fan, where faces of a fan are connected
    /// through edges with exactly two faces (a bow-tie, or a vertex on a non-manifold edge), in
    /// increasing order. Faces with a repeated index are ignored.
    std::vector<int> nonmanifold_vertices;

    [[nodiscard]] int num_edges() const { return static_cast<int>(E.rows()); }
};

/// Whether build_edge_table() looks for non-manifold vertices (one walk around every vertex,
/// about a fifth of its time); with `skip`, EdgeTable::nonmanifold_vertices stays empty.
enum class NonmanifoldVertices { find, skip };

/// Builds the edge table in O(|F| + |V|) (bucket sort on the lower endpoint).
/// \pre every index of F is in [0, num_vertices).
EdgeTable build_edge_table(const Eigen::MatrixX3i& F, int num_vertices,
                           NonmanifoldVertices nonmanifold_vertices = NonmanifoldVertices::find);

/// True when face f has two equal vertex indices.
[[nodiscard]] inline bool has_repeated_index(const Eigen::MatrixX3i& F, int f) {
    return F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0);
}

}  // namespace sdmesh
