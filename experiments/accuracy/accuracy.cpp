// Study 2, accuracy against analytic spectra under refinement: the unit sphere (Neumann-free,
// l(l+1)), the upper unit hemisphere with Dirichlet and with Neumann boundary (odd / even l+m),
// the unit disk with Dirichlet boundary (squared Bessel zeros). Each shape is meshed at several
// resolutions, well-shaped ("regular"), with the same points re-triangulated by random flips
// ("flipped"), and with the points jittered along the surface ("jittered"), and each of these
// under its original connectivity, its split self-Delaunay conversion and its iDT.
//   accuracy --out DIR [--quick]
// Writes DIR/accuracy_eigenvalues.csv, one row per eigenvalue; experiments/accuracy/plot.py
// compares them with the analytic values and fits orders of convergence.

#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "sdmesh/shapes.hpp"
#include "study.hpp"

namespace {

struct Shape {
    std::string name;
    bool dirichlet;
    int k;
    sdmesh::TriangleMesh (*make)(int level);
    bool on_sphere;  // for jittering
};

sdmesh::TriangleMesh sphere(int level) { return sdmesh::make_icosphere(level); }
sdmesh::TriangleMesh hemisphere(int rings) { return study::make_polar_mesh(study::PolarSurface::hemisphere, rings); }
sdmesh::TriangleMesh disk(int rings) { return study::make_polar_mesh(study::PolarSurface::disk, rings); }

int accuracy(const study::Args& args) {
    const std::vector<Shape> shapes = {
        {"sphere", false, args.quick ? 9 : 25, sphere, true},
        {"hemisphere_dirichlet", true, args.quick ? 6 : 15, hemisphere, true},
        {"hemisphere_neumann", false, args.quick ? 6 : 21, hemisphere, true},
        {"disk_dirichlet", true, args.quick ? 6 : 20, disk, false},
    };
    // Icosphere subdivisions; rings of the polar meshes (about the same vertex counts).
    const std::vector<int> sphere_levels = args.quick ? std::vector<int>{1, 2} : std::vector<int>{2, 3, 4, 5};
    const std::vector<int> ring_levels = args.quick ? std::vector<int>{3, 6} : std::vector<int>{6, 12, 24, 48};
    const study::FlipPerturbation retriangulation{.rounds = 6, .probability = 0.5, .max_dihedral_deg = 30};
    constexpr double kJitter = 0.3;  // of the mean edge length
    const study::Connectivity connectivities[] = {study::Connectivity::original, study::Connectivity::split,
                                                  study::Connectivity::intrinsic};

    study::Csv values("shape,triangulation,connectivity,level,vertices,regular_mean_edge_length,index,eigenvalue");
    for (const Shape& shape : shapes) {
        std::cerr << "accuracy: " << shape.name << '\n';
        const std::vector<int>& levels = shape.make == sphere ? sphere_levels : ring_levels;
        for (const int level : levels) {
            const sdmesh::TriangleMesh regular = shape.make(level);
            std::mt19937_64 rng(static_cast<unsigned long long>(level) * 7919 + 3);
            const std::pair<std::string, sdmesh::TriangleMesh> triangulations[] = {
                {"regular", regular},
                {"flipped", study::flip_random_edges(regular, retriangulation, rng)},
                {"jittered", study::jitter_vertices(regular, kJitter, shape.on_sphere, rng)},
            };
            // The resolution of a level, shared by its three triangulations (the same or jittered points).
            const double h = study::mean_edge_length(sdmesh::Triangulation::from_mesh(regular));
            for (const auto& [name, mesh] : triangulations) {
                for (const study::Connectivity c : connectivities) {
                    const study::Variant variant = study::make_variant(mesh, c);
                    const Eigen::VectorXd lambda =
                        study::smallest_eigenvalues(variant.triangulation, shape.k, shape.dirichlet);
                    for (Eigen::Index i = 0; i < lambda.size(); ++i)
                        values.row(shape.name, name, study::to_string(c), level, variant.triangulation.num_vertices, h,
                                   i, lambda[i]);
                }
            }
        }
    }
    values.save(args.out / "accuracy_eigenvalues.csv");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return study::run_study(argc, argv, "accuracy", accuracy);
}
