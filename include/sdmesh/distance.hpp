#pragma once
// Distances between triangle meshes: closest points on a triangle and on a mesh (through an AABB
// tree), and the sampled (Metro-style) two-sided Hausdorff distance that conversion and
// decimation report, relative to the bounding-box diagonal of the first mesh.

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sdmesh/mesh.hpp"

namespace sdmesh {

/// The point of a mesh nearest to a query.
struct ClosestPoint {
    double squared_distance = 0;                       ///< |query - point|²
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< on the surface
    int face = -1;                                     ///< row of the mesh's F that holds `point`
};

/// Closest point of the triangle abc to p, chosen by the Voronoi region of p (a vertex, an edge
/// or the interior). A zero-area or needle triangle — height below 1e-8 of its longest edge, where
/// its normal is not reliable in double precision — is treated as its three edges, which moves
/// the answer by at most that height. O(1); never throws; finite input gives a finite answer.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

/// An axis-aligned bounding-box tree over the faces of a mesh, for closest-point queries.
/// Keeps its own copy of the face corners: the mesh may go away after construction.
///
///     const TriangleTree tree(mesh);
///     const ClosestPoint hit = tree.closest_point({0.1, 0.2, 0.3});  // hit.face, hit.point
///
/// Build: O(n log n) for n faces (median split of the face centroids on their longest axis,
/// leaves of at most 4 faces). Query: O(log n) typical, O(n) worst case; const and thread-safe.
class TriangleTree {
public:
    /// \pre every face index in [0, |V|); faces may be degenerate (zero area, repeated vertices).
    /// \throws InvalidMeshError the mesh has no faces, a face index is out of range, or a vertex
    ///         has a NaN or infinite coordinate (the message names the face or vertex).
    explicit TriangleTree(const TriangleMesh& mesh);

    /// The nearest point of the mesh's surface to `query`; on ties, the face met first.
    [[nodiscard]] ClosestPoint closest_point(const Eigen::Vector3d& query) const;
    /// The same squared distance, found faster when the nearest point is on or near face
    /// `near_face` (e.g. the answer for a nearby query): the search starts from that face's
    /// distance. On ties the face (and point) may differ from closest_point(query)'s.
    /// \pre near_face in [0, num_faces()).
    [[nodiscard]] ClosestPoint closest_point(const Eigen::Vector3d& query, int near_face) const;
    /// closest_point(query, near_face) when it is farther than `squared_radius`; otherwise the
    /// search may stop at the first face found within it, whose point and distance are returned
    /// (for "can this query be farther than r?" at a fraction of the cost).
    [[nodiscard]] ClosestPoint closest_point_beyond(const Eigen::Vector3d& query, int near_face,
                                                    double squared_radius) const;

    /// Bounding box of the mesh's faces (unreferenced vertices excluded).
    [[nodiscard]] const Eigen::AlignedBox3d& bounds() const { return nodes_.front().box; }

    [[nodiscard]] int num_faces() const { return static_cast<int>(face_.size()); }

private:
    struct Triangle {
        std::array<Eigen::Vector3d, 3> corner;
        Eigen::Vector3d normal;  // unit, or zero for a face treated as its edges
    };
    // A leaf holds triangles [first, first + count); an inner node (count == 0) has its children
    // at index + 1 and at `first` (depth-first layout).
    struct Node {
        Eigen::AlignedBox3d box;
        int first = 0;
        int count = 0;
    };

    // Nodes of a subtree over that many faces.
    static int subtree_nodes(int faces);
    // The subtree over order[begin, end) at nodes_[index], and its subtrees after it.
    void build(std::vector<int>& order, const std::vector<Eigen::Vector3d>& centroid, int begin, int end, int index);
    // The nearest point of the faces that are nearer than `best`, else best; or the first point
    // found within `enough` (squared).
    [[nodiscard]] ClosestPoint search(const Eigen::Vector3d& query, ClosestPoint best, double enough = -1) const;

