#pragma once
// Private to sdmesh::solvers: solves with a CHOLMOD supernodal Cholesky factor.

#include <vector>

#include <Eigen/Core>
#include <cholmod.h>

namespace sdmesh::detail {

// A supernodal factor's arrays (int indices). Supernode s holds columns [super[s], super[s + 1])
// and the rows rows[row_start[s] ..], its own columns first; its values are a column-major block
// of height x columns at values + value_start[s]: a dense lower triangle on top, then the rows below.
struct SupernodalLayout {
    const int* super;
    const int* row_start;
    const int* value_start;
    const int* rows;
    double* values;

    explicit SupernodalLayout(const cholmod_factor& factor)
        : super(static_cast<const int*>(factor.super)),
          row_start(static_cast<const int*>(factor.pi)),
          value_start(static_cast<const int*>(factor.px)),
          rows(static_cast<const int*>(factor.s)),
          values(static_cast<double*>(factor.x)) {}
    [[nodiscard]] int columns(int s) const { return super[s + 1] - super[s]; }
    [[nodiscard]] int height(int s) const { return row_start[s + 1] - row_start[s]; }
};

// The supernode of each column of the factor.
[[nodiscard]] std::vector<int> supernode_of_columns(const cholmod_factor& factor);

// How a solve shares a factor's supernodes between two threads. The supernodal elimination tree
// is cut below its top into whole subtrees, dealt to two parts of about equal factor entries;
// the supernodes above the cut (the top separators, with nested dissection) stay with one
// thread. A part's substitutions touch only its own rows and the top's, so the parts run side by
// side: forward, the second part adds its updates of top rows into a buffer of its own. The
// numeric factorization (supernodal_factor.hpp) shares the work the same way. The plan depends
// only on the factor's structure, so it is made once per symbolic analysis.
struct SolvePlan {
    std::vector<int> parts[2];  // each part's supernodes, ascending
    std::vector<int> top;       // the other supernodes, ascending
    std::vector<int> top_slot;  // per row of the factor: its index among the top's columns, or -1
    int top_columns = 0;
};

// The plan for `factor` (supernodal); small factors get everything in `top` (one thread).
[[nodiscard]] SolvePlan plan_solve(const cholmod_factor& factor);

// Solves A X = B with P A Pᵀ = L Lᵀ held in `factor` (supernodal, LLᵀ, real, int indices), for
// all columns of B, on two threads as `plan` (from plan_solve for this factor's analysis) says,
// or one when OpenMP allows only one. Same results on every run of one machine, for any number
// of threads; the last bits depend on whether the processor has AVX2 and FMA.
void supernodal_solve(const cholmod_factor& factor, const SolvePlan& plan, const Eigen::Ref<const Eigen::MatrixXd>& B,
                      Eigen::Ref<Eigen::MatrixXd> X);

}  // namespace sdmesh::detail
