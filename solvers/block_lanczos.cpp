#include "block_lanczos.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <utility>

#include <Eigen/Eigenvalues>

#include "sdmesh/cholesky.hpp"
#include "sdmesh/error.hpp"

#include "blas.hpp"
#include "mass_product.hpp"

namespace sdmesh::detail {
namespace {

using Sparse = Eigen::SparseMatrix<double>;
using Matrix = Eigen::MatrixXd;
using Index = Eigen::Index;

// A direction of a new block whose M-norm fell below this fraction of the block's norm before
// orthogonalization is numerically inside the basis already (an invariant subspace was found);
// it is replaced by a fresh random direction.
constexpr double kLostDirection = 1e-10;
// A direction that the projections shortened by more than this keeps components along the basis
// of ε divided by it, which its normalization brings to full size: on the icosahedron (12
// vertices, whose block Krylov space is invariant at dimension 11), a direction shortened ~1e8×
// left ΦᵀMΦ − I at 8.6e-8. Such blocks get a third pass against the basis.
constexpr double kReprojectBelow = 1e-4;
// A block whose squared condition number is below this is orthonormal to ~100 ε after one SVQB.
constexpr double kRepeatCondition = 100;
// The margin pairs' tolerance, relative to the wanted pairs' (see block_lanczos.hpp): 100 cut
// nefertiti's solves from 208 to 196 (k = 50) and left the returned pairs' residuals unchanged.
constexpr double kMarginTolerance = 100;

// Coefficients of a new block along the older basis vectors below this, relative to the block's
// norm, are left in place (project_out_measured). The Ritz vectors then stay M-orthonormal to
// ~1e-12 (ΦᵀMΦ − I was 5e-13 on nefertiti, against 2e-15 with every correction applied); with
// 1e-10 it reached 5e-11, too close to the 1e-10 that users are promised.
constexpr double kSkippedCorrection = 1e-12;
// A step may leave out the whole-basis pass after a corrected step whose loss was below
// kMaxLossBeforeSkipping, if the first pass shortened its block by at most kMaxShrinkWhenSkipping
// (on nefertiti the loss was 1e-10 to 4e-9 and the shortening 3 to 30). Both this and leaving
// small coefficients in place (kSkippedCorrection) happen only when the basis cannot exceed
// 1 / kMinRowsPerColumnWhenSkipping of the space: they save memory traffic on large problems,
// and near a basis that fills the space, where blocks lie almost inside it, they made the
// 42-vertex icosphere's pairs fail (residuals and ΦᵀMΦ − I of 3e-7).
constexpr double kMaxLossBeforeSkipping = 1e-8;
constexpr double kMaxShrinkWhenSkipping = 100;
constexpr Index kMinRowsPerColumnWhenSkipping = 8;

// Each convergence test costs an eigendecomposition of T, O(m³) (at k = 200 on nefertiti, a
// third of the time when done at every step). After the first test, the next one waits one step
// per this many orders of magnitude that the worst residual lies above its tolerance; after two,
// half the steps that the residual's last rate of decrease needs to reach it (the rate grows as
// pairs converge, 2–4× per step near the end on nefertiti and koala, so half leaves room for it).
// At most this many steps apart (4 or 8 gave the same steps on six corpus meshes, k = 10 to 200).
// The first test waits until the basis has this many columns per tested pair: it had 2.5 (k =
// 200), 2.8 (k = 100), 3.3 (k = 50) and 4.8 (k = 10) when the pairs converged (nefertiti, koala).
// With both, koala k = 100 makes 8 tests instead of 18, nefertiti k = 50 6 instead of 12.
constexpr double kOrdersPerSkippedTest = 3;
constexpr double kFractionOfPredictedSteps = 0.5;
constexpr Eigen::Index kMaxStepsBetweenTests = 8;
constexpr Eigen::Index kColumnsPerPairBeforeTesting = 2;

// The steps until the next convergence test, from the worst residual over its tolerance now and
// at the previous test (`previous` ≤ 0: none), `elapsed` steps ago.
Eigen::Index steps_to_next_test(double worst, double previous, Eigen::Index elapsed) {
    const double orders = std::log10(worst);
    double wait = orders / kOrdersPerSkippedTest;
    if (previous > worst)
        wait = kFractionOfPredictedSteps * orders * static_cast<double>(elapsed) / std::log10(previous / worst);
    return std::clamp<Eigen::Index>(static_cast<Eigen::Index>(wait), 1, kMaxStepsBetweenTests);
}

// Deterministic pseudo-random columns in [-1, 1) (splitmix64), the same on every platform.
Matrix random_columns(Index n, Index b, std::uint64_t seed) {
    Matrix X(n, b);
    std::uint64_t state = seed;
    for (Index j = 0; j < b; ++j)
        for (Index i = 0; i < n; ++i) {
            std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
            z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
            z ^= z >> 31;
            X(i, j) = static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
        }
    return X;
}

// The squared M-norms of W's columns, given MW = M W (by the Gram matrix's diagonal: BLAS over
// two row halves side by side, where a serial column sum per step cost 1 % of nefertiti's time).
Eigen::VectorXd squared_norms(const Matrix& W, const Matrix& MW) {
    Matrix G(W.cols(), W.cols());
    multiply(true, 1.0, W, MW, 0.0, G);
    return G.diagonal();
}

// W ← W − V (Vᵀ M W): one classical Gram–Schmidt pass, which leaves components of size
// ε‖W‖ / ‖result‖ along V, so that it is done twice to reach rounding ("twice is enough").
// Returns the coefficients Vᵀ M W. This form is given MW = M W (and leaves it as it was).
Matrix project_out(const Eigen::Ref<const Matrix>& V, const Matrix& MW, Matrix& W) {
    Matrix C(V.cols(), W.cols());
    if (V.cols() == 0) return C;
    multiply(true, 1.0, V, MW, 0.0, C);
    multiply(false, -1.0, V, C, 1.0, W);
    return C;
}
// This one computes M W; `largest_norm`, when given, receives the largest M-norm of W's columns
// before the projection.
Matrix project_out(const Eigen::Ref<const Matrix>& V, const MassProduct& M, Matrix& W, double* largest_norm = nullptr) {
    const Matrix MW = M(W);
    if (largest_norm) *largest_norm = std::sqrt(squared_norms(W, MW).maxCoeff());
    return project_out(V, MW, W);
}

// The M-norm of W's shortest column, given MW = M W.
double shortest_norm(const Matrix& W, const Matrix& MW) {
    return std::sqrt(squared_norms(W, MW).minCoeff());
}

// The second pass over the whole basis V, whose last `local` columns the first pass covered.
// Along the older columns, the coefficients Vᵀ M W measure how far the basis has lost
// orthogonality since the last correction; it grows about a hundredfold per step. When they are
// all below `threshold` times the M-norm of W's shortest column, only the last `local` columns
// are projected out, which saves the pass's second read of the basis (in the first steps; later
// the loss is larger at every measured step). Returns the coefficients applied; `loss` receives
// the largest coefficient along the older columns over that norm. MW = M W, and `shortest` is
// the M-norm of W's shortest column.
Matrix project_out_measured(const Eigen::Ref<const Matrix>& V, Index local, const Matrix& MW, double shortest,
                            Matrix& W, double threshold, double& loss) {
    const Index m = V.cols(), older = m - local;
    Matrix C(m, W.cols());
    multiply(true, 1.0, V, MW, 0.0, C);
    loss = older > 0 ? C.topRows(older).cwiseAbs().maxCoeff() / shortest : 0.0;
    if (loss <= threshold) {
        C.topRows(older).setZero();
        multiply(false, -1.0, V.rightCols(local), C.bottomRows(local), 1.0, W);
    } else {
        multiply(false, -1.0, V, C, 1.0, W);
    }
    return C;
}

Matrix gram(const Matrix& W, const MassProduct& M) {
    const Matrix MW = M(W);
    Matrix G(W.cols(), W.cols());
    multiply(true, 1.0, W, MW, 0.0, G);
    return 0.5 * (G + G.transpose());
}

// W = Q R with QᵀMQ = I, by SVQB (eigendecomposition of the Gram matrix G = WᵀMW, then
// scaling). One pass loses orthogonality in proportion to the square of W's condition number, so
// a second pass follows when that square exceeds kRepeatCondition. Directions of norm below
// kLostDirection · `scale` are dropped (their rows of R are zero) and replaced by random ones,
// deflated and orthogonalized against V; those below kReprojectBelow · `scale` are projected
// against V once more first. Q (n x b, not overlapping V) receives the result, written in place
// (the basis's next block: a copy of each block cost 12 ms on nefertiti); W is scratch. Returns R.
Matrix orthonormalize(const Eigen::Ref<const Matrix>& V, const MassProduct& M, Matrix& W, const Matrix& G, double scale,
                      std::uint64_t seed, const BlockLanczosOptions& options, Eigen::Ref<Matrix> Q) {
    const Index b = W.cols();
    Eigen::SelfAdjointEigenSolver<Matrix> first(G);
    const double lost_below = kLostDirection * kLostDirection * scale * scale;
    const double reproject_below = kReprojectBelow * kReprojectBelow * scale * scale;
    if ((first.eigenvalues().array() > lost_below && first.eigenvalues().array() < reproject_below).any()) {
        project_out(V, M, W);
        first.compute(gram(W, M));
    }
    const Eigen::VectorXd d = first.eigenvalues().cwiseMax(0.0);
    Matrix R = Matrix::Zero(b, b), scaled = Matrix::Zero(b, b);
    Index lost = 0;
    for (Index i = 0; i < b; ++i) {
        if (d[i] <= lost_below) {
            ++lost;
            continue;
        }
        const double s = std::sqrt(d[i]);
        scaled.col(i) = first.eigenvectors().col(i) / s;
        R.row(i) = s * first.eigenvectors().col(i).transpose();
    }
    multiply(false, 1.0, W, scaled, 0.0, Q);
    if (lost > 0) {
        // The eigenvalues are ascending, so the lost directions are the first columns.
        Matrix fresh = random_columns(W.rows(), lost, seed);
        if (options.deflate) options.deflate(fresh);
        project_out(V, M, fresh);
        project_out(V, M, fresh);
        Q.leftCols(lost) = fresh;
    } else if (d[b - 1] <= kRepeatCondition * d[0]) {
        return R;
    }
    W = Q;
    const Eigen::SelfAdjointEigenSolver<Matrix> second(gram(W, M));
    const Eigen::VectorXd d2 = second.eigenvalues();
    if (!(d2.minCoeff() > 0)) throw NumericalError("eigenpairs: block Lanczos could not extend its basis");
    const Eigen::VectorXd root = d2.cwiseSqrt();
    scaled = second.eigenvectors() * root.cwiseInverse().asDiagonal();
    multiply(false, 1.0, W, scaled, 0.0, Q);
    return root.asDiagonal() * second.eigenvectors().transpose() * R;
}

}  // namespace

BasisShape basis_shape(Index n, const BlockLanczosOptions& options) {
    // Blocks of at most a third of n, so that small problems still take several steps. When the
    // basis may fill the whole space, the blocks divide n, so that the last one completes it
    // (the Ritz pairs are then exact).
    BasisShape shape;
    shape.capacity = std::min<Index>(n, options.max_columns);
    shape.block = std::clamp<Index>(options.block_size, 1, std::max<Index>(1, std::min(n / 3, shape.capacity)));
    if (shape.capacity == n)
        while (n % shape.block != 0) --shape.block;
    else
        shape.capacity = shape.capacity / shape.block * shape.block;
    shape.expected = std::min(shape.capacity, kExpectedColumnsPerPair * (options.wanted + options.margin));
    return shape;
}

BlockLanczosResult block_lanczos(const CholeskySolver& K, const Sparse& mass, const BlockLanczosOptions& options,
                                 Matrix V) {
    const MassProduct M(mass);
    const Index n = mass.rows();
    const auto [b, capacity, expected] = basis_shape(n, options);
    const Index tested = std::min<Index>(options.wanted + options.margin, capacity);
    const Index wanted = std::min<Index>(options.wanted, tested);

    BlockLanczosResult result;
    if (V.rows() != n || V.cols() != capacity) V.resize(n, capacity);  // pages are touched as the basis grows
    Matrix T = Matrix::Zero(capacity, capacity);
    {
        // The start block lies in the range of S = (L - σM)⁻¹M (Nour-Omid, Parlett, Ericsson and
        // Jensen, 1987). Random columns have values where M is nearly zero (a component or faces
        // of tiny area) that the M-norm hardly sees; they stay in the basis, hence in the Ritz
        // vectors, where L sees them: beside a sphere, one 1e-9 across left residuals of 1e-7.
        // Not when the basis may fill the space, whose Ritz pairs are exact from any start: S
        // damps the top of the spectrum, and on the icosahedron its last cluster was lost.
        Matrix start = random_columns(n, b, 1);
        if (capacity < n) {
            start = K.solve_columns(M(start));
            result.solves += static_cast<int>(b);
        }
        if (options.deflate) options.deflate(start);
        orthonormalize(V.leftCols(0), M, start, gram(start, M), 1.0, 2, options, V.leftCols(b));
    }
    LargestEigenpairs ritz;  // of the last convergence test
    Index m = 0, next_test = 0, previous_test = 0;
    double previous_worst = 0;  // of the previous convergence test; 0: none yet
    const bool skipping_allowed = capacity * kMinRowsPerColumnWhenSkipping <= n;
    bool may_skip = false;  // whether this step may leave out the whole-basis pass
    auto last_progress = std::chrono::steady_clock::now();
    for (Index step = 0; (step + 1) * b <= capacity; ++step) {
        m = (step + 1) * b;
        Matrix W = K.solve_columns(M(V.middleCols(step * b, b)));
        if (options.deflate) options.deflate(W);  // rounding along the modes, grown by the solve
        result.solves += static_cast<int>(b);
        result.steps = static_cast<int>(step + 1);
        // S Q_j has large components only along the last two blocks (the Lanczos recurrence);
        // along the older ones they are rounding errors grown by the loss of orthogonality. So a
        // first pass against the last two blocks, then one against the whole basis, which also
        // cleans the first pass's rounding: as accurate as two full passes, half the reads (and
        // fewer when the older blocks need no correction).
        const Index local = std::min<Index>(m, 2 * b);
        double scale = 0;  // W's largest M-norm before the projections
        const Matrix near = project_out(V.middleCols(m - local, local), M, W, &scale);
        // Right after a step whose older blocks were corrected, the loss of orthogonality regrows
        // from rounding: the next block's coefficients along them stayed below 5e-12 of its norm
        // (nefertiti k = 50, 200; koala k = 100). That step's second pass covers the last two
        // blocks only, and the whole basis is read on every other step: nefertiti 0.71 → 0.60 s,
        // koala 1.37 → 1.21 s, with ΦᵀMΦ − I ≤ 3.2e-12 (5.4e-13 when every step is measured).
        // Not when the loss had grown large (the basis nears an invariant subspace), when the
        // first pass took most of the block (it lies nearly in the basis), nor when the basis can
        // fill much of the space: on a 42-vertex sphere, skipping made the solver fail.
        Matrix H = Matrix::Zero(m, b);
        const Matrix MW = M(W);  // for both branches
        const double shortest = shortest_norm(W, MW);
        if (may_skip && scale <= kMaxShrinkWhenSkipping * shortest) {
            H.bottomRows(local) = project_out(V.middleCols(m - local, local), MW, W);
            may_skip = false;
        } else {
            double loss = 0;
            H = project_out_measured(V.leftCols(m), local, MW, shortest, W,
                                     skipping_allowed ? kSkippedCorrection : 0.0, loss);
            may_skip = skipping_allowed && loss > kSkippedCorrection && loss <= kMaxLossBeforeSkipping;
        }
        H.bottomRows(local) += near;
        const Matrix A = H.bottomRows(b);
        T.block(step * b, step * b, b, b) = 0.5 * (A + A.transpose());

        // The Ritz pairs of T: S V = V T + W Eᵀ, so the residual of Ritz vector V s is
        // ‖W s_last‖_M with s_last the last b entries of s.
        const Matrix G = gram(W, M);
        const bool last = m + b > capacity;  // then m = capacity >= tested
        if (last || (m >= kColumnsPerPairBeforeTesting * tested && step >= next_test)) {
            ritz = largest_eigenpairs(T.topLeftCorner(m, m), static_cast<int>(tested));
            double worst = 0;  // the largest residual over its tolerance
            Index converged = 0;
            for (Index i = 0; i < tested; ++i) {
                const Index col = tested - 1 - i;
                const double theta = ritz.values[col];
                const Eigen::VectorXd s = ritz.vectors.col(col).tail(b);
                const double residual = std::sqrt(std::max(0.0, s.dot(G * s)));
                const double tolerance = i < wanted ? options.tolerance : kMarginTolerance * options.tolerance;
                const double ratio = residual / (tolerance * theta);  // θ > 0: K and M are positive definite
                worst = std::max(worst, ratio);
                converged += ratio <= 1;
            }
            if (options.progress && std::chrono::steady_clock::now() - last_progress > std::chrono::seconds(1)) {
                last_progress = std::chrono::steady_clock::now();
                std::fprintf(stderr, "eigs: %d solves, %ld of %ld pairs converged (with %ld margin pairs)\n",
                             result.solves, static_cast<long>(converged), static_cast<long>(tested),
                             static_cast<long>(tested - wanted));
            }
            if (worst <= 1) {
                result.converged = true;
                break;
            }
            next_test = step + steps_to_next_test(worst, previous_worst, step - previous_test);
            previous_worst = worst;
            previous_test = step;
        }
        if (last) break;
        const Matrix R = orthonormalize(V.leftCols(m), M, W, G, scale, 3 + static_cast<std::uint64_t>(step), options,
                                        V.middleCols(m, b));
        T.block(m, step * b, b, b) = R;
        T.block(step * b, m, b, b) = R.transpose();
    }
    // The last step had m = capacity >= tested, so `ritz` holds the final Ritz pairs. Largest θ
    // first, i.e. smallest λ first.
    result.ritz_values = ritz.values.tail(wanted).reverse();
    const Matrix S = ritz.vectors.rightCols(wanted).rowwise().reverse();
    result.ritz_vectors.resize(n, wanted);
    multiply(false, 1.0, V.leftCols(m), S, 0.0, result.ritz_vectors);
    return result;
}

}  // namespace sdmesh::detail
