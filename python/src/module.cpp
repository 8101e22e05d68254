// The Python module sdmesh._sdmesh: the C++ API over NumPy arrays and SciPy sparse matrices, with
// the CLI's option names and report keys (src/cli/reports.hpp). Array conversions: arrays.hpp.
//
// Every library call runs with the GIL released; Python objects are read before and built after.

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "arrays.hpp"
#include "cli/reports.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/decimate.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/intrinsic.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/pde.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh::python {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// ---- exceptions --------------------------------------------------------------------------------

// The Python classes mirroring sdmesh::Error's hierarchy; created once, alive as long as the process.
struct ErrorClasses {
    PyObject* error = nullptr;
    PyObject* io = nullptr;
    PyObject* unsupported_format = nullptr;
    PyObject* parse = nullptr;
    PyObject* invalid_mesh = nullptr;
    PyObject* invalid_argument = nullptr;
    PyObject* numerical = nullptr;
};
ErrorClasses errors;

PyObject* add_error_class(py::module_& m, const char* name, const char* doc, py::tuple bases) {
    const std::string qualified = std::string("sdmesh.") + name;
    PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
    if (!cls) throw py::error_already_set();
    m.add_object(name, py::handle(cls));  // the module's reference; `cls` keeps its own
    return cls;
}

void register_errors(py::module_& m) {
    const py::handle base = PyExc_Exception;
    errors.error = add_error_class(m, "Error", "Base class of every exception sdmesh raises on purpose.",
                                   py::make_tuple(base));
    const py::handle error = errors.error;
    errors.io = add_error_class(m, "IoError", "A file cannot be opened, read, written or renamed.",
                                py::make_tuple(error, py::handle(PyExc_OSError)));
    errors.unsupported_format = add_error_class(
        m, "UnsupportedFormatError", "The file's extension or header names a format sdmesh does not handle.",
        py::make_tuple(error));
    errors.parse = add_error_class(m, "ParseError", "A file of a supported format with malformed content.",
                                   py::make_tuple(error));
    errors.invalid_mesh = add_error_class(
        m, "InvalidMeshError", "The mesh violates a precondition (non-manifold, non-finite, index out of range...).",
        py::make_tuple(error));
    errors.invalid_argument = add_error_class(
        m, "InvalidArgumentError", "An argument or option out of its documented range, or an array of the wrong shape.",
        py::make_tuple(error, py::handle(PyExc_ValueError)));
    errors.numerical = add_error_class(m, "NumericalError", "A numerical precondition fails (e.g. M not positive definite).",
                                       py::make_tuple(error));

    py::register_exception_translator([](std::exception_ptr thrown) {
        try {
            if (thrown) std::rethrow_exception(thrown);
        } catch (const IoError& e) {
            PyErr_SetString(errors.io, e.what());
        } catch (const UnsupportedFormatError& e) {
            PyErr_SetString(errors.unsupported_format, e.what());
        } catch (const ParseError& e) {
            PyErr_SetString(errors.parse, e.what());
        } catch (const InvalidMeshError& e) {
            PyErr_SetString(errors.invalid_mesh, e.what());
        } catch (const InvalidArgumentError& e) {
            PyErr_SetString(errors.invalid_argument, e.what());
        } catch (const NumericalError& e) {
            PyErr_SetString(errors.numerical, e.what());
        } catch (const Error& e) {
            PyErr_SetString(errors.error, e.what());
        }
    });
}

// ---- option names ------------------------------------------------------------------------------

using cli::to_string;  // BoundaryPolicy's; the library's own enums are found by argument lookup

// The enum value whose to_string() is `name`, among `values`.
template <class Enum, size_t N>
Enum parse_name(const std::string& name, const char* option, const Enum (&values)[N]) {
    std::string names;
    for (const Enum value : values) {
        if (name == to_string(value)) return value;
        if (!names.empty()) names += '|';
        names += to_string(value);
    }
    throw InvalidArgumentError(std::string(option) + " must be " + names + ", got '" + name + "'");
}

