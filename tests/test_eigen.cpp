// Sparse generalized eigenpairs: the unit sphere's spectrum under refinement, residuals,
// M-orthonormality, one zero eigenvalue per component, Dirichlet vertices, agreement with a dense
// solve, argument errors, `sdmesh eigs`.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "cli_run.hpp"
#include "meshes.hpp"
#include "sdmesh/cholesky.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/shapes.hpp"

#include "block_lanczos.hpp"      // white-box: the Lanczos path on a problem eigenpairs solves densely
#include "constant_modes.hpp"     // white-box: its two ways of projecting
#include "symmetric_product.hpp"  // white-box: against Eigen's product

namespace sdmesh {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// Both the residual and the orthogonality of every result are checked against the acceptance bounds.
void expect_accurate(const EigenResult& r, const std::string& what) {
    EXPECT_EQ(r.report.status, EigenStatus::converged) << what;
    EXPECT_LE(r.report.max_residual, 1e-8) << what;
    EXPECT_LE(r.report.max_orthogonality_error, 1e-10) << what;
    EXPECT_LT(r.report.sigma, 0.0) << what;
    EXPECT_TRUE(std::is_sorted(r.values.begin(), r.values.end())) << what;
}

// The report's residual and orthogonality, recomputed from the returned pairs.
void expect_report_is_honest(const EigenResult& r, const Sparse& L, const Sparse& M, const std::string& what) {
    const Eigen::MatrixXd& phi = r.vectors;
    const Eigen::MatrixXd gram = phi.transpose() * M * phi;
    EXPECT_LE((gram - Eigen::MatrixXd::Identity(phi.cols(), phi.cols())).cwiseAbs().maxCoeff(), 1e-10) << what;
    for (Eigen::Index j = 0; j < phi.cols(); ++j) {
        const Eigen::VectorXd m_phi = M * phi.col(j);
        const Eigen::VectorXd residual = L * phi.col(j) - r.values[j] * m_phi;
        // For λ = 0, against the terms of L φ (no residual if they are all 0).
        const double scale = r.values[j] == 0 ? (Sparse(L.cwiseAbs()) * phi.col(j).cwiseAbs()).norm()
                                              : std::max(std::abs(r.values[j]), std::abs(r.report.sigma)) * m_phi.norm();
        EXPECT_LE(scale > 0 ? residual.norm() / scale : residual.norm(), 1e-8) << what << ", pair " << j;
    }
}

TEST(SphereSpectrum, EigenvaluesAreLTimesLPlusOneAndConvergeUnderRefinement) {
    double previous_error = std::numeric_limits<double>::infinity();
    for (int level = 2; level <= 4; ++level) {
        const Triangulation t = Triangulation::from_mesh(make_icosphere(level));
        const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::mixed_voronoi);
        const EigenResult r = smallest_eigenpairs(L, M, {.k = 25});
        const std::string what = "level " + std::to_string(level);
        expect_accurate(r, what);
        expect_report_is_honest(r, L, M, what);
        ASSERT_EQ(r.values.size(), 25) << what;

        const double h = t.length.maxCoeff();
        // One zero eigenvalue: the constants, up to the solver's accuracy on the scale of σ.
        EXPECT_LE(std::abs(r.values[0]), 1e-8 * std::abs(r.report.sigma)) << what;
        double error = 0;  // largest relative error over l = 1..4
        for (int l = 1; l <= 4; ++l) {
            const double exact = l * (l + 1);
            for (int i = l * l; i < (l + 1) * (l + 1); ++i) {
                // O(λ²h²) discretisation error, with the bound test_operators uses.
                EXPECT_NEAR(r.values[i], exact, 0.1 * exact * exact * h * h) << what << ", index " << i;
                error = std::max(error, std::abs(r.values[i] - exact) / exact);
            }
            if (l < 4) {  // the 2l+1 copies form a cluster, well below the next one
                EXPECT_LT(r.values[(l + 1) * (l + 1) - 1], r.values[(l + 1) * (l + 1)] - 1.0) << what;
            }
        }
        EXPECT_LT(error, previous_error / 3) << what;  // halving h divides it by about 4
        previous_error = error;
    }
}

constexpr EigenSolver kBothSolvers[] = {EigenSolver::block_lanczos, EigenSolver::spectra_lanczos};

