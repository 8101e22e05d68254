#pragma once
// The intrinsic Delaunay triangulation (iDT) of a triangulated surface (Fisher, Springborn,
// Schröder & Bobenko 2007; ALGORITHMS.md §5): the same vertices and the same metric, only the
// connectivity changes, by Lawson flips of interior edges that are not locally Delaunay (LD).
// The comparison baseline for self-Delaunay meshes, and the choice of users who must not move
// or add a single vertex.
//
// Lawson loop: every interior edge facing an obtuse corner is tested (the others are LD), and
// after a flip the four outer edges of its hinge are tested again; an edge is flipped iff
// delaunay_margin() < -tolerance (the tolerance policy of delaunay.hpp). Boundary edges are never
// flipped, whatever their opposite angle. The new edge's length comes from laying the hinge out
// in the plane (see intrinsic.cpp). Flips preserve the surface, its area and every vertex's cone
// angle, and they terminate (Bobenko & Springborn 2007); a flip budget still turns a runaway
// into a status.
//
// The result is a Δ-complex: an edge may join a vertex to itself (self-edge) and several edges
// may join the same two vertices (repeated edges). Such an iDT is improper: then no self-Delaunay
// mesh exists on these vertices alone. Every operator of operators.hpp accepts the result.
//
// Single-threaded and deterministic: the same input gives the same flips and bit-identical lengths.
//
// Example:
//   const auto t = sdmesh::Triangulation::from_mesh(sdmesh::read_mesh("bunny.obj"));
//   const sdmesh::IntrinsicResult idt = sdmesh::intrinsic_delaunay(t);
//   if (!idt.report.proper) { /* no self-Delaunay mesh on these vertices: convert() adds some */ }
//   const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(idt.triangulation);
//   // every interior edge's cotan weight is now >= 0 (up to the tolerance)

#include <string>

#include "sdmesh/delaunay.hpp"
#include "sdmesh/triangulation.hpp"

namespace sdmesh {

struct IntrinsicOptions {
    /// An interior edge is flipped iff its margin π - (α + β) < -tolerance (radians, >= 0).
    double tolerance = kDelaunayTolerance;
    /// Flip budget: the loop stops after this many flips with status "flip_budget_exhausted".
    /// Negative: automatic, 100·|E| + 10⁶ (far above what any mesh of the corpus needs).
    long long max_flips = -1;
};

struct IntrinsicReport {
    long long flips = 0;      ///< edge flips performed
    bool proper = true;       ///< no self-edges and no repeated edges in the result
    int self_edges = 0;       ///< edges whose two ends are the same vertex
    int repeated_edges = 0;   ///< edges joining the same two vertices as an edge of smaller id
    /// Interior edges left not LD because no length fits their flipped diagonal: a hinge flat
    /// within rounding (two faces of nearly zero area, four vertices nearly on a line), whose
    /// flip would make a face of zero area.
    int unflippable_edges = 0;
    /// "delaunay" (every interior edge LD), "unflippable_edges" (every one but those) or
    /// "flip_budget_exhausted".
    std::string status;
    double seconds = 0;       ///< wall-clock time of the whole call
    double flip_seconds = 0;  ///< of which the Lawson loop (tests and flips)
};

struct IntrinsicResult {
    /// The iDT, with the input's vertices and as many faces and edges, which keep their ids: a
    /// flipped edge joins two other vertices and gets its intrinsic length, the two faces of a
    /// flip get new corners. Satisfies Triangulation::check(); equals the input when no edge
    /// was flipped.
    Triangulation triangulation;
    IntrinsicReport report;
};

/// Flips the interior edges of t until every one is LD within options.tolerance, or unflippable.
/// \pre t satisfies Triangulation::check() (verified) and is consistently oriented: the two
///      faces of an interior edge run along it in opposite directions (verified). A vertex with
///      several fans of faces is treated as one cone point per fan that happen to share an id.
/// \throws InvalidMeshError t violates a precondition (naming the element).
/// \throws InvalidArgumentError options.tolerance < 0 or not finite.
IntrinsicResult intrinsic_delaunay(const Triangulation& t, const IntrinsicOptions& options = {});

}  // namespace sdmesh
