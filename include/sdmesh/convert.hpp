#pragma once
// Conversion of a manifold triangle mesh into a self-Delaunay mesh (ALGORITHMS.md §1-§3).
//
// Methods:
//  - flip:   Delaunay edge flips on the surface (Lawson, after Dyer, Zhang & Möller 2007). Moves
//            the surface where it is not flat; edges that cannot be flipped (the new edge exists
//            already, or the unfolded hinge is not convex) stay and are counted.
//  - split:  geometry-preserving. Non-Delaunay edges are split at points on them; flips happen
//            only where the two faces are coplanar, so the surface does not move at all. A split
//            in a strip of thin faces carries its cut on across the strip, at the same fraction
//            of each long edge (a loop cut), so that a tessellated cylinder takes one ring of
//            points. At the end, split points that later ones made unnecessary are removed
//            again, until no point can go alone, and each input edge with several points gets
//            the fewest that suffice beside the points of the edges around it.
//  - hybrid: edges within max_dihedral_deg of flat are flipped, the others split: fewer new
//            vertices for a bounded change of the surface (reported as a Hausdorff distance).
//
// Every edge is judged by the one tolerance policy of delaunay.hpp; the result is certified by
// certify() on the output, whose certificate is part of the report.
//
//   const auto result = sdmesh::convert(mesh, {.method = sdmesh::ConvertMethod::hybrid,
//                                              .max_dihedral_deg = 10});
//   if (result.report.status == sdmesh::ConvertStatus::certified) write_mesh("out.obj", result.mesh);

#include <string_view>

#include "sdmesh/delaunay.hpp"
#include "sdmesh/mesh.hpp"

