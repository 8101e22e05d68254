// libFuzzer target: what `sdmesh check`, `repair`, `convert`, `operators`, `decimate`, `eigs`
// and `poisson` do, on small decoded meshes.
// The selector byte of fuzz_input.hpp also chooses the conversion method (bits 3-4: split,
// hybrid, flip, split with a pass of local search), the boundary policy (bit 5) and, for split,
// a coarse coplanar tolerance of 1e-5 rad (bit 6), whose planes chain across folds of about as
// much. Meshes are capped and convert gets a vertex budget, so that no single input runs long.
// Bad meshes may only be refused with InvalidMeshError; results must satisfy the identities every
// caller relies on, split and hybrid must certify their outputs within the budget (unless they
// report splits skipped for want of precision), and split's lower bound must hold.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <utility>

#include "fuzz_input.hpp"
#include "sdmesh/convert.hpp"
#include "sdmesh/distance.hpp"
#include "sdmesh/decimate.hpp"
#include "sdmesh/delaunay.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/pde.hpp"
#include "sdmesh/triangulation.hpp"
#include "sdmesh/validate.hpp"

namespace {

constexpr int kMaxVertices = 64;
constexpr int kMaxFaces = 128;
constexpr long long kVertexBudget = 2000;
constexpr int kMaxSolverVertices = 300;  // eigs and poisson on the conversions up to this size
// How far apart two samplings of one surface may measure it, relative to the diagonal: a needle's
// points are measured to its edges (distance.hpp), up to its height, 1e-8 of its longest edge.
constexpr double kMeasureResolution = 1e-7;

// Aborts (a crash for libFuzzer) naming the identity that failed.
void require(bool condition, int line = __builtin_LINE()) {
    if (condition) return;
    std::fprintf(stderr, "fuzz_pipeline: the requirement on line %d failed\n", line);
    std::abort();
}

void check_operators(const sdmesh::TriangleMesh& mesh) {
    const sdmesh::Triangulation t = sdmesh::Triangulation::from_mesh(mesh);
    const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t);
    // The exterior derivative twice is zero, exactly (integer entries).
    const Eigen::SparseMatrix<double> dd = sdmesh::d1(t) * sdmesh::d0(t);
    require(dd.norm() == 0);
    require(L.rows() == t.num_vertices && L.cols() == t.num_vertices);
    require((Eigen::SparseMatrix<double>(L.transpose()) - L).norm() <= 1e-12 * L.norm());
    for (const auto type : {sdmesh::MassType::barycentric, sdmesh::MassType::circumcentric,
                            sdmesh::MassType::mixed_voronoi, sdmesh::MassType::galerkin}) {
        require(sdmesh::mass_matrix(t, type).rows() == t.num_vertices);
    }
    require(sdmesh::star0(t).size() == t.num_vertices);
    require(sdmesh::star1(t).size() == t.num_edges());
    require(sdmesh::star2(t).size() == t.num_faces());
}

// sdmesh decimate on a certified conversion: every output stays self-Delaunay and keeps the
// topology (it may stall, never break).
void check_decimation(const sdmesh::TriangleMesh& mesh, sdmesh::BoundaryPolicy boundary) {
    const sdmesh::MeshInfo before = sdmesh::validate(mesh);
    const sdmesh::DecimateResult result = sdmesh::decimate(mesh, {.target_ratio = 0.3, .boundary = boundary, .measure_hausdorff = false});
    require(result.report.certificate.self_delaunay);
    require(result.report.output_vertices >= result.report.target_vertices);
    const sdmesh::MeshInfo after = sdmesh::validate(result.mesh);
    require(after.manifold() && after.genus == before.genus && after.components == before.components &&
            after.boundary_loops == before.boundary_loops);
}

