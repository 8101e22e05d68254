#pragma once
// Private to sdmesh::solvers: products with a mass matrix M. A lumped (diagonal) M, the default
// mass, scales rows: Eigen's sparse product took 0.35 ms for an n x 4 block on nefertiti, and a
// block Lanczos step makes four or five of them (nefertiti k = 50: 0.41 → 0.37 s in all).

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "symmetric_product.hpp"

namespace sdmesh::detail {

// M is symmetric and stored whole (both triangles).
class MassProduct {
public:
    static constexpr Eigen::Index kParallelRows = 1 << 14;

    explicit MassProduct(const Eigen::SparseMatrix<double>& M) : M_(M) {
        bool diagonal = M.isCompressed() && M.nonZeros() == M.rows();
        for (Eigen::Index j = 0; diagonal && j < M.outerSize(); ++j)
            diagonal = M.outerIndexPtr()[j + 1] == j + 1 && M.innerIndexPtr()[j] == j;
        if (diagonal) diagonal_ = M.diagonal();
    }

    /// out = M X (out must not overlap X).
    void apply(const Eigen::Ref<const Eigen::MatrixXd>& X, Eigen::Ref<Eigen::MatrixXd> out) const {
        if (diagonal_.size() == 0) {
            symmetric_product(M_, X, out);
            return;
        }
        // Columns on two threads for tall blocks (elementwise: the same result on any number).
#pragma omp parallel for num_threads(2) schedule(static) if (X.rows() >= kParallelRows)
        for (Eigen::Index j = 0; j < X.cols(); ++j) out.col(j) = diagonal_.cwiseProduct(X.col(j));
    }
    [[nodiscard]] Eigen::MatrixXd operator()(const Eigen::Ref<const Eigen::MatrixXd>& X) const {
        Eigen::MatrixXd MX(X.rows(), X.cols());
        apply(X, MX);
        return MX;
    }

private:
    const Eigen::SparseMatrix<double>& M_;
    Eigen::VectorXd diagonal_;  // M's diagonal when M is diagonal, else empty
};

}  // namespace sdmesh::detail
