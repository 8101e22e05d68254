#pragma once
// The Delaunay certificate of a mesh: is every edge locally Delaunay (LD) in the mesh's own
// metric, and are the circumcentric dual cells positive?
//
// Notation (ALGORITHMS.md §1): interior edge of length l between faces (l, a, b) and (l, c, d);
// α is the angle opposite the edge in the first face, β in the second.
//
// Tolerance policy (the one used everywhere in sdmesh): an interior edge is LD iff its margin
// π - (α + β) >= -tolerance, a boundary edge under the strict policy iff π/2 - α >= -tolerance.
// Margins are angles, hence dimensionless: the test gives the same verdict at every scale. The
// default tolerance, 1e-10 rad, lies far above the rounding error of the margin (~1e-15) and far
// below any margin a real mesh produces; being one-sided it makes co-circular quads count as LD,
// so a flip loop cannot cycle on them. A face whose area from its side lengths is 0 (collinear
// or coincident corners in floating point) has no angles to judge: its margins read as 0 and
// would pass, so a mesh with such a face is never certified.

#include <cmath>
#include <limits>
#include <string_view>

#include <Eigen/Core>

#include "sdmesh/mesh.hpp"
#include "sdmesh/topology.hpp"

namespace sdmesh {

inline constexpr double kDelaunayTolerance = 1e-10;

/// How boundary edges are judged.
enum class BoundaryPolicy {
    strict,  ///< LD iff the single opposite angle is <= π/2 (every ⋆1 entry and dual cell >= 0)
    free,    ///< always LD (Bobenko–Springborn)
};

/// π - (α + β) for a hinge with edge length l, first face (l, a, b), second face (l, c, d), in
/// [-π, π], from lengths only (one atan2; accurate for needles and near-co-circular hinges).
/// This and the functions below multiply up to four lengths: keep them within about 1e±75
/// (callers at other scales divide the lengths by a power of two first, as intrinsic_delaunay).
[[nodiscard]] double delaunay_margin(double l, double a, double b, double c, double d);

/// Throws InvalidArgumentError, naming `who`, unless 0 <= tolerance < π/2: the tolerances every
/// LD test accepts (beyond π/2, the tests without angles, which compare against tan(tolerance),
/// would no longer mean margin >= -tolerance).
void require_delaunay_tolerance(double tolerance, std::string_view who);

/// The verdict delaunay_margin(l, a, b, c, d) >= -tolerance, without evaluating the angle: for
/// the hot loops of flipping and conversion. \pre 0 <= tolerance < π/2.
[[nodiscard]] bool is_locally_delaunay(double l, double a, double b, double c, double d,
                                       double tolerance = kDelaunayTolerance);

/// The same given tan_tolerance = tan(tolerance): for loops that test many hinges under one
/// tolerance.
[[nodiscard]] bool is_locally_delaunay_with_tangent(double l, double a, double b, double c, double d,
                                                    double tan_tolerance);

/// The margin π - (α + β) of a hinge as the angle of the point (x, y), from its two opposite
/// angles given as 4·area and cosine numerator of their triangles (4.0 * triangle_area(l, a, b)
/// and cosine_numerator(l, a, b); likewise for (l, c, d)): for loops that share these between
/// edges. (x, y) is the product of (cos α, sin α) and (cos β, sin β), conjugated and negated,
/// times the positive 4ab·cd.
struct ScaledMargin {
    double y, x;

    /// The margin in [-π, π].
    [[nodiscard]] double radians() const { return std::atan2(y, x); }

