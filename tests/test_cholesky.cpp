// The CHOLMOD wrapper: solves, refactorization on a fixed pattern, typed errors.

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>
#include <omp.h>

#include "sdmesh/cholesky.hpp"
#include "sdmesh/error.hpp"

#include "supernodal_factor.hpp"  // white-box: the factorization against CHOLMOD's
#include "supernodal_solve.hpp"   // white-box: the two-thread solve plan

namespace sdmesh {
namespace {

// shift·I + the graph Laplacian of an n × n grid: SPD for shift > 0, singular for shift = 0,
// indefinite for shift < 0.
Eigen::SparseMatrix<double> grid_matrix(int n, double shift) {
    std::vector<Eigen::Triplet<double>> entries;
    auto id = [n](int i, int j) { return j * n + i; };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            entries.emplace_back(id(i, j), id(i, j), shift);
            for (auto [di, dj] : {std::pair{1, 0}, std::pair{0, 1}}) {
                if (i + di >= n || j + dj >= n) continue;
                const int a = id(i, j), b = id(i + di, j + dj);
                entries.emplace_back(a, a, 1.0);
                entries.emplace_back(b, b, 1.0);
                entries.emplace_back(a, b, -1.0);
                entries.emplace_back(b, a, -1.0);
            }
        }
    Eigen::SparseMatrix<double> A(n * n, n * n);
    A.setFromTriplets(entries.begin(), entries.end());
    return A;
}

TEST(Cholesky, SolvesAndRefactorizes) {
    const Eigen::SparseMatrix<double> A = grid_matrix(30, 0.1);
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(A.rows(), 3);
    CholeskySolver solver(A);
    EXPECT_EQ(solver.rows(), 900);
    const Eigen::MatrixXd x = solver.solve_columns(b);
    EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm());

    const Eigen::SparseMatrix<double> B = grid_matrix(30, 2.5);  // same pattern, other values
    solver.factorize(B);
    const Eigen::VectorXd y = solver.solve(Eigen::VectorXd(b.col(0)));
    EXPECT_LT((B * y - b.col(0)).norm(), 1e-10 * b.col(0).norm());
}

// Right-hand sides are solved four at a time, in one pass over the factor: every group size and
// remainder gives each column the answer it gets alone. The 80 x 80 grid's separators make
// supernodes of many columns, whose column counts leave every remainder modulo four.
TEST(Cholesky, SolvesAnyNumberOfColumnsAsEachAlone) {
    const Eigen::SparseMatrix<double> A = grid_matrix(80, 0.05);
    const CholeskySolver solver(A);
    for (const int columns : {1, 2, 3, 4, 5, 6, 7, 9}) {
        const Eigen::MatrixXd b = Eigen::MatrixXd::Random(A.rows(), columns);
        const Eigen::MatrixXd x = solver.solve_columns(b);
        EXPECT_LT((A * x - b).norm(), 1e-10 * b.norm()) << columns << " columns";
        for (int j = 0; j < columns; ++j) {
            const Eigen::VectorXd alone = solver.solve(Eigen::VectorXd(b.col(j)));
            EXPECT_LT((x.col(j) - alone).norm(), 1e-13 * alone.norm()) << "column " << j << " of " << columns;
        }
    }
}

// The factor's BLAS runs on one thread whatever the caller's OpenMP setting, and solves share
// the elimination tree between two threads in a fixed way, so solutions do not depend on it (a
// 200 x 200 grid has supernodes large enough for a threaded BLAS to split them, and a factor
// large enough for a two-thread solve), and the caller's setting is left as it was.
TEST(Cholesky, SolutionsDoNotDependOnTheThreadCount) {
    const Eigen::SparseMatrix<double> A = grid_matrix(200, 0.01);
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(A.rows(), 2);
    const int initial = omp_get_max_threads();
    omp_set_num_threads(1);
    const Eigen::MatrixXd x1 = CholeskySolver(A).solve_columns(b);
    omp_set_num_threads(2);
    const Eigen::MatrixXd x2 = CholeskySolver(A).solve_columns(b);
    EXPECT_EQ(omp_get_max_threads(), 2);
    omp_set_num_threads(initial);
    EXPECT_TRUE(x1 == x2) << "largest difference " << (x1 - x2).cwiseAbs().maxCoeff();
    EXPECT_LT((A * x1 - b).norm(), 1e-10 * b.norm());
}

