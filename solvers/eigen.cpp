#include "sdmesh/eigen.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/SymGEigsShiftSolver.h>
#include <Spectra/Util/SimpleRandom.h>
#include <omp.h>

#include "sdmesh/cholesky.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"

#include "blas.hpp"
#include "mass_product.hpp"
#include "block_lanczos.hpp"
#include "constant_modes.hpp"
#include "explained_factor.hpp"
#include "free_vertices.hpp"
#include "number_text.hpp"
#include "prefault.hpp"
#include "symmetric_product.hpp"

namespace sdmesh {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

constexpr std::string_view kShiftedMatrix = "eigenpairs: L - sigma M";
// L is positive semidefinite and sigma negative, so only rounding, or a sigma too near 0 for it, can fail.
const std::string kShiftAdvice = "a sigma further below 0 can help; " + std::string(detail::kIndefiniteMeshAdvice);

// The modes Lanczos leaves out (constant_modes.hpp), and the lowest unknown of each of their
// components on which L − σM is L within rounding (ConstantModes::lost_shift), pinned to 0 in the
// factorization: the solves there are then exact but for their part along the mode, which is
// removed anyway.
struct Deflation {
    const detail::ConstantModes& modes;
    std::vector<int> grounded;

    // The solves' columns (or any) M-orthogonal to the modes: the pinned rows, which a solve
    // gives the right-hand side's values, become 0 first.
    void apply(Eigen::Ref<Eigen::MatrixXd> X) const {
        for (const int i : grounded) X.row(i).setZero();
        modes.project_out(X);
    }
};

Sparse shifted_matrix(const Sparse& L, const Sparse& M, double sigma, const Deflation* deflation) {
    Sparse A = L - sigma * M;
    if (deflation != nullptr) detail::Pins(static_cast<int>(A.rows()), deflation->grounded, "eigenpairs").apply(A);
    return A;
}

// y = (L − σM)⁻¹ x for Spectra's shift-invert mode, on a CHOLMOD factor built when Spectra sets
// the shift, deflated. Counts the solves for the report.
class ShiftInvertOp {
public:
    using Scalar = double;

    ShiftInvertOp(const Sparse& L, const Sparse& M, const Deflation* deflation, int& solves)
        : L_(L), M_(M), deflation_(deflation), solves_(solves) {}

    [[nodiscard]] Eigen::Index rows() const { return L_.rows(); }
    [[nodiscard]] Eigen::Index cols() const { return L_.cols(); }

    void set_shift(double sigma) {
        const Sparse shifted = shifted_matrix(L_, M_, sigma, deflation_);
        solver_ = detail::explained(kShiftedMatrix, kShiftAdvice, [&] { return CholeskySolver(shifted); });
    }

