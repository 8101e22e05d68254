#include "sdmesh/matrix_market.hpp"

#include "io/output_file.hpp"

namespace sdmesh {

void write_matrix_market(const std::filesystem::path& path, const Eigen::SparseMatrix<double>& matrix) {
    io::write_atomically(path, path.extension() == ".gz", [&](io::OutputFile& out) {
        out.write("%%MatrixMarket matrix coordinate real general\n");
        out.write_text(static_cast<long long>(matrix.rows()));
        out.put(' ');
        out.write_text(static_cast<long long>(matrix.cols()));
        out.put(' ');
        out.write_text(static_cast<long long>(matrix.nonZeros()));
        out.put('\n');
        for (Eigen::Index j = 0; j < matrix.outerSize(); ++j)
            for (Eigen::SparseMatrix<double>::InnerIterator it(matrix, j); it; ++it) {
                out.write_text(static_cast<long long>(it.row() + 1));
                out.put(' ');
                out.write_text(static_cast<long long>(it.col() + 1));
                out.put(' ');
                out.write_text(it.value());
                out.put('\n');
            }
    });
}

}  // namespace sdmesh
