// Poisson, heat and heat-method geodesics: manufactured solutions converging at second order,
// Dirichlet data met exactly, heat steps against the spectrum, geodesic distance against the
// great circle and the plane, several sources, intrinsic triangulations, argument errors,
// `sdmesh geodesic`, `sdmesh poisson`, `sdmesh heat`.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "cli_run.hpp"
#include "meshes.hpp"
#include "sdmesh/eigen.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/intrinsic.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/pde.hpp"
#include "sdmesh/shapes.hpp"

namespace sdmesh {
namespace {

using Sparse = Eigen::SparseMatrix<double>;
constexpr double kPi = std::numbers::pi;

// √((u − v)ᵀ M (u − v)): the discrete L2 norm of u − v.
double l2_error(const Eigen::VectorXd& u, const Eigen::VectorXd& v, const Sparse& M) {
    const Eigen::VectorXd d = u - v;
    return std::sqrt(d.dot(M * d));
}

// Boundary vertices of make_grid(n, n), in index order.
std::vector<int> grid_boundary(int n) {
    std::vector<int> boundary;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            if (i == 0 || j == 0 || i == n || j == n) boundary.push_back(j * (n + 1) + i);
    return boundary;
}

// Halving h divides a second-order error by 4; "at least 3" leaves room for pre-asymptotic levels.
constexpr double kSecondOrderRatio = 3.0;

// ---- Poisson -----------------------------------------------------------------------------------------

// On the unit sphere Δz = −2z, so L u = M (2z) is solved by u = z, which has zero mean.
TEST(Poisson, SphereManufacturedSolutionConvergesAtSecondOrder) {
    double previous = std::numeric_limits<double>::infinity();
    for (int level = 2; level <= 5; ++level) {
        const TriangleMesh mesh = make_icosphere(level);
        const Triangulation t = Triangulation::from_mesh(mesh);
        const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
        const Eigen::VectorXd z = mesh.V.col(2);
        const Eigen::VectorXd u = PoissonSolver(L, M).solve(M * (2.0 * z));
        EXPECT_NEAR((M * u).sum(), 0.0, 1e-12) << "level " << level;  // zero M-mean
        const double error = l2_error(u, z, M);
        EXPECT_LT(error, previous / kSecondOrderRatio) << "level " << level;
        previous = error;
    }
}

// Solves −Δu = source on an n × n grid mesh (possibly mapped) with u = exact on its boundary;
// checks that the boundary values are met exactly and returns the L2 error.
template <class Exact, class Source>
double dirichlet_grid_error(const TriangleMesh& mesh, int n, Exact exact, Source source) {
    const Triangulation t = Triangulation::from_mesh(mesh);
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
    Eigen::VectorXd u_exact(mesh.num_vertices()), f(mesh.num_vertices());
    for (int v = 0; v < mesh.num_vertices(); ++v) {
        u_exact[v] = exact(mesh.V(v, 0), mesh.V(v, 1));
        f[v] = source(mesh.V(v, 0), mesh.V(v, 1));
    }
    const std::vector<int> boundary = grid_boundary(n);
    Eigen::VectorXd g(static_cast<Eigen::Index>(boundary.size()));
    for (size_t i = 0; i < boundary.size(); ++i) g[static_cast<Eigen::Index>(i)] = u_exact[boundary[i]];
    const Eigen::VectorXd u = PoissonSolver(L, M, boundary).solve(M * f, g);
    for (size_t i = 0; i < boundary.size(); ++i) EXPECT_EQ(u[boundary[i]], g[static_cast<Eigen::Index>(i)]);
    return l2_error(u, u_exact, M);
}

// u = sin(πx)cos(πy) + x² on the unit square, −Δu = 2π² sin(πx)cos(πy) − 2, u given on the boundary.
TEST(Poisson, SquareWithDirichletDataConvergesAtSecondOrderAndMeetsTheData) {
    auto exact = [](double x, double y) { return std::sin(kPi * x) * std::cos(kPi * y) + x * x; };
    auto source = [](double x, double y) { return 2 * kPi * kPi * std::sin(kPi * x) * std::cos(kPi * y) - 2; };
    double previous = std::numeric_limits<double>::infinity();
    for (int n : {8, 16, 32, 64}) {
        const double error = dirichlet_grid_error(make_grid(n, n), n, exact, source);
        EXPECT_LT(error, previous / kSecondOrderRatio) << "n = " << n;
        previous = error;
    }
}

// The unit disk: the grid on [−1, 1]² mapped by (x√(1 − y²/2), y√(1 − x²/2)), which takes the
// square's sides onto the circle. u = eˣcos y + x²y, −Δu = −2y, u given on the boundary circle.
TEST(Poisson, DiskWithDirichletDataConvergesAtSecondOrderAndMeetsTheData) {
    auto exact = [](double x, double y) { return std::exp(x) * std::cos(y) + x * x * y; };
    auto source = [](double, double y) { return -2 * y; };
    double previous = std::numeric_limits<double>::infinity();
    for (int n : {8, 16, 32, 64}) {
        TriangleMesh mesh = make_grid(n, n, 2.0, 2.0);
        for (int v = 0; v < mesh.num_vertices(); ++v) {
            const double x = mesh.V(v, 0) - 1, y = mesh.V(v, 1) - 1;
            mesh.V(v, 0) = x * std::sqrt(1 - y * y / 2);
            mesh.V(v, 1) = y * std::sqrt(1 - x * x / 2);
        }
        const double error = dirichlet_grid_error(mesh, n, exact, source);
        EXPECT_LT(error, previous / kSecondOrderRatio) << "n = " << n;
        previous = error;
    }
}

// u = cos(πx)cos(πy): −Δu = 2π²u, ∂u/∂n = 0 on the boundary (the natural condition), mean 0.
TEST(Poisson, SquareWithNeumannBoundaryConvergesAtSecondOrder) {
    double previous = std::numeric_limits<double>::infinity();
    for (int n : {8, 16, 32, 64}) {
        const TriangleMesh mesh = make_grid(n, n);
        const Triangulation t = Triangulation::from_mesh(mesh);
        const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::barycentric);
        Eigen::VectorXd u_exact(mesh.num_vertices());
        for (int v = 0; v < mesh.num_vertices(); ++v)
            u_exact[v] = std::cos(kPi * mesh.V(v, 0)) * std::cos(kPi * mesh.V(v, 1));
        const Eigen::VectorXd u = PoissonSolver(L, M).solve(M * (2 * kPi * kPi * u_exact));
        const double error = l2_error(u, u_exact, M);
        EXPECT_LT(error, previous / kSecondOrderRatio) << "n = " << n;
        previous = error;
    }
}

// Two spheres: each component is solved on its own, with zero mean; a constant added to f on one
// sphere is the incompatible part and is removed.
TEST(Poisson, EachComponentWithoutDirichletDataHasZeroMean) {
    const TriangleMesh a = make_icosphere(3);
    TriangleMesh both;
    both.V.resize(2 * a.V.rows(), 3);
    both.V << a.V, a.V.rowwise() + Eigen::RowVector3d(3, 0, 0);
    both.F.resize(2 * a.F.rows(), 3);
    both.F << a.F, (a.F.array() + static_cast<int>(a.V.rows())).matrix();
    const Triangulation t = Triangulation::from_mesh(both);
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    const Eigen::VectorXd z = both.V.col(2);
    Eigen::VectorXd f = 2.0 * z;
    f.tail(a.V.rows()).array() += 5.0;
    const Eigen::VectorXd u = PoissonSolver(L, M).solve(M * f);
    const Triangulation ta = Triangulation::from_mesh(a);
    const Sparse Ma = mass_matrix(ta);
    const Eigen::VectorXd single = PoissonSolver(cotan_laplacian(ta), Ma).solve(Ma * Eigen::VectorXd(2.0 * a.V.col(2)));
    const double scale = single.cwiseAbs().maxCoeff();
    EXPECT_LT((u.head(a.V.rows()) - single).cwiseAbs().maxCoeff(), 1e-10 * scale);
    EXPECT_LT((u.tail(a.V.rows()) - single).cwiseAbs().maxCoeff(), 1e-10 * scale);
}

// Solvers of one mesh share the heat solver's ordering: the same pattern gives the same factor,
// so solutions are bit-identical to those with their own (METIS) ordering, pins still exact.
TEST(Poisson, SharedOrderingGivesIdenticalSolutions) {
    const int n = 16;
    const Triangulation t = Triangulation::from_mesh(make_grid(n, n));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    const HeatSolver heat(L, M, 0.01, {}, {.ordering = CholeskyOrdering::metis});
    const CholeskyOptions shared{.same_ordering_as = &heat.factorization()};
    const std::vector<int> boundary = grid_boundary(n);
    const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(t.num_vertices, -1, 1);
    const Eigen::VectorXd g = Eigen::VectorXd::LinSpaced(static_cast<Eigen::Index>(boundary.size()), 2, 3);
    const Eigen::VectorXd u = PoissonSolver(L, M, boundary, shared).solve(M * f, g);
    EXPECT_EQ(u, PoissonSolver(L, M, boundary, {.ordering = CholeskyOrdering::metis}).solve(M * f, g));
    for (size_t i = 0; i < boundary.size(); ++i) EXPECT_EQ(u[boundary[i]], g[static_cast<Eigen::Index>(i)]);
    EXPECT_EQ(PoissonSolver(L, M, {}, shared).solve(M * f),
              PoissonSolver(L, M, {}, {.ordering = CholeskyOrdering::metis}).solve(M * f));
    EXPECT_EQ(HeatSolver(L, M, 0.01, boundary, shared).step(f, 2),
              HeatSolver(L, M, 0.01, boundary, {.ordering = CholeskyOrdering::metis}).step(f, 2));
}

// A Dirichlet vertex whose diagonal entry L does not store gets one; the solution is unchanged.
TEST(Poisson, DirichletVertexWithoutAStoredDiagonal) {
    const int n = 8;
    const Triangulation t = Triangulation::from_mesh(make_grid(n, n));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    const std::vector<int> boundary = grid_boundary(n);
    const int v = boundary.front();
    Sparse pruned = L;
    pruned.prune([v](Eigen::Index i, Eigen::Index j, double) { return !(i == v && j == v); });
    ASSERT_EQ(pruned.nonZeros(), L.nonZeros() - 1);
    const Eigen::VectorXd f = Eigen::VectorXd::Ones(t.num_vertices);
    const Eigen::VectorXd g = Eigen::VectorXd::Constant(static_cast<Eigen::Index>(boundary.size()), 0.5);
    const Eigen::VectorXd u = PoissonSolver(pruned, M, boundary).solve(M * f, g);
    EXPECT_EQ(u[v], 0.5);
    EXPECT_LT((u - PoissonSolver(L, M, boundary).solve(M * f, g)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Poisson, ArgumentsAreChecked) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(1));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    EXPECT_THROW(PoissonSolver(L, Sparse(M.topLeftCorner(5, 5))), InvalidArgumentError);
    EXPECT_THROW(PoissonSolver(L, M, {0, 0}), InvalidArgumentError);
    EXPECT_THROW(PoissonSolver(L, M, {42}), InvalidArgumentError);
    const PoissonSolver poisson(L, M, {0, 1});
    EXPECT_THROW((void)poisson.solve(Eigen::VectorXd::Ones(41)), InvalidArgumentError);
    EXPECT_THROW((void)poisson.solve(Eigen::VectorXd::Ones(42), Eigen::VectorXd::Ones(3)), InvalidArgumentError);
    // A NaN or an infinity would come out as a NaN solution.
    Eigen::VectorXd b = Eigen::VectorXd::Ones(42);
    b[7] = std::nan("");
    EXPECT_THROW((void)poisson.solve(b), InvalidArgumentError);
    EXPECT_THROW((void)poisson.solve(Eigen::VectorXd::Ones(42), Eigen::Vector2d(0, HUGE_VAL)), InvalidArgumentError);
    // No faces: L = M = 0, so every u solves L u = M f.
    const Sparse zero(3, 3);
    EXPECT_THROW(PoissonSolver(zero, zero), NumericalError);
}

// ---- heat --------------------------------------------------------------------------------------------

// An eigenvector φ (L φ = λ M φ) decays by exactly 1/(1 + tλ) per backward Euler step.
TEST(Heat, EigenvectorsDecayByTheBackwardEulerFactor) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(3));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t, MassType::mixed_voronoi);
    const EigenResult eig = smallest_eigenpairs(L, M, {.k = 10});
    HeatSolver heat(L, M, 0.05);
    for (int j : {0, 3, 9}) {
        const Eigen::VectorXd phi = eig.vectors.col(j);
        for (double step : {0.05, 0.2}) {
            heat.set_time_step(step);
            const Eigen::VectorXd u = heat.step(phi, 3);
            const Eigen::VectorXd expected = std::pow(1 + step * eig.values[j], -3) * phi;
            EXPECT_LT(l2_error(u, expected, M), 1e-8) << "pair " << j << ", step " << step;
        }
    }
}