    void perform_op(const double* x_in, double* y_out) const {
        const Eigen::Index n = rows();
        Eigen::Map<Eigen::VectorXd> y(y_out, n);
        y = solver_.solve(Eigen::Map<const Eigen::VectorXd>(x_in, n));
        if (deflation_ != nullptr) deflation_->apply(y);
        ++solves_;
    }

private:
    const Sparse& L_;
    const Sparse& M_;
    const Deflation* deflation_;
    int& solves_;
    CholeskySolver solver_;
};

// Xᵀ A Y for a symmetric sparse A, symmetrised, computed over blocks of columns of Y.
Eigen::MatrixXd projected(const Eigen::MatrixXd& X, const Sparse& A, const Eigen::MatrixXd& Y) {
    constexpr Eigen::Index kBlock = 8;
    Eigen::MatrixXd P(X.cols(), Y.cols());
    for (Eigen::Index j = 0; j < Y.cols(); j += kBlock) {
        const Eigen::Index width = std::min(kBlock, Y.cols() - j);
        const Eigen::MatrixXd AY = A * Y.middleCols(j, width);
        detail::multiply(true, 1.0, X, AY, 0.0, P.middleCols(j, width));
    }
    return 0.5 * (P + P.transpose());
}

// The least number of extra pairs asked of Lanczos (see smallest_eigenpairs).
constexpr int kMinEigenMargin = 10;

void check_arguments(const Sparse& L, const Sparse& M, const EigenOptions& options) {
    detail::check_operator_pair(L, M, "eigenpairs");
    if (!(options.tolerance > 0))
        throw InvalidArgumentError("eigenpairs: tolerance must be > 0, got " + detail::number_text(options.tolerance));
    if (options.max_iterations < 1)
        throw InvalidArgumentError("eigenpairs: max_iterations must be >= 1, got " +
                                   std::to_string(options.max_iterations));
    if (!std::isnan(options.sigma) && !(options.sigma < 0))
        throw InvalidArgumentError("eigenpairs: the shift sigma must be negative (L is singular), got " +
                                   detail::number_text(options.sigma));
    // M must be positive definite; a non-positive diagonal entry (e.g. a negative circumcentric
    // dual cell) rules that out, and Lanczos in the M inner product would break down on it.
    const Eigen::VectorXd mass = M.diagonal();
    for (Eigen::Index i = 0; i < mass.size(); ++i)
        if (!(mass[i] > 0) || !std::isfinite(mass[i]))
            throw NumericalError("eigenpairs: the mass matrix is not positive definite: M(" + std::to_string(i) +
                                 ", " + std::to_string(i) + ") = " + std::to_string(mass[i]) +
                                 " (a vertex in no face, which sdmesh repair drops, or a negative "
                                 "circumcentric dual cell, which conversion to self-Delaunay removes)");
}

// Powers of two that bring the mean diagonal entries of L and M near 1 when they are far from it
// (M's a power of four, so that its square root is exact too): at 1e-80 or 1e100 M's entries
// would otherwise take Lanczos and the factorization out of the double range. Eigenpairs scale
// exactly with them, and nearer to 1 the scaling would change no bit (tested), so L and M are
// not copied for it (a copy of L cost nefertiti ~2 %).
struct UnitScales {
    double stiffness = 1, mass = 1;
};

UnitScales unit_scales(const Sparse& L, const Sparse& M) {
    const double n = static_cast<double>(L.rows());
    const int mass = far_unit_exponent(M.diagonal().sum() / n);
    return {std::ldexp(1.0, -far_unit_exponent(L.diagonal().sum() / n)), std::ldexp(1.0, -2 * (mass / 2))};
}

// storage = factor · source, in place when source is storage.
void scale_operand(const Sparse& source, double factor, Sparse& storage) {
    if (&source == &storage)
        storage *= factor;
    else
        storage = factor * source;
}

struct Eigenpairs {
    Eigen::VectorXd values;   // ascending
    Eigen::MatrixXd vectors;  // M-orthonormal
};

// The k smallest pairs by Spectra's Lanczos, which must converge with `nev` - k more, then
// Rayleigh–Ritz on the span of its Ritz vectors (a dense generalized problem): Spectra's
// vectors drift from M-orthogonality within clusters of equal eigenvalues, this restores it to
// rounding and gives each pair its Rayleigh quotient. Products with L and M run over a few
// columns at a time, so no further n x k matrix is made (their first touch is slow).
Eigenpairs spectra_eigenpairs(const Sparse& L, const Sparse& M, int k, int nev, int basis, const EigenOptions& options,
                              const Deflation* deflation, EigenReport& report) {
    ShiftInvertOp op(L, M, deflation, report.solves);
    Spectra::SparseSymMatProd<double> mass_op(M);
    Spectra::SymGEigsShiftSolver<ShiftInvertOp, Spectra::SparseSymMatProd<double>, Spectra::GEigsMode::ShiftInvert>
        lanczos(op, mass_op, nev, basis, report.sigma);
    try {
        Eigen::VectorXd start = Spectra::SimpleRandom<double>(0).random_vec(L.rows());  // as Spectra's init()
        if (deflation != nullptr) deflation->apply(start);
        lanczos.init(start.data());
        lanczos.compute(Spectra::SortRule::LargestMagn, options.max_iterations, options.tolerance,
                        Spectra::SortRule::SmallestAlge);
    } catch (const Error&) {
        throw;
    } catch (const std::runtime_error& e) {  // Spectra's breakdowns, with its own words
        throw NumericalError(std::string("eigenpairs: Lanczos failed: ") + e.what());
    }
    report.iterations = static_cast<int>(lanczos.num_iterations());
    report.status =
        lanczos.info() == Spectra::CompInfo::Successful ? EigenStatus::converged : EigenStatus::not_converged;

    const Eigen::MatrixXd Y = lanczos.eigenvectors();
    const Eigen::MatrixXd A = projected(Y, L, Y), B = projected(Y, M, Y);
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> small(A, B);
    if (small.info() != Eigen::Success)
        throw NumericalError("eigenpairs: the Rayleigh-Ritz step failed (M not positive definite?)");
    const Eigen::Index kept = std::min<Eigen::Index>(k, Y.cols());
    Eigenpairs pairs{small.eigenvalues().head(kept), Eigen::MatrixXd(Y.rows(), kept)};
    detail::multiply(false, 1.0, Y, small.eigenvectors().leftCols(kept), 0.0, pairs.vectors);
    return pairs;
}

// The k smallest pairs by block Lanczos (block_lanczos.hpp), whose Ritz vectors are M-orthonormal
// to ~1e-12 already; λ = σ + 1/θ is as accurate as a Rayleigh quotient (both err by the square
// of the residual).
Eigenpairs block_eigenpairs(const Sparse& L, const Sparse& M, int k, int nev, int basis, const EigenOptions& options,
                            const Deflation* deflation, EigenReport& report) {
    const auto start = std::chrono::steady_clock::now();
    if (options.progress)
        std::fprintf(stderr, "eigs: factorizing L - sigma M (n = %ld)\n", static_cast<long>(L.rows()));
    detail::BlockLanczosOptions lanczos_options{.wanted = k,
                                                .margin = nev - k,
                                                .max_columns = basis,
                                                .tolerance = options.tolerance,
                                                .progress = options.progress};
    if (deflation != nullptr)
        lanczos_options.deflate = [deflation](Eigen::Ref<Eigen::MatrixXd> X) { deflation->apply(X); };
    const detail::BasisShape shape = detail::basis_shape(L.rows(), lanczos_options);
    Eigen::MatrixXd storage(L.rows(), shape.capacity);
    const Sparse A = shifted_matrix(L, M, report.sigma, deflation);
    CholeskySolver factor;
    {
        // CHOLMOD's ordering runs on one thread; the other maps the basis's expected pages
        // meanwhile, one block at a time until the analysis ends (leaving the scope, also by an
        // exception, stops and joins it). The first writes would otherwise fault them in one at
        // a time (nefertiti k = 50: 29 ms of 0.36 s).
        std::optional<std::jthread> mapper;
        if (omp_get_max_threads() > 1)
            mapper.emplace([&](const std::stop_token& stop) {
                const auto block = static_cast<size_t>(L.rows() * shape.block);
                for (Eigen::Index column = 0; column < shape.expected && !stop.stop_requested(); column += shape.block)
                    detail::prefault(storage.col(column).data(), block * sizeof(double));
            });
        factor.analyze(A);
    }
    detail::explained(kShiftedMatrix, kShiftAdvice, [&] { factor.factorize(A); });
    if (options.progress)
        std::fprintf(stderr, "eigs: factorized in %.1f s; block Lanczos for %d pairs\n",
                     std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), k);
    detail::BlockLanczosResult lanczos = detail::block_lanczos(factor, M, lanczos_options, std::move(storage));
    report.iterations = lanczos.steps;
    report.solves = lanczos.solves;
    report.status = lanczos.converged ? EigenStatus::converged : EigenStatus::not_converged;
    return {report.sigma + lanczos.ritz_values.cwiseInverse().array(), std::move(lanczos.ritz_vectors)};
}

