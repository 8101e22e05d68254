#include "symmetric_product.hpp"

#include <algorithm>

namespace sdmesh::detail {

void symmetric_product(const Eigen::SparseMatrix<double>& A, const Eigen::Ref<const Eigen::MatrixXd>& X,
                       Eigen::Ref<Eigen::MatrixXd> out) {
    constexpr Eigen::Index kWidth = 4;
    const Eigen::Index n = A.rows();
    const int* start = A.outerIndexPtr();
    const int* index = A.innerIndexPtr();
    const double* value = A.valuePtr();
    Eigen::Matrix<double, kWidth, Eigen::Dynamic> rows(kWidth, n);  // four columns of X, row by row
    for (Eigen::Index first = 0; first < X.cols(); first += kWidth) {
        const Eigen::Index width = std::min(kWidth, X.cols() - first);
        if (width < kWidth) rows.setZero();
        rows.topRows(width) = X.middleCols(first, width).transpose();
        for (Eigen::Index i = 0; i < n; ++i) {
            Eigen::Matrix<double, kWidth, 1> sum = Eigen::Matrix<double, kWidth, 1>::Zero();
            for (int k = start[i]; k < start[i + 1]; ++k) sum += value[k] * rows.col(index[k]);
            out.block(i, first, 1, width) = sum.head(width).transpose();
        }
    }
}

}  // namespace sdmesh::detail
