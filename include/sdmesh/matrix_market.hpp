#pragma once
// Sparse matrices as Matrix Market files, for SciPy (scipy.io.mmread), MATLAB, Julia and others.

#include <filesystem>

#include <Eigen/SparseCore>

namespace sdmesh {

/// Writes `matrix` as "%%MatrixMarket matrix coordinate real general": a size line "rows cols nnz"
/// and one line "i j value" per stored entry (explicit zeros included), 1-based, in column order,
/// values with up to 17 significant digits so that reading gives back the same doubles. A path
/// ending in ".gz" is gzip-compressed. The data go to a temporary file in the same folder that is
/// renamed over `path` at the end, so a failed write never leaves a partial file under `path`.
/// \throws IoError the file cannot be written or renamed.
void write_matrix_market(const std::filesystem::path& path, const Eigen::SparseMatrix<double>& matrix);

}  // namespace sdmesh