// The sizes of a Lanczos run for k pairs among n unknowns: the pairs it tests (nev, k and a
// margin) and its basis (options.basis_size or a default, at most n). Lanczos from one start
// vector can miss members of a cluster of (nearly) equal eigenvalues when only the wanted pairs
// are tested for convergence; on icospheres it did. So it is asked for a margin of extra pairs,
// which must converge too, and the k smallest are kept. Blocks find up to block-size equal
// eigenvalues at once and need a smaller margin.
struct LanczosSize {
    int nev = 0, basis = 0;
};

LanczosSize lanczos_size(int k, int n, const EigenOptions& options) {
    const bool block = options.solver == EigenSolver::block_lanczos;
    const int with_margin = std::min(n - 1, k + std::max(kMinEigenMargin, block ? k / 5 : k / 2));
    const int default_basis = block ? std::max(6 * with_margin, 160) : std::max(2 * with_margin + 1, 20);
    const int basis = std::min(n, options.basis_size == 0 ? default_basis : options.basis_size);
    return {std::min(with_margin, basis - 1), basis};
}

// The k smallest of the pairs found in the complement of the modes and the modes' own, whose
// eigenvalue is 0 (their Rayleigh quotients are rounding), ascending; modes in their order, and
// before pairs of the same value.
Eigenpairs with_constant_modes(const Eigenpairs& found, const detail::ConstantModes& modes, int k) {
    const int from_modes = std::min(k, modes.count());
    std::vector<std::pair<double, int>> order;  // value, then mode j as -1 - j or found pair i as i
    for (int j = 0; j < from_modes; ++j) order.emplace_back(0.0, -1 - j);
    for (int i = 0; i < found.values.size(); ++i) order.emplace_back(found.values[i], i);
    std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    const int kept = std::min(k, static_cast<int>(order.size()));
    Eigenpairs pairs{Eigen::VectorXd(kept), Eigen::MatrixXd(static_cast<Eigen::Index>(modes.mode_of.size()), kept)};
    for (int c = 0; c < kept; ++c) {
        const auto [value, source] = order[static_cast<size_t>(c)];
        pairs.values[c] = value;
        pairs.vectors.col(c) = source < 0 ? modes.vector(-1 - source) : Eigen::VectorXd(found.vectors.col(source));
    }
    return pairs;
}

