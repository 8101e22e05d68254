#include "cli/reports.hpp"

#include <cstdio>
#include <limits>
#include <string>

namespace sdmesh::cli {
namespace {

constexpr MassChoice kMassChoices[] = {
    {"barycentric", MassType::barycentric},
    {"circumcentric", MassType::circumcentric},
    {"mixed", MassType::mixed_voronoi},
    {"galerkin", MassType::galerkin},
};

JsonObject rejections_json(const DecimateRejections& r) {
    JsonObject json;
    json.add("topology", r.topology)
        .add("not_delaunay", r.not_delaunay)
        .add("normal_flip", r.normal_flip)
        .add("max_error", r.max_error);
    return json;
}

double min_or_infinity(const Eigen::VectorXd& x) {
    return x.size() > 0 ? x.minCoeff() : std::numeric_limits<double>::infinity();
}

}  // namespace

std::optional<MassChoice> find_mass(std::string_view name) {
    for (const MassChoice& m : kMassChoices)
        if (name == m.name) return m;
    return std::nullopt;
}

std::string_view mass_name(MassType type) {
    for (const MassChoice& m : kMassChoices)
        if (type == m.type) return m.name;
    return "unknown";
}

std::string mass_names(std::string_view separator) {
    std::string names;
    for (const MassChoice& m : kMassChoices) names += (names.empty() ? "" : std::string(separator)) + m.name;
    return names;
}

std::string_view to_string(BoundaryPolicy policy) { return policy == BoundaryPolicy::strict ? "strict" : "free"; }

JsonObject mesh_info_json(const MeshInfo& info) {
    JsonObject json;
    json.add("vertices", info.vertices)
        .add("faces", info.faces)
        .add("edges", info.edges)
        .add("components", info.components)
        .add("boundary_edges", info.boundary_edges)
        .add("boundary_loops", info.boundary_loops)
        .add("nonmanifold_edges", info.nonmanifold_edges)
        .add("nonmanifold_vertices", info.nonmanifold_vertices)
        .add("degenerate_faces", info.degenerate_faces)
        .add("euler_characteristic", info.euler_characteristic)
        .add("genus", info.genus)
        .add("orientable", info.orientable)
        .add("orientation_conflicts", info.orientation_conflicts)
        .add("repeated_index_faces", info.repeated_index_faces)
        .add("zero_area_faces", info.zero_area_faces)
        .add("duplicate_faces", info.duplicate_faces)
        .add("duplicate_vertex_positions", info.duplicate_vertex_positions)
        .add("unreferenced_vertices", info.unreferenced_vertices)
        .add("non_finite_vertices", info.non_finite_vertices);
    return json;
}

JsonObject read_report_json(const ReadReport& read) {
    JsonObject json;
    json.add("file_faces", read.file_faces)
        .add("polygons", read.polygons)
        .add("ear_clipped_polygons", read.ear_clipped_polygons)
        .add("skipped_line_faces", read.skipped_line_faces);
    return json;
}

JsonObject repair_json(const RepairReport& report, const MeshInfo& repaired) {
    JsonObject json;
    json.add("merged_vertices", report.merged_vertices)
        .add("collapsed_needles", report.collapsed_needles)
        .add("dropped_repeated_index_faces", report.dropped_repeated_index_faces)
        .add("dropped_duplicate_faces", report.dropped_duplicate_faces)
        .add("split_vertices", report.split_vertices)
        .add("flipped_faces", report.flipped_faces)
        .add("non_orientable_components", report.non_orientable_components)
        .add("flipped_caps", report.flipped_caps)
        .add("dropped_caps", report.dropped_caps)
        .add("dropped_vertices", report.dropped_vertices)
        .add("vertices", repaired.vertices)
        .add("faces", repaired.faces)
        .add("manifold", repaired.manifold())
        .add("orientable", repaired.orientable);
    return json;
}

JsonObject certificate_json(const DelaunayCertificate& cert, const CertifyOptions& options) {
    const double fraction = cert.interior_edges > 0 ? double(cert.non_delaunay_edges) / cert.interior_edges : 0.0;
    JsonObject json;
    json.add("interior_edges", cert.interior_edges)
        .add("non_delaunay_edges", cert.non_delaunay_edges)
        .add("non_delaunay_fraction", fraction)
        .add("boundary_obtuse_edges", cert.boundary_obtuse_edges)
        .add("min_delaunay_margin", cert.min_delaunay_margin)
        .add("negative_dual_cells", cert.negative_dual_cells)
        .add("negative_cotan_weights", cert.negative_cotan_weights)
        .add("gabriel_violations", cert.gabriel_violations)
        .add("collinear_faces", cert.collinear_faces)
        .add("boundary_policy", to_string(options.boundary))
        .add("tolerance", options.tolerance)
        .add("self_delaunay", cert.self_delaunay);
    return json;
}

JsonObject conversion_json(const ConvertOptions& options, const ConversionReport& r) {
    JsonObject json;
    json.add("method", to_string(options.method))
        .add("split_rule", to_string(options.split_rule))
        .add("max_dihedral_deg", options.max_dihedral_deg)
        .add("coplanar_tolerance", options.coplanar_tolerance)
        .add("cascade_trials", options.cascade_trials)
        .add("local_search", options.local_search)
        .add("input_vertices", r.input_vertices)
        .add("output_vertices", r.output_vertices)
        .add("input_faces", r.input_faces)
        .add("output_faces", r.output_faces)
        .add("input_non_delaunay_edges", r.input_non_delaunay_edges)
        .add("input_nonflat_non_delaunay_edges", r.input_nonflat_non_delaunay_edges)
        .add("flips", r.flips)
        .add("splits", r.splits)
        .add("unflippable_edges", r.unflippable_edges)
        .add("vertices_inside_faces", r.vertices_inside_faces)
        .add("skipped_splits", r.skipped_splits)
        .add("removed_points", r.removed_points)
        .add("local_search_saved", r.local_search_saved)
        .add("fewest_points_saved", r.fewest_points_saved)
        .add("added_vertices_lower_bound", r.added_vertices_lower_bound)
        .add("status", to_string(r.status))
        .add("seconds", r.seconds)
        .add("hausdorff_rel", r.hausdorff_rel)
        .add("certificate",
             certificate_json(r.certificate, {.boundary = options.boundary, .tolerance = options.tolerance}));
    return json;
}

JsonObject decimation_counts_json(const DecimateOptions& options, const DecimateReport& r) {
    JsonObject json;
    json.add("input_vertices", r.input_vertices)
        .add("input_faces", r.input_faces)
        .add("target_vertices", r.target_vertices)
        .add("output_vertices", r.output_vertices)
        .add("output_faces", r.output_faces)
        .add("collapses", r.collapses)
        .add("rejected", rejections_json(r.rejected))
        .add("max_error", options.max_error);
    return json;
}

JsonObject decimation_outcome_json(const DecimateOptions& options, const DecimateReport& r) {
    JsonObject json;
    json.add("status", to_string(r.status))
        .add("seconds", r.seconds)
        .add("hausdorff_rel", r.hausdorff_rel)
        .add("certificate",
             certificate_json(r.certificate, {.boundary = options.boundary, .tolerance = options.tolerance}));
    return json;
}

JsonObject operator_summary_json(const Triangulation& t, std::string_view mass_name,
                                 const Eigen::SparseMatrix<double>& L, const Eigen::SparseMatrix<double>& M,
                                 const Eigen::VectorXd& s0, const Eigen::VectorXd& s1) {
    JsonObject json;
    json.add("vertices", t.num_vertices)
        .add("edges", t.num_edges())
        .add("faces", t.num_faces())
        .add("mass", mass_name)
        .add("nnz_L", static_cast<long long>(L.nonZeros()))
        .add("nnz_M", static_cast<long long>(M.nonZeros()))
        .add("min_star0", min_or_infinity(s0))
        .add("min_star1", min_or_infinity(s1))
        .add("negative_star0", static_cast<long long>((s0.array() < 0).count()))
        .add("negative_star1", static_cast<long long>((s1.array() < 0).count()));
    return json;
}

JsonObject intrinsic_json(const IntrinsicOptions& options, const IntrinsicReport& r) {
    JsonObject json;
    json.add("tolerance", options.tolerance)
        .add("flips", r.flips)
        .add("proper", r.proper)
        .add("self_edges", r.self_edges)
        .add("repeated_edges", r.repeated_edges)
        .add("unflippable_edges", r.unflippable_edges)
        .add("status", r.status)
        .add("intrinsic_seconds", r.seconds)
        .add("flip_seconds", r.flip_seconds);
    return json;
}

std::string not_certified_summary(const ConversionReport& report) {
    return "not certified (" + std::string(to_string(report.status)) + ", " +
           std::to_string(report.certificate.non_delaunay_edges) + " non-Delaunay edges and " +
           std::to_string(report.certificate.boundary_obtuse_edges) + " obtuse boundary edges left)";
}

std::string intrinsic_shortfall(const IntrinsicReport& report) {
    if (report.status == "flip_budget_exhausted")
        return "the intrinsic flips ran out of their budget after " + std::to_string(report.flips) +
               " flips: the triangulation is not Delaunay (--max-flips sets the budget)";
    if (report.unflippable_edges > 0)
        return "the intrinsic triangulation is not Delaunay: " + std::to_string(report.unflippable_edges) +
               " interior edges are not, and no flip can mend them, their hinges being flat within rounding "
               "(faces of nearly zero area)";
    return {};
}

std::string not_converged_message(const EigenReport& report) {
    char residual[32];
    std::snprintf(residual, sizeof residual, "%.3g", report.max_residual);
    return std::string("not converged (largest relative residual ") + residual +
           "); the pairs are approximations: solver spectra, or a sigma just below the wanted eigenvalues, can help";
}

JsonObject eigen_json(int k, const EigenResult& result) {
    const EigenReport& r = result.report;
    JsonObject json;
    json.add("k", k)
        .add("converged_pairs", static_cast<long long>(result.values.size()))
        .add("status", to_string(r.status))
        .add("solver", to_string(r.solver))
        .add("iterations", r.iterations)
        .add("solves", r.solves)
        .add("sigma", r.sigma)
        .add("max_residual", r.max_residual)
        .add("max_orthogonality_error", r.max_orthogonality_error)
        .add("seconds", r.seconds);
    return json;
}

}  // namespace sdmesh::cli