// Several components side by side (a forest of elimination trees).
Eigen::SparseMatrix<double> block_diagonal(const std::vector<Eigen::SparseMatrix<double>>& blocks) {
    std::vector<Eigen::Triplet<double>> entries;
    int offset = 0;
    for (const auto& block : blocks) {
        for (int j = 0; j < block.outerSize(); ++j)
            for (Eigen::SparseMatrix<double>::InnerIterator it(block, j); it; ++it)
                entries.emplace_back(offset + static_cast<int>(it.row()), offset + j, it.value());
        offset += static_cast<int>(block.rows());
    }
    Eigen::SparseMatrix<double> A(offset, offset);
    A.setFromTriplets(entries.begin(), entries.end());
    return A;
}

// A CHOLMOD supernodal analysis of A's lower triangle with one ordering, freed with it.
struct CholmodAnalysis {
    cholmod_common common{};
    Eigen::SparseMatrix<double> lower;
    cholmod_sparse view{};  // of `lower`, no copy
    cholmod_factor* factor = nullptr;

    CholmodAnalysis(const Eigen::SparseMatrix<double>& A, int ordering) : lower(A.triangularView<Eigen::Lower>()) {
        cholmod_start(&common);
        common.supernodal = CHOLMOD_SUPERNODAL;
        common.nmethods = 1;
        common.method[0].ordering = ordering;
        view.nrow = view.ncol = static_cast<size_t>(lower.rows());
        view.nzmax = static_cast<size_t>(lower.nonZeros());
        view.p = lower.outerIndexPtr();
        view.i = lower.innerIndexPtr();
        view.x = lower.valuePtr();
        view.stype = -1;
        view.itype = CHOLMOD_INT;
        view.xtype = CHOLMOD_REAL;
        view.dtype = CHOLMOD_DOUBLE;
        view.sorted = view.packed = 1;
        factor = cholmod_analyze(&view, &common);
    }
    ~CholmodAnalysis() {
        if (factor) cholmod_free_factor(&factor, &common);
        cholmod_finish(&common);
    }
    CholmodAnalysis(const CholmodAnalysis&) = delete;
    CholmodAnalysis& operator=(const CholmodAnalysis&) = delete;
};

// One elimination tree and a forest, both large enough for two-thread plans.
std::vector<std::pair<std::string, Eigen::SparseMatrix<double>>> two_thread_cases() {
    return {{"grid 200", grid_matrix(200, 0.01)},
            {"three grids", block_diagonal({grid_matrix(150, 0.01), grid_matrix(90, 0.01), grid_matrix(120, 0.01)})}};
}

// The plan of a two-thread solve partitions the supernodes into two parts of whole subtrees and
// a top closed towards the root, with the parts' work (factor entries) balanced, for one tree
// (nested dissection, AMD) and for a forest.
TEST(Cholesky, TwoThreadSolvePlanSplitsTheEliminationTreeEvenly) {
    for (const auto& [name, A] : two_thread_cases()) {
        for (const int ordering : {CHOLMOD_AMD, CHOLMOD_METIS}) {
            const CholmodAnalysis analysis(A, ordering);
            const cholmod_factor* factor = analysis.factor;
            ASSERT_NE(factor, nullptr);
            const detail::SolvePlan plan = detail::plan_solve(*factor);

            const auto* super = static_cast<const int*>(factor->super);
            const auto* row_start = static_cast<const int*>(factor->pi);
            const auto* rows = static_cast<const int*>(factor->s);
            const int supernodes = static_cast<int>(factor->nsuper);
            std::vector<int> owner(static_cast<size_t>(supernodes), -2), supernode_of(factor->n);
            long work[3] = {0, 0, 0};
            for (int part = 0; part < 3; ++part)
                for (const int s : part < 2 ? plan.parts[part] : plan.top) {
                    EXPECT_EQ(owner[s], -2) << "supernode " << s << " twice";
                    owner[s] = part;
                }
            for (int s = 0; s < supernodes; ++s) {
                ASSERT_NE(owner[s], -2) << name << ": supernode " << s << " in no part";
                for (int c = super[s]; c < super[s + 1]; ++c) supernode_of[c] = s;
                work[owner[s]] += static_cast<long>(super[s + 1] - super[s]) * (row_start[s + 1] - row_start[s]);
            }
            int top_columns = 0;
            for (int s = 0; s < supernodes; ++s) {
                const int columns = super[s + 1] - super[s];
                if (row_start[s + 1] - row_start[s] > columns) {
                    const int parent = supernode_of[rows[row_start[s] + columns]];
                    EXPECT_TRUE(owner[parent] == owner[s] || owner[parent] == 2)
                        << name << ": supernode " << s << " of part " << owner[s] << " has its parent in part "
                        << owner[parent];
                }
                for (int c = super[s]; c < super[s + 1]; ++c)
                    EXPECT_EQ(plan.top_slot[c], owner[s] == 2 ? top_columns++ : -1);
            }
            EXPECT_EQ(plan.top_columns, top_columns);
            const double total = static_cast<double>(work[0] + work[1] + work[2]);
            EXPECT_LT(std::abs(work[0] - work[1]), 0.05 * total) << name << ", ordering " << ordering;
            EXPECT_LT(work[2], 0.15 * total) << name << ", ordering " << ordering;
        }
    }
}

