#include "free_vertices.hpp"

#include <string>

#include "sdmesh/error.hpp"

namespace sdmesh::detail {

void check_square_pair(const Sparse& L, const Sparse& M, std::string_view who) {
    if (L.rows() != L.cols() || M.rows() != M.cols() || L.rows() != M.rows())
        throw InvalidArgumentError(std::string(who) + ": L is " + std::to_string(L.rows()) + " x " +
                                   std::to_string(L.cols()) + " and M is " + std::to_string(M.rows()) + " x " +
                                   std::to_string(M.cols()) + "; both must be square and of the same size");
}

VertexSplit VertexSplit::make(int n, const std::vector<int>& fixed, std::string_view who) {
    std::vector<char> is_fixed(static_cast<size_t>(n), 0);
    std::vector<Eigen::Triplet<double>> fixed_entries, free_entries;
    for (int v : fixed) {
        if (v < 0 || v >= n)
            throw InvalidArgumentError(std::string(who) + ": Dirichlet vertex " + std::to_string(v) +
                                       " is out of range [0, " + std::to_string(n) + ")");
        if (is_fixed[static_cast<size_t>(v)])
            throw InvalidArgumentError(std::string(who) + ": Dirichlet vertex " + std::to_string(v) + " is given twice");
        is_fixed[static_cast<size_t>(v)] = 1;
        fixed_entries.emplace_back(static_cast<int>(fixed_entries.size()), v, 1.0);
    }
    for (int v = 0; v < n; ++v)
        if (!is_fixed[static_cast<size_t>(v)]) free_entries.emplace_back(static_cast<int>(free_entries.size()), v, 1.0);
    VertexSplit split;
    split.free.resize(static_cast<int>(free_entries.size()), n);
    split.free.setFromTriplets(free_entries.begin(), free_entries.end());
    split.fixed.resize(static_cast<int>(fixed_entries.size()), n);
    split.fixed.setFromTriplets(fixed_entries.begin(), fixed_entries.end());
    return split;
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
