// Study 3, Wardetzky et al.'s four properties of a discrete Laplacian (2007) plus positive dual
// cells, measured on the cotan Laplacian of corpus meshes and of planar meshes, each under its
// original connectivity, its self-Delaunay conversions (split, hybrid) and its iDT:
//  - symmetry: max |L − Lᵀ|;
//  - locality: off-diagonal entries of L between vertices that share no edge;
//  - linear precision (planar meshes only): max over interior vertices of |(L x)_i| for the
//    coordinate functions x, relative to Σ_j |L_ij x_j|;
//  - positive weights (the maximum principle): edges with a negative cotan weight ⋆1 beyond the
//    tolerance of delaunay.hpp (margin < −1e-10 rad; converted meshes keep weights of about
//    −1e-13 on nearly co-circular hinges, which the policy counts as Delaunay);
//  - positive dual cells: vertices with a negative circumcentric dual area ⋆0.
//   wardetzky --out DIR [--corpus DIR] [--quick]
// Writes DIR/wardetzky.csv; experiments/wardetzky/plot.py makes the table and the figure.

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <unordered_set>
#include <vector>

#include "sdmesh/delaunay.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/shapes.hpp"
#include "study.hpp"

namespace {

struct Subject {
    std::string name;
    sdmesh::TriangleMesh mesh;
    bool planar;
};

struct LaplacianProperties {
    double symmetry_error = 0;
    long long nonlocal_entries = 0;
    double linear_precision_residual = std::numeric_limits<double>::quiet_NaN();
};

LaplacianProperties laplacian_properties(const study::Variant& variant, bool planar) {
    const sdmesh::Triangulation& t = variant.triangulation;
    const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t);
    LaplacianProperties properties;
    const Eigen::SparseMatrix<double> asymmetry = L - Eigen::SparseMatrix<double>(L.transpose());
    properties.symmetry_error = asymmetry.nonZeros() > 0 ? asymmetry.coeffs().cwiseAbs().maxCoeff() : 0.0;
    std::unordered_set<long long> edges;
    const long long n = t.num_vertices;
    for (int e = 0; e < t.num_edges(); ++e) edges.insert(t.E(e, 0) * n + t.E(e, 1));
    for (int j = 0; j < L.outerSize(); ++j)
        for (Eigen::SparseMatrix<double>::InnerIterator it(L, j); it; ++it) {
            const long long lo = std::min<long long>(it.row(), j), hi = std::max<long long>(it.row(), j);
            if (lo != hi && it.value() != 0 && !edges.contains(lo * n + hi)) ++properties.nonlocal_entries;
        }
    if (planar) {
        // The iDT keeps the input's vertices, so the variant's mesh holds the right positions.
        std::vector<char> on_boundary(static_cast<std::size_t>(n), 0);
        for (const int v : study::boundary_vertices(t)) on_boundary[v] = 1;
        const Eigen::SparseMatrix<double> absolute = L.cwiseAbs();
        double residual = 0;
        for (int axis = 0; axis < 2; ++axis) {
            const Eigen::VectorXd x = variant.mesh.V.col(axis);
            const Eigen::VectorXd Lx = L * x, scale = absolute * x.cwiseAbs();
            for (Eigen::Index v = 0; v < n; ++v)
                if (!on_boundary[v] && scale[v] > 0) residual = std::max(residual, std::abs(Lx[v]) / scale[v]);
        }
        properties.linear_precision_residual = residual;
    }
    return properties;
}

int wardetzky(const study::Args& args) {
    std::vector<Subject> subjects;
    std::mt19937_64 rng(29);
    const sdmesh::TriangleMesh disk = study::make_polar_mesh(study::PolarSurface::disk, args.quick ? 4 : 16);
    subjects.push_back({"planar_disk_jittered", study::jitter_vertices(disk, 0.3, false, rng), true});
    subjects.push_back({"planar_grid_sheared", sdmesh::make_grid(args.quick ? 4 : 20, args.quick ? 4 : 20, 1, 1, 1.5),
                        true});
    if (!args.quick) {
        for (const char* name : {"cgal_elk.off", "npm_bunny.obj", "cgal_couplingdown.off", "cgal_mushroom.off",
                                 "cgal_cheese.off", "oded_spot.obj", "oded_boot.obj", "oded_mountain.obj",
                                 "c3d_nefertiti.obj", "oded_koala.obj"})
            subjects.push_back({name, study::corpus_mesh(args, name), false});
    }
    const study::Connectivity connectivities[] = {study::Connectivity::original, study::Connectivity::split,
                                                  study::Connectivity::hybrid, study::Connectivity::intrinsic};
    study::Csv table(
        "mesh,connectivity,vertices,edges,symmetry_error,nonlocal_entries,linear_precision_residual,"
        "negative_weights,negative_weight_fraction,min_weight,min_interior_margin,negative_dual_cells,"
        "negative_dual_fraction,min_dual_area_over_mean");
    for (const Subject& subject : subjects) {
        std::cerr << "wardetzky: " << subject.name << '\n';
        for (const study::Connectivity c : connectivities) {
            const study::Variant variant = study::make_variant(subject.mesh, c);
            const sdmesh::Triangulation& t = variant.triangulation;
            const LaplacianProperties properties = laplacian_properties(variant, subject.planar);
            const Eigen::VectorXd star1 = sdmesh::star1(t), star0 = sdmesh::star0(t);
            const double mean_dual_area = star0.sum() / t.num_vertices;
            // Rounding leaves |⋆0| ~ 1e-16 of the cell sizes on exactly co-circular configurations.
            const double dual_tolerance = 1e-12 * mean_dual_area;
            const auto negative_weights = (study::delaunay_margins(t).array() < -sdmesh::kDelaunayTolerance).count();
            const auto negative_cells = (star0.array() < -dual_tolerance).count();
            table.row(subject.name, study::to_string(c), t.num_vertices, t.num_edges(), properties.symmetry_error,
                      properties.nonlocal_entries, properties.linear_precision_residual,
                      negative_weights, static_cast<double>(negative_weights) / t.num_edges(), star1.minCoeff(),
                      study::min_interior_margin(t), negative_cells,
                      static_cast<double>(negative_cells) / t.num_vertices, star0.minCoeff() / mean_dual_area);
        }
    }
    table.save(args.out / "wardetzky.csv");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return study::run_study(argc, argv, "wardetzky", wardetzky);
}
