#include "supernodal_factor.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <cblas.h>
#include <omp.h>

#include "sdmesh/error.hpp"

#include "blas.hpp"

extern "C" {
// LAPACK's Cholesky factorization of a dense symmetric matrix (Fortran interface).
void dpotrf_(const char* uplo, const int* n, double* a, const int* lda, int* info);
}

namespace sdmesh::detail {
namespace {

// Updates with fewer multiply-adds than this are computed inline; larger ones by BLAS, whose
// per-call cost (argument checks, packing) only pays off on larger blocks.
constexpr long kMinBlasUpdate = 4096;
// Supernodes with more columns than this are factored by LAPACK and BLAS, smaller ones inline.
constexpr int kMinLapackColumns = 32;

// Per-thread scratch: the local row of each factor row in the supernode being factored, and the
// update matrix of one descendant.
struct Scratch {
    std::vector<int> local_row;
    std::vector<double> update;
};

// The descendants waiting to update each supernode, as linked lists kept apart by the group of
// the descendant, so that the parts' threads never write the same list and every supernode
// takes its updates in the same order on any number of threads: group 0's, 1's, then 2's.
struct PendingUpdates {
    std::vector<int> head[3];   // per group and target supernode: the first descendant, or -1
    std::vector<int> next;      // per supernode: the next descendant in its list
    std::vector<int> position;  // per supernode: its first row not yet used in an update
};

// C = L_d(p1:, :) L_d(p1:p2, :)ᵀ, lower trapezoid (n2 x n1, column-major, leading dimension n2).
void compute_update(const double* block, int height, int columns, int p1, int n1, int n2, double* C) {
    const double* top = block + p1;
    if (static_cast<long>(n1) * n2 * columns >= kMinBlasUpdate) {
        cblas_dsyrk(CblasColMajor, CblasLower, CblasNoTrans, n1, columns, 1.0, top, height, 0.0, C, n2);
        if (n2 > n1)
            cblas_dgemm(CblasColMajor, CblasNoTrans, CblasTrans, n2 - n1, n1, columns, 1.0, top + n1, height, top,
                        height, 0.0, C + n1, n2);
        return;
    }
    for (int j = 0; j < n1; ++j) {
        double* c = C + static_cast<long>(j) * n2;
        std::fill(c + j, c + n2, 0.0);
        for (int k = 0; k < columns; ++k) {
            const double* l = top + static_cast<long>(k) * height;
            const double ljk = l[j];
            for (int i = j; i < n2; ++i) c[i] += l[i] * ljk;
        }
    }
}

// Cholesky of a supernode's block (height x columns, column-major): the triangle on top becomes
// L_ss and the rows below B become B L_ss⁻ᵀ. Returns -1 or the failing column.
int factor_block(double* block, int height, int columns) {
    if (columns > kMinLapackColumns) {
        int info = 0;
        dpotrf_("L", &columns, block, &height, &info);
        if (info != 0) return info - 1;
        if (height > columns)
            cblas_dtrsm(CblasColMajor, CblasRight, CblasLower, CblasTrans, CblasNonUnit, height - columns, columns,
                        1.0, block, height, block + columns, height);
        return -1;
    }
    for (int j = 0; j < columns; ++j) {
        double* c = block + static_cast<long>(j) * height;
        for (int k = 0; k < j; ++k) {
            const double* l = block + static_cast<long>(k) * height;
            const double ljk = l[j];
            for (int i = j; i < height; ++i) c[i] -= l[i] * ljk;
        }
        if (!(c[j] > 0) || !std::isfinite(c[j])) return j;
        const double pivot = std::sqrt(c[j]), inverse = 1 / pivot;
        c[j] = pivot;
        for (int i = j + 1; i < height; ++i) c[i] *= inverse;
    }
    return -1;
}

// Queues supernode d for the supernode holding `row`, the first of its rows not yet used.
void queue_update(PendingUpdates& pending, const FactorPlan& plan, int d, int row) {
    int& list = pending.head[plan.group[d]][plan.supernode_of[row]];
    pending.next[d] = list;
    list = d;
}

// Subtracts descendant d's update from supernode s's block (whose rows scratch.local_row maps)
// and queues d for the next supernode its rows reach.
void apply_update(const SupernodalLayout& f, int d, int s, double* block, const FactorPlan& plan,
                  PendingUpdates& pending, Scratch& scratch) {
    const int first = f.super[s], end = f.super[s + 1], height = f.height(s);
    const int d_height = f.height(d);
    const int* d_rows = f.rows + f.row_start[d];
    const int p1 = pending.position[d];
    int p2 = p1;
    while (p2 < d_height && d_rows[p2] < end) ++p2;
    const int n1 = p2 - p1, n2 = d_height - p1;
    double* C = scratch.update.data();
    compute_update(f.values + f.value_start[d], d_height, f.columns(d), p1, n1, n2, C);
    for (int j = 0; j < n1; ++j) {
        double* target = block + static_cast<long>(d_rows[p1 + j] - first) * height;
        const double* c = C + static_cast<long>(j) * n2;
        for (int i = j; i < n2; ++i) target[scratch.local_row[d_rows[p1 + i]]] -= c[i];
    }
    pending.position[d] = p2;
    if (p2 < d_height) queue_update(pending, plan, d, d_rows[p2]);
}

// Factors the supernodes of one group, ascending (left-looking: each takes the updates of its
// descendants, then is queued for its first ancestor). Returns -1 or the failing column.
int factor_group(const SupernodalLayout& f, const std::vector<int>& supernodes, const FactorPlan& plan, const double* a,
                 PendingUpdates& pending, Scratch& scratch) {
    for (const int s : supernodes) {
        const int columns = f.columns(s), height = f.height(s);
        const int* rows = f.rows + f.row_start[s];
        double* block = f.values + f.value_start[s];
        std::fill(block, block + static_cast<long>(height) * columns, 0.0);
        for (int k = plan.start[s]; k < plan.start[s + 1]; ++k) block[plan.offset[k]] += a[plan.source[k]];
        for (int i = 0; i < height; ++i) scratch.local_row[rows[i]] = i;
        for (auto& head : pending.head)
            for (int d = std::exchange(head[s], -1); d >= 0;) {
                const int next = pending.next[d];  // apply_update relinks d
                apply_update(f, d, s, block, plan, pending, scratch);
                d = next;
            }
        const int failed = factor_block(block, height, columns);
        if (failed >= 0) return f.super[s] + failed;
        pending.position[s] = columns;
        if (height > columns) queue_update(pending, plan, s, rows[columns]);
    }
    return -1;
}

}  // namespace

std::uint64_t pattern_hash(const Eigen::SparseMatrix<double>& A) {
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the pattern's integers
    const auto mix = [&hash](std::uint64_t value) {
        hash ^= value;
        hash *= 1099511628211ull;
    };
    mix(static_cast<std::uint64_t>(A.rows()));
    mix(static_cast<std::uint64_t>(A.cols()));
    for (Eigen::Index c = 0; c <= A.cols(); ++c) mix(static_cast<std::uint64_t>(A.outerIndexPtr()[c]));
    for (Eigen::Index k = 0; k < A.nonZeros(); ++k) mix(static_cast<std::uint64_t>(A.innerIndexPtr()[k]));
    return hash;
}

FactorPlan plan_factor(const cholmod_factor& factor, const SolvePlan& solve_plan, const Eigen::SparseMatrix<double>& A) {
    const SupernodalLayout f(factor);
    const auto n = static_cast<int>(factor.n);
    const auto supernodes = static_cast<int>(factor.nsuper);
    const auto* perm = static_cast<const int*>(factor.Perm);
    FactorPlan plan;
    plan.pattern_hash = pattern_hash(A);
    plan.supernode_of = supernode_of_columns(factor);
    plan.group.assign(static_cast<size_t>(supernodes), 2);
    for (int part = 0; part < 2; ++part)
        for (const int s : solve_plan.parts[part]) plan.group[s] = static_cast<signed char>(part);

    // A's lower-triangle entries by the factor column they land in, min(p(r), p(c)).
    std::vector<int> inverse(static_cast<size_t>(n));
    for (int k = 0; k < n; ++k) inverse[perm[k]] = k;
    std::vector<int> column_start(static_cast<size_t>(n) + 1, 0);
    for (int c = 0; c < n; ++c)
        for (int k = A.outerIndexPtr()[c]; k < A.outerIndexPtr()[c + 1]; ++k)
            if (const int r = A.innerIndexPtr()[k]; r >= c) ++column_start[std::min(inverse[r], inverse[c]) + 1];
    for (int j = 0; j < n; ++j) column_start[j + 1] += column_start[j];
    plan.source.resize(static_cast<size_t>(column_start[n]));
    std::vector<int> other_row(plan.source.size()), fill(column_start.begin(), column_start.end() - 1);
    for (int c = 0; c < n; ++c)
        for (int k = A.outerIndexPtr()[c]; k < A.outerIndexPtr()[c + 1]; ++k)
            if (const int r = A.innerIndexPtr()[k]; r >= c) {
                const int slot = fill[std::min(inverse[r], inverse[c])]++;
                plan.source[slot] = k;
                other_row[slot] = std::max(inverse[r], inverse[c]);
            }

    // Their offsets in the supernodes' blocks, and the largest update matrix.
    plan.start.resize(static_cast<size_t>(supernodes) + 1);
    plan.offset.resize(plan.source.size());
    std::vector<int> local_row(static_cast<size_t>(n));
    for (int s = 0; s < supernodes; ++s) {
        const int first = f.super[s], height = f.height(s), columns = f.columns(s);
        const int* rows = f.rows + f.row_start[s];
        plan.start[s] = column_start[first];
        for (int i = 0; i < height; ++i) local_row[rows[i]] = i;
        for (int j = first; j < f.super[s + 1]; ++j)
            for (int k = column_start[j]; k < column_start[j + 1]; ++k)
                plan.offset[k] = (j - first) * height + local_row[other_row[k]];
        for (int p1 = columns; p1 < height;) {
            const int last = f.super[plan.supernode_of[rows[p1]] + 1];
            int p2 = p1;
            while (p2 < height && rows[p2] < last) ++p2;
            plan.max_update = std::max(plan.max_update, static_cast<long>(height - p1) * (p2 - p1));
            p1 = p2;
        }
    }
    plan.start[supernodes] = column_start[n];
    return plan;
}

int factorize_supernodal(cholmod_factor& factor, const SolvePlan& solve_plan, const FactorPlan& plan,
                         const Eigen::SparseMatrix<double>& A, cholmod_common& common) {
    if (pattern_hash(A) != plan.pattern_hash)
        throw InvalidArgumentError("Cholesky: the matrix does not have the analysed pattern");
    if (factor.xtype == CHOLMOD_PATTERN &&
        !cholmod_change_factor(CHOLMOD_REAL, true, true, true, true, &factor, &common))
        throw NumericalError("Cholesky: could not allocate the factor (CHOLMOD status " +
                             std::to_string(common.status) + ")");
    const SupernodalLayout f(factor);
    const auto supernodes = static_cast<size_t>(factor.nsuper);
    PendingUpdates pending;
    for (auto& head : pending.head) head.assign(supernodes, -1);
    pending.next.assign(supernodes, -1);
    pending.position.assign(supernodes, 0);
    Scratch scratch[2];
    for (auto& s : scratch) {
        s.local_row.resize(factor.n);
        s.update.resize(static_cast<size_t>(std::max(plan.max_update, 1L)));
    }

    // The two parts side by side (BLAS runs on one thread inside a parallel region), then the top.
    const bool split = !solve_plan.parts[0].empty();
    const int threads = std::min(2, omp_get_max_threads());
    int failed[2] = {-1, -1};
#pragma omp parallel for num_threads(threads) schedule(static, 1) if (split)
    for (int part = 0; part < 2; ++part)
        failed[part] = factor_group(f, solve_plan.parts[part], plan, A.valuePtr(), pending, scratch[part]);
    if (failed[0] >= 0 || failed[1] >= 0)
        return failed[0] < 0 ? failed[1] : failed[1] < 0 ? failed[0] : std::min(failed[0], failed[1]);
    const SerialBlas serial;
    return factor_group(f, solve_plan.top, plan, A.valuePtr(), pending, scratch[0]);
}

}  // namespace sdmesh::detail