// The solve runs on L and M scaled to unit mean diagonals by powers of two, so a mesh in any unit
// of length gives the same pairs, scaled exactly: λ by 2^-2e, φ by 2^-e. Unscaled, M's entries
// of ~1e-163 (the bunny at 1e-80) gave negative eigenvalues and residuals of 600 as "converged".
TEST(SphereSpectrum, TheUnitOfLengthOnlyScalesThePairs) {
    const TriangleMesh bunny = read_mesh(std::string(SDMESH_TEST_DATA_DIR) + "/bunny.obj");
    for (EigenSolver solver : kBothSolvers) {
        const auto solve = [&](const TriangleMesh& mesh) {
            const Triangulation t = Triangulation::from_mesh(mesh);
            return smallest_eigenpairs(cotan_laplacian(t), mass_matrix(t), {.k = 8, .solver = solver});
        };
        const EigenResult reference = solve(bunny);
        for (const int exponent : {-480, -260, 250, 480}) {
            const EigenResult scaled = solve(scaled_by_power_of_two(bunny, exponent));
            const std::string what = std::string(to_string(solver)) + ", 2^" + std::to_string(exponent);
            expect_accurate(scaled, what);
            EXPECT_TRUE(scaled.values == reference.values.unaryExpr([&](double x) { return std::ldexp(x, -2 * exponent); }))
                << what;
            EXPECT_TRUE(scaled.vectors ==
                        reference.vectors.unaryExpr([&](double x) { return std::ldexp(x, -exponent); }))
                << what;
        }
        // Not a power of two: the same to rounding.
        const EigenResult scaled = solve(TriangleMesh{1e-80 * bunny.V, bunny.F});
        expect_accurate(scaled, "1e-80");
        for (int i = 1; i < 8; ++i) EXPECT_NEAR(scaled.values[i] * 1e-160, reference.values[i], 1e-9 * reference.values[i]);
    }
    // A Laplacian of any scale, too (products with one of 2^700 would overflow); it is brought to
    // a unit mean diagonal, which the cotan Laplacian is not, so the same to rounding only.
    const Triangulation t = Triangulation::from_mesh(bunny);
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    const EigenResult reference = smallest_eigenpairs(L, M, {.k = 8});
    for (const int exponent : {-700, 700}) {
        const EigenResult scaled = smallest_eigenpairs(std::ldexp(1.0, exponent) * L, M, {.k = 8});
        expect_accurate(scaled, "L times 2^" + std::to_string(exponent));
        for (int i = 1; i < 8; ++i)
            EXPECT_NEAR(std::ldexp(scaled.values[i], -exponent), reference.values[i], 1e-10 * reference.values[i]);
        // The same eigenvectors up to sign (the eigenvalues here are simple).
        const Eigen::MatrixXd overlap = scaled.vectors.transpose() * M * reference.vectors;
        for (int i = 1; i < 8; ++i) EXPECT_NEAR(std::abs(overlap(i, i)), 1.0, 1e-8) << i;
    }
}

// Icosphere 1 (42 vertices) lets block Lanczos's basis fill the whole space, where its blocks end
// up nearly inside the basis.
TEST(SphereSpectrum, AgreesWithADenseSolve) {
    for (EigenSolver solver : kBothSolvers)
        for (MassType mass : {MassType::barycentric, MassType::galerkin})
            for (const auto& [level, k] : {std::pair{1, 9}, std::pair{2, 16}}) {
                const Triangulation t = Triangulation::from_mesh(make_icosphere(level));
                const Sparse L = cotan_laplacian(t), M = mass_matrix(t, mass);
                const EigenResult r = smallest_eigenpairs(L, M, {.k = k, .solver = solver});
                const std::string what = std::string(to_string(solver)) + ", icosphere " + std::to_string(level);
                expect_accurate(r, what);
                EXPECT_EQ(r.report.solver, solver);
                const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(
                    Eigen::MatrixXd(L), Eigen::MatrixXd(M), Eigen::EigenvaluesOnly);
                // Both are accurate to rounding on the scale of the largest eigenvalue asked for.
                const double tolerance = 1e-9 * dense.eigenvalues()[k - 1];
                for (int i = 0; i < k; ++i)
                    EXPECT_NEAR(r.values[i], dense.eigenvalues()[i], tolerance) << what << ", index " << i;
            }
}

// The two Lanczos variants on a corpus-sized problem (bunny, 2.5k vertices), k = 60: the same
// eigenvalues to 1e-9 relative.
TEST(SphereSpectrum, BlockAndSpectraLanczosAgree) {
    const Triangulation t = Triangulation::from_mesh(read_mesh(std::string(SDMESH_TEST_DATA_DIR) + "/bunny.obj"));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    const EigenResult block = smallest_eigenpairs(L, M, {.k = 60, .solver = EigenSolver::block_lanczos});
    const EigenResult spectra = smallest_eigenpairs(L, M, {.k = 60, .solver = EigenSolver::spectra_lanczos});
    expect_accurate(block, "block");
    expect_accurate(spectra, "spectra");
    ASSERT_EQ(block.values.size(), 60);
    ASSERT_EQ(spectra.values.size(), 60);
    for (int i = 0; i < 60; ++i)
        EXPECT_NEAR(block.values[i], spectra.values[i], 1e-9 * std::max(spectra.values[i], 1.0)) << "index " << i;
}

