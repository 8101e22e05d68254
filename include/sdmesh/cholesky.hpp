#pragma once
// Sparse Cholesky factorization of a symmetric positive definite matrix (supernodal, with a
// fill-reducing ordering and symbolic analysis from CHOLMOD), kept for repeated solves. The symbolic analysis depends only on the
// sparsity pattern, so matrices that share a pattern (M + tL for several t) are refactorized
// without analysing again. CHOLMOD stays behind this header (target sdmesh::solvers).
//
//   sdmesh::CholeskySolver solver(A);          // analyse + factorize
//   Eigen::VectorXd x = solver.solve(b);       // A x = b
//   solver.factorize(A2);                      // same pattern, new values
//   sdmesh::CholeskySolver other(A3, {.same_ordering_as = &solver});  // no new ordering

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace sdmesh {

class CholeskySolver;

/// The fill-reducing ordering computed by analyze().
enum class CholeskyOrdering {
    automatic,          ///< AMD, then also METIS when AMD's fill is high; the one with less fill
    amd,                ///< approximate minimum degree: fastest to compute, most fill on meshes
    metis,              ///< METIS nested dissection: little fill on meshes, slower to compute
    nested_dissection,  ///< CHOLMOD's nested dissection (METIS + constrained AMD): a little less fill, slower
    /// CHOLMOD's nested dissection stopped at parts of 20,000 vertices (its own "method 5"): on a
    /// 500k-vertex mesh ~40 % faster to compute than METIS for ~20 % more fill.
    coarse_nested_dissection,
};

struct CholeskyOptions {
    /// Ordering to compute (default automatic). On a mesh of 500k vertices AMD takes ~1 s and
    /// METIS ~3.5 s but leaves a factor with ~4x fewer flops, so automatic pays for both; for a
    /// single factorization of a large mesh coarse_nested_dissection is the cheapest in total.
    CholeskyOrdering ordering = CholeskyOrdering::automatic;
    /// An analysed solver whose ordering is reused instead of computing one (default none;
    /// `ordering` is then ignored). Meant for matrices with the same pattern (M + tL and L),
    /// which then get the same symbolic factor; only read during analyze().
    const CholeskySolver* same_ordering_as = nullptr;
};

class CholeskySolver {
public:
    CholeskySolver();
    /// analyze(A, options) then factorize(A).
    explicit CholeskySolver(const Eigen::SparseMatrix<double>& A, const CholeskyOptions& options = {});
    ~CholeskySolver();
    CholeskySolver(CholeskySolver&&) noexcept;
    CholeskySolver& operator=(CholeskySolver&&) noexcept;

    /// Symbolic analysis of the pattern of A (square, symmetric; only its lower triangle is read).
    /// \throws InvalidArgumentError A is not square; options.same_ordering_as is not analysed
    ///         or of another size.
    /// \throws NumericalError the analysis fails (e.g. METIS asked for but not in CHOLMOD).
    void analyze(const Eigen::SparseMatrix<double>& A, const CholeskyOptions& options = {});

    /// Numeric factorization of A, whose pattern must be the analysed one. Large factors are
    /// computed on two OpenMP threads (unless OMP_NUM_THREADS=1), the same for any thread count.
    /// \throws InvalidArgumentError nothing analysed yet, or a different size or pattern.
    /// \throws NumericalError A is not positive definite (the message names the failing column).
    void factorize(const Eigen::SparseMatrix<double>& A);

    /// Solves A x = b.
    /// \throws InvalidArgumentError no factorization yet, or b has the wrong number of rows.
    [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

    /// Solves A X = B for all columns of B at once, four per pass over the factor (on a 500k-vertex
    /// mesh four columns take 1.4× the time of one); throws as solve(). Large factors are solved on
    /// two OpenMP threads (unless OMP_NUM_THREADS=1), with results independent of the thread count.
    [[nodiscard]] Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& B) const;

    [[nodiscard]] int rows() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace sdmesh
