// `sdmesh operators`: the cotan Laplacian, a mass matrix and the DEC operators of a mesh as
// Matrix Market files, plus report.json; and the pieces `sdmesh intrinsic` shares with it.

#include <chrono>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <system_error>

#include "cli/commands.hpp"
#include "cli/operator_files.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/matrix_market.hpp"

namespace sdmesh::cli {
namespace {

constexpr MassChoice kMassChoices[] = {
    {"barycentric", MassType::barycentric},
    {"circumcentric", MassType::circumcentric},
    {"mixed", MassType::mixed_voronoi},
    {"galerkin", MassType::galerkin},
};

double min_or_infinity(const Eigen::VectorXd& x) {
    return x.size() > 0 ? x.minCoeff() : std::numeric_limits<double>::infinity();
}

}  // namespace

MassChoice parse_mass(Args& args) {
    const std::string value = args.option("--mass").value_or("barycentric");
    for (const MassChoice& m : kMassChoices)
        if (value == m.name) return m;
    throw UsageError("--mass must be barycentric, circumcentric, mixed or galerkin, got '" + value + "'");
}

void write_operators(const Triangulation& t, const MassChoice& mass, const std::filesystem::path& dir,
                     JsonObject& report) {
    const Eigen::SparseMatrix<double> L = cotan_laplacian(t), M = mass_matrix(t, mass.type);
    const Eigen::VectorXd s0 = star0(t), s1 = star1(t);

    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw IoError(dir.string() + ": cannot create the output folder: " + ec.message());
    write_matrix_market(dir / "L.mtx", L);
    write_matrix_market(dir / "M.mtx", M);
    write_matrix_market(dir / "d0.mtx", d0(t));
    write_matrix_market(dir / "d1.mtx", d1(t));
    write_matrix_market(dir / "star0.mtx", diagonal_matrix(s0));
    write_matrix_market(dir / "star1.mtx", diagonal_matrix(s1));
    write_matrix_market(dir / "star2.mtx", diagonal_matrix(star2(t)));

    report.add("vertices", t.num_vertices)
        .add("edges", t.num_edges())
        .add("faces", t.num_faces())
        .add("mass", mass.name)
        .add("nnz_L", static_cast<long long>(L.nonZeros()))
        .add("nnz_M", static_cast<long long>(M.nonZeros()))
        .add("min_star0", min_or_infinity(s0))
        .add("min_star1", min_or_infinity(s1))
        .add("negative_star0", static_cast<long long>((s0.array() < 0).count()))
        .add("negative_star1", static_cast<long long>((s1.array() < 0).count()));
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
    const Triangulation t = about_file(path, [&] { return Triangulation::from_mesh(mesh); });
    JsonObject report;
    report.add("file", path);
    write_operators(t, mass, dir, report);
    report.add("seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    write_report(dir, report);
    return kSuccess;
}

}  // namespace sdmesh::cli