    std::vector<Node> nodes_;
    std::vector<Triangle> triangles_;  // in leaf order
    std::vector<int> face_;            // face_[i]: the mesh face of triangles_[i]
    std::vector<int> slot_;            // slot_[f]: the index in triangles_ of mesh face f
};

/// How densely hausdorff_distance samples each mesh.
struct HausdorffOptions {
    /// Points inside each face: the centroids of a k × k subdivision of the face, k² ≤ this
    /// (default 16: k = 4). Every vertex and the three edge midpoints of each face are sampled too.
    int samples_per_face = 16;
    /// Budget of samples on each mesh; k is lowered until vertices + faces·(k² + 3) fits, but never
    /// below k = 1. Default 10 million.
    long long max_samples = 10'000'000;
    /// Compute HausdorffReport::mean_forward. Without it (NaN then), the search of a sample stops
    /// at the first face within the largest distance found so far, as the sample cannot raise it:
    /// the same maxima, bit for bit, in about half the time (igea against its decimation to 10 %:
    /// 2.9 → 1.45 s, of which 0.33 s build the trees). Conversion and decimation measure so.
    bool mean = true;
};

/// Result of hausdorff_distance. Sampled values never exceed the true ones, but for the height
/// a needle adds (closest_point_on_triangle: at most 1e-8 of its longest edge); a one-sided true
/// distance exceeds its sampled value by at most 2/(3k) of the longest edge of the sampled mesh
/// (every point of a face is that close to the centroid of its sub-triangle).
struct HausdorffReport {
    double forward = 0;        ///< max over samples x of A of dist(x, B)
    double backward = 0;       ///< max over samples y of B of dist(y, A)
    double hausdorff = 0;      ///< max(forward, backward)
    double diagonal = 0;       ///< bounding-box diagonal of A's faces
    double hausdorff_rel = 0;  ///< hausdorff / diagonal (0 when hausdorff is 0)
    double mean_forward = 0;   ///< area-weighted mean of dist(x, B) over A's face-interior samples (NaN
                               ///< without HausdorffOptions::mean)
    long long samples = 0;     ///< samples taken on A and B together
};

/// Two-sided Hausdorff distance between the surfaces of a and b, sampled deterministically
/// (Metro-style). Bit-identical results for any number of OpenMP threads.
/// Cost: a TriangleTree on each mesh, O(n log n), plus one tree query (O(log n) typical) per sample.
/// \throws InvalidMeshError as TriangleTree, for either mesh.
/// \throws InvalidArgumentError samples_per_face < 1 or max_samples < 1.
HausdorffReport hausdorff_distance(const TriangleMesh& a, const TriangleMesh& b, const HausdorffOptions& options = {});

/// Where a mesh b made from a mesh a by changing some of its faces can leave a's surface, and
/// where b can leave part of a's surface uncovered.
struct SurfaceEdit {
    /// By face of b: may leave a's surface. Unflagged faces must lie in it.
    std::vector<char> changed_faces;
    /// By face of a: parts of it may be uncovered by b's unflagged faces (empty: none flagged).
    std::vector<char> replaced_faces;
    /// More of a's surface that may be uncovered, as triangles lying in it; the faces of a that
    /// meet them are found by distance.
    TriangleMesh replaced;
};

/// hausdorff_distance(a, b, options) measured only where an edit can have changed the surface:
/// on b's changed faces and on a's faces that are replaced or meet `replaced`. Samples elsewhere
/// are at distance 0 up to rounding and are skipped at the same density, so the result is
/// hausdorff_distance's unless that is a rounding error (then 0); `samples` counts the samples
/// measured. Conversion by flips uses it: its changes are local.
/// \throws as hausdorff_distance; InvalidArgumentError when the flags do not match the meshes' faces.
HausdorffReport hausdorff_distance_of_edit(const TriangleMesh& a, const TriangleMesh& b, const SurfaceEdit& edit,
                                           const HausdorffOptions& options = {});

}  // namespace sdmesh