// shift·I + the graph Laplacian of a path of n vertices: its elimination tree is a chain, which
// no cut balances.
Eigen::SparseMatrix<double> path_matrix(int n, double shift) {
    std::vector<Eigen::Triplet<double>> entries;
    for (int i = 0; i < n; ++i) {
        entries.emplace_back(i, i, shift + (i > 0) + (i + 1 < n));
        if (i + 1 < n) {
            entries.emplace_back(i, i + 1, -1.0);
            entries.emplace_back(i + 1, i, -1.0);
        }
    }
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(entries.begin(), entries.end());
    return A;
}

// The factor against CHOLMOD's own numeric factorization on the same symbolic analysis, entry by
// entry: small supernodes (inline kernels) and the nested-dissection separators of a 200 x 200
// grid (LAPACK and BLAS), on one tree and on a forest, on one thread and two. The factors must
// agree to rounding and be bit-identical for one and two threads.
TEST(Cholesky, SupernodalFactorMatchesCholmods) {
    const int initial = omp_get_max_threads();
    for (const auto& [name, A] : two_thread_cases()) {
        for (const int ordering : {CHOLMOD_AMD, CHOLMOD_METIS}) {
            CholmodAnalysis analysis(A, ordering);
            cholmod_factor* reference = analysis.factor;
            ASSERT_NE(reference, nullptr);
            const detail::SolvePlan solve_plan = detail::plan_solve(*reference);
            ASSERT_FALSE(solve_plan.parts[0].empty()) << name << ": too small for two threads";
            const detail::FactorPlan plan = detail::plan_factor(*reference, solve_plan, analysis.lower);
            std::vector<double> ours[2];
            for (const int threads : {1, 2}) {
                cholmod_factor* factor = cholmod_copy_factor(reference, &analysis.common);
                omp_set_num_threads(threads);
                const int failed = detail::factorize_supernodal(*factor, solve_plan, plan, analysis.lower, analysis.common);
                const auto* x = static_cast<const double*>(factor->x);
                ours[threads - 1].assign(x, x + factor->xsize);
                cholmod_free_factor(&factor, &analysis.common);
                ASSERT_EQ(failed, -1) << name;
            }
            ASSERT_TRUE(cholmod_factorize(&analysis.view, reference, &analysis.common));  // its BLAS on one thread
            omp_set_num_threads(initial);
            const auto* expected = static_cast<const double*>(reference->x);
            ASSERT_EQ(ours[0].size(), reference->xsize);
            double largest = 0, error = 0;
            for (size_t k = 0; k < ours[0].size(); ++k) {
                largest = std::max(largest, std::abs(expected[k]));
                error = std::max(error, std::abs(ours[0][k] - expected[k]));
            }
            EXPECT_LT(error, 1e-13 * largest) << name << ", ordering " << ordering;
            EXPECT_TRUE(ours[0] == ours[1]) << name << ", ordering " << ordering << ": depends on the thread count";
        }
    }
}

// Two-thread solves against a simplicial reference, with either ordering, on one tree, on a
// forest and on a chain.
TEST(Cholesky, TwoThreadSolvesMatchAReferenceFactorization) {
    for (const auto& A : {grid_matrix(200, 0.01), block_diagonal({grid_matrix(150, 0.01), grid_matrix(90, 0.01)}),
                          path_matrix(400000, 0.01)}) {
        const Eigen::MatrixXd b = Eigen::MatrixXd::Random(A.rows(), 5);
        const Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> reference(A);
        const Eigen::MatrixXd expected = reference.solve(b);
        for (const auto ordering : {CholeskyOrdering::amd, CholeskyOrdering::metis}) {
            const Eigen::MatrixXd x = CholeskySolver(A, {.ordering = ordering}).solve_columns(b);
            EXPECT_LT((x - expected).norm(), 1e-10 * expected.norm());
        }
    }
}

