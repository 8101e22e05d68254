#pragma once
// Sparse Cholesky factorization of a symmetric positive definite matrix (CHOLMOD, supernodal,
// fill-reducing ordering), kept for repeated solves. The symbolic analysis depends only on the
// sparsity pattern, so matrices that share a pattern (M + tL for several t) are refactorized
// without analysing again. CHOLMOD stays behind this header (target sdmesh::solvers).
//
//   sdmesh::CholeskySolver solver(A);          // analyse + factorize
//   Eigen::VectorXd x = solver.solve(b);       // A x = b
//   solver.factorize(A2);                      // same pattern, new values

#include <memory>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace sdmesh {

class CholeskySolver {
public:
    CholeskySolver();
    /// analyze(A) then factorize(A).
    explicit CholeskySolver(const Eigen::SparseMatrix<double>& A);
    ~CholeskySolver();
    CholeskySolver(CholeskySolver&&) noexcept;
    CholeskySolver& operator=(CholeskySolver&&) noexcept;

    /// Symbolic analysis of the pattern of A (square, symmetric; only its lower triangle is read).
    /// \throws InvalidArgumentError A is not square.
    void analyze(const Eigen::SparseMatrix<double>& A);

    /// Numeric factorization of A, whose pattern must be the analysed one.
    /// \throws InvalidArgumentError nothing analysed yet, or a different size or pattern size.
    /// \throws NumericalError A is not positive definite (the message names the failing column).
    void factorize(const Eigen::SparseMatrix<double>& A);

    /// Solves A x = b.
    /// \throws InvalidArgumentError no factorization yet, or b has the wrong number of rows.
    [[nodiscard]] Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

    /// Solves A X = B for all columns of B at once; throws as solve().
    [[nodiscard]] Eigen::MatrixXd solve_columns(const Eigen::MatrixXd& B) const;

    [[nodiscard]] int rows() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace sdmesh
