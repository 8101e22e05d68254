#pragma once
// Edge flips inside planes after a collapse (internal, not installed). A collapse whose new star
// leaves some edges not locally Delaunay may still keep the mesh self-Delaunay if those edges lie
// inside a plane: there they can be flipped without moving the surface, as the conversion does
// (Lawson's flips, which end with the plane's part Delaunay). FlatFlips runs those flips on a copy
// of the faces around the new vertex and says whether every edge they touch ends locally
// Delaunay; the collapser then applies them to the mesh with the collapse.
//
// An edge counts as inside a plane when the normals of its two faces differ by at most
// kFlatAngle. On midpoint-subdivided or CAD meshes most vertices lie inside planes, and without
// these flips a collapse that removes one exactly is often refused.

#include <array>
#include <vector>

#include "decimate/mesh_state.hpp"

namespace sdmesh::decimation {

/// Whether the faces (a, b, c) and (b, a, d) lie in one plane (normals within kFlatAngle).
bool inside_a_plane(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

class FlatFlips {
public:
    enum class Outcome { delaunay, not_delaunay, outside_half };

    /// The faces of the new star of collapsing q into p at x (their ids; corners with q renamed
    /// p), flipped in memory until every edge is locally Delaunay. Faces across the star are
    /// taken in as flips reach them; with half >= 0 they must all lie in that half (outside_half
    /// otherwise). not_delaunay: an edge that is not LD is not inside a plane, cannot be flipped
    /// (the quad is not convex, or its other diagonal is an edge already), is a boundary edge
    /// obtuse under the policy, or the flips exceed a budget.
    Outcome run(const MeshState& mesh, int p, int q, const Vec3& x, const std::vector<int>& star_faces,
                const std::vector<int>& removed_faces, BoundaryPolicy boundary, double tolerance, int half);

    /// After run() returned delaunay, applies the flips to the mesh, whose collapse of q into p
    /// is done. Out: the edges flipped in and out (u < w; in the order of the flips) and the
    /// vertices whose faces changed.
    void apply(MeshState& mesh, std::vector<std::pair<int, int>>& flipped_in, std::vector<std::pair<int, int>>& flipped_out,
               std::vector<int>& changed) const;

    [[nodiscard]] int flips() const { return flips_; }

private:
    struct Face {
        int id;
        std::array<int, 3> v;       // counter-clockwise, as flipped
        std::array<int, 3> before;  // as in the mesh (after the collapse)
    };

    [[nodiscard]] Vec3 position(int v) const { return v == p_ ? x_ : mesh_->P[v]; }
    int face_with_side(int from, int to);  // a patch face with side from -> to, taking in a face across; -1 if none
    [[nodiscard]] bool has_edge(int a, int b) const;
    // Whether edge a-b of the faces (a, b, c) and (b, a, d) is LD and both faces have an area,
    // by the certificate's formulas.
    [[nodiscard]] bool locally_delaunay(int a, int b, int c, int d, double tan_tolerance) const;

    const MeshState* mesh_ = nullptr;
    int p_ = -1, half_ = -1;
    Vec3 x_;
    const std::vector<int>* removed_ = nullptr;
    std::vector<Face> faces_;
    std::vector<std::pair<int, int>> flipped_in_, flipped_out_;
    std::vector<std::pair<int, int>> pending_;
    int flips_ = 0;
    bool outside_half_ = false;
};

}  // namespace sdmesh::decimation
