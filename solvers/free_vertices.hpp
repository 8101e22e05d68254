#pragma once
// Private to sdmesh::solvers: checking an (L, M) pair, splitting the vertices into fixed (Dirichlet) and free ones, so that
// solves run on the free rows and columns (eigenpairs) or keep the matrix's pattern with the fixed
// ones pinned (Poisson, heat), and the connected components seen by a Laplacian.

#include <string_view>
#include <vector>

#include <Eigen/SparseCore>

namespace sdmesh::detail {

using Sparse = Eigen::SparseMatrix<double>;

struct VertexSplit {
    Sparse free;   ///< |free| x n selection matrix, free vertices ascending
    Sparse fixed;  ///< |fixed| x n selection matrix, fixed vertices in the order given

    /// \throws InvalidArgumentError (message starting with `who`) a fixed vertex out of [0, n) or
    ///         given twice.
    static VertexSplit make(int n, const std::vector<int>& fixed, std::string_view who);
};

/// \throws InvalidArgumentError (message starting with `who`) L or M is not square, their sizes
///         differ, an entry is not finite, or one is not symmetric (up to 1e-12 of its largest
///         entry: the solvers read one triangle, and would solve another problem unseen).
void check_operator_pair(const Sparse& L, const Sparse& M, std::string_view who);

/// Dirichlet vertices imposed without changing the size or pattern of a symmetric matrix, so that
/// every system on one mesh shares a fill-reducing ordering: the rows and columns of the fixed
/// vertices become those of the identity (their other entries explicit zeros). The system
/// decouples, so the fixed unknowns come out equal to their right-hand side exactly.
class Pins {
public:
    /// \throws InvalidArgumentError (message starting with `who`) a fixed vertex out of [0, n) or
    ///         given twice.
    Pins(int n, const std::vector<int>& fixed, std::string_view who);

    /// A with the pins applied in place; a diagonal entry A lacks is added (a new pattern).
    void apply(Sparse& A) const;

    /// A(:, fixed): n x |fixed|, what pinned_rhs() needs of the matrix before apply().
    [[nodiscard]] Sparse coupling(const Sparse& A) const;

    [[nodiscard]] const std::vector<int>& fixed() const { return fixed_; }

private:
    std::vector<int> fixed_;
    std::vector<char> is_fixed_;
};

/// The right-hand side for the pinned A u = b with u = g on the fixed vertices (in their given
/// order; empty: all 0): b − A(:, fixed)·g, then g on the fixed rows.
Eigen::VectorXd pinned_rhs(const Eigen::VectorXd& b, const std::vector<int>& fixed, const Sparse& coupling,
                           const Eigen::VectorXd& g);

/// P A Qᵀ: the rows of A selected by P and the columns selected by Q.
inline Sparse restrict_to(const Sparse& A, const Sparse& P, const Sparse& Q) { return Sparse(P * A * Q.transpose()); }

/// Component id (0, 1, ...) of each vertex, two vertices being joined when L stores an entry
/// between them; ids are numbered in the order of their smallest vertex.
std::vector<int> connected_components(const Sparse& L, int& count);

}  // namespace sdmesh::detail