// Below this many unknowns a basis that fills half the space or more is replaced by a dense
// solve: block Lanczos's last blocks then lie almost inside its basis. On the icosahedron (12
// vertices, eigenvalues of multiplicities 1, 3, 5, 3) its pairs came out with ΦᵀMΦ − I of 1e-7,
// and on a converted soup of 166 vertices with six components and a basis of 160, of 7.7e-8 with
// residuals of 6.4e-5 (both found by fuzz_pipeline).
constexpr int kMaxDenseUnknowns = 400;

// All pairs of the dense problem, the k smallest kept (exact to rounding, M-orthonormal), one
// block at a time: each component with a mode, then the other unknowns together (L and M have
// no entries between blocks). Solved whole, a component of tiny area had spoilt the others: the
// solver scales by M^(-1/2), so its errors are of the order of the largest eigenvalue, which
// such a component makes huge; beside a sphere 1e-9 across, the sphere's pairs came out with an
// eigenvalue of -7,443 (`Components.ATinyComponentKeepsEveryResidualSmall`). A block's mode is
// moved above the rest of its spectrum: L + μ (MZ)(MZ)ᵀ, Z the M-normalised mode, has it at μ and
// every pair M-orthogonal to it unchanged, and μ = 1 + 2‖M⁻¹L‖_F exceeds every eigenvalue, so it
// is the block's last pair, left out. (A basis of the modes' complement instead made an
// ill-conditioned mass matrix: on a soup with vertex areas from 4e-3 to 2.5e9, ΦᵀMΦ − I of 1.8e-8.)
Eigenpairs dense_eigenpairs(const Sparse& L, const Sparse& M, int k, const detail::ConstantModes* deflated,
                            EigenReport& report) {
    const int n = static_cast<int>(L.rows());
    const int modes = deflated != nullptr ? deflated->count() : 0;
    std::vector<std::vector<int>> blocks(static_cast<size_t>(modes) + 1);
    for (int i = 0; i < n; ++i) {
        const int mode = deflated != nullptr ? deflated->mode_of[static_cast<size_t>(i)] : -1;
        blocks[static_cast<size_t>(mode >= 0 ? mode : modes)].push_back(i);
    }
    const Eigen::MatrixXd dense_L(L), dense_M(M);
    struct Pair {
        double value;
        int block, column;
    };
    std::vector<Pair> found;
    std::vector<Eigen::MatrixXd> vectors(blocks.size());
    for (int b = 0; b < static_cast<int>(blocks.size()); ++b) {
        const std::vector<int>& rows = blocks[static_cast<size_t>(b)];
        if (rows.empty()) continue;
        Eigen::MatrixXd A = dense_L(rows, rows);
        const Eigen::MatrixXd B = dense_M(rows, rows);
        const bool has_mode = b < modes;
        if (has_mode) {
            const Eigen::VectorXd MZ = B * Eigen::VectorXd(deflated->vector(b)(rows));
            const double above = 1 + 2 * B.llt().solve(A).norm();
            A.selfadjointView<Eigen::Lower>().rankUpdate(MZ, above);
            A.triangularView<Eigen::StrictlyUpper>() = A.transpose();
        }
        const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense{A, B};
        if (dense.info() != Eigen::Success)
            throw NumericalError("eigenpairs: the dense solve failed (M not positive definite?)");
        const int block_pairs = static_cast<int>(rows.size()) - (has_mode ? 1 : 0);
        for (int c = 0; c < block_pairs; ++c) found.push_back({dense.eigenvalues()[c], b, c});
        vectors[static_cast<size_t>(b)] = dense.eigenvectors();
    }
    std::stable_sort(found.begin(), found.end(), [](const Pair& x, const Pair& y) { return x.value < y.value; });
    const int kept = std::min(k, static_cast<int>(found.size()));
    Eigenpairs pairs{Eigen::VectorXd(kept), Eigen::MatrixXd::Zero(n, kept)};
    for (int j = 0; j < kept; ++j) {
        const Pair& p = found[static_cast<size_t>(j)];
        pairs.values[j] = p.value;
        const std::vector<int>& rows = blocks[static_cast<size_t>(p.block)];
        pairs.vectors.col(j)(rows) = vectors[static_cast<size_t>(p.block)].col(p.column);
    }
    report.status = EigenStatus::converged;
    return pairs;
}