namespace sdmesh {

enum class ConvertMethod { flip, split, hybrid };

/// Where a non-Delaunay edge is split (ALGORITHMS.md §3).
enum class SplitRule {
    /// Inside the interval that keeps both halves locally Delaunay (Liu et al. 2015), keeping as
    /// many of the four outer edges locally Delaunay as possible (non-flat ones first: they would
    /// need a vertex, flat ones only a flip; where a non-flat one must break, preferably one whose
    /// own split will not break another); pieces shorter than a quarter of their input edge
    /// that end at an input vertex follow the shells below, which stops small input angles from
    /// cascading. Non-Delaunay edges whose faces share outer edges (a terrain's grid cells) are
    /// split first, at positions chosen together so that the shared edges stay Delaunay.
    interval,
    /// On concentric shells around input vertices (Dyer's rule, after Ruppert): at a power of
    /// two of a fixed unit from the input endpoint, within [l/3, 2l/3); the midpoint otherwise.
    shell,
};

enum class ConvertStatus {
    certified,         ///< the output is self-Delaunay
    budget_exhausted,  ///< max_vertices or max_flips was reached first; the output is valid but
                       ///< not certified
    not_certified,     ///< flip method: unflippable non-Delaunay edges remain
};

/// The default ConvertOptions::coplanar_tolerance: faces this close to coplanar are taken as one
/// plane, and a flip across their edge moves the surface by less than 1e-10 of the edge's length.
inline constexpr double kExactlyCoplanar = 1e-10;

struct ConvertOptions {
    ConvertMethod method = ConvertMethod::split;
    SplitRule split_rule = SplitRule::interval;
    /// hybrid: edges whose dihedral angle is within this many degrees of flat (180°) are flipped.
    double max_dihedral_deg = 10.0;
    /// split: two faces count as coplanar (so their edge may be flipped) when their normals differ
    /// by at most this angle, in radians, in [0, π/2). At the default the surface does not move;
    /// above it a flip can move it by about this angle times an edge length (to absorb a file's
    /// rounding of planar faces), and report.hausdorff_rel measures how far.
    double coplanar_tolerance = kExactlyCoplanar;
    BoundaryPolicy boundary = BoundaryPolicy::strict;
    double tolerance = kDelaunayTolerance;  ///< the locally-Delaunay tolerance, radians, [0, π/2)
    /// Stop with status budget_exhausted when this many vertices have been made: the input's and
    /// every split point, also those removed again later (their ids are not reused), so the
    /// output can hold fewer; 0 = 10·|V| + 1000000.
    long long max_vertices = 0;
    /// Stop with status budget_exhausted after this many flips; 0 = 100·|E| + 1000000, |E| the
    /// edges of the mesh as it is then (splits add edges). Lawson's flips terminate in exact
    /// arithmetic, but on nearly degenerate input (coordinates spanning many orders of
    /// magnitude) rounding can make the LD verdicts cycle.
    long long max_flips = 0;
    /// split (and hybrid's splits): where every position for a split point breaks a physical
    /// side, so that the split costs more vertices, up to this many positions are tried: each
    /// split is made, the cascade it starts is followed for 16 splits and taken back, and the
    /// cheapest is kept (experiments/conversion_table/JOURNAL.md: what more trials save and cost).
    /// 0 or 1 = none: the first position by the sides it keeps and what they look like next.
    int cascade_trials = 4;
    /// split: passes of local search after the conversion. Around each split point, the split
    /// points of its two input faces are placed again with their neighbours known, and the
    /// result is kept where it has fewer vertices; then each split point whose faces around are
    /// all single-face planes is taken out while the points near it move until every piece is
    /// locally Delaunay again (deterministic: a fixed pseudo-random sequence per point). See
    /// experiments/conversion_table/JOURNAL.md for what it saves and costs. 0 = none.
    int local_search = 0;
    /// split: also compute report.added_vertices_lower_bound (linear in the mesh size).
    bool lower_bound = false;
    /// Print progress lines to stderr: each phase as it starts, and about every second the
    /// queue's splits and flips, the points removed and left to try, the fewest-points pass's
    /// share of the edges done, or local search's share of the points done.
    bool progress = false;
    /// Compute the two-sided sampled Hausdorff distance output <-> input (0 for split). Off,
    /// report.hausdorff_rel is NaN wherever flips may have moved the surface: on a mesh of a
    /// million faces the measure takes several times as long as the conversion.
    bool measure_hausdorff = true;
};

struct ConversionReport {
    long long input_vertices = 0;
    long long output_vertices = 0;
    long long input_faces = 0;
    long long output_faces = 0;
    long long input_non_delaunay_edges = 0;  ///< interior non-LD + boundary-obtuse (policy)
    long long input_nonflat_non_delaunay_edges = 0;  ///< of those, edges that are not flat
    long long flips = 0;
    long long splits = 0;
    long long unflippable_edges = 0;  ///< flip method: non-LD edges left at the end
    long long vertices_inside_faces = 0;  ///< split points not on an input edge
    /// splits not made: every point tried on the edge fell on a vertex in double precision
    /// (cascades 1e-15 deep); the edge is tried again when its hinge changes, else left for the
    /// certificate to count
    long long skipped_splits = 0;
    /// split: points removed again at the end, once later points had made them unnecessary
    /// (output vertices = input vertices + splits - removed_points)
    long long removed_points = 0;
    /// split: vertices fewer thanks to local search (options.local_search); included above
    long long local_search_saved = 0;
    /// split: vertices fewer because the points of an input edge were placed again, the fewest
    /// that suffice with the points of the other edges in place; included above
    long long fewest_points_saved = 0;
    /// split with options.lower_bound: at least this many vertices must be added by any
    /// conversion that keeps the surface and puts its vertices on input edges (this one
    /// included), from what a split point asks of the edges next to it; -1 when not computed.
    /// Always >= input_nonflat_non_delaunay_edges.
    long long added_vertices_lower_bound = -1;
    ConvertStatus status = ConvertStatus::certified;
    double seconds = 0;
    /// Two-sided, relative to the input's bounding-box diagonal, sampled; 0 for split at the
    /// default coplanar tolerance (nothing moves); NaN when not measured.
    double hausdorff_rel = 0;
    DelaunayCertificate certificate;  ///< of the output, under the same boundary policy
};

struct ConversionResult {
    TriangleMesh mesh;
    ConversionReport report;
};

/// Converts a mesh to a self-Delaunay one (see the methods above). New vertices are appended
/// after the input's; the input's vertices keep their indices.
/// \throws InvalidMeshError the mesh is not a manifold with finite coordinates, or has a face of
///         zero area (run repair() first); the message names the first offending element.
/// \throws InvalidArgumentError an option out of range.
ConversionResult convert(const TriangleMesh& mesh, const ConvertOptions& options = {});

std::string_view to_string(ConvertStatus status);
std::string_view to_string(ConvertMethod method);
std::string_view to_string(SplitRule rule);

}  // namespace sdmesh