TEST(Cholesky, RejectsMatricesThatAreNotPositiveDefinite) {
    EXPECT_THROW(CholeskySolver(grid_matrix(10, -0.5)), NumericalError);
    EXPECT_THROW(CholeskySolver(grid_matrix(200, -0.5)), NumericalError);  // in the two-thread parts
    EXPECT_THROW(CholeskySolver(grid_matrix(200, 0.0)), NumericalError);   // singular: the last pivot is 0
    CholeskySolver solver(grid_matrix(10, 1.0));
    EXPECT_THROW(solver.factorize(grid_matrix(10, -0.5)), NumericalError);
    EXPECT_THROW((void)solver.solve(Eigen::VectorXd::Ones(100)), InvalidArgumentError);  // factor is gone
    // The message names the failing row in the matrix's numbering, not in the factor's order:
    // every other principal submatrix is definite, so the first pivot to fail is row 437's.
    Eigen::SparseMatrix<double> A = grid_matrix(30, 0.1);
    A.coeffRef(437, 437) = -100;
    try {
        CholeskySolver indefinite(A);
        ADD_FAILURE() << "no NumericalError";
    } catch (const NumericalError& e) {
        EXPECT_NE(std::string(e.what()).find("the pivot of row 437 is not positive"), std::string::npos) << e.what();
    }
}

TEST(Cholesky, RejectsMisuse) {
    CholeskySolver solver;
    EXPECT_THROW(solver.factorize(grid_matrix(4, 1.0)), InvalidArgumentError);
    EXPECT_THROW((void)solver.solve(Eigen::VectorXd::Ones(16)), InvalidArgumentError);
    EXPECT_THROW(solver.analyze(Eigen::SparseMatrix<double>(3, 4)), InvalidArgumentError);
    solver.analyze(grid_matrix(4, 1.0));
    EXPECT_THROW(solver.factorize(grid_matrix(5, 1.0)), InvalidArgumentError);
    // As many entries as the analysed matrix, in other places: (0, 5) and (5, 0) for (0, 1) and (1, 0).
    Eigen::SparseMatrix<double> moved = grid_matrix(4, 1.0);
    moved.prune([](Eigen::Index row, Eigen::Index column, double) { return row + column != 1; });
    moved.insert(0, 5) = moved.insert(5, 0) = -0.5;
    moved.makeCompressed();
    ASSERT_EQ(moved.nonZeros(), grid_matrix(4, 1.0).nonZeros());
    EXPECT_THROW(solver.factorize(moved), InvalidArgumentError);
    solver.factorize(grid_matrix(4, 1.0));
    EXPECT_THROW((void)solver.solve(Eigen::VectorXd::Ones(15)), InvalidArgumentError);
}

TEST(Cholesky, EveryOrderingSolves) {
    const Eigen::SparseMatrix<double> A = grid_matrix(30, 0.1);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1, 2);
    for (CholeskyOrdering ordering : {CholeskyOrdering::automatic, CholeskyOrdering::amd, CholeskyOrdering::metis,
                                      CholeskyOrdering::nested_dissection, CholeskyOrdering::coarse_nested_dissection}) {
        const CholeskySolver solver(A, {.ordering = ordering});
        EXPECT_LT((A * solver.solve(b) - b).norm(), 1e-10 * b.norm()) << "ordering " << static_cast<int>(ordering);
    }
}

TEST(Cholesky, SameOrderingAsGivesIdenticalSolutions) {
    const Eigen::SparseMatrix<double> A = grid_matrix(30, 0.1), B = grid_matrix(30, 2.5);
    const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(A.rows(), -1, 2);
    for (CholeskyOrdering ordering : {CholeskyOrdering::amd, CholeskyOrdering::metis}) {
        const CholeskySolver first(A, {.ordering = ordering});
        // Same pattern, the ordering reused: the same factor, so bit-identical solutions.
        const CholeskySolver shared(B, {.same_ordering_as = &first});
        const CholeskySolver own(B, {.ordering = ordering});
        EXPECT_EQ(shared.solve(b), own.solve(b));
        EXPECT_LT((B * shared.solve(b) - b).norm(), 1e-10 * b.norm());
    }
    // Reusing a solver's own ordering for a new analysis.
    CholeskySolver solver(A, {.ordering = CholeskyOrdering::metis});
    const Eigen::VectorXd x = solver.solve(b);
    solver.analyze(A, {.same_ordering_as = &solver});
    solver.factorize(A);
    EXPECT_EQ(solver.solve(b), x);
}

TEST(Cholesky, SameOrderingAsMustBeAnalysedAndOfTheSameSize) {
    const CholeskySolver empty;
    CholeskySolver solver;
    EXPECT_THROW(solver.analyze(grid_matrix(4, 1.0), {.same_ordering_as = &empty}), InvalidArgumentError);
    const CholeskySolver small(grid_matrix(4, 1.0));
    EXPECT_THROW(solver.analyze(grid_matrix(5, 1.0), {.same_ordering_as = &small}), InvalidArgumentError);
}

}  // namespace
}  // namespace sdmesh