// λ = 0, 1, 2, each ten times (L diagonal, M = I): more equal eigenvalues than a block has
// columns. The Krylov space becomes invariant after three blocks; the lost directions are
// replaced by random ones, and the 20 smallest come out whole.
TEST(BlockLanczos, FindsEqualEigenvaluesBeyondTheBlockSize) {
    const int n = 30;
    Sparse L(n, n), M(n, n);
    for (int i = 0; i < n; ++i) {
        L.insert(i, i) = i / 10;
        M.insert(i, i) = 1.0;
    }
    const EigenResult r = smallest_eigenpairs(L, M, {.k = 20});
    expect_accurate(r, "diagonal");
    ASSERT_EQ(r.values.size(), 20);
    for (int i = 0; i < 20; ++i) EXPECT_NEAR(r.values[i], i / 10, 1e-10) << "index " << i;
    expect_report_is_honest(r, L, M, "diagonal");
}

// A basis too small to converge is a status with the best approximations, not an exception.
// The icosahedron's eigenvalues have multiplicities 1, 3, 5 and 3, so the Krylov space of a
// block of four is invariant at dimension 11 of 12: one direction of the second block shrinks to
// rounding and is replaced, another nearly so. Found by fuzz_pipeline (ΦᵀMΦ − I was 8.6e-8, then
// 1.2e-7 for another vertex order); problems this small whose basis fills the space now get a
// dense solve.
TEST(SmallProblems, TheIcosahedronIsSolvedExactly) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(0));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
    const EigenResult r = smallest_eigenpairs(L, M, {.k = 6});
    expect_accurate(r, "icosahedron");
    expect_report_is_honest(r, L, M, "icosahedron");
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(Eigen::MatrixXd(L), Eigen::MatrixXd(M),
                                                                         Eigen::EigenvaluesOnly);
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(r.values[i], dense.eigenvalues()[i], 1e-9 * dense.eigenvalues()[5]);
}

// A split point 1e-7 of its edge from an end (as conversions make) gives its vertex and that end
// cotan weight sums of about 1e7, against 3.5 elsewhere; a shift from their mean sat four orders
// of magnitude below the spectrum, where Lanczos cannot tell the low eigenvalues apart.
TEST(SphereSpectrum, ASliverDoesNotThrowTheShiftOff) {
    TriangleMesh mesh = make_icosphere(3);
    const int a = mesh.F(0, 0), b = mesh.F(0, 1), c = mesh.F(0, 2), x = mesh.num_vertices();
    int across = -1;  // the face (b, a, d)
    for (int f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k)
            if (mesh.F(f, k) == b && mesh.F(f, (k + 1) % 3) == a) across = f;
    ASSERT_GE(across, 0);
    const int d = mesh.F(across, 0) + mesh.F(across, 1) + mesh.F(across, 2) - a - b;
    mesh.V.conservativeResize(x + 1, 3);
    mesh.V.row(x) = mesh.V.row(a) + 1e-7 * (mesh.V.row(b) - mesh.V.row(a));
    mesh.F.conservativeResize(mesh.num_faces() + 2, 3);
    mesh.F.row(0) << a, x, c;
    mesh.F.row(across) << b, x, d;
    mesh.F.bottomRows(2) << x, b, c, x, a, d;
    const Triangulation t = Triangulation::from_mesh(mesh);
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
    ASSERT_GT(L.coeff(x, x), 1e6);
    const EigenResult r = smallest_eigenpairs(L, M, {.k = 10});
    EXPECT_EQ(r.report.status, EigenStatus::converged);
    EXPECT_GT(r.report.sigma, -2.0);
    // Weights of 1e7 leave L φ with rounding of about 1e-9, so residuals of 1e-7 are all
    // doubles can tell.
    EXPECT_LE(r.report.max_residual, 1e-6);
    EXPECT_LE(r.report.max_orthogonality_error, 1e-10);
    EXPECT_LE(std::abs(r.values[0]), 1e-8 * std::abs(r.report.sigma));
    for (int i = 1; i <= 3; ++i) EXPECT_NEAR(r.values[i], 2.0, 0.05);
}

// Block Lanczos itself on the icosahedron (white-box: eigenpairs would take the dense path). Its
// block Krylov space is invariant at dimension 11 of 12, so the last blocks lose directions to
// rounding or nearly so; a direction shortened ~1e8× and then normalized carried its rounding
// along the basis to full size (ΦᵀMΦ − I was 8.6e-8) until such blocks got a third pass.
TEST(BlockLanczos, NearlyLostDirectionsStayOrthogonal) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(0));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
    const int n = static_cast<int>(L.rows());
    const double sigma = -L.diagonal().sum() / (n * M.diagonal().sum());
    const CholeskySolver K(Sparse(L - sigma * M));
    const detail::BlockLanczosResult r = detail::block_lanczos(K, M, {.wanted = 6, .margin = 4, .max_columns = n});
    ASSERT_TRUE(r.converged);
    const Eigen::MatrixXd& phi = r.ritz_vectors;
    const Eigen::MatrixXd gram = phi.transpose() * M * phi;
    EXPECT_LE((gram - Eigen::MatrixXd::Identity(6, 6)).cwiseAbs().maxCoeff(), 1e-10);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(Eigen::MatrixXd(L), Eigen::MatrixXd(M),
                                                                         Eigen::EigenvaluesOnly);
    for (int i = 0; i < 6; ++i)
        EXPECT_NEAR(sigma + 1 / r.ritz_values[i], dense.eigenvalues()[i], 1e-9 * dense.eigenvalues()[5]);
}

