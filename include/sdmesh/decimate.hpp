#pragma once
// Delaunay-preserving decimation (ALGORITHMS.md §4, after Dyer et al. 2007): edge collapses of a
// self-Delaunay mesh, cheapest first, each keeping the mesh self-Delaunay, so that every
// intermediate mesh — and every level of a hierarchy — is one. A collapse costs its quadric
// error (Garland–Heckbert) plus 3x the squared distance of the farther of its two old positions
// from the new faces, which sees what the quadric misses at the tip of a thin fold.
//
// A collapse of edge [p, q] into a vertex v is accepted only if
//  - the link condition holds (genus and boundary loops are kept) and no link vertex drops
//    below three neighbours (two on the boundary);
//  - v lies in the allowable region: the linearised spoke and link constraints of §4; v is the
//    quadric optimum inside it (on the edge for a boundary edge, at the boundary vertex when one
//    end is on the boundary), and then every spoke and link edge passes the exact LD test of
//    delaunay.hpp (boundary edges under the chosen policy) — or, without max_error, fails it
//    only inside a plane, where edge flips that move nothing make every edge around LD (so
//    that vertices inside the planes of CAD or subdivided meshes can go at no cost);
//  - no face of the new star flips its normal or becomes degenerate;
//  - with max_error > 0, the two-sided distance output <-> input stays within max_error·diagonal
//    at the points the report's Hausdorff measurement samples (vertices, edge midpoints, centroids
//    of each face's 2 × 2 subdivision): the input's points are kept with a face of the output
//    they are that close to, and the new faces' points are checked against the input.
// When no allowable collapse is left before the target, decimation stops with status stalled.
// Large meshes (options.halves_from_vertices) are decimated in two halves of space side by side
// for most of the way, each in its own cheapest-first order up to a common cost threshold at a
// time, the seam between them after each step up to the same threshold; the last collapses
// before each stop follow one global order.
//
//   const auto result = sdmesh::decimate(mesh, {.target_ratio = 0.1, .max_error = 0.01});
//   if (result.report.status == sdmesh::DecimateStatus::reached_target) write_mesh("out.obj", result.mesh);

#include <string_view>
#include <vector>

#include "sdmesh/delaunay.hpp"
#include "sdmesh/mesh.hpp"

namespace sdmesh {

enum class DecimateStatus {
    reached_target,  ///< the output has the target number of vertices
    stalled,         ///< no allowable collapse was left before the target
};

struct DecimateOptions {
    /// Stop at this many vertices (> 0), or 0 to use target_ratio.
    long long target_vertices = 0;
    /// Stop at this fraction of the input's vertices, in (0, 1]; used when target_vertices is 0.
    double target_ratio = 0.5;
    /// Largest two-sided distance to the input, relative to its bounding-box diagonal, at the
    /// sample points of report.hausdorff_rel (so that it never exceeds this); 0 = no bound.
    double max_error = 0;
    BoundaryPolicy boundary = BoundaryPolicy::strict;
    double tolerance = kDelaunayTolerance;  ///< the locally-Delaunay tolerance, radians, [0, π/2)
    /// Vertex counts, decreasing and above the target, at which a copy of the mesh is kept as a
    /// level of the hierarchy (DecimateResult::levels).
    std::vector<long long> levels = {};
    /// When the quadric optimum inside the linearised region fails the exact tests (or the region
    /// is empty), also try the unconstrained optimum, the edge's midpoint and its two ends.
    bool search_candidates = true;
    /// Meshes with at least this many vertices are decimated in two halves of space side by side
    /// (on two threads when OpenMP has them) for most of the way: each half in its own
    /// cheapest-first order, both up to a common cost threshold at a time, the seam and the last
    /// collapses before each stop in one global order. 0 = one global order throughout. The
    /// output depends on this choice, never on the number of threads.
    long long halves_from_vertices = 50'000;
    /// Print a progress line to stderr about every second.
    bool progress = false;
    /// Measure the two-sided sampled Hausdorff distance output <-> input for the report.
    bool measure_hausdorff = true;
};

/// Collapses refused, by the first reason found.
struct DecimateRejections {
    long long topology = 0;      ///< link condition, a boundary rule or a too-small neighbourhood
    long long not_delaunay = 0;  ///< empty allowable region, or an affected edge failed the LD test
    long long normal_flip = 0;   ///< a face of the new star flipped or became degenerate
    long long max_error = 0;     ///< the distance bound would be exceeded
};

struct DecimateReport {
    long long input_vertices = 0;
    long long input_faces = 0;
    long long target_vertices = 0;
    long long output_vertices = 0;
    long long output_faces = 0;
    long long collapses = 0;
    DecimateRejections rejected;
    DecimateStatus status = DecimateStatus::reached_target;
    double seconds = 0;
    /// Two-sided sampled Hausdorff distance output <-> input (hausdorff_distance with
    /// samples_per_face = 4), relative to the input's bounding-box diagonal; NaN when
    /// options.measure_hausdorff is off and an edge was collapsed.
    double hausdorff_rel = 0;
    DelaunayCertificate certificate;  ///< of the output, under the same boundary policy
};

struct DecimateResult {
    TriangleMesh mesh;  ///< vertices compacted; survivors keep their relative order
    DecimateReport report;
    /// One mesh per reached entry of options.levels, in that order (a stalled run stops early).
    std::vector<TriangleMesh> levels;
};

/// Decimates a self-Delaunay mesh, keeping it self-Delaunay (see above). Deterministic.
/// \throws InvalidMeshError the mesh is not an oriented manifold with finite coordinates and no
///         zero-area face (the message names the first offending element).
/// \throws InvalidArgumentError the mesh is not self-Delaunay under options.boundary and
///         options.tolerance (run convert() first), or an option is out of range.
DecimateResult decimate(const TriangleMesh& mesh, const DecimateOptions& options = {});

std::string_view to_string(DecimateStatus status);

}  // namespace sdmesh
