// Study 1, connectivity robustness: the same vertices under different connectivities. Each base
// mesh is perturbed several times without moving a vertex (random flips of near-flat edges: one
// light pass, or several heavy passes that re-triangulate the points), and the smallest
// eigenvalues of L φ = λ M φ (M barycentric) are computed on each perturbed mesh, on its
// self-Delaunay conversions (split, hybrid) and on its iDT.
//   robustness --out DIR [--corpus DIR] [--quick]
// Writes DIR/robustness_eigenvalues.csv (one row per eigenvalue) and DIR/robustness_meshes.csv
// (one row per mesh and connectivity: size, area, smallest Delaunay margin). experiments/robustness/plot.py draws the spread.

#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "sdmesh/operators.hpp"
#include "sdmesh/shapes.hpp"
#include "study.hpp"

namespace {

struct BaseMesh {
    std::string name;
    sdmesh::TriangleMesh mesh;
    int k;  // eigenvalues wanted
};

struct PerturbationKind {
    std::string name;
    study::FlipPerturbation flips;
};

int robustness(const study::Args& args) {
    std::vector<BaseMesh> bases;
    int perturbations = 8;
    if (args.quick) {
        bases.push_back({"icosphere2", sdmesh::make_icosphere(2), 10});
        perturbations = 2;
    } else {
        bases.push_back({"icosphere4", sdmesh::make_icosphere(4), 100});
        bases.push_back({"npm_bunny", study::corpus_mesh(args, "npm_bunny.obj"), 50});
        bases.push_back({"oded_spot", study::corpus_mesh(args, "oded_spot.obj"), 50});
    }
    const std::vector<PerturbationKind> kinds = {
        // Near-flat edges only (5°), so that the surface itself changes little.
        {"flips", {.rounds = 1, .probability = 0.3, .max_dihedral_deg = 5}},
        {"retriangulation", {.rounds = 6, .probability = 0.5, .max_dihedral_deg = 5}},
    };
    const study::Connectivity connectivities[] = {study::Connectivity::original, study::Connectivity::split,
                                                  study::Connectivity::hybrid, study::Connectivity::intrinsic};

    study::Csv values("mesh,kind,perturbation,connectivity,vertices,index,eigenvalue");
    study::Csv meshes("mesh,kind,perturbation,connectivity,vertices,faces,area,min_interior_margin");
    const auto measure = [&](const BaseMesh& base, const std::string& kind, int id, const sdmesh::TriangleMesh& mesh,
                             study::Connectivity connectivity) {
        const study::Variant variant = study::make_variant(mesh, connectivity);
        const sdmesh::Triangulation& t = variant.triangulation;
        const Eigen::VectorXd lambda = study::smallest_eigenvalues(t, base.k);
        const std::string_view name = study::to_string(connectivity);
        for (Eigen::Index i = 0; i < lambda.size(); ++i)
            values.row(base.name, kind, id, name, t.num_vertices, i, lambda[i]);
        meshes.row(base.name, kind, id, name, t.num_vertices, t.num_faces(), sdmesh::face_areas(t).sum(),
                   study::min_interior_margin(t));
    };
    for (const BaseMesh& base : bases) {
        std::cerr << "robustness: " << base.name << '\n';
        for (const study::Connectivity c : connectivities) measure(base, "none", 0, base.mesh, c);
        for (std::size_t kind = 0; kind < kinds.size(); ++kind) {
            std::mt19937_64 rng(1000 * kind + 17);  // fixed seeds: the same perturbations on every run
            for (int id = 0; id < perturbations; ++id) {
                const sdmesh::TriangleMesh perturbed = study::flip_random_edges(base.mesh, kinds[kind].flips, rng);
                for (const study::Connectivity c : connectivities) measure(base, kinds[kind].name, id, perturbed, c);
            }
        }
    }
    values.save(args.out / "robustness_eigenvalues.csv");
    meshes.save(args.out / "robustness_meshes.csv");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return study::run_study(argc, argv, "robustness", robustness);
}