// The row-gathering product of a symmetric sparse matrix (the accuracy report's L Φ, a
// consistent mass matrix in Lanczos) against Eigen's, for every remainder of its four-column groups.
TEST(SymmetricProduct, MatchesEigensProduct) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(2));
    for (const Sparse& A : {cotan_laplacian(t), mass_matrix(t, MassType::galerkin)}) {
        for (const int columns : {1, 3, 4, 5, 9}) {
            const Eigen::MatrixXd X = Eigen::MatrixXd::Random(A.rows(), columns);
            Eigen::MatrixXd out(A.rows(), columns);
            detail::symmetric_product(A, X, out);
            const Eigen::MatrixXd expected = A * X;
            EXPECT_LE((out - expected).cwiseAbs().maxCoeff(), 1e-14 * expected.cwiseAbs().maxCoeff())
                << columns << " columns";
        }
    }
}

TEST(BlockLanczos, ABasisTooSmallIsReportedAsNotConverged) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(4));
    const EigenResult r = smallest_eigenpairs(cotan_laplacian(t), mass_matrix(t), {.k = 20, .basis_size = 24});
    EXPECT_EQ(r.report.status, EigenStatus::not_converged);
    EXPECT_EQ(r.values.size(), 20);
    EXPECT_GT(r.report.max_residual, 1e-8);
    EXPECT_LE(r.report.max_orthogonality_error, 1e-10);
    // A basis narrower than a block: one block of its width (for the pair after the constant),
    // after the start block's solves.
    const EigenResult narrow = smallest_eigenpairs(cotan_laplacian(t), mass_matrix(t), {.k = 2, .basis_size = 3});
    EXPECT_EQ(narrow.values.size(), 2);
    EXPECT_EQ(narrow.report.solves, 2 * 3);
}

// Two icospheres side by side in one matrix pair (block diagonal): two zero eigenvalues, each
// eigenvector constant on one sphere; the spectrum is the union of the two.
// Single-vector Lanczos found only 6 of the 9 eigenvalues near l = 4 here (and three of l = 5
// instead) before it was asked for a margin of extra pairs.
TEST(SphereSpectrum, ClustersOfEqualEigenvaluesAreFoundWhole) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(5));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::galerkin);
    for (EigenSolver solver : kBothSolvers) {
        const EigenResult r = smallest_eigenpairs(L, M, {.k = 25, .solver = solver});
        std::vector<int> group_size(5, 0);
        for (int i = 0; i < 25; ++i) {
            const long l = std::lround((std::sqrt(1 + 4 * r.values[i]) - 1) / 2);  // λ ≈ l(l + 1)
            ASSERT_LE(l, 4) << to_string(solver) << ", index " << i << ": " << r.values[i];
            ++group_size[static_cast<size_t>(l)];
        }
        EXPECT_EQ(group_size, (std::vector<int>{1, 3, 5, 7, 9})) << to_string(solver);
    }
}

// The meshes side by side in one mesh, each moved 3 units along x from the one before.
TriangleMesh side_by_side(const std::vector<TriangleMesh>& parts) {
    TriangleMesh all;
    for (size_t i = 0; i < parts.size(); ++i) all = test::disjoint_union(all, parts[i], 3.0 * static_cast<double>(i));
    return all;
}

// Two spheres side by side: solved densely (42 vertices each) and by Lanczos (162 each).
TEST(Components, OneZeroEigenvaluePerComponent) {
    for (const int subdivisions : {1, 2}) {
        const TriangleMesh sphere = make_icosphere(subdivisions);
        const Eigen::Index half = sphere.V.rows();
        const Triangulation t = Triangulation::from_mesh(side_by_side({sphere, sphere}));
        const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
        const EigenResult r = smallest_eigenpairs(L, M, {.k = 8});
        const std::string what = "two spheres of " + std::to_string(half) + " vertices";
        expect_accurate(r, what);
        const double zero = 1e-8 * std::abs(r.report.sigma);
        EXPECT_LE(std::abs(r.values[0]), zero) << what;
        EXPECT_LE(std::abs(r.values[1]), zero) << what;
        for (int i = 2; i < 8; ++i)
            EXPECT_NEAR(r.values[i], 2.0, 0.1 * 4 * t.length.maxCoeff() * t.length.maxCoeff()) << what;
        // The zero pairs are the spheres' constant functions, the first sphere's first.
        for (int j = 0; j < 2; ++j) {
            const Eigen::VectorXd phi = r.vectors.col(j);
            EXPECT_GT(phi.segment(j * half, half).minCoeff(), 0) << what;
            EXPECT_EQ(phi.segment(j * half, half).minCoeff(), phi.segment(j * half, half).maxCoeff()) << what;
            EXPECT_EQ((phi.array() != 0).count(), half) << what;
        }
    }
}

