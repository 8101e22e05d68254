#pragma once
// Private to sdmesh::solvers: products of a symmetric sparse matrix with a few dense columns.

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace sdmesh::detail {

/// out = A X for a symmetric A stored whole (both triangles; compressed), out not overlapping X.
/// A's column i is its row i, so row i of the product gathers the rows of X that it names, four
/// columns at a time from a row-major copy: Eigen's column-major product scatters into X's rows
/// instead and took 2.3x as long (nefertiti's L times 50 columns: 23 against 10 ms).
void symmetric_product(const Eigen::SparseMatrix<double>& A, const Eigen::Ref<const Eigen::MatrixXd>& X,
                       Eigen::Ref<Eigen::MatrixXd> out);

}  // namespace sdmesh::detail
