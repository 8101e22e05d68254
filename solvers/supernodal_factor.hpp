#pragma once
// Private to sdmesh::solvers: the numeric supernodal Cholesky factorization, on the symbolic
// analysis (ordering, supernodes, row structure) that CHOLMOD's cholmod_analyze made.
//
// Why not cholmod_factorize: it makes a dsyrk and a dgemm call for every update of one supernode
// by another, and a mesh's supernodes are small (nefertiti: 5,774 of 8.7 columns on average), so
// its time went to the calls rather than to the arithmetic (0.098 s for 2.1e8 flops on
// nefertiti), and it runs on one thread. Here small updates are computed inline (0.023 s on one
// thread), and the two parts of the solve plan's elimination tree, whose supernodes update only
// their own part and the top, are factored side by side before the top (0.016 s).

#include <cstdint>
#include <vector>

#include <Eigen/SparseCore>
#include <cholmod.h>

#include "supernodal_solve.hpp"

namespace sdmesh::detail {

// Where each entry of the analysed matrix goes in the factor, and which supernodes update which
// in what order; made once per symbolic analysis.
struct FactorPlan {
    std::vector<int> supernode_of;  // per column of the factor
    std::vector<signed char> group; // per supernode: 0, 1 (the solve plan's parts) or 2 (its top)
    // A's lower-triangle entries, grouped by supernode: entry k's value A.valuePtr()[source[k]]
    // is added at offset[k] in its supernode's block; supernode s has entries [start[s], start[s + 1]).
    std::vector<int> start, source, offset;
    long max_update = 0;            // entries of the largest update matrix
    std::uint64_t pattern_hash = 0; // of A's pattern, to refuse another one
};

// The plan for factorizing A (the lower triangle is read) into `factor`, a supernodal symbolic
// analysis of A, with the parts of `solve_plan`.
[[nodiscard]] FactorPlan plan_factor(const cholmod_factor& factor, const SolvePlan& solve_plan,
                                     const Eigen::SparseMatrix<double>& A);

// A hash of A's sparsity pattern (dimensions, column starts, row indices).
[[nodiscard]] std::uint64_t pattern_hash(const Eigen::SparseMatrix<double>& A);

// P A Pᵀ = L Lᵀ into `factor` (its values are allocated on first use), with A of the planned
// pattern. Returns -1, or the first column of the factor (in its order) whose pivot was not
// positive: A is not positive definite (within rounding) and the factor is not usable. Same
// factor on every run of one machine, for any number of threads.
[[nodiscard]] int factorize_supernodal(cholmod_factor& factor, const SolvePlan& solve_plan, const FactorPlan& plan,
                                       const Eigen::SparseMatrix<double>& A, cholmod_common& common);

}  // namespace sdmesh::detail