// The report's accuracy: the largest relative residual and the largest entry of ΦᵀMΦ − I (of
// its lower triangle, computed alone). A residual is ‖Lφ − λMφ‖ / (max(|λ|, |σ|) ‖Mφ‖), but
// ‖Lφ‖ / ‖|L||φ|‖ for λ = 0 exactly (the components' constant modes): there the eigenvalue gives
// no scale, and Lφ is the rounding of L's row sums, which over |σ| ‖Mφ‖ grows without bound as a
// component's area shrinks (1e8 for 0 on a whiteboard's sliver of area 1.5e-11). Blocks of
// columns, two side by side, each thread reusing its products' storage (fresh pages are slow to
// touch); maxima do not depend on the order.
void measure_accuracy(const Sparse& L, const Sparse& M, const Eigen::VectorXd& values, const Eigen::MatrixXd& phi,
                      EigenReport& report) {
    constexpr Eigen::Index kBlock = 8;
    const Eigen::Index n = phi.rows(), k = phi.cols(), blocks = (k + kBlock - 1) / kBlock;
    const detail::MassProduct mass(M);
    Eigen::VectorXd residual(k);
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(k, k);  // ΦᵀMΦ, lower triangle
    const bool zeros = (values.array() == 0).any();
    const Sparse absolute_L = zeros ? Sparse(L.cwiseAbs()) : Sparse();
#pragma omp parallel num_threads(2)
    {
        Eigen::MatrixXd L_phi(n, std::min(kBlock, k)), M_phi(n, std::min(kBlock, k));
#pragma omp for schedule(static, 1)
        for (Eigen::Index block = 0; block < blocks; ++block) {
            const Eigen::Index first = block * kBlock, width = std::min(kBlock, k - first);
            detail::symmetric_product(L, phi.middleCols(first, width), L_phi.leftCols(width));
            mass.apply(phi.middleCols(first, width), M_phi.leftCols(width));
            for (Eigen::Index j = 0; j < width; ++j) {
                const double lambda = values[first + j];
                if (lambda == 0) {
                    const Eigen::VectorXd terms = absolute_L * phi.col(first + j).cwiseAbs();
                    const double size = terms.norm();  // 0: φ lives on rows of L that are all 0
                    residual[first + j] = size > 0 ? L_phi.col(j).norm() / size : 0.0;
                    continue;
                }
                const double scale = std::max(std::abs(lambda), std::abs(report.sigma)) * M_phi.col(j).norm();
                residual[first + j] = (L_phi.col(j) - lambda * M_phi.col(j)).norm() / scale;
            }
            detail::multiply(true, 1.0, phi.rightCols(k - first), M_phi.leftCols(width), 0.0,
                             gram.block(first, first, k - first, width));
        }
    }
    report.max_residual = residual.maxCoeff();
    report.max_orthogonality_error =
        (gram - Eigen::MatrixXd::Identity(k, k)).triangularView<Eigen::Lower>().toDenseMatrix().cwiseAbs().maxCoeff();
}