// sdmesh eigs and poisson on a certified conversion (L positive semidefinite, M positive): the
// Cholesky factorizations, block Lanczos and the triangular solves may refuse a degenerate mesh
// only with a typed error; what they return satisfies its equations.
void check_solvers(const sdmesh::TriangleMesh& mesh) {
    const sdmesh::Triangulation t = sdmesh::Triangulation::from_mesh(mesh);
    const int n = t.num_vertices;
    if (n < 4 || n > kMaxSolverVertices) return;
    const Eigen::SparseMatrix<double> L = sdmesh::cotan_laplacian(t), M = sdmesh::mass_matrix(t);
    try {
        const int k = std::min(6, n - 1);
        const sdmesh::EigenResult eigen = sdmesh::smallest_eigenpairs(L, M, {.k = k});
        require(eigen.values.size() == k && eigen.vectors.rows() == n && eigen.vectors.cols() == k);
        // Not the residual itself: convergence is measured on the shift-inverted operator, and on
        // meshes with near-zero vertex areas (1e-11 against 1.5) converged pairs had residuals of
        // 1e-4. L is positive semidefinite, so no eigenvalue lies further below 0 than the
        // residual allows.
        if (eigen.report.status == sdmesh::EigenStatus::converged) {
            require(std::isfinite(eigen.report.max_residual) && eigen.report.max_orthogonality_error <= 1e-8);
            const double scale = std::max(eigen.values.cwiseAbs().maxCoeff(), std::abs(eigen.report.sigma));
            require(eigen.values.minCoeff() >= -10 * std::max(eigen.report.max_residual, 1e-12) * scale);
        }
        const sdmesh::PoissonSolver poisson(L, M, {0});
        const Eigen::VectorXd b = M * Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
        const Eigen::VectorXd u = poisson.solve(b, Eigen::VectorXd::Constant(1, 0.5));
        require(u[0] == 0.5 && u.allFinite());
        // With one component every other vertex is free: L u = b there.
        if (sdmesh::validate(mesh).components == 1) {
            const Eigen::VectorXd residual = (L * u - b).tail(n - 1);
            require(residual.norm() <= 1e-8 * (L.norm() * u.norm() + b.norm()));
        }
    } catch (const sdmesh::NumericalError&) {
    } catch (const sdmesh::InvalidArgumentError&) {
    }
}