// With the natural boundary, 1ᵀL = 0, so every step conserves the total heat 1ᵀMu; with the
// boundary held at 0, heat leaves and u stays 0 there.
TEST(Heat, ConservesHeatWithNeumannAndLosesItWithDirichletBoundary) {
    const int n = 20;
    const Triangulation t = Triangulation::from_mesh(make_grid(n, n));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    Eigen::VectorXd u0 = Eigen::VectorXd::Zero(t.num_vertices);
    u0[(n / 2) * (n + 1) + n / 2] = 1.0;
    const double total = (M * u0).sum();
    const Eigen::VectorXd neumann = HeatSolver(L, M, 0.01).step(u0, 5);
    EXPECT_NEAR((M * neumann).sum(), total, 1e-14 * total);
    const std::vector<int> boundary = grid_boundary(n);
    const Eigen::VectorXd dirichlet = HeatSolver(L, M, 0.01, boundary).step(u0, 5);
    EXPECT_LT((M * dirichlet).sum(), total);
    for (int v : boundary) EXPECT_EQ(dirichlet[v], 0.0);
    EXPECT_GE(dirichlet.minCoeff(), 0.0);  // maximum principle: M-matrix system, non-negative data
}

// The solvers read one triangle of L and M: an asymmetric or non-finite operator (a user's own,
// from Python) would solve another problem unseen, or fail far from the cause. Rounding-level
// asymmetry is accepted.
TEST(Solvers, RefuseAnAsymmetricOrNonFiniteOperatorByName) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(1));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    Sparse::InnerIterator entry(L, 0);
    if (entry.row() == 0) ++entry;  // column 0's first entry off the diagonal
    const Eigen::Index neighbour = entry.row();
    ASSERT_NE(L.coeff(neighbour, 0), 0.0);
    Sparse lopsided = L;
    lopsided.coeffRef(neighbour, 0) += 0.25;
    Sparse broken = M;
    broken.coeffRef(4, 4) = std::nan("");
    Sparse rounded = L;
    rounded.coeffRef(neighbour, 0) *= 1 + 1e-15;
    const std::vector<std::pair<std::string, std::function<void(const Sparse&, const Sparse&)>>> solvers = {
        {"Poisson", [](const Sparse& l, const Sparse& m) { PoissonSolver(l, m, {0}); }},
        {"heat", [](const Sparse& l, const Sparse& m) { HeatSolver(l, m, 0.1); }},
        {"eigenpairs", [](const Sparse& l, const Sparse& m) { (void)smallest_eigenpairs(l, m, {.k = 3}); }},
    };
    auto message = [](const auto& run) {
        try {
            run();
        } catch (const InvalidArgumentError& e) {
            return std::string(e.what());
        }
        return std::string("no InvalidArgumentError");
    };
    for (const auto& [who, solve] : solvers) {
        EXPECT_EQ(message([&] { solve(lopsided, M); }).rfind(who + ": L is not symmetric: L(", 0), 0u) << who;
        EXPECT_EQ(message([&] { solve(L, broken); }), who + ": M(4, 4) = nan is not finite");
        EXPECT_NO_THROW(solve(rounded, M)) << who;
    }
}

