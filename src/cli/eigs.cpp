// `sdmesh eigs MESH -k K --out DIR`: the K smallest eigenpairs of L φ = λ M φ.
//
// Files written into DIR:
//   eigenvalues.csv  one eigenvalue per line, ascending
//   eigenvectors.bin little-endian int32 n, int32 k, then the k eigenvectors (M-orthonormal), each
//                    n doubles, in the order of eigenvalues.csv
//   report.json      the input summary and the solver report (status, iterations, residual, ...)

#include <bit>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <utility>

#include "cli/commands.hpp"
#include "cli/solver_input.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"

namespace sdmesh::cli {
namespace {

static_assert(std::endian::native == std::endian::little, "eigenvectors.bin is written in native byte order");

std::string eigenvalues_csv(const Eigen::VectorXd& values) {
    std::string text;
    char line[32];
    for (double value : values) {
        std::snprintf(line, sizeof line, "%.17g\n", value);
        text += line;
    }
    return text;
}

std::string eigenvectors_bin(const Eigen::MatrixXd& vectors) {
    const std::int32_t sizes[2] = {static_cast<std::int32_t>(vectors.rows()), static_cast<std::int32_t>(vectors.cols())};
    std::string bytes(reinterpret_cast<const char*>(sizes), sizeof sizes);
    bytes.append(reinterpret_cast<const char*>(vectors.data()), static_cast<size_t>(vectors.size()) * sizeof(double));
    return bytes;
}

}  // namespace

int run_eigs(Args& args) {
    const auto usage =
        "sdmesh eigs MESH -k K --out DIR [--mass barycentric|circumcentric|mixed|galerkin] "
        "[--convert split|hybrid|flip | --intrinsic] [--sigma S] [--tolerance T] [--solver block|spectra] "
        "[--progress]";
    const SolverChoices choices = parse_solver_choices(args);
    const auto k = args.whole_number("-k", 1, 1'000'000'000);
    EigenOptions options;
    options.sigma = args.number("--sigma").value_or(options.sigma);
    options.tolerance = args.number("--tolerance").value_or(options.tolerance);
    options.progress = args.flag("--progress");
    options.solver = args.choice("--solver",
                                 {std::pair{to_string(EigenSolver::block_lanczos).data(), EigenSolver::block_lanczos},
                                  std::pair{to_string(EigenSolver::spectra_lanczos).data(),
                                            EigenSolver::spectra_lanczos}})
                         .value_or(options.solver);
    const auto out = args.option("--out");
    const auto path = args.positionals(1, usage)[0];
    if (!out) args.missing("--out DIR is", usage);
    if (!k) args.missing("-k K is", usage);
    options.k = static_cast<int>(*k);
    const std::filesystem::path dir = *out;

    JsonObject report;
    check_output_folder(dir);  // before a conversion and a solve
    const SolverInput input = load_solver_input(path, choices, report);
    if (const int n = input.triangulation.num_vertices; options.k >= n)
        throw InvalidArgumentError("eigs: -k " + std::to_string(options.k) + " needs a mesh with more than " +
                                   std::to_string(options.k) + " vertices; " + path + " has " + std::to_string(n) +
                                   (choices.convert ? " after its conversion" : ""));
    const EigenResult result = about_file(path, [&] {
        return smallest_eigenpairs(cotan_laplacian(input.triangulation),
                                   mass_matrix(input.triangulation, choices.mass.type), options);
    });

    make_output_folder(dir);
    write_text_file(dir / "eigenvalues.csv", eigenvalues_csv(result.values));
    write_text_file(dir / "eigenvectors.bin", eigenvectors_bin(result.vectors));
    report.merge(eigen_json(options.k, result));
    write_report(dir, report);
    // The pairs are written either way, approximations when they did not converge.
    return exit_code_after(
        "eigs", path,
        {input.shortfall, result.report.status == EigenStatus::converged ? "" : not_converged_message(result.report)});
}

}  // namespace sdmesh::cli
