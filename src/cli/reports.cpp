#include "cli/reports.hpp"

namespace sdmesh::cli {

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
        .add("boundary_policy", options.boundary == BoundaryPolicy::strict ? "strict" : "free")
        .add("tolerance", options.tolerance)
        .add("self_delaunay", cert.self_delaunay);
    return json;
}

}  // namespace sdmesh::cli
