#pragma once
// What the solver commands (eigs, geodesic, ...) share: the mesh they work on, after an optional
// self-Delaunay conversion (--convert METHOD) or intrinsic Delaunay flips (--intrinsic), and the
// mass matrix (--mass).

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "cli/args.hpp"
#include "cli/json.hpp"
#include "cli/operator_files.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/mesh.hpp"
#include "sdmesh/triangulation.hpp"

namespace sdmesh::cli {

struct SolverChoices {
    MassChoice mass;
    std::optional<ConvertMethod> convert = {};  ///< --convert split|hybrid|flip
    bool intrinsic = false;                ///< --intrinsic
};

/// Consumes --mass, --convert and --intrinsic.
/// \throws UsageError an unknown value, or --convert together with --intrinsic.
SolverChoices parse_solver_choices(Args& args);

struct SolverInput {
    /// The mesh whose vertices the results live on: the converted mesh with --convert, else the
    /// file's (an iDT keeps the vertices).
    TriangleMesh mesh;
    /// Its triangulation, or the iDT with --intrinsic.
    Triangulation triangulation;
    /// Empty, or why the --convert or --intrinsic mesh is not Delaunay (the commands still solve
    /// on it, and say so).
    std::string shortfall;
};

/// Reads `path` and applies the choices; adds file, mesh (extrinsic|converted|intrinsic), mass,
/// vertices, faces and the conversion or flip status to report.
SolverInput load_solver_input(const std::string& path, const SolverChoices& choices, JsonObject& report);

/// Vertex indices separated by commas ("3,17"), for --source.
/// \throws UsageError anything else, or no index.
std::vector<int> parse_vertex_list(const std::string& option, const std::string& text);

/// \throws InvalidArgumentError a vertex index not below `num_vertices`, the vertex count of the
///         mesh read from `path` ("<command>: <option>: vertex 12 is out of range [0, 12) of PATH").
void check_vertex_range(std::string_view command, std::string_view option, const std::vector<int>& vertices,
                        int num_vertices, const std::string& path);

/// A text file of whitespace-separated numbers: `columns` per line (blank lines and lines starting
/// with '#' skipped), returned row by row.
/// \throws IoError unreadable; ParseError a line with another count or a non-number (naming the line).
Eigen::MatrixXd read_table(const std::string& path, int columns);

}  // namespace sdmesh::cli