// A connected mesh has one mode over every unknown, projected out by vector products; the general
// loop over components gives the same columns, each M-orthogonal to the constant function.
TEST(Components, OneModeOverEveryUnknownProjectsAsTheGeneralLoop) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(3));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
    detail::ConstantModes modes = detail::constant_modes(L, M);
    ASSERT_EQ(modes.count(), 1);
    ASSERT_TRUE(modes.one_covering_all);
    const Eigen::MatrixXd X = Eigen::MatrixXd::Random(L.rows(), 5) + Eigen::MatrixXd::Constant(L.rows(), 5, 3.0);
    Eigen::MatrixXd fast = X, general = X;
    modes.project_out(fast);
    modes.one_covering_all = false;
    modes.project_out(general);
    EXPECT_LE((fast - general).cwiseAbs().maxCoeff(), 1e-14 * X.cwiseAbs().maxCoeff());
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(L.rows());
    EXPECT_LE((ones.transpose() * M * fast).cwiseAbs().maxCoeff(),
              1e-13 * (ones.transpose() * M * X).cwiseAbs().maxCoeff());
    // Two spheres: two modes, and the general loop.
    const Triangulation two = Triangulation::from_mesh(side_by_side({make_icosphere(1), make_icosphere(1)}));
    const Sparse L2 = cotan_laplacian(two), M2 = mass_matrix(two, MassType::barycentric);
    EXPECT_FALSE(detail::constant_modes(L2, M2).one_covering_all);
}

// A soup of 1,000 separate triangles (as CAD exports write them), of sizes 0.1 to 10, has 1,000
// zero eigenvalues: more than a Lanczos basis resolves as one cluster. Block Lanczos ended not
// converged here with residuals of 3e-2 (and up to 1e3 on such meshes of 49 to 3,026 components
// from the unseen sweep). Each component's constant function is known to be an eigenvector, so
// these pairs are not left to the iteration.
TEST(Components, ASoupOfTrianglesGivesExactZeroPairs) {
    std::vector<TriangleMesh> triangles;
    for (int i = 0; i < 1000; ++i) {
        const double size = std::pow(10.0, 0.5 * (i % 5) - 1), lean = 0.1 * (i % 7), height = 0.5 + 0.1 * (i % 11);
        triangles.push_back(test::make_mesh({{0, 0, 0}, {size, 0, 0.1 * size}, {lean * size, height * size, 0}}, {{0, 1, 2}}));
    }
    const Triangulation t = Triangulation::from_mesh(side_by_side(triangles));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    // The scale of the eigenvalues' rounding: the largest weight sum over its vertex area.
    const double scale = (Eigen::VectorXd(L.diagonal()).array() / Eigen::VectorXd(M.diagonal()).array()).maxCoeff();
    for (EigenSolver solver : kBothSolvers) {
        const EigenResult r = smallest_eigenpairs(L, M, {.k = 6, .solver = solver});
        expect_accurate(r, std::string(to_string(solver)));
        expect_report_is_honest(r, L, M, std::string(to_string(solver)));
        for (int j = 0; j < 6; ++j) {
            EXPECT_LE(std::abs(r.values[j]), 1e-12 * scale) << to_string(solver) << ", pair " << j;
            // Constant on one triangle, zero elsewhere.
            const Eigen::VectorXd& phi = r.vectors.col(j);
            EXPECT_EQ((phi.array() != 0).count(), 3) << to_string(solver) << ", pair " << j;
        }
    }
}

// A sphere 1e-6, 1e-9 or 1e-12 across beside a unit sphere. Its constant function's Lφ is the
// rounding of L's row sums, which against |σ| ‖Mφ‖ would read as a residual of 5e-3 (0.06 with
// 642 vertices); against the terms of those sums it is rounding. Its masses of 1e-13 once left
// errors that the M-norm does not see and L does: the dense solve (n = 204) had residuals of
// 3.5e-3 (1e-9 across: an eigenvalue of -7,443), block Lanczos started outside the range of
// (L - σM)⁻¹M (n = 804) 2e-9 (1e-9 across: 1e-7). From 1e-9 on, L - σM is singular within
// rounding on the tiny sphere, whose factorization failed without a pinned vertex there.
TEST(Components, ATinyComponentKeepsEveryResidualSmall) {
    for (const int exponent : {-6, -9, -12})
        for (const int tiny_subdivisions : {1, 3}) {
            TriangleMesh tiny = make_icosphere(tiny_subdivisions);
            tiny.V *= std::pow(10.0, exponent);
            const Triangulation t = Triangulation::from_mesh(side_by_side({make_icosphere(2), tiny}));
            const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
            for (EigenSolver solver : kBothSolvers) {
                const std::string what = std::string(to_string(solver)) + ", n = " + std::to_string(L.rows()) +
                                         ", size 1e" + std::to_string(exponent);
                const EigenResult r = smallest_eigenpairs(L, M, {.k = 5, .solver = solver});
                expect_accurate(r, what);
                expect_report_is_honest(r, L, M, what);
                EXPECT_LE(r.report.max_residual, 1e-11) << what;
                EXPECT_EQ(r.values[0], 0.0) << what;
                EXPECT_EQ(r.values[1], 0.0) << what;
                for (int i = 2; i < 5; ++i) EXPECT_NEAR(r.values[i], 2.0, 0.1) << what;
                // The second zero pair is the tiny sphere's, and the old measure would fail it.
                const Eigen::VectorXd phi = r.vectors.col(1);
                EXPECT_EQ((phi.array() != 0).count(), tiny.V.rows()) << what;
                EXPECT_GT((L * phi).norm() / (std::abs(r.report.sigma) * (M * phi).norm()), 1e-3) << what;
            }
        }
}

