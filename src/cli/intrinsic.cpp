// `sdmesh intrinsic`: the intrinsic Delaunay triangulation of a mesh, written as the same
// operator files as `sdmesh operators`, plus report.json with the flip report.

#include <chrono>
#include <filesystem>
#include <string>

#include "cli/commands.hpp"
#include "cli/operator_files.hpp"
#include "sdmesh/intrinsic.hpp"
#include "sdmesh/io.hpp"

namespace sdmesh::cli {

int run_intrinsic(Args& args) {
    const auto usage =
        "sdmesh intrinsic MESH --out DIR [--mass barycentric|circumcentric|mixed|galerkin] [--tolerance RAD] "
        "[--max-flips N]";
    const MassChoice mass = parse_mass(args);
    IntrinsicOptions options;
    options.tolerance = args.number("--tolerance").value_or(kDelaunayTolerance);
    options.max_flips = args.whole_number("--max-flips", 0, 1LL << 53).value_or(options.max_flips);
    const auto out = args.option("--out");
    const auto path = args.positionals(1, usage)[0];
    if (!out) args.missing("--out DIR is", usage);
    const std::filesystem::path dir = *out;

    const auto start = std::chrono::steady_clock::now();
    const TriangleMesh mesh = read_mesh(path);
    check_output_folder(dir);
    const IntrinsicResult idt =
        about_file(path, [&] { return intrinsic_delaunay(Triangulation::from_mesh(mesh), options); });
    JsonObject report;
    report.add("file", path);
    write_operators(idt.triangulation, mass, dir, report);
    report.merge(intrinsic_json(options, idt.report))
        .add("seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    write_report(dir, report);
    return exit_code_after("intrinsic", path, {intrinsic_shortfall(idt.report)});
}

}  // namespace sdmesh::cli
