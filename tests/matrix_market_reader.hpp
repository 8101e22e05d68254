#pragma once
// Reads back the Matrix Market files sdmesh writes ("coordinate real general", 1-based), as an
// independent check of the writer; duplicate entries are summed, as scipy.io.mmread does.

#include <sstream>
#include <string>
#include <vector>

#include <Eigen/SparseCore>
#include <gtest/gtest.h>

namespace sdmesh::test {

inline Eigen::SparseMatrix<double> parse_matrix_market(const std::string& text) {
    std::istringstream in(text);
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "%%MatrixMarket matrix coordinate real general");
    long long rows = 0, cols = 0, nnz = 0;
    in >> rows >> cols >> nnz;
    std::vector<Eigen::Triplet<double>> triplets;
    for (long long k = 0; k < nnz; ++k) {
        long long i = 0, j = 0;
        double x = 0;
        in >> i >> j >> x;
        triplets.emplace_back(static_cast<int>(i - 1), static_cast<int>(j - 1), x);
    }
    EXPECT_FALSE(in.fail());
    Eigen::SparseMatrix<double> m(static_cast<int>(rows), static_cast<int>(cols));
    m.setFromTriplets(triplets.begin(), triplets.end());
    return m;
}

}  // namespace sdmesh::test