// A needle of width 1e-12 on a unit sphere (a vertex moved that close to a neighbour) raises the
// mean cotan weight sum 1e10-fold, not the median: measured by the mean, the sphere passed for a
// component whose shift is lost to rounding, had a vertex pinned, and its pairs of 2 came out as
// 2.288 (residual 1.8). They stay within the needle's own rounding (residual ~1e-3) of 2.
TEST(Components, ANeedleDoesNotMakeItsComponentLookSmall) {
    TriangleMesh sphere = make_icosphere(3);
    const int neighbour = sphere.F(0, 1) == 0 ? sphere.F(0, 2) : sphere.F(0, 1);
    const int moved = sphere.F(0, 1) == 0 || sphere.F(0, 2) == 0 ? 0 : sphere.F(0, 0);
    sphere.V.row(moved) = sphere.V.row(neighbour) + 1e-12 * (sphere.V.row(moved) - sphere.V.row(neighbour));
    const Triangulation t = Triangulation::from_mesh(sphere);
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    for (EigenSolver solver : kBothSolvers) {
        const EigenResult r = smallest_eigenpairs(L, M, {.k = 6, .solver = solver});
        for (int i = 1; i < 4; ++i) EXPECT_NEAR(r.values[i], 2.0, 0.01) << to_string(solver) << ", pair " << i;
    }
}

// Slivers (a 1 x 1 grid of 2000 x 2 cells) put the automatic shift at -1000, 125 times the first
// eigenvalue (8) below 0, where 1/(λ - σ) crowds the pairs together: in a basis of 60 columns
// block Lanczos does not converge them there, and runs again from a tenth of its smallest Ritz
// value below 0, where they converge. (A CAD plate of 2,193 vertices needed it with the default
// basis, σ 30 times its first eigenvalue below 0.)
TEST(BlockLanczos, AShiftFarBelowTheSpectrumIsMovedNearerOnce) {
    const Triangulation t = Triangulation::from_mesh(make_grid(2000, 2));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    const EigenResult far = smallest_eigenpairs(L, M, {.k = 6, .sigma = -1000, .basis_size = 60});
    EXPECT_EQ(far.report.status, EigenStatus::not_converged);  // a sigma given is kept
    const EigenResult r = smallest_eigenpairs(L, M, {.k = 6, .basis_size = 60});
    expect_accurate(r, "automatic shift");
    EXPECT_GT(r.report.sigma, -1.0);
    EXPECT_GT(r.report.solves, far.report.solves);  // both runs' solves
    // 8 and 16 in y (two cells, lumped), (π i)² in x.
    const double pi2 = std::numbers::pi * std::numbers::pi, exact[] = {0, 8, pi2, 16, 8 + pi2, 16 + pi2};
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(r.values[i], exact[i], 1e-4) << i;
}

// Twelve spheres of radii 1 to 2.1: twelve zero eigenvalues, then the spheres' own l = 1 triples
// (2 / r², largest sphere first), as a dense solve of the whole problem finds them.
TEST(Components, ZeroPairsMergeWithTheOthersInOrder) {
    std::vector<TriangleMesh> spheres;
    for (int i = 0; i < 12; ++i) {
        spheres.push_back(make_icosphere(1));
        spheres.back().V *= 1.0 + 0.1 * i;
    }
    const Triangulation t = Triangulation::from_mesh(side_by_side(spheres));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense{Eigen::MatrixXd(L), Eigen::MatrixXd(M)};
    for (EigenSolver solver : kBothSolvers) {
        const EigenResult r = smallest_eigenpairs(L, M, {.k = 20, .solver = solver});
        expect_accurate(r, std::string(to_string(solver)));
        expect_report_is_honest(r, L, M, std::string(to_string(solver)));
        for (int j = 0; j < 20; ++j)
            EXPECT_NEAR(r.values[j], dense.eigenvalues()[j], 1e-9 * std::abs(dense.eigenvalues()[19]))
                << to_string(solver) << ", pair " << j;
    }
}