    /// radians() >= -tolerance without the arctangent, given tan_tolerance = tan(tolerance).
    [[nodiscard]] bool locally_delaunay(double tan_tolerance) const {
        // The margin is in [0, π] for y >= 0, below -π/2 for y < 0 <= -x, and atan(y/x) for
        // y < 0 < x, which is >= -tolerance iff y >= -tan(tolerance)·x. Bitwise, without
        // branches: the verdicts of a mesh's edges come in no predictable order.
        return (y >= 0) | ((x > 0) & (y >= -tan_tolerance * x));
    }
};

/// The ScaledMargin of the opposite angles α (4·area, cosine numerator) and β (likewise).
[[nodiscard]] inline ScaledMargin scaled_margin(double area4_alpha, double cosine_alpha, double area4_beta,
                                                double cosine_beta) {
    return {.y = area4_alpha * cosine_beta + cosine_alpha * area4_beta,
            .x = area4_alpha * area4_beta - cosine_alpha * cosine_beta};
}

/// is_locally_delaunay from the scaled opposite angles (see ScaledMargin), with
/// tan_tolerance = tan(tolerance).
[[nodiscard]] inline bool is_locally_delaunay_scaled(double area4_alpha, double cosine_alpha, double area4_beta,
                                                     double cosine_beta, double tan_tolerance) {
    return scaled_margin(area4_alpha, cosine_alpha, area4_beta, cosine_beta).locally_delaunay(tan_tolerance);
}

/// π/2 - α for a boundary edge of length l in the face (l, a, b).
[[nodiscard]] double boundary_margin(double l, double a, double b);

/// The same from the angle's 4·area and cosine numerator (see is_locally_delaunay_scaled).
[[nodiscard]] inline double boundary_margin_scaled(double area4, double cosine) { return std::atan2(cosine, area4); }

/// (cot α + cot β) / 2, the cotan weight of an interior edge (± infinity next to a zero-area face).
[[nodiscard]] double cotan_weight(double l, double a, double b, double c, double d);

/// The square-root-free LD test: (l² - (a-b)²)(l² - (c-d)²) <= ((a+b)² - l²)((c+d)² - l²),
/// i.e. tan(α/2)·tan(β/2) <= 1. Exact-arithmetic equivalent of delaunay_margin >= 0; used to
/// cross-check it. No tolerance.
[[nodiscard]] bool is_delaunay_sqrt_free(double l, double a, double b, double c, double d);

struct CertifyOptions {
    BoundaryPolicy boundary = BoundaryPolicy::strict;  ///< how boundary edges are judged
    double tolerance = kDelaunayTolerance;             ///< see the tolerance policy above, in [0, π/2)
    bool edge_margins = false;                         ///< also fill DelaunayCertificate::edge_margin
};

/// The result of certify(). Per-element arrays follow the EdgeTable numbering of the mesh.
struct DelaunayCertificate {
    /// Per edge, when CertifyOptions::edge_margins (else empty): π - (α+β) (interior), π/2 - α
    /// (boundary), NaN on non-manifold edges. The counts below need no arctangent, these do.
    Eigen::VectorXd edge_margin;
    /// Per vertex: signed circumcentric dual area Σ_j (l_ij²/8)(cot α_ij + cot β_ij)
    /// (ALGORITHMS.md §6); 0 for unreferenced vertices, non-finite next to a zero-area face.
    Eigen::VectorXd dual_area;

    int interior_edges = 0;          ///< edges with exactly two faces
    int boundary_edges = 0;          ///< edges with one face
    int nonmanifold_edges = 0;       ///< edges with three or more faces (not judged)
    int nonmanifold_vertices = 0;    ///< vertices with more than one fan (see topology.hpp)
    int repeated_index_faces = 0;    ///< faces with a repeated vertex (ignored)
    /// Faces whose area from their side lengths (Kahan's formula) is 0: collinear or coincident
    /// corners, so no angles and no cotan weights. (MeshInfo::zero_area_faces is a coarser test,
    /// for repairs: area <= 1e-12 of the longest side squared.)
    int collinear_faces = 0;
    int non_delaunay_edges = 0;      ///< interior edges with margin < -tolerance
    int boundary_obtuse_edges = 0;   ///< boundary edges with margin < -tolerance (any policy)
    int negative_cotan_weights = 0;  ///< interior + boundary edges whose cotan weight is < 0
    int negative_dual_cells = 0;     ///< referenced vertices with dual area < -tol·Σ|terms|
                                     ///< or non-finite
    int gabriel_violations = 0;      ///< interior edges with an opposite vertex strictly inside
                                     ///< the other face's circumsphere
    /// Smallest margin over interior edges (+inf when there are none), and one edge attaining it.
    double min_delaunay_margin = std::numeric_limits<double>::infinity();
    int worst_edge = -1;

    /// Every edge manifold, every vertex manifold, no repeated-index or collinear face, every
    /// interior edge LD and, under the strict policy, every boundary edge LD.
    bool self_delaunay = false;
};

/// Certifies a mesh. Lengths come from V; the mesh may have boundaries, several components and
/// non-manifold parts (which are counted, not judged).
/// \throws InvalidMeshError a coordinate is not finite, or a face index is out of range.
/// \throws InvalidArgumentError tolerance outside [0, π/2).
DelaunayCertificate certify(const TriangleMesh& mesh, const CertifyOptions& options = {});

/// The same on an edge table already built for this mesh (saves rebuilding it).
DelaunayCertificate certify(const TriangleMesh& mesh, const EdgeTable& edges,
                            const CertifyOptions& options = {});

}  // namespace sdmesh
