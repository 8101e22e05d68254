#pragma once
// Poisson and heat solves with the cotan Laplacian, and geodesic distance by the heat method.
// Each solver factors its matrix once (CHOLMOD, behind sdmesh::solvers) and then solves any
// number of right-hand sides.
//
// Conventions: L is the positive semidefinite cotan Laplacian and M a mass matrix, both n x n
// (operators.hpp, both triangles stored), so L u = M f is the weak form of −Δu = f.
// Dirichlet vertices carry prescribed values; everywhere else the boundary condition is the
// natural (Neumann) one. A connected component of the mesh (of L's pattern) without a Dirichlet
// vertex determines u only up to a constant: there the right-hand side is made compatible by
// removing its component-wise mean, and the solution is the one with zero M-mean on the component.
// Dirichlet rows and columns are replaced by the identity's rather than removed, so every matrix
// keeps the pattern of L (plus M) and the solvers of one mesh can share a fill-reducing ordering
// (CholeskyOptions::same_ordering_as).
//
//   sdmesh::PoissonSolver poisson(L, M, boundary);          // factor once
//   Eigen::VectorXd u = poisson.solve(M * f, boundary_values);
//
//   sdmesh::HeatGeodesics geodesics(t);                     // t: a Triangulation
//   Eigen::VectorXd d = geodesics.distance({source});

#include <chrono>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "sdmesh/cholesky.hpp"
#include "sdmesh/operators.hpp"
#include "sdmesh/triangulation.hpp"

namespace sdmesh {

/// Solves L u = b with u = g on the Dirichlet vertices (for −Δu = f pass b = M f).
class PoissonSolver {
public:
    /// Factors L with the Dirichlet vertices (plus one pinned vertex per component without a
    /// Dirichlet vertex) fixed, with the given ordering options.
    /// \throws InvalidArgumentError L, M not square, of different sizes, not symmetric or not
    ///         finite; a Dirichlet vertex out of range or repeated; as CholeskySolver::analyze for
    ///         the options.
    /// \throws NumericalError L on the free vertices is not positive definite (L not positive
    ///         semidefinite; the cotan Laplacian always is); M has no positive entry (no area).
    PoissonSolver(const Eigen::SparseMatrix<double>& L, const Eigen::SparseMatrix<double>& M,
                  const std::vector<int>& dirichlet_vertices = {}, const CholeskyOptions& cholesky = {});

    /// u (n) with L u = b on the free vertices and u = dirichlet_values exactly (in the order of
    /// the constructor's vertices; empty means all 0) on the Dirichlet ones. On a component without
    /// Dirichlet vertices b is first replaced by its compatible part b − (Σ_c b)·M1/(1ᵀM1), and u
    /// has zero M-mean there.
    /// \throws InvalidArgumentError b or dirichlet_values of the wrong size.
    [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& b, const Eigen::VectorXd& dirichlet_values = {}) const;

    /// The factorization of L with its Dirichlet rows and columns replaced by the identity's.
    [[nodiscard]] const CholeskySolver& factorization() const { return solver_; }

private:
    std::vector<int> fixed_;                 // Dirichlet vertices, then the pinned ones
    Eigen::SparseMatrix<double> coupling_;   // L(:, fixed_)
    std::vector<int> component_;             // per vertex
    std::vector<char> neumann_component_;                      // no Dirichlet vertex in it
    Eigen::VectorXd lumped_mass_;                              // M·1
    Eigen::VectorXd component_area_;                           // 1ᵀM1 per component
    int dirichlet_count_ = 0;
    CholeskySolver solver_;
};

/// Backward Euler for the heat equation u' = Δu: (M + tL) u_{k+1} = M u_k, with u = 0 on the
/// Dirichlet vertices (Neumann elsewhere). On a component without Dirichlet vertices where tL
/// swamps M to rounding (one far smaller than √t, e.g. 1e-6 of the mesh beside it), M + tL is
/// singular within rounding; there one vertex is pinned, and the step is exact up to about M's
/// share of M + tL (below 1e-8) and conserves the component's heat 1ᵀMu.
class HeatSolver {
public:
    /// \throws InvalidArgumentError sizes as PoissonSolver; time step t <= 0 or not finite; as
    ///         CholeskySolver::analyze for the options.
    /// \throws NumericalError a vertex that is not a Dirichlet vertex has M(v, v) = L(v, v) = 0 (a
    ///         vertex in no face; the message names it); M + tL is not positive definite.
    HeatSolver(const Eigen::SparseMatrix<double>& L, const Eigen::SparseMatrix<double>& M, double t,
               const std::vector<int>& dirichlet_vertices = {}, const CholeskyOptions& cholesky = {});

    /// Refactors for another time step (same pattern, no new analysis).
    void set_time_step(double t);

    /// u after `steps` steps from u0 (values of u0 on Dirichlet vertices are ignored; u is exactly
    /// 0 there).
    /// \throws InvalidArgumentError u0 of the wrong size, steps < 0.
    [[nodiscard]] Eigen::VectorXd step(const Eigen::VectorXd& u0, int steps = 1) const;