TEST(Heat, ArgumentsAreChecked) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(1));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    EXPECT_THROW(HeatSolver(L, M, 0.0), InvalidArgumentError);
    EXPECT_THROW(HeatSolver(L, M, std::nan("")), InvalidArgumentError);
    HeatSolver heat(L, M, 1.0);
    EXPECT_THROW(heat.set_time_step(-1.0), InvalidArgumentError);
    EXPECT_THROW((void)heat.step(Eigen::VectorXd::Ones(41)), InvalidArgumentError);
    EXPECT_THROW((void)heat.step(Eigen::VectorXd::Ones(42), -1), InvalidArgumentError);
    EXPECT_THROW((void)heat.step(Eigen::VectorXd::Constant(42, -HUGE_VAL)), InvalidArgumentError);
}

// A mass matrix with a negative entry (circumcentric cells of a mesh that is not self-Delaunay)
// makes M + tL indefinite for small t: the error names the matrix, the vertex and the cure, when
// the solver is made and when its step changes.
TEST(Heat, AnIndefiniteMatrixIsNamedWithItsVertex) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(1));
    const Sparse L = cotan_laplacian(t);
    Sparse M = mass_matrix(t);
    auto expect_named = [](const std::function<void()>& make) {
        try {
            make();
            ADD_FAILURE() << "no NumericalError";
        } catch (const NumericalError& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind("heat: M + tL: Cholesky: the matrix is not positive definite within rounding "
                                    "(the pivot of row 7 is not positive); on a mesh that is not self-Delaunay",
                                    0),
                      0u)
                << message;
        }
    };
    M.coeffRef(7, 7) = -M.coeff(7, 7);
    expect_named([&] { HeatSolver(L, M, 1e-3); });
    HeatSolver negative(L, M, 10.0);  // tL outweighs the negative mass
    expect_named([&] { negative.set_time_step(1e-3); });
}

