#pragma once
// Mutable connectivity for edge flips, splits and merges, shared by the conversion and intrinsic
// modules (internal, not installed). Corner-table layout: face f owns halfedges 3f, 3f+1, 3f+2, and
// halfedge 3f+k is the side OPPOSITE corner k, running from corner k+1 to corner k+2 — the
// convention of topology.hpp and Triangulation. Twins are explicit, never looked up by vertex
// pairs, so a Δ-complex (repeated edges, self-loops) is representable. Each halfedge also holds
// a side length, for flip loops on edge lengths: all that one face's test needs is one record.

#include <vector>

#include "sdmesh/triangulation.hpp"

namespace sdmesh {

class HalfedgeMesh {
public:
    /// Connectivity of a Triangulation (which guarantees a manifold-edge face list); edge ids
    /// and orientation are kept.
    explicit HalfedgeMesh(const Triangulation& t);

    /// The same from the connectivity arrays alone (as in Triangulation or EdgeTable), with room
    /// for the faces and edges of `spare_splits` splits of interior edges before the records
    /// move (moving them copies every record into pages mapped anew).
    /// \pre at most two faces per edge, no face with a repeated index.
    HalfedgeMesh(const Eigen::MatrixX3i& F, const Eigen::MatrixX3i& face_edge,
                 const Eigen::MatrixX2i& edge_halfedges, int num_vertices, int spare_splits = 0);

    [[nodiscard]] int num_vertices() const { return num_vertices_; }
    [[nodiscard]] int num_faces() const { return static_cast<int>(face_.size()); }
    [[nodiscard]] int num_edges() const { return static_cast<int>(edge_halfedge_.size()); }

    // Navigation.
    [[nodiscard]] static int face(int h) { return h / 3; }
    [[nodiscard]] static int next(int h) { return h - h % 3 + (h % 3 + 1) % 3; }
    [[nodiscard]] static int prev(int h) { return h - h % 3 + (h % 3 + 2) % 3; }
    [[nodiscard]] int corner(int f, int k) const { return face_[f].corner[k]; }
    [[nodiscard]] int opposite_vertex(int h) const { return corner_of(h); }
    [[nodiscard]] int tail(int h) const { return corner_of(next(h)); }
    [[nodiscard]] int head(int h) const { return corner_of(prev(h)); }
    [[nodiscard]] int twin(int h) const { return face_[h / 3].twin[h % 3]; }  ///< -1 on the boundary
    [[nodiscard]] int edge(int h) const { return face_[h / 3].edge[h % 3]; }
    [[nodiscard]] int halfedge(int e) const { return edge_halfedge_[e]; }  ///< one of its halfedges
    [[nodiscard]] bool is_boundary_edge(int e) const { return twin(edge_halfedge_[e]) < 0; }

    /// The length stored on side h: 0 until set; flip() moves it with its side, split() leaves
    /// it on the side it was on.
    [[nodiscard]] double side_length(int h) const { return face_[h / 3].length[h % 3]; }
    void set_side_length(int h, double length) {
        touch_face(h / 3);
        face_[h / 3].length[h % 3] = length;
    }
    /// Requests the record of h's face into the cache (no effect on the mesh; h may be -1).
    void prefetch(int h) const {
        if (h >= 0) __builtin_prefetch(&face_[h / 3]);
    }

    /// Replaces the diagonal of the two faces on interior edge e: with h = halfedge(e) in face
    /// (p, q, r) and its twin in (q, p, s), the faces become (r, p, s) and (s, q, r). The edge
    /// keeps its id (now joining r and s); the four outer sides keep theirs. Faces keep their
    /// ids; halfedge(e) is afterwards in the first face and runs s -> r. The outer sides keep
    /// their side lengths; those of e are left to the caller.
    /// \pre e is interior and its two faces are distinct.
    void flip(int e);