// Minus the median cotan weight sum over the area (see EigenOptions::sigma). A mean was thrown off
// by slivers: on a converted lettuce of 338 vertices one vertex's sum of 2.6e7 put the shift at
// -13,195 for eigenvalues 0-11, whose transformed values 1/(λ - σ) then lay within 0.1 % of each
// other, and block Lanczos ended with λ0 = 0.9999 (not converged); the median gives -0.52.
double automatic_shift(const Sparse& L, const Sparse& M) {
    Eigen::VectorXd weight_sums = L.diagonal();
    const auto middle = weight_sums.begin() + weight_sums.size() / 2;
    std::nth_element(weight_sums.begin(), middle, weight_sums.end());
    return -*middle / M.diagonal().sum();
}

}  // namespace

std::string_view to_string(EigenStatus status) {
    return status == EigenStatus::converged ? "converged" : "not_converged";
}

std::string_view to_string(EigenSolver solver) {
    return solver == EigenSolver::block_lanczos ? "block" : "spectra";
}

EigenResult smallest_eigenpairs(const Sparse& L_full, const Sparse& M_full, const EigenOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    check_arguments(L_full, M_full, options);
    const int n_all = static_cast<int>(L_full.rows());
    const bool restricted = !options.dirichlet_vertices.empty();
    const Sparse P =
        restricted ? detail::VertexSplit::make(n_all, options.dirichlet_vertices, "eigenpairs").free : Sparse();
    // The products below use both triangles, compressed: the free rows and columns, or the
    // matrices themselves (a copy only if they are not compressed).
    const auto operand = [&](const Sparse& full, Sparse& storage) -> const Sparse& {
        if (restricted)
            storage = detail::restrict_to(full, P, P);
        else if (!full.isCompressed())
            storage = full;
        else
            return full;
        storage.makeCompressed();
        return storage;
    };
    Sparse L_storage, M_storage;
    const Sparse& L = operand(L_full, L_storage);
    const Sparse& M = operand(M_full, M_storage);
    const UnitScales scales = unit_scales(L, M);
    if (scales.stiffness != 1) scale_operand(L, scales.stiffness, L_storage);
    if (scales.mass != 1) scale_operand(M, scales.mass, M_storage);
    const Sparse& L_unit = scales.stiffness != 1 ? L_storage : L;
    const Sparse& M_unit = scales.mass != 1 ? M_storage : M;
    const int n = static_cast<int>(L.rows());
    const int k = options.k;
    if (k < 1 || k >= n)
        throw InvalidArgumentError("eigenpairs: k must satisfy 1 <= k < n = " + std::to_string(n) + ", got " +
                                   std::to_string(k));
    if (options.basis_size != 0 && (options.basis_size <= k || options.basis_size > n))
        throw InvalidArgumentError("eigenpairs: basis_size must be in (k, n] = (" + std::to_string(k) + ", " +
                                   std::to_string(n) + "], got " + std::to_string(options.basis_size));
    const bool block = options.solver == EigenSolver::block_lanczos;

    EigenReport report;
    report.solver = options.solver;
    // The solve runs on the unit problem (L_unit, M_unit) = (aL, cM), whose pairs are (aλ/c, φ/√c).
    const double to_unit = scales.stiffness / scales.mass;
    report.sigma = std::isnan(options.sigma) ? automatic_shift(L_unit, M_unit) : options.sigma * to_unit;
    if (!(report.sigma < 0))
        throw InvalidArgumentError("eigenpairs: the automatic shift is not negative (trace(L) = " +
                                   std::to_string(L.diagonal().sum()) + ", trace(M) = " +
                                   std::to_string(M.diagonal().sum()) + "); pass sigma");

    EigenResult result;
    const bool dense = block && 2 * lanczos_size(k, n, options).basis >= n && n <= kMaxDenseUnknowns;
    // The components' constant functions are eigenvectors of eigenvalue 0 (constant_modes.hpp),
    // hence among the smallest pairs, L being positive semidefinite. The solvers seek the other
    // pairs in their complement (Lanczos when its basis leaves room there; else all k).
    const detail::ConstantModes modes = detail::constant_modes(L_unit, M_unit);
    const int known = std::min(k, modes.count()), complement = n - modes.count();
    const bool deflate = known > 0 && (dense || lanczos_size(k - known, complement, options).basis < complement);
    const int sought = deflate ? k - known : k;
    const LanczosSize size = lanczos_size(sought, deflate ? complement : n, options);
    Deflation deflation{modes, {}};
    const auto ground = [&] {  // for the shift report.sigma
        deflation.grounded.clear();
        if (deflate && !dense)
            for (const int j : modes.lost_shift(L_unit, -report.sigma)) deflation.grounded.push_back(modes.first[j]);
    };
    ground();
    const Deflation* deflated = deflate ? &deflation : nullptr;
    if (options.progress && !block && sought > 0)
        std::fprintf(stderr, "eigs: Spectra's Lanczos for %d pairs (n = %d; no lines until it ends)\n", sought, n);
    const auto [nev, basis] = size;
    Eigenpairs pairs = sought == 0 ? Eigenpairs{}
                       : dense     ? dense_eigenpairs(L_unit, M_unit, sought, deflate ? &modes : nullptr, report)
                       : block     ? block_eigenpairs(L_unit, M_unit, sought, nev, basis, options, deflated, report)
                                   : spectra_eigenpairs(L_unit, M_unit, sought, nev, basis, options, deflated, report);
    // The automatic shift can sit far below the spectrum, where the transformed eigenvalues
    // 1/(λ - σ) crowd together and the basis fills before they converge: on a CAD plate whose
    // slivers raise the median weight sum, σ was 30 times the first eigenvalue below 0, and 160
    // columns did not converge 4 pairs. Then a second run starts from a tenth of the smallest
    // Ritz value below 0 (an upper bound of λ₁, so the shift stays below the spectrum). Not when
    // that value is nearly 0 against σ: a zero eigenvalue not deflated (its rows' sums not 0 to
    // rounding) would leave L − σM nearly singular.
    if (block && !dense && std::isnan(options.sigma) && report.status == EigenStatus::not_converged &&
        pairs.values.size() > 0 && pairs.values.minCoeff() > 1e-6 * -report.sigma &&
        pairs.values.minCoeff() < -report.sigma) {
        const int solves = report.solves, iterations = report.iterations;
        const double sigma = report.sigma;
        report.sigma = -0.1 * pairs.values.minCoeff();
        if (options.progress)
            std::fprintf(stderr, "eigs: not converged with sigma = %g; again with sigma = %g, nearer the spectrum\n",
                         sigma / to_unit, report.sigma / to_unit);
        ground();
        pairs = block_eigenpairs(L_unit, M_unit, sought, nev, basis, options, deflated, report);
        report.solves += solves;
        report.iterations += iterations;
    }
    if (deflate) pairs = with_constant_modes(pairs, modes, k);
    measure_accuracy(L_unit, M_unit, pairs.values, pairs.vectors, report);  // relative: the same in any unit
    report.sigma /= to_unit;
    result.values = pairs.values / to_unit;
    pairs.vectors *= std::sqrt(scales.mass);
    result.vectors = restricted ? Eigen::MatrixXd(P.transpose() * pairs.vectors) : std::move(pairs.vectors);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (options.progress)
        std::fprintf(stderr, "eigs: %s, %d solves, %.1f s\n", to_string(report.status).data(), report.solves,
                     report.seconds);
    result.report = report;
    return result;
}

}  // namespace sdmesh
