#include "free_vertices.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "sdmesh/error.hpp"
#include "number_text.hpp"

namespace sdmesh::detail {

namespace {

void check_finite_symmetric(const Sparse& A, std::string_view name, std::string_view who) {
    auto at = [&](Eigen::Index r, Eigen::Index c) {
        return std::string(name) + "(" + std::to_string(r) + ", " + std::to_string(c) + ")";
    };
    double largest = 0;
    for (Eigen::Index k = 0; k < A.outerSize(); ++k)
        for (Sparse::InnerIterator it(A, k); it; ++it) {
            if (!std::isfinite(it.value()))
                throw InvalidArgumentError(std::string(who) + ": " + at(it.row(), it.col()) + " = " +
                                           number_text(it.value()) + " is not finite");
            largest = std::max(largest, std::abs(it.value()));
        }
    // Each stored entry against its mirror (found by binary search; 0 when not stored): no copy
    // of the matrix (a transposed copy cost the geodesics' precompute on igea about 4 %).
    for (Eigen::Index k = 0; k < A.outerSize(); ++k)
        for (Sparse::InnerIterator it(A, k); it; ++it)
            if (const double mirror = A.coeff(it.col(), it.row()); std::abs(it.value() - mirror) > 1e-12 * largest)
                throw InvalidArgumentError(std::string(who) + ": " + std::string(name) + " is not symmetric: " +
                                           at(it.row(), it.col()) + " = " + number_text(it.value()) + " but " +
                                           at(it.col(), it.row()) + " = " + number_text(mirror));
}

// Flags of the fixed vertices among n, each checked to be in range and given once.
std::vector<char> fixed_flags(int n, const std::vector<int>& fixed, std::string_view who) {
    std::vector<char> is_fixed(static_cast<size_t>(n), 0);
    for (int v : fixed) {
        if (v < 0 || v >= n)
            throw InvalidArgumentError(std::string(who) + ": Dirichlet vertex " + std::to_string(v) +
                                       " is out of range [0, " + std::to_string(n) + ")");
        if (is_fixed[static_cast<size_t>(v)])
            throw InvalidArgumentError(std::string(who) + ": Dirichlet vertex " + std::to_string(v) + " is given twice");
        is_fixed[static_cast<size_t>(v)] = 1;
    }
    return is_fixed;
}

}  // namespace

void check_operator_pair(const Sparse& L, const Sparse& M, std::string_view who) {
    if (L.rows() != L.cols() || M.rows() != M.cols() || L.rows() != M.rows())
        throw InvalidArgumentError(std::string(who) + ": L is " + std::to_string(L.rows()) + " x " +
                                   std::to_string(L.cols()) + " and M is " + std::to_string(M.rows()) + " x " +
                                   std::to_string(M.cols()) + "; both must be square and of the same size");
    check_finite_symmetric(L, "L", who);
    check_finite_symmetric(M, "M", who);
}

VertexSplit VertexSplit::make(int n, const std::vector<int>& fixed, std::string_view who) {
    const std::vector<char> is_fixed = fixed_flags(n, fixed, who);
    std::vector<Eigen::Triplet<double>> fixed_entries, free_entries;
    for (int v : fixed) fixed_entries.emplace_back(static_cast<int>(fixed_entries.size()), v, 1.0);
    for (int v = 0; v < n; ++v)
        if (!is_fixed[static_cast<size_t>(v)]) free_entries.emplace_back(static_cast<int>(free_entries.size()), v, 1.0);
    VertexSplit split;
    split.free.resize(static_cast<int>(free_entries.size()), n);
    split.free.setFromTriplets(free_entries.begin(), free_entries.end());
    split.fixed.resize(static_cast<int>(fixed_entries.size()), n);
    split.fixed.setFromTriplets(fixed_entries.begin(), fixed_entries.end());
    return split;
}

Pins::Pins(int n, const std::vector<int>& fixed, std::string_view who)
    : fixed_(fixed), is_fixed_(fixed_flags(n, fixed, who)) {}

void Pins::apply(Sparse& A) const {
    if (fixed_.empty()) return;
    bool has_diagonals = true;
    for (int v : fixed_) has_diagonals = has_diagonals && A.coeff(v, v) != 0.0;
    if (!has_diagonals) {  // rare (the cotan Laplacian stores every diagonal): a structural zero
        Sparse zero(A.rows(), A.cols());
        zero.setIdentity();
        A = Sparse(A + 0.0 * zero);
    }
    const auto n = static_cast<int>(A.cols());
    for (int j = 0; j < n; ++j)
        for (Sparse::InnerIterator it(A, j); it; ++it)
            if (is_fixed_[static_cast<size_t>(j)] || is_fixed_[static_cast<size_t>(it.row())])
                it.valueRef() = it.row() == j ? 1.0 : 0.0;
}

Sparse Pins::coupling(const Sparse& A) const {
    std::vector<Eigen::Triplet<double>> entries;
    for (int k = 0; k < static_cast<int>(fixed_.size()); ++k)
        for (Sparse::InnerIterator it(A, fixed_[static_cast<size_t>(k)]); it; ++it)
            entries.emplace_back(static_cast<int>(it.row()), k, it.value());
    Sparse c(A.rows(), static_cast<Eigen::Index>(fixed_.size()));
    c.setFromTriplets(entries.begin(), entries.end());
    return c;
}

Eigen::VectorXd pinned_rhs(const Eigen::VectorXd& b, const std::vector<int>& fixed, const Sparse& coupling,
                           const Eigen::VectorXd& g) {
    if (g.size() == 0) {
        Eigen::VectorXd r = b;
        for (int v : fixed) r[v] = 0;
        return r;
    }
    Eigen::VectorXd r = b - coupling * g;
    for (size_t k = 0; k < fixed.size(); ++k) r[fixed[k]] = g[static_cast<Eigen::Index>(k)];
    return r;
}

std::vector<int> connected_components(const Sparse& L, int& count) {
    const int n = static_cast<int>(L.rows());
    std::vector<int> component(static_cast<size_t>(n), -1), stack;
    count = 0;
    for (int seed = 0; seed < n; ++seed) {
        if (component[static_cast<size_t>(seed)] >= 0) continue;
        component[static_cast<size_t>(seed)] = count;
        stack.push_back(seed);
        while (!stack.empty()) {
            const int v = stack.back();
            stack.pop_back();
            for (Sparse::InnerIterator it(L, v); it; ++it) {
                const auto w = static_cast<size_t>(it.row());
                if (component[w] < 0) {
                    component[w] = count;
                    stack.push_back(static_cast<int>(w));
                }
            }
        }
        ++count;
    }
    return component;
}

}  // namespace sdmesh::detail
