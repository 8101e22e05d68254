// `sdmesh geodesic MESH --source V[,V...] --out FILE.ply`: heat-method geodesic distance from the
// nearest source, written as the per-vertex field `distance` of the mesh (the converted mesh with
// --convert; the input's vertices keep their indices). The report goes to stdout as JSON.

#include <chrono>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "cli/solver_input.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/pde.hpp"

namespace sdmesh::cli {
int run_geodesic(Args& args) {
    const auto usage =
        "sdmesh geodesic MESH --source V[,V...] --out FILE.ply [--mass ...] "
        "[--convert split|hybrid|flip | --intrinsic] [--time T]";
    const SolverChoices choices = parse_solver_choices(args);
    GeodesicOptions options{.mass = choices.mass.type};
    options.time = args.number("--time").value_or(options.time);
    const auto source = args.option("--source");
    const auto out = args.option("--out");
    const auto path = args.positionals(1, usage)[0];
    if (!source || !out)
        args.missing("--source and --out are", usage);
    const std::vector<int> sources = parse_vertex_list("--source", *source);

    JsonObject report;
    check_mesh_output(*out, /*with_vertex_fields=*/true);  // before a conversion and a solve
    const SolverInput input = load_solver_input(path, choices, report);
    if (input.triangulation.num_edges() == 0)
        throw InvalidArgumentError("geodesic: " + path + " has no edges, so there is no distance to compute");
    check_vertex_range("geodesic", "--source", sources, input.triangulation.num_vertices, path);
    const HeatGeodesics geodesics = about_file(path, [&] { return HeatGeodesics(input.triangulation, options); });
    const auto start = std::chrono::steady_clock::now();
    const Eigen::VectorXd distance = geodesics.distance(sources);
    const double query_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_mesh(*out, input.mesh, {.vertex_fields = {{"distance", distance}}});

    // Components without a source are at +inf, which JSON cannot hold: the report gives the
    // farthest vertex the sources reach, and how many they do not.
    const auto reached = distance.array().isFinite();
    const double max_distance =
        reached.any() ? reached.select(distance.array(), -std::numeric_limits<double>::infinity()).maxCoeff() : 0.0;
    report.add("sources", static_cast<long long>(sources.size()))
        .add("time", geodesics.report().time)
        .add("boundary_vertices", geodesics.report().boundary_vertices)
        .add("max_distance", max_distance)
        .add("unreached_vertices", static_cast<long long>(distance.size() - reached.count()))
        .add("precompute_seconds", geodesics.report().precompute_seconds)
        .add("query_seconds", query_seconds);
    std::cout << report.str() << '\n';
    return exit_code_after("geodesic", path, {input.shortfall});
}

}  // namespace sdmesh::cli
