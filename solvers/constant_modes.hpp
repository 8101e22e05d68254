#pragma once
// Private to sdmesh::solvers: eigenvectors of L φ = λ M φ known before any iteration. The rows of
// a Laplacian sum to zero, so the constant function on each connected component (of the graph of
// L and M together) is an eigenvector of eigenvalue 0. A soup of triangles, as CAD exports write
// them, has one per triangle: thousands of equal eigenvalues, more than a Lanczos basis resolves
// as one cluster (block Lanczos ended not converged, residuals up to 1e3, on 11 meshes of 49 to
// 3,026 components in the unseen sweep). Lanczos runs in the M-orthogonal complement of these
// modes instead, and they are merged with its pairs.

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace sdmesh::detail {

struct ConstantModes {
    std::vector<int> mode_of;     ///< per unknown: the index of its component's mode, or -1
    Eigen::VectorXd column_mass;  ///< per unknown: the sum of M's column (1ᵀ M e_j)
    Eigen::VectorXd mass;         ///< per mode: 1ᵀ M 1 over its component
    std::vector<int> first;       ///< per mode: the lowest unknown of its component
    bool one_covering_all = false;  ///< one mode, of every unknown (a connected mesh): vector products

    [[nodiscard]] int count() const { return static_cast<int>(mass.size()); }
    /// Mode j as an M-normalised column.
    [[nodiscard]] Eigen::VectorXd vector(int j) const;
    /// X ← X − Z Zᵀ M X, with Z the M-normalised modes: each column M-orthogonal to every mode.
    /// O(n) per column: a mode's coefficient is the sum of column_mass · x over its component.
    void project_out(Eigen::Ref<Eigen::MatrixXd> X) const;
    /// The modes whose component's L + sM (s > 0: −σ for eigenpairs, 1/t for heat) is L within
    /// rounding, singular along the mode: a component far smaller than the mesh whose s is set
    /// for (beside a unit sphere, one 1e-9 across failed to factor in both). s M is lost there
    /// when s·1ᵀM1 over the component is below kLostShift of its median diagonal entry of L:
    /// that ratio is about s over its smallest non-zero eigenvalue, within a factor of ~100 for
    /// any shape, and is 1 on the component that sets σ. (The mean entry instead is led by
    /// slivers: a unit sphere with one needle of width 1e-12 had it 1e10 times the median, and
    /// its pairs came out wrong, with residuals of 1.8.) Pinning one unknown to 0 then makes
    /// the matrix definite, and the solution is exact but for its part along the mode (and
    /// errors of about that ratio elsewhere), which the caller restores: deflation
    /// (eigenpairs), conservation of 1ᵀMu (heat).
    [[nodiscard]] std::vector<int> lost_shift(const Eigen::SparseMatrix<double>& L, double s) const;
};

inline constexpr double kLostShift = 1e-8;

/// The components of the graph of L's and M's off-diagonal non-zeros on which L's rows sum to
/// zero (each within 8·ε·(row entries) of the sum of their magnitudes), numbered by their lowest
/// unknown. Rows next to a Dirichlet vertex do not, nor do those of an L that is not a Laplacian.
[[nodiscard]] ConstantModes constant_modes(const Eigen::SparseMatrix<double>& L, const Eigen::SparseMatrix<double>& M);

}  // namespace sdmesh::detail