    /// The factorization of M + tL with its pinned rows and columns (Dirichlet vertices, one per
    /// component where tL swamps M) replaced by the identity's; e.g. the same_ordering_as of
    /// other solvers on the mesh.
    [[nodiscard]] const CholeskySolver& factorization() const { return solver_; }

private:
    // M + tL with the Dirichlet vertices pinned, and the lowest vertex of each component without
    // one on which tL swamps M to rounding (a component far smaller than the mesh): there the
    // matrix is singular within rounding, while the step only smooths to the component's mean.
    // Sets pinned_ and the diffused components.
    Eigen::SparseMatrix<double> pinned_matrix(double t);
    // A diffused component's solve is exact up to a constant, set by the heat the step conserves
    // (1ᵀMu = 1ᵀb, as 1ᵀL = 0).
    void restore_conserved_heat(const Eigen::VectorXd& b, Eigen::VectorXd& u) const;

    Eigen::SparseMatrix<double> L_, M_;
    std::vector<int> fixed_;         // Dirichlet vertices
    std::vector<int> pinned_;        // fixed_, then one vertex per diffused component
    std::vector<int> diffused_of_;   // per vertex: its diffused component, or -1 (empty: none)
    Eigen::VectorXd diffused_mass_;  // per diffused component: 1ᵀM1
    CholeskySolver solver_;
};

struct GeodesicOptions {
    /// Heat time t; NaN (default) means h², h the mean edge length (Crane et al. 2013, m = 1) of
    /// each connected component on its own.
    double time = std::numeric_limits<double>::quiet_NaN();
    /// Mass matrix of the heat step.
    MassType mass = MassType::barycentric;
    /// On a mesh with boundary, diffuse heat as the mean of the Neumann and the (zero) Dirichlet
    /// solutions, as Crane et al. recommend; false: Neumann only. Without an interior vertex the
    /// Dirichlet solution is 0 everywhere, so such a mesh gets the Neumann solution alone.
    bool average_boundary_conditions = true;
};

struct GeodesicReport {
    double time = 0;               ///< the heat time t used (of the component with the most vertices)
    int boundary_vertices = 0;     ///< Dirichlet vertices of the second heat solve (0 without one)
    double precompute_seconds = 0; ///< operators and factorizations
};

/// Geodesic distance by the heat method (Crane, Weischedel, Wardetzky 2013) on a Triangulation,
/// hence on extrinsic meshes, converted self-Delaunay meshes and intrinsic triangulations alike:
/// heat u from the sources for time t, X = −∇u/|∇u| per face, then L φ = −div X (Neumann), and φ
/// shifted so that its mean over the sources of each component is 0. Factorizations are kept,
/// so each further query costs three back-substitutions. They share one coarse nested
/// dissection ordering of L's pattern and run concurrently on the OpenMP threads.
class HeatGeodesics {
public:
    /// \throws InvalidMeshError as the operators; InvalidArgumentError options.time <= 0;
    ///         NumericalError a factorization fails (a mass matrix that is not positive
    ///         definite, e.g. circumcentric on a mesh that is not self-Delaunay).
    explicit HeatGeodesics(const Triangulation& t, const GeodesicOptions& options = {});

    /// Distance (n) from the nearest of the sources; +inf on components without a source.
    /// \throws InvalidArgumentError no source, or a source out of range.
    [[nodiscard]] Eigen::VectorXd distance(const std::vector<int>& sources) const;

    [[nodiscard]] const GeodesicReport& report() const { return report_; }

private:
    // The work is done on the triangulation with its lengths divided by 2^length_exponent, a unit
    // mean edge (a copy, only when the mean is far from 1): the gradients hold cubes of lengths,
    // which overflow (underflow) from lengths of about 1e100 (1e-100) on. Distances are
    // multiplied back.
    struct UnitLengths {
        const Triangulation& input;
        std::optional<Triangulation> scaled;  // only far from a unit length (far_unit_exponent)
        int length_exponent = 0;
        [[nodiscard]] const Triangulation& t() const { return scaled ? *scaled : input; }
    };
    static UnitLengths unit_lengths(const Triangulation& t);
    HeatGeodesics(const UnitLengths& unit, const GeodesicOptions& options, std::chrono::steady_clock::time_point start);
    HeatGeodesics(const UnitLengths& unit, const GeodesicOptions& options, std::chrono::steady_clock::time_point start,
                  const Eigen::SparseMatrix<double>& L, const Eigen::SparseMatrix<double>& M);

    struct Factorizations {
        HeatSolver neumann_heat;
        std::optional<HeatSolver> dirichlet_heat;  // with boundary and averaging only
        PoissonSolver poisson;
        int dirichlet_vertices = 0;  // of dirichlet_heat
    };
    // Heat with timed_L, (T / time) L for the components' times T; Poisson with L.
    static Factorizations factorize(const Triangulation& t, const GeodesicOptions& options,
                                    const Eigen::SparseMatrix<double>& L, const Eigen::SparseMatrix<double>& timed_L,
                                    const Eigen::SparseMatrix<double>& M, double time);

    int num_vertices_ = 0;
    int length_exponent_ = 0;
    Eigen::SparseMatrix<double> divergence_;  // −Gᵀ·area: its transpose is −area·∇ per face
    int component_count_ = 0;
    std::vector<int> component_;
    Eigen::VectorXd component_time_;  // heat time per component, in unit lengths
    double time_ = 0;                 // the largest component's
    Factorizations solvers_;
    GeodesicReport report_;
};

/// One-call form: HeatGeodesics(t, options).distance(sources).
Eigen::VectorXd heat_geodesic_distance(const Triangulation& t, const std::vector<int>& sources,
                                       const GeodesicOptions& options = {});

}  // namespace sdmesh