TEST(Heat, AVertexInNoFaceIsNamedUnlessItIsPinned) {
    TriangleMesh mesh = make_icosphere(1);
    mesh.V.conservativeResize(mesh.V.rows() + 1, 3);
    mesh.V.row(42) << 5, 5, 5;  // in no face
    const Triangulation t = Triangulation::from_mesh(mesh);
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    try {
        HeatSolver heat(L, M, 0.1);
        FAIL() << "no exception";
    } catch (const NumericalError& e) {
        EXPECT_NE(std::string(e.what()).find("vertex 42 has no mass"), std::string::npos) << e.what();
    }
    // Pinned, it keeps its Dirichlet value 0 and the heat elsewhere is that of the sphere alone.
    const HeatSolver pinned(L, M, 0.1, {42});
    const Triangulation sphere = Triangulation::from_mesh(make_icosphere(1));
    const HeatSolver alone(cotan_laplacian(sphere), mass_matrix(sphere), 0.1);
    Eigen::VectorXd u0 = Eigen::VectorXd::Zero(43);
    u0[3] = 1;
    const Eigen::VectorXd u = pinned.step(u0);
    EXPECT_EQ(u[42], 0);
    EXPECT_LT((u.head(42) - alone.step(u0.head(42))).norm(), 1e-14);
}

// A sphere 1e-3, 1e-6 or 1e-9 across beside a unit sphere, t = 0.01: on the small one tL swamps
// M (from 1e-6 on, to rounding: at 1e-9 the factorization failed). Two steps leave there its
// mean up to (1/(tλ₁))² (λ₁ = 2/r²) or the error of a solve with one vertex pinned, about M's
// share of M + tL (below 1e-8 where it is pinned), and conserve the heat, to a rounding that
// grows with the condition of M + tL (1e-11 at 1e-3) where it is factored as it is; the unit
// sphere's heat is that of the sphere alone.
TEST(Heat, AComponentFarSmallerThanTheTimeStepIsSmoothedToItsMean) {
    for (const int exponent : {-3, -6, -9}) {
        TriangleMesh tiny = make_icosphere(1);
        tiny.V *= std::pow(10.0, exponent);
        const TriangleMesh unit = make_icosphere(2);
        const Triangulation t = Triangulation::from_mesh(test::disjoint_union(unit, tiny, 3.0));
        const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
        const Eigen::Index n = L.rows(), big = unit.V.rows(), small = n - big;
        const std::string what = "size 1e" + std::to_string(exponent);
        const HeatSolver heat(L, M, 0.01);
        Eigen::VectorXd u0 = Eigen::VectorXd::Zero(n);
        u0[3] = 1;
        u0[big + 5] = 1;
        const Eigen::VectorXd u = heat.step(u0, 2);
        const Eigen::VectorXd on_tiny = u.tail(small);
        const double heat_in = (M * u0).tail(small).sum();
        EXPECT_NEAR((M * u).tail(small).sum(), heat_in, (exponent == -3 ? 1e-10 : 1e-14) * heat_in) << what;
        const double mean = heat_in / M.bottomRightCorner(small, small).sum();
        const double damping = std::pow(10.0, 2 * exponent) / (2 * 0.01);
        EXPECT_LE((on_tiny.array() - mean).abs().maxCoeff(), std::max(10 * damping * damping, 1e-8) * mean) << what;
        const Triangulation sphere = Triangulation::from_mesh(unit);
        const HeatSolver alone(cotan_laplacian(sphere), mass_matrix(sphere), 0.01);
        EXPECT_LT((u.head(big) - alone.step(u0.head(big), 2)).norm(), 1e-14) << what;
    }
}

