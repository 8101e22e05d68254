#pragma once
// Private to sdmesh::solvers: solves with a CHOLMOD supernodal Cholesky factor.

#include <Eigen/Core>
#include <cholmod.h>

namespace sdmesh::detail {

// Solves A X = B with P A Pᵀ = L Lᵀ held in `factor` (supernodal, LLᵀ, real, int indices), for
// all columns of B. Same results on every run of one machine; the last bits depend on whether the
// processor has AVX2 and FMA.
void supernodal_solve(const cholmod_factor& factor, const Eigen::Ref<const Eigen::MatrixXd>& B,
                      Eigen::Ref<Eigen::MatrixXd> X);

}  // namespace sdmesh::detail
