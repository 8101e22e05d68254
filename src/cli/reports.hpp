#pragma once
// JSON forms of the library's reports and the names of option values, shared by the commands
// that print them and by the Python module (which turns the same JSON into dicts), so that every
// key and every option name has one source. Built as the internal library sdmesh_reports.

#include <optional>
#include <string>
#include <string_view>

#include <Eigen/SparseCore>

#include "cli/json.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/decimate.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/intrinsic.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh::cli {

struct MassChoice {
    const char* name;  ///< as given to --mass and written to report.json
    MassType type;
};

/// The mass matrix named `name` (barycentric, circumcentric, mixed, galerkin), if any.
std::optional<MassChoice> find_mass(std::string_view name);

/// The name of a mass matrix type, as find_mass() takes it.
std::string_view mass_name(MassType type);

/// The names find_mass() accepts, separated by `separator`.
std::string mass_names(std::string_view separator);

/// "strict" or "free".
std::string_view to_string(BoundaryPolicy policy);

/// The validation keys of `sdmesh check --json` (vertices ... non_finite_vertices).
JsonObject mesh_info_json(const MeshInfo& info);

/// What `sdmesh check --json` adds about the file: file_faces, polygons, ear_clipped_polygons,
/// skipped_line_faces.
JsonObject read_report_json(const ReadReport& read);

/// What `sdmesh repair` did (merged_vertices ... dropped_vertices) and what came of it
/// (vertices, faces, manifold, orientable); `repaired` is validate() of the result.
JsonObject repair_json(const RepairReport& report, const MeshInfo& repaired);

/// The certificate's counts and verdict (the keys of `sdmesh check --json` that concern it).
JsonObject certificate_json(const DelaunayCertificate& cert, const CertifyOptions& options);

/// `sdmesh convert`'s report after the file names: options, counts, status, certificate.
JsonObject conversion_json(const ConvertOptions& options, const ConversionReport& report);

/// `sdmesh decimate`'s counts, from input_vertices to max_error (the CLI writes its file names
/// before them and "levels" after them).
JsonObject decimation_counts_json(const DecimateOptions& options, const DecimateReport& report);

/// `sdmesh decimate`'s outcome after "levels": status, seconds, hausdorff_rel, certificate.
JsonObject decimation_outcome_json(const DecimateOptions& options, const DecimateReport& report);

/// The operator summary of `sdmesh operators` / `sdmesh intrinsic`: vertices, edges, faces, mass,
/// nnz_L, nnz_M, min_star0, min_star1, negative_star0, negative_star1.
JsonObject operator_summary_json(const Triangulation& t, std::string_view mass_name,
                                 const Eigen::SparseMatrix<double>& L, const Eigen::SparseMatrix<double>& M,
                                 const Eigen::VectorXd& s0, const Eigen::VectorXd& s1);

/// What `sdmesh intrinsic` adds to the operator summary (flip report, before "seconds").
JsonObject intrinsic_json(const IntrinsicOptions& options, const IntrinsicReport& report);

/// "not certified (STATUS, N non-Delaunay edges and M obtuse boundary edges left)": what a
/// conversion that is not certified says where `sdmesh convert`'s own advice does not apply.
std::string not_certified_summary(const ConversionReport& report);

/// Why intrinsic flips did not reach the iDT (their budget ran out, or edges were unflippable);
/// empty when they did.
std::string intrinsic_shortfall(const IntrinsicReport& report);

/// The solver part of `sdmesh eigs`'s report.json (k, converged_pairs, status, ..., seconds).
JsonObject eigen_json(int k, const EigenResult& result);

/// What `sdmesh eigs` prints, and Python warns, when the pairs did not converge.
std::string not_converged_message(const EigenReport& report);

}  // namespace sdmesh::cli
