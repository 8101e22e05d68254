#pragma once
// What `sdmesh operators` and `sdmesh intrinsic` share (and `sdmesh eigs`, the output folder):
// the --mass option, the Matrix Market files, the operator summary of report.json and its writing
// (implemented in operators.cpp).

#include <filesystem>

#include "cli/args.hpp"
#include "cli/json.hpp"
#include "cli/reports.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/triangulation.hpp"

namespace sdmesh::cli {

/// --mass barycentric|circumcentric|mixed|galerkin, default barycentric.
/// \throws UsageError another value.
MassChoice parse_mass(Args& args);

/// Writes L, M (of the chosen type), d0, d1, star0, star1, star2 of t as Matrix Market files into
/// dir (created with its parents), and adds the summary to report: vertices, edges, faces, mass,
/// nnz_L, nnz_M, min_star0, min_star1, negative_star0, negative_star1.
void write_operators(const Triangulation& t, const MassChoice& mass, const std::filesystem::path& dir,
                     JsonObject& report);

/// What creating the output folder `dir` (with its parents) would fail on, checked before the
/// work: its nearest existing ancestor must be a folder that takes new entries. \throws IoError
void check_output_folder(const std::filesystem::path& dir);

/// Creates the output folder `dir` with its parents. \throws IoError
void make_output_folder(const std::filesystem::path& dir);

/// Writes report.json into dir (atomically, see write_text_file) and prints it.
void write_report(const std::filesystem::path& dir, const JsonObject& report);

}  // namespace sdmesh::cli