BoundaryPolicy parse_boundary(const std::string& name) {
    return parse_name(name, "boundary", {BoundaryPolicy::strict, BoundaryPolicy::free});
}

cli::MassChoice parse_mass(const std::string& name) {
    if (const auto mass = cli::find_mass(name)) return *mass;
    throw InvalidArgumentError("mass must be " + cli::mass_names("|") + ", got '" + name + "'");
}

const std::string kDefaultMass(cli::mass_name(MassType::barycentric));

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---- meshes and operators ----------------------------------------------------------------------

py::tuple read_mesh_py(const std::filesystem::path& path) {
    TriangleMesh mesh;
    {
        py::gil_scoped_release unlocked;
        mesh = read_mesh(path);
    }
    return py::make_tuple(to_numpy(std::move(mesh.V)), to_numpy(std::move(mesh.F)));
}

void write_mesh_py(const std::filesystem::path& path, py::handle V, py::handle F, py::handle fields, bool ply_ascii) {
    const TriangleMesh mesh = mesh_from_arrays(V, F);
    WriteOptions options;
    options.ply_ascii = ply_ascii;
    if (!fields.is_none())
        for (const auto& [name, values] : fields.cast<py::dict>())
            options.vertex_fields.push_back({name.cast<std::string>(),
                                             vector_from_array(values, "a vertex field", mesh.num_vertices())});
    py::gil_scoped_release unlocked;
    write_mesh(path, mesh, options);
}

py::dict check_py(py::handle V, py::handle F, const std::string& boundary, double tolerance) {
    const TriangleMesh mesh = mesh_from_arrays(V, F);
    const CertifyOptions options{.boundary = parse_boundary(boundary), .tolerance = tolerance};
    cli::JsonObject report;
    {
        py::gil_scoped_release unlocked;
        const auto start = std::chrono::steady_clock::now();
        require_indices_in_range(mesh);
        const EdgeTable edges = build_edge_table(mesh.F, mesh.num_vertices());
        const MeshInfo info = validate(mesh, edges);
        const DelaunayCertificate cert = certify(mesh, edges, options);
        report.merge(cli::mesh_info_json(info)).merge(cli::certificate_json(cert, options)).add("seconds", seconds_since(start));
    }
    return to_dict(report);
}

py::tuple repair_py(py::handle V, py::handle F, const RepairOptions& options) {
    const TriangleMesh mesh = mesh_from_arrays(V, F);
    RepairReport counts;
    TriangleMesh repaired;
    MeshInfo info;
    {
        py::gil_scoped_release unlocked;
        repaired = repair(mesh, options, &counts);
        info = validate(repaired);
    }
    const py::dict report = to_dict(cli::repair_json(counts, info));
    return py::make_tuple(to_numpy(std::move(repaired.V)), to_numpy(std::move(repaired.F)), report);
}

// Where the CLI exits 1 with a line on stderr (a conversion not certified, intrinsic flips out of
// their budget, eigenpairs not converged), Python warns; the report says the same.
void warn(const std::string& message) {
    py::module_::import("warnings").attr("warn")(message, py::handle(PyExc_RuntimeWarning));
}

py::tuple convert_py(py::handle V, py::handle F, const std::string& method, const std::string& split_rule,
                     double max_dihedral_deg, double coplanar_tolerance, const std::string& boundary, double tolerance,
                     long long max_vertices, int cascade_trials, int local_search, bool progress,
                     bool measure_hausdorff) {
    const TriangleMesh mesh = mesh_from_arrays(V, F);
    const ConvertOptions options{
        .method = parse_name(method, "method", {ConvertMethod::split, ConvertMethod::hybrid, ConvertMethod::flip}),
        .split_rule = parse_name(split_rule, "split_rule", {SplitRule::interval, SplitRule::shell}),
        .max_dihedral_deg = max_dihedral_deg,
        .coplanar_tolerance = coplanar_tolerance,
        .boundary = parse_boundary(boundary),
        .tolerance = tolerance,
        .max_vertices = max_vertices,
        .cascade_trials = cascade_trials,
        .local_search = local_search,
        .progress = progress,
        .measure_hausdorff = measure_hausdorff,
    };
    ConversionResult result;
    {
        py::gil_scoped_release unlocked;
        result = convert(mesh, options);
    }
    if (result.report.status != ConvertStatus::certified)
        warn("convert: " + cli::not_certified_summary(result.report) + "; the report says more");
    const py::dict report = to_dict(cli::conversion_json(options, result.report));
    return py::make_tuple(to_numpy(std::move(result.mesh.V)), to_numpy(std::move(result.mesh.F)), report);
}