// Through the library a component may come with no mass at all (here a sphere's block of M set to
// 0): tL alone is singular there, and with nothing to diffuse the step leaves 0 on it, finite.
TEST(Heat, AComponentWithoutMassKeepsNoHeat) {
    const TriangleMesh unit = make_icosphere(1);
    const Triangulation t = Triangulation::from_mesh(test::disjoint_union(unit, unit, 3.0));
    const Eigen::Index half = unit.V.rows();
    const Sparse L = cotan_laplacian(t);
    Sparse M = mass_matrix(t);
    for (int j = static_cast<int>(half); j < M.outerSize(); ++j)
        for (Sparse::InnerIterator it(M, j); it; ++it) it.valueRef() = 0;
    Eigen::VectorXd u0 = Eigen::VectorXd::Ones(2 * half);
    const Eigen::VectorXd u = HeatSolver(L, M, 0.1).step(u0, 2);
    EXPECT_TRUE(u.tail(half).isZero(0)) << u.tail(half).transpose();
    EXPECT_LT((u.head(half) - Eigen::VectorXd::Ones(half)).cwiseAbs().maxCoeff(), 1e-14);
}

// ---- heat-method geodesics ---------------------------------------------------------------------------

// Mean of |d − exact| / exact over the vertices where exact > 0.
double mean_relative_error(const Eigen::VectorXd& d, const Eigen::VectorXd& exact) {
    double sum = 0;
    int count = 0;
    for (Eigen::Index v = 0; v < d.size(); ++v) {
        if (exact[v] <= 0) continue;
        sum += std::abs(d[v] - exact[v]) / exact[v];
        ++count;
    }
    return sum / count;
}

// Great-circle distance on the unit sphere from vertex s.
Eigen::VectorXd great_circle(const TriangleMesh& mesh, int s) {
    Eigen::VectorXd d(mesh.num_vertices());
    const Eigen::Vector3d p = mesh.V.row(s).normalized();
    for (int v = 0; v < mesh.num_vertices(); ++v) {
        const Eigen::Vector3d q = mesh.V.row(v).normalized();
        d[v] = std::atan2(p.cross(q).norm(), p.dot(q));
    }
    return d;
}

TEST(Geodesics, SphereDistanceApproachesTheGreatCircle) {
    double previous = std::numeric_limits<double>::infinity();
    for (int level = 3; level <= 5; ++level) {
        const TriangleMesh mesh = make_icosphere(level);
        const Eigen::VectorXd d = heat_geodesic_distance(Triangulation::from_mesh(mesh), {0});
        EXPECT_EQ(d[0], 0.0);
        const double error = mean_relative_error(d, great_circle(mesh, 0));
        if (level == 5) {
            EXPECT_LE(error, 0.01) << mesh.num_vertices() << " vertices";
        }
        EXPECT_LT(error, previous) << "level " << level;
        previous = error;
    }
}

// Several sources: the distance to the nearest, i.e. the pointwise minimum of the single-source
// distances, within the error the method makes for one source (mean absolute error; the largest
// errors sit on the cut locus, where the heat flow rounds the kink off over a width of about √t).
// With a very short heat time u is ~1e-200 on the far side, where |∇u|² underflows; the
// directions must survive (they did not: the largest distance was 2.17 instead of ~3).
TEST(Geodesics, ShortHeatTimeStillReachesTheFarSide) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(4));
    const double h = t.length.mean();
    const Eigen::VectorXd d = heat_geodesic_distance(t, {0}, {.time = h * h / 1e5});
    EXPECT_GT(d.maxCoeff(), 0.95 * kPi);
}

// The work is done at a unit mean edge length, by a power of two: distances scale exactly with the
// mesh. Unscaled, the gradients' cubes of lengths overflowed (underflowed) from lengths of ~1e100
// (1e-100) on, and every distance came out NaN.
TEST(Geodesics, TheUnitOfLengthOnlyScalesTheDistance) {
    const TriangleMesh sphere = make_icosphere(3);
    const Eigen::VectorXd reference = heat_geodesic_distance(Triangulation::from_mesh(sphere), {0, 7});
    for (const int exponent : {-495, -350, 350, 495}) {
        const Triangulation t = Triangulation::from_mesh(scaled_by_power_of_two(sphere, exponent));
        const HeatGeodesics geodesics(t);
        EXPECT_TRUE(geodesics.distance({0, 7}) == reference.unaryExpr([&](double x) { return std::ldexp(x, exponent); }))
            << exponent;
        const double h = t.length.mean();
        EXPECT_EQ(geodesics.report().time, h * h) << exponent;
    }
}

// Each component has the heat time of its own edges: a sphere 2^-10, 2^-20 or 2^-30 across
// beside a unit sphere has the distances of that sphere alone, scaled. With one time for both,
// its heat was its mean to rounding and its distances far too short (1.8e-7 for π·1e-6). (The
// small sphere is the one not moved: moved by 3, its coordinates would keep few of its bits.)
TEST(Geodesics, EachComponentHasAHeatTimeForItsSize) {
    const TriangleMesh unit = make_icosphere(3);
    const Triangulation alone = Triangulation::from_mesh(unit);
    const Eigen::VectorXd from_0 = heat_geodesic_distance(alone, {0}), from_7 = heat_geodesic_distance(alone, {7});
    const Eigen::Index n = unit.V.rows();
    for (const int exponent : {-10, -20, -30}) {
        const Triangulation t =
            Triangulation::from_mesh(test::disjoint_union(scaled_by_power_of_two(unit, exponent), unit, 3.0));
        const HeatGeodesics geodesics(t);
        const Eigen::VectorXd d = geodesics.distance({7, static_cast<int>(n)});
        const std::string what = "size 2^" + std::to_string(exponent);
        const Eigen::VectorXd small = d.head(n).unaryExpr([&](double x) { return std::ldexp(x, -exponent); });
        EXPECT_LT((small - from_7).cwiseAbs().maxCoeff(), 1e-12) << what;
        EXPECT_LT((d.tail(n) - from_0).cwiseAbs().maxCoeff(), 1e-12) << what;
        const double h = alone.length.mean();
        // The time reported is the first of the two components of the most vertices, the small one.
        const double time = std::ldexp(h * h, 2 * exponent);
        EXPECT_NEAR(geodesics.report().time, time, 1e-13 * time) << what;
    }
}

