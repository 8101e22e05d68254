#pragma once
// The k smallest eigenpairs of the generalized problem L φ = λ M φ (L symmetric positive
// semidefinite, M symmetric positive definite, both n x n): shift-invert Lanczos on a sparse
// Cholesky factor of L − σM with a negative shift σ, so L − σM is positive definite even though
// L is singular. Two Lanczos variants: block Lanczos (default: blocks of 4 solves, BLAS-3
// orthogonalization) and Spectra's restarted single-vector Lanczos. A mesh gets one zero
// eigenvalue per connected component, with the component's constant function: these pairs are
// known (where L's rows sum to zero), returned first, normalised, in the order of the components'
// lowest vertices, and Lanczos seeks only the others, in their M-orthogonal complement.
// Spectra and CHOLMOD stay behind this header (target sdmesh::solvers).
//
//   const auto t = sdmesh::Triangulation::from_mesh(sdmesh::read_mesh("bunny.obj"));
//   const sdmesh::EigenResult r = sdmesh::smallest_eigenpairs(
//       sdmesh::cotan_laplacian(t), sdmesh::mass_matrix(t), {.k = 50});
//   if (r.report.status != sdmesh::EigenStatus::converged) ...  // r.values holds what converged

#include <limits>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace sdmesh {

enum class EigenSolver {
    /// Block Lanczos in the M inner product, blocks of 4 columns, basis not restarted (its size
    /// is basis_size) and a margin of max(10, k/5) extra pairs (converged to 100 × tolerance,
    /// not returned). 8–12× faster than Spectra's on meshes of 50k vertices (nefertiti k = 50:
    /// 0.30 against 2.37 s; koala k = 100: 0.64 against 7.7 s), with the same results on any
    /// thread count.
    block_lanczos,
    /// Spectra's implicitly restarted single-vector Lanczos (SymGEigsShiftSolver).
    spectra_lanczos,
};

struct EigenOptions {
    /// Number of eigenpairs wanted, 1 <= k < n (n: the free vertices, see dirichlet_vertices).
    int k = 10;
    /// Shift σ < 0 of the shift-invert transform; NaN (default) picks σ = −median_i(L_ii) /
    /// trace(M), minus the median cotan weight sum over the area. It is invariant under
    /// refinement and scales like 1/area, as the low eigenvalues do, and sits an order of
    /// magnitude below the first non-zero one on compact surfaces; slivers, whose weight sums
    /// can be 10⁶ times the others, do not move it as they moved the mean. Where slivers are
    /// most of the faces (CAD meshes), the median can still put it far below the spectrum; when
    /// block Lanczos then fills its basis unconverged, it runs once more from a tenth of its
    /// smallest Ritz value below 0 (the report gives that shift, and both runs' solves).
    double sigma = std::numeric_limits<double>::quiet_NaN();
    EigenSolver solver = EigenSolver::block_lanczos;
    /// Relative tolerance of the Lanczos Ritz values: residual ≤ tolerance · |θ| with
    /// θ = 1 / (λ − σ) (Spectra's tol).
    double tolerance = 1e-10;
    /// Maximum number of Lanczos restarts (spectra_lanczos only).
    int max_iterations = 1000;
    /// Lanczos basis size; 0 (default) picks, with p = k plus the margin of extra pairs
    /// (max(10, k/2) for spectra_lanczos, max(10, k/5) for block_lanczos), max(2p + 1, 20) for
    /// spectra_lanczos and max(6p, 160) for block_lanczos, capped at n. Block Lanczos stores
    /// its basis (n x basis_size doubles at most) and reports not_converged when it is full.
    int basis_size = 0;
    /// Vertices where φ = 0 (homogeneous Dirichlet condition): the problem is solved on the rows
    /// and columns of the other vertices and the eigenvectors are 0 here. Empty: natural
    /// (Neumann) boundary.
    std::vector<int> dirichlet_vertices = {};
    /// Print progress lines to stderr: when the factorization starts and ends, and (block
    /// Lanczos) about every second, the solves so far and the pairs converged.
    bool progress = false;
};

enum class EigenStatus {
    converged,      ///< all k pairs met the tolerance
    /// max_iterations (spectra_lanczos) or the basis size (block_lanczos) reached first; the
    /// result holds the pairs that converged (spectra_lanczos) or the best approximations.
    not_converged,
};

/// "converged" / "not_converged", as in report.json.
std::string_view to_string(EigenStatus status);
/// "block" / "spectra", as in report.json and `sdmesh eigs --solver`.
std::string_view to_string(EigenSolver solver);

struct EigenReport {
    EigenStatus status = EigenStatus::converged;
    EigenSolver solver = EigenSolver::block_lanczos;  ///< the Lanczos variant that ran
    int iterations = 0;        ///< Lanczos restarts (spectra_lanczos) or block steps (block_lanczos)
    int solves = 0;            ///< applications of (L − σM)⁻¹, the dominant cost
    double sigma = 0;          ///< the shift used
    /// max over pairs of ‖Lφ − λMφ‖ / (max(|λ|, |σ|) · ‖Mφ‖); for λ = 0 exactly (the constant
    /// functions of components), ‖Lφ‖ / ‖|L||φ|‖: the row sums' rounding against their terms
    double max_residual = 0;
    double max_orthogonality_error = 0;  ///< max |ΦᵀMΦ − I| entry
    double seconds = 0;        ///< wall time, factorization included
};

struct EigenResult {
    /// Eigenvalues, ascending (k of them, fewer if not converged).
    Eigen::VectorXd values;
    /// n x k eigenvectors, column j for values[j], M-orthonormal: ΦᵀMΦ = I.
    Eigen::MatrixXd vectors;
    EigenReport report;
};

/// The k smallest eigenpairs of L φ = λ M φ; L and M store both triangles, as operators.hpp
/// returns them.
/// With spectra_lanczos, a final Rayleigh–Ritz step on the Ritz vectors makes them M-orthonormal
/// to rounding; block_lanczos keeps its basis M-orthonormal to ~1e-12 throughout (it corrects
/// the loss of orthogonality every other step; report.max_orthogonality_error gives ΦᵀMΦ − I).
/// \throws InvalidArgumentError L, M not square, of different sizes, not symmetric or not
///         finite; k < 1 or k >= n; σ >= 0; a Dirichlet vertex out of range or repeated;
///         tolerance <= 0; max_iterations < 1; a basis size other than 0 outside (k, n].
/// \throws NumericalError L − σM is not positive definite (M not positive definite, L not
///         positive semidefinite).
EigenResult smallest_eigenpairs(const Eigen::SparseMatrix<double>& L, const Eigen::SparseMatrix<double>& M,
                                const EigenOptions& options = {});

}  // namespace sdmesh
