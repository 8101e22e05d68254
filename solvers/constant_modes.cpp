#include "constant_modes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "union_find.hpp"

namespace sdmesh::detail {

using Sparse = Eigen::SparseMatrix<double>;

Eigen::VectorXd ConstantModes::vector(int j) const {
    Eigen::VectorXd z = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mode_of.size()));
    const double height = 1 / std::sqrt(mass[j]);
    for (size_t i = 0; i < mode_of.size(); ++i)
        if (mode_of[i] == j) z[static_cast<Eigen::Index>(i)] = height;
    return z;
}

void ConstantModes::project_out(Eigen::Ref<Eigen::MatrixXd> X) const {
    if (one_covering_all) {
        X.rowwise() -= (column_mass.transpose() * X) / mass[0];
        return;
    }
    const auto n = static_cast<Eigen::Index>(mode_of.size());
    Eigen::VectorXd mean(count());
    for (Eigen::Index c = 0; c < X.cols(); ++c) {
        mean.setZero();
        for (Eigen::Index i = 0; i < n; ++i)
            if (mode_of[i] >= 0) mean[mode_of[i]] += column_mass[i] * X(i, c);
        mean.array() /= mass.array();
        for (Eigen::Index i = 0; i < n; ++i)
            if (mode_of[i] >= 0) X(i, c) -= mean[mode_of[i]];
    }
}

std::vector<int> ConstantModes::lost_shift(const Sparse& L, double s) const {
    // The diagonal entries grouped by mode (a counting sort), for each group's median.
    std::vector<int> start(static_cast<size_t>(count()) + 1, 0);
    for (const int mode : mode_of)
        if (mode >= 0) ++start[static_cast<size_t>(mode) + 1];
    for (size_t j = 0; j < static_cast<size_t>(count()); ++j) start[j + 1] += start[j];
    std::vector<double> grouped(static_cast<size_t>(start.back()));
    std::vector<int> next(start.begin(), start.end() - 1);
    const Eigen::VectorXd diagonal = L.diagonal();
    for (size_t i = 0; i < mode_of.size(); ++i)
        if (const int mode = mode_of[i]; mode >= 0)
            grouped[static_cast<size_t>(next[static_cast<size_t>(mode)]++)] = diagonal[static_cast<Eigen::Index>(i)];
    std::vector<int> lost;
    for (int j = 0; j < count(); ++j) {
        const auto begin = grouped.begin() + start[static_cast<size_t>(j)];
        const auto end = grouped.begin() + start[static_cast<size_t>(j) + 1];
        const auto middle = begin + (end - begin) / 2;
        std::nth_element(begin, middle, end);
        if (s * mass[j] < kLostShift * *middle) lost.push_back(j);
    }
    return lost;
}

ConstantModes constant_modes(const Sparse& L, const Sparse& M) {
    const int n = static_cast<int>(L.rows());
    UnionFind components(n);
    for (const Sparse* A : {&L, &M})
        for (int j = 0; j < A->outerSize(); ++j)
            for (Sparse::InnerIterator it(*A, j); it; ++it)
                if (it.value() != 0 && it.row() != j) components.unite(static_cast<int>(it.row()), j);
    // A component qualifies when every row of L in it sums to zero, to the rounding of its
    // entries (L is symmetric: columns are rows).
    std::vector<char> qualifies(static_cast<size_t>(n), 1);  // per component root
    for (int j = 0; j < L.outerSize(); ++j) {
        double sum = 0, magnitude = 0;
        int entries = 0;
        for (Sparse::InnerIterator it(L, j); it; ++it) sum += it.value(), magnitude += std::abs(it.value()), ++entries;
        if (!(std::abs(sum) <= 8 * entries * std::numeric_limits<double>::epsilon() * magnitude))
            qualifies[components.find(j)] = 0;
    }
    ConstantModes modes;
    modes.mode_of.assign(static_cast<size_t>(n), -1);
    std::vector<int> mode_of_root(static_cast<size_t>(n), -1);
    int count = 0;
    for (int v = 0; v < n; ++v) {
        const int root = components.find(v);
        if (!qualifies[root]) continue;
        if (mode_of_root[root] < 0) {
            mode_of_root[root] = count++;
            modes.first.push_back(v);
        }
        modes.mode_of[v] = mode_of_root[root];
    }
    // Column sums: M's columns lie inside their component.
    modes.column_mass = Eigen::VectorXd::Zero(n);
    modes.mass = Eigen::VectorXd::Zero(count);
    for (int j = 0; j < n; ++j) {
        if (modes.mode_of[j] < 0) continue;
        for (Sparse::InnerIterator it(M, j); it; ++it) modes.column_mass[j] += it.value();
        modes.mass[modes.mode_of[j]] += modes.column_mass[j];
    }
    modes.one_covering_all =
        count == 1 && std::all_of(modes.mode_of.begin(), modes.mode_of.end(), [](int m) { return m == 0; });
    return modes;
}

}  // namespace sdmesh::detail
