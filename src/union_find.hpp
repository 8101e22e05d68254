#pragma once
// Disjoint sets with path halving and union by size; deterministic.

#include <numeric>
#include <utility>
#include <vector>

namespace sdmesh {

class UnionFind {
public:
    explicit UnionFind(int n) : parent_(static_cast<size_t>(n)), size_(static_cast<size_t>(n), 1) {
        std::iota(parent_.begin(), parent_.end(), 0);
    }

    int find(int x) {
        while (parent_[x] != x) {
            parent_[x] = parent_[parent_[x]];
            x = parent_[x];
        }
        return x;
    }

    /// Joins the sets of a and b; false when they were already one set.
    bool unite(int a, int b) {
        a = find(a);
        b = find(b);
        if (a == b) return false;
        if (size_[a] < size_[b]) std::swap(a, b);
        parent_[b] = a;
        size_[a] += size_[b];
        return true;
    }

private:
    std::vector<int> parent_;
    std::vector<int> size_;
};

}  // namespace sdmesh