py::tuple decimate_py(py::handle V, py::handle F, long long target_vertices, double target_ratio, double max_error,
                      const std::string& boundary, double tolerance, py::handle levels, bool search_candidates,
                      long long halves_from_vertices, bool progress, bool measure_hausdorff) {
    const TriangleMesh mesh = mesh_from_arrays(V, F);
    DecimateOptions options{.target_vertices = target_vertices,
                            .target_ratio = target_ratio,
                            .max_error = max_error,
                            .boundary = parse_boundary(boundary),
                            .tolerance = tolerance,
                            .search_candidates = search_candidates,
                            .halves_from_vertices = halves_from_vertices,
                            .progress = progress,
                            .measure_hausdorff = measure_hausdorff};
    if (!levels.is_none())
        for (const int count : indices_from_array(levels, "levels")) options.levels.push_back(count);
    DecimateResult result;
    {
        py::gil_scoped_release unlocked;
        result = decimate(mesh, options);
    }
    // The CLI's keys, with "levels" the vertex counts of the levels (the CLI maps file names to them).
    py::dict report = to_dict(cli::decimation_counts_json(options, result.report));
    py::list level_counts, level_meshes;
    for (TriangleMesh& level : result.levels) {
        level_counts.append(level.num_vertices());
        level_meshes.append(py::make_tuple(to_numpy(std::move(level.V)), to_numpy(std::move(level.F))));
    }
    report["levels"] = level_counts;
    for (const auto& [key, value] : to_dict(cli::decimation_outcome_json(options, result.report))) report[key] = value;
    return py::make_tuple(to_numpy(std::move(result.mesh.V)), to_numpy(std::move(result.mesh.F)), report, level_meshes);
}

// L, M, d0, d1 and the three stars of t (as diagonal matrices, like the CLI's files); the summary
// of report.json goes to `summary` when given.
py::dict operator_dict(const Triangulation& t, const cli::MassChoice& mass, cli::JsonObject* summary) {
    SparseMatrix L, M, D0, D1, S0, S1, S2;
    {
        py::gil_scoped_release unlocked;
        L = cotan_laplacian(t);
        M = mass_matrix(t, mass.type);
        D0 = d0(t);
        D1 = d1(t);
        const Eigen::VectorXd s0 = star0(t), s1 = star1(t);
        if (summary) summary->merge(cli::operator_summary_json(t, mass.name, L, M, s0, s1));
        S0 = diagonal_matrix(s0);
        S1 = diagonal_matrix(s1);
        S2 = diagonal_matrix(star2(t));
    }
    py::dict out;
    out["L"] = to_csc(std::move(L));
    out["M"] = to_csc(std::move(M));
    out["d0"] = to_csc(std::move(D0));
    out["d1"] = to_csc(std::move(D1));
    out["star0"] = to_csc(std::move(S0));
    out["star1"] = to_csc(std::move(S1));
    out["star2"] = to_csc(std::move(S2));
    return out;
}

Triangulation triangulation_of(const TriangleMesh& mesh) {
    py::gil_scoped_release unlocked;
    return Triangulation::from_mesh(mesh);
}

py::dict operators_py(py::handle V, py::handle F, const std::string& mass) {
    const cli::MassChoice choice = parse_mass(mass);
    return operator_dict(triangulation_of(mesh_from_arrays(V, F)), choice, nullptr);
}