// With t far above the squared edge lengths, M + tL loses M to rounding: refused, by name.
// Below the limit the heat is still conserved (M alone conserves it).
TEST(Heat, ATimeStepThatSwampsTheMassIsRefused) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(2));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    for (const double time : {1e12, 1e30}) {
        try {
            const HeatSolver heat(L, M, time);
            ADD_FAILURE() << "t = " << time << ": no error";
        } catch (const InvalidArgumentError& e) {
            EXPECT_NE(std::string(e.what()).find("take a smaller t"), std::string::npos) << e.what();
        }
    }
    HeatSolver heat(L, M, 1e8);
    EXPECT_THROW(heat.set_time_step(1e30), InvalidArgumentError);
    Eigen::VectorXd u0 = Eigen::VectorXd::Zero(L.rows());
    u0[0] = 1;
    const Eigen::VectorXd u = heat.step(u0);
    EXPECT_NEAR((M * u).sum(), M.coeff(0, 0), 1e-6 * M.coeff(0, 0));
}

TEST(Geodesics, SeveralSourcesGiveTheDistanceToTheNearest) {
    const TriangleMesh mesh = make_icosphere(4);
    const HeatGeodesics geodesics(Triangulation::from_mesh(mesh));
    const std::vector<int> sources = {0, 5, 11};
    Eigen::VectorXd nearest = Eigen::VectorXd::Constant(mesh.num_vertices(), std::numeric_limits<double>::infinity());
    Eigen::VectorXd exact = nearest;
    double single_error = 0;  // largest mean absolute error of a single-source run
    for (int s : sources) {
        const Eigen::VectorXd d = geodesics.distance({s}), e = great_circle(mesh, s);
        single_error = std::max(single_error, (d - e).cwiseAbs().mean());
        nearest = nearest.cwiseMin(d);
        exact = exact.cwiseMin(e);
    }
    const Eigen::VectorXd d = geodesics.distance(sources);
    EXPECT_LE((d - exact).cwiseAbs().mean(), 2 * single_error);
    EXPECT_LE((d - nearest).cwiseAbs().mean(), 3 * single_error);  // both carry the method's error
    for (int s : sources) EXPECT_LE(std::abs(d[s]), single_error) << "source " << s;
}

// In a convex planar domain the geodesic distance is the Euclidean one; the boundary needs the
// averaged Neumann/Dirichlet heat (Crane et al. §3.2). The iDT of a sheared (non-Delaunay) grid
// gives the same distances, since it describes the same flat metric.
TEST(Geodesics, PlanarDistanceIsEuclideanOnExtrinsicAndIntrinsicMeshes) {
    double previous = std::numeric_limits<double>::infinity();
    for (int n : {16, 32, 64}) {
        const TriangleMesh mesh = make_grid(n, n);
        const int source = (n / 4) * (n + 1) + n / 2;
        Eigen::VectorXd exact(mesh.num_vertices());
        for (int v = 0; v < mesh.num_vertices(); ++v) exact[v] = (mesh.V.row(v) - mesh.V.row(source)).norm();
        const HeatGeodesics geodesics(Triangulation::from_mesh(mesh));
        EXPECT_EQ(geodesics.report().boundary_vertices, 4 * n);
        const double error = mean_relative_error(geodesics.distance({source}), exact);
        EXPECT_LT(error, previous) << "n = " << n;
        previous = error;

        const TriangleMesh sheared = make_grid(n, n, 1.0, 1.0, 1.7);
        Eigen::VectorXd sheared_exact(mesh.num_vertices());
        for (int v = 0; v < mesh.num_vertices(); ++v)
            sheared_exact[v] = (sheared.V.row(v) - sheared.V.row(source)).norm();
        const Triangulation idt = intrinsic_delaunay(Triangulation::from_mesh(sheared)).triangulation;
        EXPECT_LT(mean_relative_error(heat_geodesic_distance(idt, {source}), sheared_exact), 2 * error) << "n = " << n;
    }
}

TEST(Geodesics, MeshWithoutInteriorVertexUsesTheNeumannSolutionAlone) {
    // A single equilateral triangle: the heat method's one unit direction (away from the source,
    // across the face) integrates to the height √3/2 at both other corners.
    const TriangleMesh triangle = test::make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(0.75), 0}}, {{0, 1, 2}});
    const HeatGeodesics geodesics(Triangulation::from_mesh(triangle));
    EXPECT_EQ(geodesics.report().boundary_vertices, 0);
    const Eigen::VectorXd d = geodesics.distance({0});
    EXPECT_EQ(d[0], 0);
    EXPECT_NEAR(d[1], std::sqrt(0.75), 1e-12);
    EXPECT_NEAR(d[2], std::sqrt(0.75), 1e-12);
}

