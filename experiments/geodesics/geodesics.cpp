// Study 6, heat-method geodesics (Crane et al. 2013) on original, self-Delaunay and iDT
// connectivity:
//  - unit spheres under refinement, well-shaped ("regular") and re-triangulated by random flips
//    ("flipped"): error against the great-circle distance arccos(p·s) at the input's vertices;
//  - corpus meshes, without an exact answer: how far the field is from a distance function,
//    the area-weighted mean of | |∇d| − 1 | over the faces (the eikonal residual), and the
//    fields themselves, written as PLY files for drawing.
//   geodesics --out DIR [--corpus DIR] [--quick]
// Writes DIR/geodesics_sphere.csv, DIR/geodesics_corpus.csv and, for the flipped icosphere of
// level 4 and the elk, DIR/geodesics_<mesh>_<connectivity>.ply.

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/pde.hpp"
#include "sdmesh/shapes.hpp"
#include "study.hpp"

namespace {

constexpr int kSource = 0;

// Writes the field as DIR/geodesics_<stem>_<connectivity>.ply for drawing (the iDT on the input's
// faces); plot.py draws original, split and iDT.
void write_field(const study::Args& args, const std::string& stem, const study::Variant& variant,
                 const Eigen::VectorXd& distance) {
    if (variant.connectivity == study::Connectivity::hybrid) return;
    const std::string name = "geodesics_" + stem + "_" + std::string(study::to_string(variant.connectivity)) + ".ply";
    sdmesh::write_mesh(args.out / name, variant.mesh, {.vertex_fields = {{"distance", distance}}, .ply_ascii = true});
}

// Area-weighted mean over the faces of | |∇d| − 1 |.
double eikonal_residual(const sdmesh::Triangulation& t, const Eigen::VectorXd& distance) {
    const Eigen::VectorXd gradient = sdmesh::gradient(t) * distance;  // x, y per face
    const Eigen::VectorXd area = sdmesh::face_areas(t);
    double weighted = 0;
    for (int f = 0; f < t.num_faces(); ++f)
        weighted += area[f] * std::abs(std::hypot(gradient[2 * f], gradient[2 * f + 1]) - 1);
    return weighted / area.sum();
}

int geodesics(const study::Args& args) {
    const study::Connectivity connectivities[] = {study::Connectivity::original, study::Connectivity::split,
                                                  study::Connectivity::hybrid, study::Connectivity::intrinsic};
    const study::FlipPerturbation retriangulation{.rounds = 6, .probability = 0.5, .max_dihedral_deg = 30};

    const int drawn_level = args.quick ? 2 : 4;  // the flipped icosphere whose field is drawn
    study::Csv sphere("triangulation,connectivity,level,vertices,regular_mean_edge_length,mean_abs_error,max_abs_error,"
                      "eikonal_residual");
    for (const int level : args.quick ? std::vector<int>{1, 2} : std::vector<int>{2, 3, 4, 5}) {
        std::cerr << "geodesics: icosphere " << level << '\n';
        const sdmesh::TriangleMesh regular = sdmesh::make_icosphere(level);
        std::mt19937_64 rng(static_cast<unsigned long long>(level) * 104729 + 11);
        const std::pair<std::string, sdmesh::TriangleMesh> triangulations[] = {
            {"regular", regular}, {"flipped", study::flip_random_edges(regular, retriangulation, rng)}};
        const double h = study::mean_edge_length(sdmesh::Triangulation::from_mesh(regular));  // of the level
        for (const auto& [name, mesh] : triangulations) {
            const Eigen::Vector3d source = mesh.V.row(kSource).transpose();
            for (const study::Connectivity c : connectivities) {
                const study::Variant variant = study::make_variant(mesh, c);
                const Eigen::VectorXd d = sdmesh::heat_geodesic_distance(variant.triangulation, {kSource});
                double sum = 0, worst = 0;
                for (int v = 0; v < mesh.num_vertices(); ++v) {  // the input's vertices lie on the sphere
                    const double exact = std::acos(std::clamp(source.dot(mesh.V.row(v).transpose()), -1.0, 1.0));
                    sum += std::abs(d[v] - exact);
                    worst = std::max(worst, std::abs(d[v] - exact));
                }
                sphere.row(name, study::to_string(c), level, variant.triangulation.num_vertices, h,
                           sum / mesh.num_vertices(), worst, eikonal_residual(variant.triangulation, d));
                if (level == drawn_level && name == "flipped")
                    write_field(args, "icosphere" + std::to_string(level) + "_flipped", variant, d);
            }
        }
    }
    sphere.save(args.out / "geodesics_sphere.csv");

    study::Csv corpus("mesh,connectivity,vertices,eikonal_residual,max_distance");
    std::vector<std::pair<std::string, sdmesh::TriangleMesh>> meshes;
    if (args.quick) {
        meshes.emplace_back("sheared_grid", sdmesh::make_grid(8, 8, 1, 1, 1.5));
    } else {
        for (const char* name : {"npm_bunny.obj", "cgal_elk.off", "cgal_mushroom.off", "oded_spot.obj"})
            meshes.emplace_back(name, study::corpus_mesh(args, name));
    }
    for (const auto& [name, mesh] : meshes) {
        std::cerr << "geodesics: " << name << '\n';
        const std::string stem = name.substr(0, name.find('.'));
        for (const study::Connectivity c : connectivities) {
            const study::Variant variant = study::make_variant(mesh, c);
            const Eigen::VectorXd d = sdmesh::heat_geodesic_distance(variant.triangulation, {kSource});
            corpus.row(name, study::to_string(c), variant.triangulation.num_vertices,
                       eikonal_residual(variant.triangulation, d), d.maxCoeff());
            if (stem == "cgal_elk") write_field(args, stem, variant, d);
        }
    }
    corpus.save(args.out / "geodesics_corpus.csv");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return study::run_study(argc, argv, "geodesics", geodesics);
}