py::tuple intrinsic_operators_py(py::handle V, py::handle F, const std::string& mass, double tolerance,
                                 long long max_flips) {
    const auto start = std::chrono::steady_clock::now();
    const cli::MassChoice choice = parse_mass(mass);
    const TriangleMesh mesh = mesh_from_arrays(V, F);
    const IntrinsicOptions options{.tolerance = tolerance, .max_flips = max_flips};
    IntrinsicResult idt;
    {
        py::gil_scoped_release unlocked;
        idt = intrinsic_delaunay(Triangulation::from_mesh(mesh), options);
    }
    if (const std::string shortfall = cli::intrinsic_shortfall(idt.report); !shortfall.empty())
        warn("intrinsic_operators: " + shortfall);
    cli::JsonObject report;
    py::dict operators = operator_dict(idt.triangulation, choice, &report);
    report.merge(cli::intrinsic_json(options, idt.report)).add("seconds", seconds_since(start));
    return py::make_tuple(operators, to_dict(report));
}

// ---- solvers -----------------------------------------------------------------------------------

// The (L, M) of the solver functions: given as two sparse matrices, or built from (V, F) with the
// chosen mass matrix, on the intrinsic Delaunay triangulation when `intrinsic`.
struct Operators {
    SparseMatrix L, M;
};

Operators solver_operators(py::handle first, py::handle second, const std::optional<std::string>& mass, bool intrinsic) {
    if (is_sparse(first)) {
        if (mass || intrinsic)
            throw InvalidArgumentError("mass and intrinsic apply to a mesh (V, F), not to given matrices (L, M)");
        return {sparse_from_scipy(first, "L"), sparse_from_scipy(second, "M")};
    }
    // Dense matrices would otherwise be read as a mesh and fail on F's integers, which misleads.
    if (is_sparse(second)) throw py::type_error("V_or_L is not sparse but F_or_M is: pass L and M both as scipy.sparse");
    if (py::isinstance<py::array>(second) && second.cast<py::array>().dtype().kind() == 'f')
        throw py::type_error("F_or_M holds floats: a mesh's faces F are integers, and matrices L and M must both be "
                             "scipy.sparse");
    const MassType type = parse_mass(mass.value_or(kDefaultMass)).type;
    const TriangleMesh mesh = mesh_from_arrays(first, second);
    Triangulation t;
    std::string shortfall;
    {
        py::gil_scoped_release unlocked;
        t = Triangulation::from_mesh(mesh);
        if (intrinsic) {
            IntrinsicResult idt = intrinsic_delaunay(t);
            t = std::move(idt.triangulation);
            shortfall = cli::intrinsic_shortfall(idt.report);
        }
    }
    if (!shortfall.empty()) warn("intrinsic: " + shortfall);
    py::gil_scoped_release unlocked;
    return {cotan_laplacian(t), mass_matrix(t, type)};
}

py::object eigs_py(py::handle first, py::handle second, int k, const std::optional<std::string>& mass, bool intrinsic,
                   std::optional<double> sigma, double tolerance, int max_iterations, int basis_size,
                   py::handle dirichlet, const std::string& solver, bool progress, bool return_report) {
    EigenOptions options{.k = k, .tolerance = tolerance, .max_iterations = max_iterations, .basis_size = basis_size};
    options.progress = progress;
    options.solver = parse_name(solver, "solver", {EigenSolver::block_lanczos, EigenSolver::spectra_lanczos});
    if (sigma) options.sigma = *sigma;
    if (!dirichlet.is_none()) options.dirichlet_vertices = indices_from_array(dirichlet, "dirichlet");
    const Operators ops = solver_operators(first, second, mass, intrinsic);
    EigenResult result;
    {
        py::gil_scoped_release unlocked;
        result = smallest_eigenpairs(ops.L, ops.M, options);
    }
    if (result.report.status != EigenStatus::converged) warn("eigs: " + cli::not_converged_message(result.report));
    const py::dict report = to_dict(cli::eigen_json(k, result));
    py::array values = to_numpy(std::move(result.values)), vectors = to_numpy(std::move(result.vectors));
    if (return_report) return py::make_tuple(values, vectors, report);
    return py::make_tuple(values, vectors);
}