// On the unit square with the boundary fixed, λ = π²(a² + b²): 2π², 5π² (twice), 8π².
TEST(Dirichlet, SquareMatchesTheAnalyticSpectrumAndVanishesOnTheBoundary) {
    const int n = 40;
    const Triangulation t = Triangulation::from_mesh(make_grid(n, n));
    std::vector<int> boundary;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            if (i == 0 || j == 0 || i == n || j == n) boundary.push_back(j * (n + 1) + i);
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
    const EigenResult r = smallest_eigenpairs(L, M, {.k = 4, .dirichlet_vertices = boundary});
    expect_accurate(r, "square");
    const double pi2 = std::numbers::pi * std::numbers::pi, h = 1.0 / n;
    const double expected[] = {2 * pi2, 5 * pi2, 5 * pi2, 8 * pi2};
    for (int i = 0; i < 4; ++i)  // O(λ²h²), same constant as on the sphere
        EXPECT_NEAR(r.values[i], expected[i], 0.1 * expected[i] * expected[i] * h * h) << "index " << i;
    for (int v : boundary) EXPECT_EQ(r.vectors.row(v).cwiseAbs().maxCoeff(), 0.0) << "vertex " << v;
}

TEST(Arguments, AreChecked) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(0));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    EXPECT_THROW(smallest_eigenpairs(L, M, {.k = 0}), InvalidArgumentError);
    EXPECT_THROW(smallest_eigenpairs(L, M, {.k = 12}), InvalidArgumentError);  // k >= n
    EXPECT_THROW(smallest_eigenpairs(L, Sparse(M.topLeftCorner(11, 11)), {.k = 3}), InvalidArgumentError);
    EXPECT_THROW(smallest_eigenpairs(L, M, {.k = 3, .sigma = 0.5}), InvalidArgumentError);
    EXPECT_THROW(smallest_eigenpairs(L, M, {.k = 3, .dirichlet_vertices = {12}}), InvalidArgumentError);
    EXPECT_THROW(smallest_eigenpairs(L, M, {.k = 3, .basis_size = 3}), InvalidArgumentError);
    EXPECT_THROW(smallest_eigenpairs(L, Sparse(-M), {.k = 3}), NumericalError);  // M not positive
    EXPECT_THROW(smallest_eigenpairs(L, M, {.k = 3, .sigma = -1.0, .tolerance = 0}), InvalidArgumentError);
    // The value at fault is printed as it reads back, not with six decimals.
    for (const auto& [options, value] : {std::pair{EigenOptions{.k = 3, .sigma = 1e300}, "got 1e+300"},
                                         std::pair{EigenOptions{.k = 3, .tolerance = -1e-20}, "got -1e-20"}}) {
        try {
            (void)smallest_eigenpairs(L, M, options);
            ADD_FAILURE() << "no exception for " << value;
        } catch (const InvalidArgumentError& e) {
            EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
        }
    }
}

TEST(Arguments, MassWithANegativeDualCellIsRefusedByName) {
    const Triangulation t = Triangulation::from_mesh(test::make_negative_dual_fan());
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::circumcentric);
    Eigen::Index negative = 0;
    ASSERT_LT(M.diagonal().minCoeff(&negative), 0);
    try {
        (void)smallest_eigenpairs(L, M, {.k = 2});
        ADD_FAILURE() << "no exception";
    } catch (const NumericalError& e) {
        const std::string entry = "M(" + std::to_string(negative) + ", " + std::to_string(negative) + ")";
        EXPECT_NE(std::string(e.what()).find(entry), std::string::npos) << e.what();
    }
}

// ---- the CLI ---------------------------------------------------------------------------------------

namespace fs = std::filesystem;
using Cli = test::CliTest;

TEST_F(Cli, WritesTheLibrarysEigenpairs) {
    write_mesh(dir_ / "sphere.off", make_icosphere(2));
    const fs::path out = dir_ / "eigs";
    ASSERT_EQ(run("eigs " + (dir_ / "sphere.off").string() + " -k 9 --mass mixed --out " + out.string()), 0)
        << read(dir_ / "err.txt");

    const Triangulation t = Triangulation::from_mesh(read_mesh(dir_ / "sphere.off"));
    const EigenResult r =
        smallest_eigenpairs(cotan_laplacian(t), mass_matrix(t, MassType::mixed_voronoi), {.k = 9});
    std::istringstream csv(read(out / "eigenvalues.csv"));
    for (int i = 0; i < 9; ++i) {
        double value = 0;
        csv >> value;
        EXPECT_EQ(value, r.values[i]) << "line " << i;  // 17 significant digits round-trip
    }
    double extra = 0;
    EXPECT_FALSE(csv >> extra) << "more than k lines";

    const std::string bin = read(out / "eigenvectors.bin");
    std::int32_t sizes[2] = {};
    ASSERT_EQ(bin.size(), sizeof sizes + sizeof(double) * static_cast<size_t>(t.num_vertices) * 9);
    std::memcpy(sizes, bin.data(), sizeof sizes);
    EXPECT_EQ(sizes[0], t.num_vertices);
    EXPECT_EQ(sizes[1], 9);
    Eigen::MatrixXd vectors(t.num_vertices, 9);
    std::memcpy(vectors.data(), bin.data() + sizeof sizes, sizeof(double) * static_cast<size_t>(vectors.size()));
    EXPECT_EQ(vectors, r.vectors);

    const std::string report = read(out / "report.json");
    for (const char* key : {"\"status\": \"converged\"", "\"mass\": \"mixed\"", "\"iterations\": ",
                            "\"max_residual\": ", "\"sigma\": -", "\"seconds\": "})
        EXPECT_NE(report.find(key), std::string::npos) << key << "\n" << report;
}

