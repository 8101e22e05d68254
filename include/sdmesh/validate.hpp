#pragma once
// What is in a mesh, what is wrong with it, and the repairs that change no geometry.

#include <string>

#include <Eigen/Core>

#include "sdmesh/mesh.hpp"
#include "sdmesh/topology.hpp"

namespace sdmesh {

/// Counts describing a mesh. Vertices count only if a face references them (as in V - E + F);
/// faces with a repeated index are counted and otherwise left out of the topology.
struct MeshInfo {
    int vertices = 0;                    ///< referenced vertices
    int unreferenced_vertices = 0;       ///< rows of V no face uses
    int faces = 0;
    int edges = 0;
    int interior_edges = 0;              ///< edges with exactly two faces
    int boundary_edges = 0;              ///< edges with one face
    int nonmanifold_edges = 0;           ///< edges with three or more faces
    int nonmanifold_vertices = 0;        ///< vertices with more than one fan of faces
    int components = 0;                  ///< connected components of the faces
    int boundary_loops = 0;              ///< connected components of the boundary-edge graph
    int euler_characteristic = 0;        ///< vertices - edges + faces
    int genus = -1;                      ///< Σ over components; -1 unless orientable manifold
    int repeated_index_faces = 0;        ///< faces with two equal vertex indices
    int zero_area_faces = 0;             ///< area <= 1e-12 · (longest side)², finite positions
    int degenerate_faces = 0;            ///< repeated index or zero area
    int duplicate_faces = 0;             ///< same vertex set as an earlier face
    int duplicate_vertex_positions = 0;  ///< referenced vertices equal to an earlier one
    int non_finite_vertices = 0;         ///< vertices with a NaN or infinite coordinate
    int orientation_conflicts = 0;       ///< interior edges both faces traverse the same way
    bool orientable = true;              ///< the faces can be oriented consistently

    // One offending element of each kind, for messages (-1: none).
    Eigen::Vector2i first_nonmanifold_edge{-1, -1};  ///< as its two vertex indices
    int first_nonmanifold_vertex = -1;
    int first_repeated_index_face = -1;
    int first_non_finite_vertex = -1;
    int first_zero_area_face = -1;

    /// No non-manifold edge or vertex and no face with a repeated index.
    [[nodiscard]] bool manifold() const {
        return nonmanifold_edges == 0 && nonmanifold_vertices == 0 && repeated_index_faces == 0;
    }
};

/// How much validate() counts: everything, or the defects alone — what first_defect() and
/// require_oriented_manifold() read. Then duplicate_faces, duplicate_vertex_positions,
/// components and boundary_loops stay 0 and genus -1: they sort or walk the whole mesh, and
/// the mesh-editing algorithms, which check their input, do not need them.
enum class ValidateScope { everything, defects };

/// Analyses a mesh in O(|V| + |F| log |F|).
/// \throws InvalidMeshError a face index is out of range (nothing else can be analysed then).
MeshInfo validate(const TriangleMesh& mesh);

/// The same on an edge table already built for this mesh.
MeshInfo validate(const TriangleMesh& mesh, const EdgeTable& edges, ValidateScope scope = ValidateScope::everything);

/// One sentence naming the first thing that keeps the mesh from being a manifold with finite
/// coordinates ("edge (3, 7) has more than two faces (12 such edges)"); empty when there is none.
std::string first_defect(const MeshInfo& info);

/// \throws InvalidMeshError "<what>: <first_defect(info)>" unless first_defect(info) is empty.
void require_manifold(const MeshInfo& info, const std::string& what);

/// What the mesh-editing algorithms (convert, decimate) need: a manifold, consistently oriented,
/// with no zero-area face. \throws InvalidMeshError "<what>: ..." naming the first defect.
void require_oriented_manifold(const MeshInfo& info, const std::string& what);

/// Safe repairs, each optional; they move a vertex by at most 1e-12 of the bounding-box diagonal
/// (merge_coincident_vertices) or by the short side of a needle (collapse_needles), and the
/// surface by at most the height of a zero-area face (flip_caps). Applied in this order; after a
/// pass that mended caps and left none, or that left fewer zero-area faces than the pass before,
/// all but the drop of unreferenced vertices run again (a flip can make a needle or a
/// duplicate face; a dropped cap can leave parted sheets to join). A repaired mesh with no
/// zero-area face left, and orientable, repairs to itself: the same mesh, and a report of zeros.
struct RepairOptions {
    /// vertices at exactly the same position become one, and so do the two ends of a face side
    /// shorter than 1e-12 of the bounding-box diagonal (the same point up to rounding); the
    /// smallest index stays, where it was
    bool merge_coincident_vertices = true;
    /// a needle (a zero-area face whose shortest side is below 1e-6 of its longest: two nearly
    /// coincident vertices, which no flip mends) has the two ends of that side made one, the
    /// smallest index staying where it was; the needle and the face across that side go
    bool collapse_needles = true;
    bool drop_repeated_index_faces = true;  ///< faces with two equal indices
    bool drop_duplicate_faces = true;       ///< keep the first face of each vertex set
    /// each fan of faces around a non-manifold vertex gets its own copy of the vertex (sheets
    /// meeting at an edge with more than two faces come apart along it, with boundaries there);
    /// a fan whose corners were all one vertex before the merge of coincident vertices gets
    /// that vertex back (vertices at one point whose merge would be parted again stay apart)
    bool split_nonmanifold_vertices = true;
    bool orient = true;  ///< re-wind faces so each orientable component is consistent, keeping
                         ///< the orientation of its first face
    /// zero-area faces with a vertex inside their longest side (caps) are flipped away with the
    /// face across that side, which the two new faces tile, or dropped when that side is on the
    /// boundary (their two other sides then run along it; an apex that is on the boundary
    /// elsewhere too gets a copy for each side, if split_nonmanifold_vertices); needs the
    /// orientation repair
    bool flip_caps = true;
    bool drop_unreferenced_vertices = true; ///< compact V; remaining vertices keep their order
};

struct RepairReport {
    int merged_vertices = 0;
    int collapsed_needles = 0;  ///< vertices merged by collapse_needles alone
    int dropped_repeated_index_faces = 0;
    int dropped_duplicate_faces = 0;
    int split_vertices = 0;  ///< copies made by split_nonmanifold_vertices
    int flipped_faces = 0;
    int non_orientable_components = 0;  ///< components left as they were
    int flipped_caps = 0;
    int dropped_caps = 0;  ///< caps on the boundary, dropped by flip_caps
    int dropped_vertices = 0;

    friend bool operator==(const RepairReport&, const RepairReport&) = default;
};

/// Returns the repaired mesh.
/// \throws InvalidMeshError a face index is out of range.
TriangleMesh repair(const TriangleMesh& mesh, const RepairOptions& options = {},
                    RepairReport* report = nullptr);

}  // namespace sdmesh