py::array poisson_py(py::handle first, py::handle second, py::handle f, py::handle dirichlet_vertices,
                     py::handle dirichlet_values, const std::optional<std::string>& mass, bool intrinsic) {
    const Operators ops = solver_operators(first, second, mass, intrinsic);
    const Eigen::VectorXd rhs = vector_from_array(f, "f", ops.M.rows());
    std::vector<int> vertices;
    Eigen::VectorXd values;
    if (!dirichlet_vertices.is_none()) vertices = indices_from_array(dirichlet_vertices, "dirichlet_vertices");
    if (!dirichlet_values.is_none())
        values = vector_from_array(dirichlet_values, "dirichlet_values", static_cast<Eigen::Index>(vertices.size()));
    Eigen::VectorXd u;
    {
        py::gil_scoped_release unlocked;
        u = PoissonSolver(ops.L, ops.M, vertices).solve(ops.M * rhs, values);
    }
    return to_numpy(std::move(u));
}

py::array heat_py(py::handle first, py::handle second, py::handle u0, double time, int steps,
                  const std::optional<std::string>& mass, bool intrinsic) {
    const Operators ops = solver_operators(first, second, mass, intrinsic);
    Eigen::VectorXd u = vector_from_array(u0, "u0", ops.M.rows());
    if (steps < 0) throw InvalidArgumentError("heat: steps must be >= 0, got " + std::to_string(steps));
    {
        py::gil_scoped_release unlocked;
        const HeatSolver heat(ops.L, ops.M, time);
        // One step at a time so that Ctrl-C is honoured between steps (same arithmetic as step(u, steps)).
        for (int s = 0; s < steps; ++s) {
            u = heat.step(u, 1);
            const py::gil_scoped_acquire locked;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();
        }
    }
    return to_numpy(std::move(u));
}

py::array geodesic_py(py::handle V, py::handle F, py::handle sources, std::optional<double> time,
                      const std::string& mass, bool average_boundary_conditions, bool intrinsic) {
    GeodesicOptions options{.mass = parse_mass(mass).type, .average_boundary_conditions = average_boundary_conditions};
    if (time) options.time = *time;
    const std::vector<int> source_list = indices_from_array(sources, "sources");
    const TriangleMesh mesh = mesh_from_arrays(V, F);
    Eigen::VectorXd distance;
    {
        py::gil_scoped_release unlocked;
        Triangulation t = Triangulation::from_mesh(mesh);
        if (intrinsic) t = intrinsic_delaunay(t).triangulation;
        distance = heat_geodesic_distance(t, source_list, options);
    }
    return to_numpy(std::move(distance));
}

}  // namespace
}  // namespace sdmesh::python