// --progress reports on stderr (the factorization, the final status) and changes no result.
TEST_F(Cli, ProgressGoesToStandardErrorAndChangesNothing) {
    write_mesh(dir_ / "sphere.off", make_icosphere(3));
    const std::string base = "eigs " + (dir_ / "sphere.off").string() + " -k 12 --out ";
    ASSERT_EQ(run(base + (dir_ / "quiet").string()), 0) << read(dir_ / "err.txt");
    EXPECT_EQ(read(dir_ / "err.txt"), "");
    ASSERT_EQ(run(base + (dir_ / "loud").string() + " --progress"), 0) << read(dir_ / "err.txt");
    const std::string err = read(dir_ / "err.txt");
    // The constant function is known: Lanczos seeks 11 pairs.
    for (const char* line : {"eigs: factorizing L - sigma M (n = 642)\n", "eigs: factorized in ",
                             "; block Lanczos for 11 pairs\n", "eigs: converged, "})
        EXPECT_NE(err.find(line), std::string::npos) << line << "\n" << err;
    for (const char* file : {"eigenvalues.csv", "eigenvectors.bin"})
        EXPECT_EQ(read(dir_ / "loud" / file), read(dir_ / "quiet" / file)) << file;
}

// Pairs that did not converge are written, with the status in report.json, one line on stderr
// and exit code 1.
TEST_F(Cli, SaysOnStandardErrorWhenItDidNotConverge) {
    write_mesh(dir_ / "sphere.off", make_icosphere(3));
    const fs::path out = dir_ / "eigs";
    ASSERT_EQ(run("eigs " + (dir_ / "sphere.off").string() + " -k 6 --tolerance 1e-30 --out " + out.string()), 1)
        << read(dir_ / "err.txt");
    EXPECT_NE(read(out / "report.json").find("\"status\": \"not_converged\""), std::string::npos);
    const std::string err = read(dir_ / "err.txt");
    EXPECT_NE(err.find("sphere.off: not converged (largest relative residual "), std::string::npos) << err;
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    std::istringstream csv(read(out / "eigenvalues.csv"));
    double first = 1;
    csv >> first;
    EXPECT_NEAR(first, 0.0, 1e-6);  // approximations, not garbage
}

TEST_F(Cli, SolvesOnConvertedAndIntrinsicMeshes) {
    write_mesh(dir_ / "grid.obj", make_grid(8, 8, 1.0, 1.0, 1.7));  // sheared: not self-Delaunay
    for (const char* choice : {"--convert split", "--intrinsic"}) {
        const fs::path out = dir_ / "eigs";
        ASSERT_EQ(run("eigs " + (dir_ / "grid.obj").string() + " -k 4 --out " + out.string() + " " + choice), 0)
            << choice << ": " << read(dir_ / "err.txt");
        std::istringstream csv(read(out / "eigenvalues.csv"));
        double first = 1;
        csv >> first;
        EXPECT_NEAR(first, 0.0, 1e-8) << choice;  // the constants, Neumann boundary
        EXPECT_NE(read(out / "report.json").find("\"status\": \"converged\""), std::string::npos) << choice;
    }
}

TEST_F(Cli, RejectsBadArguments) {
    write_mesh(dir_ / "sphere.off", make_icosphere(0));
    const std::string mesh = (dir_ / "sphere.off").string(), out = " --out " + (dir_ / "o").string();
    EXPECT_EQ(run("eigs " + mesh + out), 2);                       // no -k
    EXPECT_EQ(run("eigs " + mesh + " -k 2.5" + out), 2);           // not whole
    EXPECT_EQ(run("eigs " + mesh + " -k 3"), 2);                   // no --out
    EXPECT_EQ(run("eigs " + mesh + " -k 3 --intrinsic --convert split" + out), 2);
    EXPECT_EQ(run("eigs " + mesh + " -k 3 --convert sideways" + out), 2);
    EXPECT_EQ(run("eigs " + mesh + " -k 12" + out), 7);            // k >= n
    EXPECT_NE(read(dir_ / "err.txt").find("eigs: -k 12 needs a mesh with more than 12 vertices; " + mesh + " has 12"),
              std::string::npos)
        << read(dir_ / "err.txt");
    EXPECT_EQ(run("eigs " + mesh + " -k 12 --convert split" + out), 7);
    EXPECT_NE(read(dir_ / "err.txt").find(" has 12 after its conversion"), std::string::npos) << read(dir_ / "err.txt");
    EXPECT_FALSE(fs::exists(dir_ / "o" / "eigenvalues.csv"));
}

}  // namespace
}  // namespace sdmesh