TEST(Geodesics, ComponentsWithoutASourceAreInfinitelyFar) {
    const TriangleMesh a = make_icosphere(2);
    TriangleMesh both;
    both.V.resize(2 * a.V.rows(), 3);
    both.V << a.V, a.V.rowwise() + Eigen::RowVector3d(3, 0, 0);
    both.F.resize(2 * a.F.rows(), 3);
    both.F << a.F, (a.F.array() + static_cast<int>(a.V.rows())).matrix();
    const Eigen::VectorXd d = heat_geodesic_distance(Triangulation::from_mesh(both), {0});
    const Eigen::VectorXd alone = heat_geodesic_distance(Triangulation::from_mesh(a), {0});
    EXPECT_LT((d.head(a.V.rows()) - alone).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_TRUE(d.tail(a.V.rows()).array().isInf().all());
}

TEST(Geodesics, ArgumentsAreChecked) {
    const Triangulation t = Triangulation::from_mesh(make_icosphere(1));
    EXPECT_THROW((void)heat_geodesic_distance(t, {}), InvalidArgumentError);
    EXPECT_THROW((void)heat_geodesic_distance(t, {42}), InvalidArgumentError);
    EXPECT_THROW((void)heat_geodesic_distance(t, {0}, {.time = -1.0}), InvalidArgumentError);
}

// ---- the CLI ---------------------------------------------------------------------------------------

using Cli = test::CliTest;

// The field `name` of a binary PLY written with x, y, z and that field as doubles per vertex.
Eigen::VectorXd read_vertex_field(const std::string& ply, const std::string& name, int vertices) {
    const std::string end = "end_header\n";
    const size_t body = ply.find(end) + end.size();
    EXPECT_NE(ply.find("property double " + name + "\n"), std::string::npos) << name;
    Eigen::VectorXd distance(vertices);
    for (int v = 0; v < vertices; ++v)
        std::memcpy(&distance[v], ply.data() + body + (4 * static_cast<size_t>(v) + 3) * sizeof(double), sizeof(double));
    return distance;
}

TEST_F(Cli, GeodesicWritesTheLibrarysDistance) {
    write_mesh(dir_ / "sphere.off", make_icosphere(3));
    const Triangulation t = Triangulation::from_mesh(read_mesh(dir_ / "sphere.off"));
    for (const char* choice : {"", " --intrinsic"}) {  // the icosphere is its own iDT
        ASSERT_EQ(run("geodesic " + (dir_ / "sphere.off").string() + " --source 0,7 --out " +
                      (dir_ / "d.ply").string() + choice),
                  0)
            << read(dir_ / "err.txt");
        EXPECT_EQ(read_vertex_field(read(dir_ / "d.ply"), "distance", t.num_vertices), heat_geodesic_distance(t, {0, 7}))
            << choice;
        const std::string report = read(dir_ / "out.txt");
        for (const char* key : {"\"sources\": 2", "\"time\": ", "\"precompute_seconds\": ", "\"query_seconds\": "})
            EXPECT_NE(report.find(key), std::string::npos) << key << "\n" << report;
    }
}

TEST_F(Cli, GeodesicRejectsBadArguments) {
    write_mesh(dir_ / "sphere.off", make_icosphere(0));
    const std::string mesh = (dir_ / "sphere.off").string(), out = " --out " + (dir_ / "d.ply").string();
    EXPECT_EQ(run("geodesic " + mesh + out), 2);                           // no source
    EXPECT_EQ(run("geodesic " + mesh + " --source 1"), 2);                 // no output
    EXPECT_EQ(run("geodesic " + mesh + " --source 1,x" + out), 2);
    EXPECT_EQ(run("geodesic " + mesh + " --source -1" + out), 2);
    EXPECT_EQ(run("geodesic " + mesh + " --source 12" + out), 7);          // out of range
    EXPECT_NE(read(dir_ / "err.txt").find("geodesic: --source: vertex 12 is out of range [0, 12) of " + mesh),
              std::string::npos)
        << read(dir_ / "err.txt");
    EXPECT_EQ(run("geodesic " + mesh + " --source 1 --time 0" + out), 7);
    EXPECT_FALSE(std::filesystem::exists(dir_ / "d.ply"));
}

TEST_F(Cli, SolverCommandsNameAVertexInNoFace) {
    TriangleMesh mesh = make_icosphere(0);
    mesh.V.conservativeResize(mesh.V.rows() + 1, 3);
    mesh.V.row(12) << 2, 2, 2;
    write_mesh(dir_ / "loose.off", mesh);
    std::ofstream f(dir_ / "f.txt");
    for (int v = 0; v < 13; ++v) f << "1\n";
    f.close();
    const std::string file = (dir_ / "loose.off").string();
    for (const std::string& command :
         {"eigs " + file + " -k 2 --out " + (dir_ / "e").string(),
          "geodesic " + file + " --source 0 --out " + (dir_ / "d.ply").string(),
          "heat " + file + " --source 0 --time 0.1 --out " + (dir_ / "h.ply").string(),
          "poisson " + file + " --f " + (dir_ / "f.txt").string() + " --out " + (dir_ / "p.ply").string()}) {
        EXPECT_EQ(run(command), 6) << command;
        const std::string error = read(dir_ / "err.txt");
        EXPECT_NE(error.find(file + ": vertex 12 is in no face"), std::string::npos) << error;
    }
    for (const char* output : {"d.ply", "h.ply", "p.ply"}) EXPECT_FALSE(std::filesystem::exists(dir_ / output));
}

TEST_F(Cli, PoissonAndHeatWriteTheLibrarysSolutions) {
    const TriangleMesh mesh = make_icosphere(3);
    write_mesh(dir_ / "sphere.off", mesh);
    const Triangulation t = Triangulation::from_mesh(read_mesh(dir_ / "sphere.off"));
    const Sparse L = cotan_laplacian(t), M = mass_matrix(t);
    const Eigen::VectorXd f = 2.0 * mesh.V.col(2);
    {
        std::ofstream file(dir_ / "f.txt");
        file.precision(17);
        for (double value : f) file << value << '\n';
        std::ofstream dirichlet(dir_ / "dirichlet.txt");
        dirichlet << "# vertex value\n3 0.25\n7 -1.5\n";
    }
    const std::string sphere = (dir_ / "sphere.off").string(), out = " --out " + (dir_ / "u.ply").string();
    ASSERT_EQ(run("poisson " + sphere + " --f " + (dir_ / "f.txt").string() + " --dirichlet " +
                  (dir_ / "dirichlet.txt").string() + out),
              0)
        << read(dir_ / "err.txt");
    const Eigen::VectorXd u = read_vertex_field(read(dir_ / "u.ply"), "u", t.num_vertices);
    EXPECT_EQ(u, PoissonSolver(L, M, {3, 7}).solve(M * f, Eigen::Vector2d(0.25, -1.5)));
    EXPECT_EQ(u[3], 0.25);
    EXPECT_EQ(u[7], -1.5);

    ASSERT_EQ(run("heat " + sphere + " --source 0,4 --time 0.1 --steps 2" + out), 0) << read(dir_ / "err.txt");
    Eigen::VectorXd u0 = Eigen::VectorXd::Zero(t.num_vertices);
    u0[0] = u0[4] = 1;
    EXPECT_EQ(read_vertex_field(read(dir_ / "u.ply"), "u", t.num_vertices), HeatSolver(L, M, 0.1).step(u0, 2));

    {
        std::ofstream short_file(dir_ / "short.txt");
        short_file << "1\n2\n";
        std::ofstream bad(dir_ / "bad.txt");
        bad << "9999 1\n";
    }
    EXPECT_EQ(run("poisson " + sphere + " --f " + (dir_ / "short.txt").string() + out), 5);
    EXPECT_EQ(run("poisson " + sphere + " --f " + (dir_ / "f.txt").string() + " --dirichlet " +
                  (dir_ / "bad.txt").string() + out),
              7);
    EXPECT_EQ(run("poisson " + sphere + out), 2);  // no --f
    EXPECT_EQ(run("heat " + sphere + " --source 0 --time 0" + out), 7);
    EXPECT_EQ(run("heat " + sphere + " --source 0 --u0 " + (dir_ / "f.txt").string() + " --time 1" + out), 2);
}

TEST_F(Cli, ValueFilesTakeEveryFiniteDoubleAndRejectWhatUnderflows) {
    write_mesh(dir_ / "sphere.off", make_icosphere(1));
    const int n = static_cast<int>(make_icosphere(1).V.rows());
    {
        std::ofstream f(dir_ / "f.txt");
        for (int v = 0; v < n; ++v) f << (v % 2 ? "+1e-300\n" : "-2.5\n");
        std::ofstream dirichlet(dir_ / "dirichlet.txt");
        dirichlet << "3 3.56e-313\n";  // subnormal
        std::ofstream underflow(dir_ / "underflow.txt");
        underflow << "3 1e-400\n";
    }
    const std::string sphere = (dir_ / "sphere.off").string(), out = " --out " + (dir_ / "u.ply").string();
    const std::string f = " --f " + (dir_ / "f.txt").string();
    ASSERT_EQ(run("poisson " + sphere + f + " --dirichlet " + (dir_ / "dirichlet.txt").string() + out), 0)
        << read(dir_ / "err.txt");
    EXPECT_EQ(read_vertex_field(read(dir_ / "u.ply"), "u", n)[3], 3.56e-313);
    EXPECT_EQ(run("poisson " + sphere + f + " --dirichlet " + (dir_ / "underflow.txt").string() + out), 5);
    EXPECT_NE(read(dir_ / "err.txt").find("'1e-400' is out of double range"), std::string::npos) << read(dir_ / "err.txt");
    // from_chars reads "nan" and "inf": refused by name, not solved into a NaN field.
    for (const char* value : {"nan", "-inf", "1.5x"}) {
        std::ofstream(dir_ / "bad.txt") << "3 " << value << "\n";
        EXPECT_EQ(run("poisson " + sphere + f + " --dirichlet " + (dir_ / "bad.txt").string() + out), 5) << value;
        EXPECT_NE(read(dir_ / "err.txt").find("bad.txt:1: '" + std::string(value) + "' is not"), std::string::npos)
            << read(dir_ / "err.txt");
    }
    // Control bytes (here a terminal's colour escape) are not echoed to the terminal.
    std::ofstream(dir_ / "bad.txt") << "3 \x1b[31m\n";
    EXPECT_EQ(run("poisson " + sphere + f + " --dirichlet " + (dir_ / "bad.txt").string() + out), 5);
    EXPECT_NE(read(dir_ / "err.txt").find("bad.txt:1: '?[31m' is not a number\n"), std::string::npos)
        << read(dir_ / "err.txt");
}

}  // namespace
}  // namespace sdmesh