PYBIND11_MODULE(_sdmesh, m) {
    namespace py = pybind11;
    using namespace sdmesh;
    using namespace sdmesh::python;
    using py::arg;

    m.doc() = "sdmesh: self-Delaunay meshes, the cotan Laplacian, DEC operators and solvers (C++ core).";
    m.attr("__version__") = SDMESH_VERSION;
    register_errors(m);

    const ConvertOptions convert_defaults;
    const EigenOptions eigen_defaults;
    const IntrinsicOptions intrinsic_defaults;
    const GeodesicOptions geodesic_defaults;
    const std::string strict(cli::to_string(BoundaryPolicy::strict));

    m.def("read_mesh", &read_mesh_py, arg("path"), R"(read_mesh(path) -> (V, F)

Reads an OBJ, OFF, PLY or STL file (optionally .gz). V: float64 (n, 3), F: int32 (m, 3), both
Fortran-ordered views of the C++ arrays (no copy). Polygons are triangulated (fans, or ear
clipping where a fan would fold over).
Raises IoError, UnsupportedFormatError, ParseError.)");

    m.def("write_mesh", &write_mesh_py, arg("path"), arg("V"), arg("F"), arg("fields") = py::none(),
          arg("ply_ascii") = false, R"(write_mesh(path, V, F, fields=None, ply_ascii=False)

Writes OBJ, OFF or PLY (by extension, .gz compresses), atomically. `fields` maps names to
per-vertex arrays of n values, written as double vertex properties (PLY only).
Raises UnsupportedFormatError, InvalidArgumentError, IoError.)");

    m.def("check", &check_py, arg("V"), arg("F"), arg("boundary") = strict, arg("tolerance") = kDelaunayTolerance,
          R"(check(V, F, boundary="strict", tolerance=1e-10) -> dict

Validation and Delaunay certificate of a mesh: the keys of `sdmesh check --json` except those about
the file (file, file_faces, polygons, ear_clipped_polygons, skipped_line_faces). boundary: "strict" or "free"; tolerance in radians.
report["self_delaunay"] is the verdict. Raises InvalidMeshError (index out of range, non-finite).)");

    const RepairOptions repair_defaults;
    m.def(
        "repair",
        [](py::handle V, py::handle F, bool merge_coincident_vertices, bool collapse_needles,
           bool drop_repeated_index_faces, bool drop_duplicate_faces, bool split_nonmanifold_vertices, bool orient, bool flip_caps,
           bool drop_unreferenced_vertices) {
            return repair_py(V, F,
                             {.merge_coincident_vertices = merge_coincident_vertices,
                              .collapse_needles = collapse_needles,
                              .drop_repeated_index_faces = drop_repeated_index_faces,
                              .drop_duplicate_faces = drop_duplicate_faces,
                              .split_nonmanifold_vertices = split_nonmanifold_vertices,
                              .orient = orient,
                              .flip_caps = flip_caps,
                              .drop_unreferenced_vertices = drop_unreferenced_vertices});
        },
        arg("V"), arg("F"), py::kw_only(), arg("merge_coincident_vertices") = repair_defaults.merge_coincident_vertices,
        arg("collapse_needles") = repair_defaults.collapse_needles,
        arg("drop_repeated_index_faces") = repair_defaults.drop_repeated_index_faces,
        arg("drop_duplicate_faces") = repair_defaults.drop_duplicate_faces,
        arg("split_nonmanifold_vertices") = repair_defaults.split_nonmanifold_vertices,
        arg("orient") = repair_defaults.orient, arg("flip_caps") = repair_defaults.flip_caps,
        arg("drop_unreferenced_vertices") = repair_defaults.drop_unreferenced_vertices,
        R"(repair(V, F, *, merge_coincident_vertices=True, collapse_needles=True,
       drop_repeated_index_faces=True, drop_duplicate_faces=True, split_nonmanifold_vertices=True,
       orient=True, flip_caps=True, drop_unreferenced_vertices=True) -> (V, F, report)

The safe repairs of `sdmesh repair`, each on unless turned off (see sdmesh/validate.hpp): what
to run before convert or decimate when they raise InvalidMeshError. report: the keys of
`sdmesh repair`'s JSON except input/output. Raises InvalidMeshError (an index out of range).)");

    m.def("convert", &convert_py, arg("V"), arg("F"), py::kw_only(), arg("method") = std::string(to_string(convert_defaults.method)),
          arg("split_rule") = std::string(to_string(convert_defaults.split_rule)),
          arg("max_dihedral_deg") = convert_defaults.max_dihedral_deg,
          arg("coplanar_tolerance") = convert_defaults.coplanar_tolerance, arg("boundary") = strict,
          arg("tolerance") = convert_defaults.tolerance, arg("max_vertices") = convert_defaults.max_vertices,
          arg("cascade_trials") = convert_defaults.cascade_trials, arg("local_search") = convert_defaults.local_search,
          arg("progress") = convert_defaults.progress, arg("measure_hausdorff") = convert_defaults.measure_hausdorff,
          R"(convert(V, F, *, method="split", split_rule="interval", max_dihedral_deg=10.0,
        coplanar_tolerance=1e-10, boundary="strict", tolerance=1e-10, max_vertices=0,
        cascade_trials=4, local_search=0, progress=False, measure_hausdorff=True) -> (V, F, report)

Converts a manifold mesh into a self-Delaunay mesh (method "split", "hybrid" or "flip"; see
sdmesh/convert.hpp). cascade_trials: split positions tried where a split must break a side
(0: none). local_search: passes of local search after a split conversion, for fewer
vertices at more time (0: none). measure_hausdorff=False skips report["hausdorff_rel"] (None then,
where flips may have moved the surface). New vertices come after the input's. report: the keys of `sdmesh convert`'s
JSON except input/output; report["status"] is "certified", "budget_exhausted" or "not_certified"
(a RuntimeWarning says so when it is not "certified").
Raises InvalidMeshError (run a repair first), InvalidArgumentError.)");

    const DecimateOptions decimate_defaults;
    m.def("decimate", &decimate_py, arg("V"), arg("F"), py::kw_only(),
          arg("target_vertices") = decimate_defaults.target_vertices, arg("target_ratio") = decimate_defaults.target_ratio,
          arg("max_error") = decimate_defaults.max_error, arg("boundary") = strict,
          arg("tolerance") = decimate_defaults.tolerance, arg("levels") = py::none(),
          arg("search_candidates") = decimate_defaults.search_candidates,
          arg("halves_from_vertices") = decimate_defaults.halves_from_vertices, arg("progress") = decimate_defaults.progress,
          arg("measure_hausdorff") = decimate_defaults.measure_hausdorff,
          R"(decimate(V, F, *, target_vertices=0, target_ratio=0.5, max_error=0.0, boundary="strict",
         tolerance=1e-10, levels=None, search_candidates=True, halves_from_vertices=50000,
         progress=False, measure_hausdorff=True) -> (V, F, report, levels)

