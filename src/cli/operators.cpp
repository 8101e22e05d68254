// `sdmesh operators`: the cotan Laplacian, a mass matrix and the DEC operators of a mesh as
// Matrix Market files, plus report.json; and the pieces `sdmesh intrinsic` shares with it.

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>

#include <unistd.h>

#include "cli/commands.hpp"
#include "cli/operator_files.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/matrix_market.hpp"

namespace sdmesh::cli {
void check_output_folder(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::path existing = dir;
    while (!existing.empty() && !std::filesystem::exists(existing, ec)) existing = existing.parent_path();
    if (existing.empty()) existing = ".";
    if (!std::filesystem::is_directory(existing, ec))
        throw IoError(dir.string() + ": cannot create the output folder: " + existing.string() + " is not a folder");
    if (::access(existing.c_str(), W_OK | X_OK) != 0)
        throw IoError(dir.string() + ": cannot create the output folder: " + std::strerror(errno));
}

void make_output_folder(const std::filesystem::path& dir) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw IoError(dir.string() + ": cannot create the output folder: " + ec.message());
}

MassChoice parse_mass(Args& args) {
    const std::string value = args.option("--mass").value_or("barycentric");
    if (const auto mass = find_mass(value)) return *mass;
    throw UsageError("--mass must be " + mass_names("|") + ", got '" + value + "'");
}

void write_operators(const Triangulation& t, const MassChoice& mass, const std::filesystem::path& dir,
                     JsonObject& report) {
    const Eigen::SparseMatrix<double> L = cotan_laplacian(t), M = mass_matrix(t, mass.type);
    const Eigen::VectorXd s0 = star0(t), s1 = star1(t);

    make_output_folder(dir);
    write_matrix_market(dir / "L.mtx", L);
    write_matrix_market(dir / "M.mtx", M);
    write_matrix_market(dir / "d0.mtx", d0(t));
    write_matrix_market(dir / "d1.mtx", d1(t));
    write_matrix_market(dir / "star0.mtx", diagonal_matrix(s0));
    write_matrix_market(dir / "star1.mtx", diagonal_matrix(s1));
    write_matrix_market(dir / "star2.mtx", diagonal_matrix(star2(t)));

    report.merge(operator_summary_json(t, mass.name, L, M, s0, s1));
}

void write_report(const std::filesystem::path& dir, const JsonObject& report) {
    const std::string json = report.str() + "\n";
    write_text_file(dir / "report.json", json);
    std::cout << json;
}

int run_operators(Args& args) {
    const auto usage = "sdmesh operators MESH --out DIR [--mass barycentric|circumcentric|mixed|galerkin]";
    const MassChoice mass = parse_mass(args);
    const auto out = args.option("--out");
    const auto path = args.positionals(1, usage)[0];
    if (!out) args.missing("--out DIR is", usage);
    const std::filesystem::path dir = *out;

    const auto start = std::chrono::steady_clock::now();
    const TriangleMesh mesh = read_mesh(path);
    check_output_folder(dir);
    const Triangulation t = about_file(path, [&] { return Triangulation::from_mesh(mesh); });
    JsonObject report;
    report.add("file", path);
    write_operators(t, mass, dir, report);
    report.add("seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    write_report(dir, report);
    return kSuccess;
}

}  // namespace sdmesh::cli
