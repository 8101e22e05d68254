// Study 4, a negative dual cell (the situation of the thesis' Appendix A): a planar unit-disk mesh
// whose centre vertex has six neighbours, every other one pulled towards the centre. The three
// long spokes then face obtuse angles on both sides, their cotan weights are negative, and the
// circumcentric dual area ⋆0 of the centre — Σ over its edges of (l²/8)(cot α + cot β) — is
// negative. The study records ⋆0 and what the operators with the circumcentric mass M = ⋆0 do
// with it, beside the barycentric mass, before and after conversion and on the iDT:
//  - the pointwise Laplacian (L u)_centre / M_centre of the exact solution u = (1 − r²)·eˣ of
//    −Δu = f, u = 0 on the boundary (exact value f(0) = 3), and the error of the Poisson solve;
//  - one backward-Euler heat step (M + tL) u₁ = M u₀ from a unit of heat at the centre, whose
//    values a maximum principle keeps >= 0;
//  - whether a heat step with a small t and the eigenpairs run (both need M + tL, L − σM positive
//    definite).
// (For f = 1 the circumcentric solve would be exact whatever the signs: on a planar mesh the cotan
// Laplacian gives L·r² = −4⋆0 exactly.)
//   negative_dual --out DIR [--quick]
// Writes DIR/negative_dual_vertices.csv (per vertex and connectivity), DIR/negative_dual.csv (per
// connectivity) and DIR/negative_dual_faces.csv (the triangles, for drawing).

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "sdmesh/delaunay.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/pde.hpp"
#include "study.hpp"

namespace {

constexpr double kPulledRadius = 0.2;  // of the first ring's radius, for every other neighbour

// The unit-disk polar mesh with every other vertex of the first ring pulled towards the centre.
sdmesh::TriangleMesh make_negative_dual_disk(int rings) {
    sdmesh::TriangleMesh mesh = study::make_polar_mesh(study::PolarSurface::disk, rings);
    for (int v = 2; v <= 6; v += 2) mesh.V.row(v) *= kPulledRadius;  // first ring: vertices 1..6
    return mesh;
}

// "ok", or the message of the sdmesh::Error the call threw.
template <typename Call>
std::string outcome(Call call) {
    try {
        call();
        return "ok";
    } catch (const sdmesh::Error& error) {
        return std::string("fails: ") + error.what();
    }
}

std::string csv_text(std::string text) {
    for (char& c : text)
        if (c == ',' || c == '"' || c == '\n') c = ';';
    return text;
}

int negative_dual(const study::Args& args) {
    const sdmesh::TriangleMesh mesh = make_negative_dual_disk(args.quick ? 4 : 12);
    study::Csv vertices("connectivity,mass,vertex,x,y,star0,u,u_exact,heat_from_centre");
    study::Csv summary(
        "connectivity,mass,vertices,centre_star0,centre_star0_over_mean,negative_dual_cells,negative_weights,"
        "pointwise_laplacian_centre,max_error,centre_error,heat_step_h2,heat_step_h2_over_10000,eigenpairs,"
        "heat_from_centre_min,heat_from_centre_max");
    const auto exact = [](double x, double y) { return (1 - x * x - y * y) * std::exp(x); };
    const auto source = [](double x, double y) { return std::exp(x) * (3 + 4 * x + x * x + y * y); };  // −Δ exact
    study::Csv faces("connectivity,a,b,c");
    for (const study::Connectivity c :
         {study::Connectivity::original, study::Connectivity::split, study::Connectivity::intrinsic}) {
        const study::Variant variant = study::make_variant(mesh, c);
        const sdmesh::Triangulation& t = variant.triangulation;
        if (c != study::Connectivity::intrinsic)  // the iDT's faces are not straight in the plane
            for (int f = 0; f < variant.mesh.num_faces(); ++f)
                faces.row(study::to_string(c), variant.mesh.F(f, 0), variant.mesh.F(f, 1), variant.mesh.F(f, 2));
        const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t);
        const Eigen::VectorXd star0 = sdmesh::star0(t);
        const std::vector<int> boundary = study::boundary_vertices(t);
        const double h = study::mean_edge_length(t);
        Eigen::VectorXd f(t.num_vertices), u_exact(t.num_vertices);
        for (int v = 0; v < t.num_vertices; ++v) {
            f[v] = source(variant.mesh.V(v, 0), variant.mesh.V(v, 1));
            u_exact[v] = exact(variant.mesh.V(v, 0), variant.mesh.V(v, 1));
        }
        // Not LD beyond the tolerance (co-circular quads of the ring mesh have weights of about −1e-16).
        const auto negative_weights = (study::delaunay_margins(t).array() < -sdmesh::kDelaunayTolerance).count();
        for (const sdmesh::MassType mass : {sdmesh::MassType::circumcentric, sdmesh::MassType::barycentric}) {
            const std::string mass_name = mass == sdmesh::MassType::circumcentric ? "circumcentric" : "barycentric";
            const Eigen::SparseMatrix<double> M = sdmesh::mass_matrix(t, mass);
            const Eigen::VectorXd u = sdmesh::PoissonSolver(L, M, boundary).solve(M * f);
            // One heat step from a unit of heat at the centre: a maximum principle keeps it >= 0.
            const Eigen::VectorXd heat = sdmesh::HeatSolver(L, M, h * h).step(Eigen::VectorXd::Unit(t.num_vertices, 0));
            for (int v = 0; v < t.num_vertices; ++v)
                vertices.row(study::to_string(c), mass_name, v, variant.mesh.V(v, 0), variant.mesh.V(v, 1), star0[v],
                             u[v], u_exact[v], heat[v]);
            const auto heat_step = [&](double time) {
                return outcome([&] { const sdmesh::HeatSolver heat_solver(L, M, time); });
            };
            const std::string eigen = outcome([&] { sdmesh::smallest_eigenpairs(L, M, {.k = 10}); });
            summary.row(study::to_string(c), mass_name, t.num_vertices, star0[0], star0[0] / star0.mean(),
                        (star0.array() < 0).count(), negative_weights, (L * u_exact)[0] / M.coeff(0, 0),
                        (u - u_exact).cwiseAbs().maxCoeff(), std::abs(u[0] - u_exact[0]), csv_text(heat_step(h * h)),
                        csv_text(heat_step(h * h / 10000)), csv_text(eigen), heat.minCoeff(), heat.maxCoeff());
        }
    }
    vertices.save(args.out / "negative_dual_vertices.csv");
    summary.save(args.out / "negative_dual.csv");
    faces.save(args.out / "negative_dual_faces.csv");
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    return study::run_study(argc, argv, "negative_dual", negative_dual);
}