Coarsens a self-Delaunay mesh by edge collapses that keep it self-Delaunay (sdmesh/decimate.hpp), to
target_vertices (or target_ratio of the input's vertices when it is 0). max_error: largest distance
to the input relative to its bounding-box diagonal (0: none). levels: decreasing vertex counts at
which a copy of the mesh is kept; returned as a list of (V, F). halves_from_vertices: meshes this
large are decimated in two halves of space side by side for most of the way (0: one global order;
the output never depends on the thread count). report: the keys of `sdmesh decimate`'s JSON except
input/output, "levels" holding the levels' vertex counts; report["status"] is "reached_target" or
"stalled".
Raises InvalidArgumentError (the mesh is not self-Delaunay: convert() it first), InvalidMeshError.)");

    m.def("operators", &operators_py, arg("V"), arg("F"), arg("mass") = kDefaultMass,
          R"(operators(V, F, mass="barycentric") -> dict

The cotan Laplacian and DEC operators as scipy.sparse.csc_matrix (views of the C++ arrays, no copy):
L (n x n, positive semidefinite, L = d0ᵀ star1 d0), M (mass: "barycentric", "circumcentric",
"mixed" or "galerkin"), d0 (|E| x n), d1 (|F| x |E|), star0 (n x n), star1 (|E| x |E|) and
star2 (|F| x |F|) as diagonal matrices. Edges are numbered as in the CLI's files.
Raises InvalidMeshError (non-manifold edge, repeated index, zero-length edge...).)");

    m.def("intrinsic_operators", &intrinsic_operators_py, arg("V"), arg("F"), arg("mass") = kDefaultMass,
          arg("tolerance") = intrinsic_defaults.tolerance, arg("max_flips") = intrinsic_defaults.max_flips,
          R"(intrinsic_operators(V, F, mass="barycentric", tolerance=1e-10, max_flips=-1) -> (dict, report)

The operators of operators() on the intrinsic Delaunay triangulation of the mesh (same vertices,
edges flipped), and the report of `sdmesh intrinsic` (without "file"): flips, proper, status...
max_flips < 0: automatic budget; status "flip_budget_exhausted" (a RuntimeWarning says so) when it
runs out, "unflippable_edges" (likewise) when edges whose hinges are flat within rounding stay not
locally Delaunay. The solvers' intrinsic=True warns the same way.)");

    m.def("eigs", &eigs_py, arg("V_or_L"), arg("F_or_M"), arg("k") = eigen_defaults.k, py::kw_only(),
          arg("mass") = py::none(), arg("intrinsic") = false, arg("sigma") = py::none(),
          arg("tolerance") = eigen_defaults.tolerance, arg("max_iterations") = eigen_defaults.max_iterations,
          arg("basis_size") = eigen_defaults.basis_size, arg("dirichlet") = py::none(), arg("solver") = "block",
          arg("progress") = eigen_defaults.progress, arg("return_report") = false,
          R"(eigs(V, F, k=10, *, mass=None, intrinsic=False, sigma=None, tolerance=1e-10,
     max_iterations=1000, basis_size=0, dirichlet=None, solver="block", progress=False,
     return_report=False)
     -> (evals, evecs[, report])
eigs(L, M, k=10, ...)

The k smallest eigenpairs of L φ = λ M φ, from a mesh (cotan L and the `mass` matrix, default
"barycentric", on the intrinsic Delaunay triangulation if `intrinsic`) or from given sparse L, M.
evals: (k,) ascending; evecs: (n, k), M-orthonormal. sigma: shift < 0 (None: automatic);
dirichlet: vertices where φ = 0. solver: "block" (block Lanczos) or "spectra" (Spectra's
Lanczos). progress: lines on stderr (the factorization, then about every second). report: the solver keys of `sdmesh eigs`'s report.json; when report["status"] is
"not_converged" (a RuntimeWarning says so), spectra returns fewer than k pairs, block its best approximations.
Raises InvalidArgumentError (k >= n, ...), NumericalError (M not positive definite).)");

    m.def("poisson", &poisson_py, arg("V_or_L"), arg("F_or_M"), arg("f"), py::kw_only(),
          arg("dirichlet_vertices") = py::none(), arg("dirichlet_values") = py::none(), arg("mass") = py::none(),
          arg("intrinsic") = false,
          R"(poisson(V, F, f, *, dirichlet_vertices=None, dirichlet_values=None, mass=None, intrinsic=False) -> u
poisson(L, M, f, ...)

Solves −Δu = f (L u = M f) with u = dirichlet_values on dirichlet_vertices (0 if values are None)
and the natural boundary condition elsewhere; without Dirichlet vertices f's mean is removed and
u has zero M-mean, as `sdmesh poisson`.)");

    m.def("heat", &heat_py, arg("V_or_L"), arg("F_or_M"), arg("u0"), arg("time"), arg("steps") = 1, py::kw_only(),
          arg("mass") = py::none(), arg("intrinsic") = false,
          R"(heat(V, F, u0, time, steps=1, *, mass=None, intrinsic=False) -> u
heat(L, M, u0, time, steps=1)

`steps` backward Euler steps (M + time·L) u' = M u of the heat equation from u0, Neumann boundary,
as `sdmesh heat`. Ctrl-C (KeyboardInterrupt) is honoured between steps.)");

    m.def("geodesic", &geodesic_py, arg("V"), arg("F"), arg("sources"), py::kw_only(), arg("time") = py::none(),
          arg("mass") = std::string(cli::mass_name(geodesic_defaults.mass)),
          arg("average_boundary_conditions") = geodesic_defaults.average_boundary_conditions,
          arg("intrinsic") = false,
          R"(geodesic(V, F, sources, *, time=None, mass="barycentric", average_boundary_conditions=True,
         intrinsic=False) -> distances

Geodesic distance (n,) from the nearest source vertex by the heat method, as `sdmesh geodesic`;
time None: h², h the mean edge length of each connected component. +inf on components without a
source.)");
}