    /// Splits edge e by a new vertex x (id num_vertices() before the call), joined to the
    /// opposite vertex of each face on e. Edge e keeps the half at halfedge(e)'s tail; the other
    /// half, then the spoke(s) get new ids, appended in that order (interior edge: 2 faces and 3
    /// edges added; boundary edge: 1 face and 2 edges).
    /// \pre the faces on e are distinct and no two of their outer sides are glued together.
    /// \returns the new vertex id.
    int split(int e);

    /// Undoes a split: h is the side p -> x of the face (r, p, x), x lies on the straight line
    /// from p to q, and x's only other neighbours are r and, across the line, s (none on a
    /// boundary line). The faces of h and of its twin become (r, p, q) and (s, q, p), and edge(h)
    /// joins p and q; their side lengths are left to the caller. x is left without faces. The
    /// other two faces and three edges stay in place, marked removed (their ids are not reused).
    void merge(int h);

    /// True for an edge that merge() removed.
    [[nodiscard]] bool is_removed_edge(int e) const { return edge_halfedge_[e] < 0; }
    /// True for a face that merge() removed.
    [[nodiscard]] bool is_removed_face(int f) const { return face_[f].corner[0] < 0; }

    /// True if the vertices opposite interior halfedge h and its twin are joined by an edge (a
    /// flip of h's edge would repeat it). Both fans are walked in turns: the smaller one's cost.
    [[nodiscard]] bool has_diagonal(int h) const;

    /// Writes the current faces and a per-edge array into a Triangulation (lengths are the
    /// caller's, indexed by edge id); E(e,·) is ordered so that E(e,0) <= E(e,1). On a self-edge
    /// the side listed first in edge_halfedges gets sign +1 and its twin -1. \pre no merge().
    [[nodiscard]] Triangulation to_triangulation(Eigen::VectorXd length) const;

    /// The faces as an array with one row per face, in order, without those merge() removed.
    [[nodiscard]] Eigen::MatrixX3i faces() const;

    /// Trials, for searches that try a change and take it back when it does not pay: after
    /// begin_trial(), every change is recorded, rollback() restores the mesh exactly as it was
    /// (ids included) and commit() keeps it. Their cost is that of the changes, not of the mesh.
    void begin_trial();
    void rollback();
    void commit();

private:
    // One cache line per face: a flip test reads and a flip writes two records.
    struct alignas(64) Face {
        double length[3];
        int corner[3];
        int twin[3];
        int edge[3];
    };

    [[nodiscard]] int corner_of(int h) const { return face_[h / 3].corner[h % 3]; }
    int& corner_of(int h) {
        touch_face(h / 3);
        return face_[h / 3].corner[h % 3];
    }
    int& twin_of(int h) {
        touch_face(h / 3);
        return face_[h / 3].twin[h % 3];
    }
    int& edge_of(int h) {
        touch_face(h / 3);
        return face_[h / 3].edge[h % 3];
    }
    int& halfedge_of(int e) {
        if (in_trial_ && e < trial_edges_) [[unlikely]]
            edge_log_.emplace_back(e, edge_halfedge_[e]);
        return edge_halfedge_[e];
    }
    // Records face f before a change, inside a trial (faces added by the trial need no record).
    void touch_face(int f) {
        if (in_trial_ && f < trial_faces_) [[unlikely]]
            face_log_.emplace_back(f, face_[f]);
    }
    // Makes a and b twins (either may be -1 for a boundary side) with edge id e.
    void glue(int a, int b, int e);
    // Gives slot `to` the twin, edge and side length of slot `from`.
    void move_side(int from, int to);
    int add_face(int a, int b, int c);
    int add_edge();

    int num_vertices_ = 0;
    std::vector<Face> face_;
    std::vector<int> edge_halfedge_;  // per edge
    // The open trial: the sizes it started from and the records changed since, oldest first.
    bool in_trial_ = false;
    int trial_faces_ = 0, trial_edges_ = 0, trial_vertices_ = 0;
    std::vector<std::pair<int, Face>> face_log_;
    std::vector<std::pair<int, int>> edge_log_;
};

}  // namespace sdmesh
