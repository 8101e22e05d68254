// `sdmesh poisson MESH --f FILE --out FILE.ply [--dirichlet FILE]`: solves −Δu = f, i.e.
// L u = M f, with u given on the vertices listed in the Dirichlet file and the natural (Neumann)
// condition elsewhere; without Dirichlet vertices, f's mean is removed and u has zero mean.
// `sdmesh heat MESH (--u0 FILE | --source V[,V...]) --time T [--steps N] --out FILE.ply`:
// backward Euler steps (M + TL) u' = M u of the heat equation, Neumann boundary.
//
// Files: --f and --u0 hold one value per vertex (one per line); --dirichlet holds lines
// "VERTEX VALUE". The result is the PLY vertex field `u` of the mesh (the converted mesh with
// --convert); the report (JSON) goes to stdout.

#include <chrono>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/solver_input.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/pde.hpp"

namespace sdmesh::cli {
namespace {

// One value per vertex from a file.
Eigen::VectorXd read_vertex_values(const std::string& path, int vertices) {
    const Eigen::VectorXd values = read_table(path, 1).col(0);
    if (values.size() != vertices)
        throw ParseError(path + ": " + std::to_string(values.size()) + " values, expected one per vertex (" +
                         std::to_string(vertices) + ")");
    return values;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int run_poisson(Args& args) {
    const auto usage =
        "sdmesh poisson MESH --f FILE --out FILE.ply [--dirichlet FILE] [--mass ...] "
        "[--convert split|hybrid|flip | --intrinsic]";
    const SolverChoices choices = parse_solver_choices(args);
    const auto f_path = args.option("--f");
    const auto dirichlet_path = args.option("--dirichlet");
    const auto out = args.option("--out");
    const auto path = args.positionals(1, usage)[0];
    if (!f_path || !out) args.missing("--f and --out are", usage);

    JsonObject report;
    check_mesh_output(*out, /*with_vertex_fields=*/true);  // before a conversion and a solve
    const SolverInput input = load_solver_input(path, choices, report);
    const int n = input.triangulation.num_vertices;
    const Eigen::VectorXd f = read_vertex_values(*f_path, n);
    std::vector<int> vertices;
    Eigen::VectorXd values;
    if (dirichlet_path) {
        const Eigen::MatrixXd table = read_table(*dirichlet_path, 2);
        values = table.col(1);
        for (Eigen::Index i = 0; i < table.rows(); ++i) {
            const double v = table(i, 0);
            if (v != std::floor(v) || v < 0 || v >= n)
                throw InvalidArgumentError(*dirichlet_path + ": vertex " + std::to_string(v) +
                                           " is not an index in [0, " + std::to_string(n) + ")");
            vertices.push_back(static_cast<int>(v));
        }
    }
    const auto start = std::chrono::steady_clock::now();
    const Eigen::SparseMatrix<double> L = cotan_laplacian(input.triangulation),
                                      M = mass_matrix(input.triangulation, choices.mass.type);
    const Eigen::VectorXd u = about_file(path, [&] { return PoissonSolver(L, M, vertices).solve(M * f, values); });
    const double solve_seconds = seconds_since(start);
    write_mesh(*out, input.mesh, {.vertex_fields = {{"u", u}}});
    report.add("dirichlet_vertices", static_cast<long long>(vertices.size()))
        .add("min_u", u.minCoeff())
        .add("max_u", u.maxCoeff())
        .add("seconds", solve_seconds);
    std::cout << report.str() << '\n';
    return exit_code_after("poisson", path, {input.shortfall});
}

int run_heat(Args& args) {
    const auto usage =
        "sdmesh heat MESH (--u0 FILE | --source V[,V...]) --time T --out FILE.ply [--steps N] [--mass ...] "
        "[--convert split|hybrid|flip | --intrinsic]";
    const SolverChoices choices = parse_solver_choices(args);
    const auto u0_path = args.option("--u0");
    const auto source = args.option("--source");
    const auto time = args.number("--time");
    const long long steps = args.whole_number("--steps", 0, 1'000'000'000).value_or(1);
    const auto out = args.option("--out");
    const auto path = args.positionals(1, usage)[0];
    if (!out || !time || u0_path.has_value() == source.has_value())
        args.missing("--time, --out and one of --u0, --source are", usage);

    JsonObject report;
    check_mesh_output(*out, /*with_vertex_fields=*/true);  // before a conversion and a solve
    const SolverInput input = load_solver_input(path, choices, report);
    const int n = input.triangulation.num_vertices;
    Eigen::VectorXd u0 = Eigen::VectorXd::Zero(n);
    if (u0_path) {
        u0 = read_vertex_values(*u0_path, n);
    } else {
        const std::vector<int> sources = parse_vertex_list("--source", *source);
        check_vertex_range("heat", "--source", sources, n, path);
        for (const int v : sources) u0[v] = 1;
    }
    const auto start = std::chrono::steady_clock::now();
    const Eigen::VectorXd u = about_file(path, [&] {
        return HeatSolver(cotan_laplacian(input.triangulation), mass_matrix(input.triangulation, choices.mass.type),
                          *time)
            .step(u0, static_cast<int>(steps));
    });
    const double solve_seconds = seconds_since(start);
    write_mesh(*out, input.mesh, {.vertex_fields = {{"u", u}}});
    report.add("time", *time)
        .add("steps", steps)
        .add("min_u", u.minCoeff())
        .add("max_u", u.maxCoeff())
        .add("seconds", solve_seconds);
    std::cout << report.str() << '\n';
    return exit_code_after("heat", path, {input.shortfall});
}

}  // namespace sdmesh::cli