// The area of the faces and the longest side's square, for the tolerance of area comparisons.
std::pair<double, double> area_and_longest_squared(const sdmesh::TriangleMesh& mesh) {
    double area = 0, longest = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
        const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)), c = mesh.V.row(mesh.F(f, 2));
        area += 0.5 * (b - a).cross(c - a).norm();
        longest = std::max({longest, (b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    }
    return {area, longest};
}

// sdmesh repair: mending the zero-area caps changes no area (the caps have none; the two faces
// of a flip tile the face across) and no count but that of the caps dropped on the boundary, and
// copies of non-manifold vertices change only the count of vertices. After a pass that mended
// caps or left some the steps run again: needles that flips make are collapsed (which drops their
// faces and moves a vertex by their short side), and faces that merges or flips made repeat
// others are dropped. A repaired mesh that is left with no zero-area face and is orientable
// repairs to itself.
void check_repair(const sdmesh::TriangleMesh& mesh) {
    sdmesh::RepairReport report, kept_report;
    const sdmesh::TriangleMesh repaired = sdmesh::repair(mesh, {}, &report);
    const sdmesh::TriangleMesh kept =
        sdmesh::repair(mesh, {.split_nonmanifold_vertices = false, .flip_caps = false}, &kept_report);
    const bool later_needles = report.collapsed_needles > kept_report.collapsed_needles;
    const int later_drops = report.dropped_repeated_index_faces - kept_report.dropped_repeated_index_faces +
                            report.dropped_duplicate_faces - kept_report.dropped_duplicate_faces;
    require(later_drops == 0 || report.flipped_caps + report.dropped_caps > 0 || sdmesh::validate(kept).zero_area_faces > 0);
    require(repaired.num_faces() + report.dropped_caps + later_drops == kept.num_faces());
    require(report.dropped_caps > 0 || later_needles || later_drops > 0 || repaired.num_vertices() >= kept.num_vertices());
    const auto [before, longest_squared] = area_and_longest_squared(kept);
    if (!later_needles && later_drops == 0 && std::isfinite(before) && std::isfinite(longest_squared))
        require(std::abs(area_and_longest_squared(repaired).first - before) <= 1e-9 * (before + longest_squared));
    const sdmesh::MeshInfo info = sdmesh::validate(repaired);
    if (info.zero_area_faces == 0 && report.non_orientable_components == 0) {
        sdmesh::RepairReport again;
        const sdmesh::TriangleMesh twice = sdmesh::repair(repaired, {}, &again);
        require(again == sdmesh::RepairReport{} && twice.V == repaired.V && twice.F == repaired.F);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    sdmesh::TriangleMesh mesh;
    try {
        mesh = sdmesh::fuzz::parse_fuzz_input(data, size);
    } catch (const sdmesh::ParseError&) {
        return 0;
    } catch (const sdmesh::UnsupportedFormatError&) {
        return 0;
    }
    if (mesh.num_vertices() > kMaxVertices || mesh.F.rows() > kMaxFaces) return 0;

    constexpr sdmesh::ConvertMethod kMethods[] = {sdmesh::ConvertMethod::split, sdmesh::ConvertMethod::hybrid,
                                                  sdmesh::ConvertMethod::flip, sdmesh::ConvertMethod::split};
    sdmesh::ConvertOptions options;
    options.method = kMethods[(data[0] >> 3) & 3];
    options.local_search = (data[0] >> 3 & 3) == 3 ? 1 : 0;
    options.boundary = (data[0] & 32) != 0 ? sdmesh::BoundaryPolicy::free : sdmesh::BoundaryPolicy::strict;
    if ((data[0] & 64) != 0 && options.method == sdmesh::ConvertMethod::split) options.coplanar_tolerance = 1e-5;
    options.max_vertices = kVertexBudget;
    options.lower_bound = true;
    try {
        // sdmesh check
        const sdmesh::EdgeTable edges = sdmesh::build_edge_table(mesh.F, mesh.num_vertices());
        const sdmesh::MeshInfo info = sdmesh::validate(mesh, edges);
        require(info.faces == mesh.F.rows());
        sdmesh::certify(mesh, edges, {.boundary = options.boundary});
        if (info.non_finite_vertices == 0) check_repair(mesh);
        // sdmesh convert, then sdmesh operators on its output
        const sdmesh::ConversionResult result = sdmesh::convert(mesh, options);
        require(result.mesh.num_vertices() >= mesh.num_vertices());
        require(result.mesh.num_vertices() <= kVertexBudget + kMaxVertices);
        require((result.mesh.V.topRows(mesh.num_vertices()).array() == mesh.V.array()).all());
        check_operators(result.mesh);
        const sdmesh::ConversionReport& report = result.report;
        // Split and hybrid certify what they finish, but where split points would fall on
        // vertices in double precision (skipped_splits: a spike 4e8 long beside unit edges); only
        // flip may leave other edges it cannot fix.
        if (options.method != sdmesh::ConvertMethod::flip)
            require(report.status != sdmesh::ConvertStatus::not_certified || report.skipped_splits > 0);
        if (options.method != sdmesh::ConvertMethod::split) {
            // Measured only where flips moved the surface: what sampling both meshes whole gives,
            // within the resolution (unchanged needles measured 3.5e-9 at most on 6,400 inputs).
            const double whole =
                sdmesh::hausdorff_distance(mesh, result.mesh, {.samples_per_face = 4, .max_samples = 4'000'000})
                    .hausdorff_rel;
            require(std::abs(report.hausdorff_rel - whole) <= kMeasureResolution);
        }
        if (options.method == sdmesh::ConvertMethod::split) {
            require(report.added_vertices_lower_bound >= report.input_nonflat_non_delaunay_edges);
            // A bound above what a conversion that moves nothing added would be wrong.
            if (report.status == sdmesh::ConvertStatus::certified && report.vertices_inside_faces == 0)
                require(report.added_vertices_lower_bound <= report.output_vertices - report.input_vertices);
        }
        if (result.report.status == sdmesh::ConvertStatus::certified) {
            check_decimation(result.mesh, options.boundary);
            check_solvers(result.mesh);
        }
    } catch (const sdmesh::InvalidMeshError&) {
    }
    return 0;
}
