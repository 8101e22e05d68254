#pragma once
// Private to sdmesh::solvers: block Lanczos for the largest eigenvalues θ of the shift-invert
// operator S = K⁻¹M (K = L − σM), which is self-adjoint in the M inner product; θ = 1 / (λ − σ).
//
// Why not only Spectra's single-vector Lanczos (EigenSolver::spectra_lanczos): its full
// reorthogonalization reads the whole basis three to five times per solve, matrix-vector products
// bound by memory bandwidth that took 50–58 % of its time on nefertiti and igea, and each solve
// reads the whole Cholesky factor for one column. A block of b columns pays each basis pass and
// each factor read once for b columns (BLAS-3), and finds up to b equal eigenvalues at once.
// The basis is never restarted: it grows until the wanted pairs converge or max_columns is full.
// The margin pairs are there to make clusters of equal eigenvalues at the end of the wanted
// range come out whole; they are not returned, so a looser tolerance suffices for them.
// b = 4 was fastest on nefertiti (k = 50): 1.2 s against 1.3 s for b = 2 and 1.6 s for b = 8,
// which needs more solves (272 against 208).

#include <functional>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace sdmesh {
class CholeskySolver;
}

namespace sdmesh::detail {

struct BlockLanczosOptions {
    int wanted = 10;           ///< eigenpairs returned, which must converge to `tolerance`
    int margin = 10;           ///< further pairs that must converge, to kMarginTolerance · tolerance
    int block_size = 4;        ///< columns per block (capped at n / 3)
    int max_columns = 0;       ///< basis size limit (multiple of block_size after capping at n)
    double tolerance = 1e-10;  ///< Ritz residual relative to θ, as Spectra's tol
    bool progress = false;     ///< a line on stderr about every second (at convergence tests)
    /// Known eigenvectors to leave out (constant_modes.hpp): removes from the columns given their
    /// parts along them, M-orthogonally. Applied to the start block, to each block of solves
    /// and to fresh random directions, so that the basis stays in their complement. Empty: none.
    std::function<void(Eigen::Ref<Eigen::MatrixXd>)> deflate = {};
};

struct BlockLanczosResult {
    Eigen::VectorXd ritz_values;   ///< the `wanted` largest θ, descending (λ = σ + 1/θ ascending)
    Eigen::MatrixXd ritz_vectors;  ///< n x wanted, M-orthonormal, for ritz_values; the last
                                   ///< basis's best if not converged
    int steps = 0;                 ///< block steps
    int solves = 0;                ///< columns solved with K
    bool converged = false;
};

/// The basis's block size and capacity (columns) for n unknowns, and the columns it is expected
/// to reach: the basis grew to 3.3 (nefertiti k = 50, igea k = 50) and 2.8 (koala k = 100) columns
/// per tested pair (wanted + margin).
struct BasisShape {
    Eigen::Index block = 0, capacity = 0, expected = 0;
};
inline constexpr Eigen::Index kExpectedColumnsPerPair = 3;
[[nodiscard]] BasisShape basis_shape(Eigen::Index n, const BlockLanczosOptions& options);

/// K is the factor of L − σM, M the (sparse, SPD) mass matrix. `basis`: storage for the basis,
/// n x basis_shape().capacity, whose expected columns a caller may have mapped (prefault) on
/// another thread while K was analysed, so that the page faults leave the critical path; other
/// sizes are replaced.
BlockLanczosResult block_lanczos(const CholeskySolver& K, const Eigen::SparseMatrix<double>& M,
                                 const BlockLanczosOptions& options, Eigen::MatrixXd basis = {});

}  // namespace sdmesh::detail
