#include "supernodal_solve.hpp"

#include <algorithm>
#include <cstring>
#include <memory>
#include <new>

#include <omp.h>

#include "sdmesh/error.hpp"

// Why not cholmod_solve: it makes one dtrsm and one dgemm call per supernode, and a mesh's
// supernodes are small (igea: 7 columns, 24 rows on average), so with a few right-hand sides its
// time went to the BLAS calls and their packing rather than to reading the factor. Here each
// factor entry is read once per pass and used for up to four right-hand sides, whose values for
// one row sit together in one vector register. bench_eigen's CholeskySolve, against
// cholmod_solve in the same minutes: igea 153 → 106 ms for four columns, 85 → 75 ms for one;
// nefertiti 7.7 → 3.5 ms and 3.0 → 2.4 ms. Two threads (SolvePlan) then took igea to 60 and
// 43 ms, nefertiti to 2.1 and 1.5 ms.

namespace sdmesh::detail {
namespace {

// The values of R right-hand sides for one row (GCC/Clang vector extension; R = 1, 2, 4).
template <int R>
struct Lanes;
template <>
struct Lanes<1> {
    using type = double;
};
template <>
struct Lanes<2> {
    typedef double type __attribute__((vector_size(2 * sizeof(double))));
};
template <>
struct Lanes<4> {
    typedef double type __attribute__((vector_size(4 * sizeof(double))));
};

// below[i] += Σ_j L(i, j) z_j over the `columns` columns of a supernode's part under its diagonal
// block (column j at block + j·height), four columns per sweep: each row of `below` is loaded
// and stored once per four factor entries.
template <typename Row>
[[gnu::always_inline]] inline void add_below(const double* block, int height, int columns, const Row* z, int under,
                                             Row* below) {
    int j = 0;
    for (; j + 3 < columns; j += 4) {
        const double *c0 = block + static_cast<long>(j) * height, *c1 = c0 + height, *c2 = c1 + height,
                     *c3 = c2 + height;
        const Row z0 = z[j], z1 = z[j + 1], z2 = z[j + 2], z3 = z[j + 3];
        for (int i = 0; i < under; ++i) below[i] += c0[i] * z0 + c1[i] * z1 + c2[i] * z2 + c3[i] * z3;
    }
    for (; j < columns; ++j) {
        const double* c = block + static_cast<long>(j) * height;
        const Row zj = z[j];
        for (int i = 0; i < under; ++i) below[i] += c[i] * zj;
    }
}

// sum[k] = Σ_i c_k[i] below[i] for K columns c_k at once, so that each row of `below` is loaded
// once per K factor entries.
template <int K, typename Row>
[[gnu::always_inline]] inline void dot_columns(const double* const* c, const Row* below, int under, Row* sum) {
    for (int k = 0; k < K; ++k) sum[k] = Row{};
    for (int i = 0; i < under; ++i)
        for (int k = 0; k < K; ++k) sum[k] += c[k][i] * below[i];
}

// One right-hand side: the sums run four rows at a time in vector lanes (a scalar sum would wait
// on each of its additions).
typedef double Quad __attribute__((vector_size(4 * sizeof(double))));
template <int K>
[[gnu::always_inline]] inline void dot_columns(const double* const* c, const double* below, int under, double* sum) {
    // Four doubles from any address (memcpy: Clang keeps a vector type's full alignment even
    // when a typedef asks for less, and an aligned load from an unaligned address faults).
    const auto load = [](Quad& q, const double* p) { std::memcpy(&q, p, sizeof q); };
    Quad lanes[K] = {}, b, x;
    int i = 0;
    for (; i + 3 < under; i += 4) {
        load(b, below + i);
        for (int k = 0; k < K; ++k) {
            load(x, c[k] + i);
            lanes[k] += x * b;
        }
    }
    for (int k = 0; k < K; ++k) {
        sum[k] = (lanes[k][0] + lanes[k][1]) + (lanes[k][2] + lanes[k][3]);
        for (int r = i; r < under; ++r) sum[k] += c[k][r] * below[r];
    }
}

// w[j] −= Σ_i L(i, j) below[i] for the `columns` columns of a supernode's part under its diagonal
// block, four columns per sweep.
template <typename Row>
[[gnu::always_inline]] inline void subtract_below(const double* block, int height, int columns, const Row* below,
                                                  int under, Row* w) {
    int j = 0;
    for (; j + 3 < columns; j += 4) {
        const double* c[4] = {block + static_cast<long>(j) * height, block + static_cast<long>(j + 1) * height,
                              block + static_cast<long>(j + 2) * height, block + static_cast<long>(j + 3) * height};
        Row sum[4];
        dot_columns<4>(c, below, under, sum);
        for (int k = 0; k < 4; ++k) w[j + k] -= sum[k];
    }
    for (; j < columns; ++j) {
        const double* c = block + static_cast<long>(j) * height;
        Row sum;
        dot_columns<1>(&c, below, under, &sum);
        w[j] -= sum;
    }
}

// L z = y on the given supernodes, ascending: forward substitution on each triangle, then the
// rows below get their updates. With `top_updates`, the updates of the plan's top rows are added
// there instead (y −= top_updates follows).
template <int R>
[[gnu::always_inline]] inline void forward(const SupernodalLayout& f, const std::vector<int>& supernodes,
                                           typename Lanes<R>::type* y, typename Lanes<R>::type* below,
                                           typename Lanes<R>::type* top_updates, const int* top_slot) {
    using Row = typename Lanes<R>::type;
    for (const int s : supernodes) {
        const int first = f.super[s], columns = f.columns(s), height = f.height(s), under = height - columns;
        const int* row = f.rows + f.row_start[s] + columns;
        const double* block = f.values + f.value_start[s];
        Row* z = y + first;
        for (int j = 0; j < columns; ++j) {
            const double* column = block + static_cast<long>(j) * height;
            z[j] /= column[j];
            for (int i = j + 1; i < columns; ++i) z[i] -= column[i] * z[j];
        }
        std::fill(below, below + under, Row{});
        add_below(block + columns, height, columns, z, under, below);
        if (top_updates) {
            for (int i = 0; i < under; ++i) {
                const int slot = top_slot[row[i]];
                if (slot >= 0)
                    top_updates[slot] += below[i];
                else
                    y[row[i]] -= below[i];
            }
        } else {
            for (int i = 0; i < under; ++i) y[row[i]] -= below[i];
        }
    }
}

// Lᵀ w = z on the given supernodes, descending: the rows below (solved already) first, then
// backward substitution on each triangle.
template <int R>
[[gnu::always_inline]] inline void backward(const SupernodalLayout& f, const std::vector<int>& supernodes,
                                            typename Lanes<R>::type* y, typename Lanes<R>::type* below) {
    using Row = typename Lanes<R>::type;
    for (auto s_it = supernodes.rbegin(); s_it != supernodes.rend(); ++s_it) {
        const int s = *s_it;
        const int first = f.super[s], columns = f.columns(s), height = f.height(s), under = height - columns;
        const int* row = f.rows + f.row_start[s] + columns;
        const double* block = f.values + f.value_start[s];
        Row* w = y + first;
        for (int i = 0; i < under; ++i) below[i] = y[row[i]];
        subtract_below(block + columns, height, columns, below, under, w);
        for (int j = columns - 1; j >= 0; --j) {
            const double* column = block + static_cast<long>(j) * height;
            Row sum{};
            for (int i = j + 1; i < columns; ++i) sum += column[i] * w[i];
            w[j] = (w[j] - sum) / column[j];
        }
    }
}

// One sweep over a list of supernodes, forward or backward.
template <int R>
[[gnu::always_inline]] inline void sweep(bool is_forward, const SupernodalLayout& f, const std::vector<int>& supernodes,
                                         typename Lanes<R>::type* y, typename Lanes<R>::type* below,
                                         typename Lanes<R>::type* top_updates, const int* top_slot) {
    if (is_forward)
        forward<R>(f, supernodes, y, below, top_updates, top_slot);
    else
        backward<R>(f, supernodes, y, below);
}

#if defined(__x86_64__) || defined(__i386__)
template <int R>
[[gnu::target("avx2,fma")]] void sweep_avx2(bool is_forward, const SupernodalLayout& f, const std::vector<int>& supernodes,
                                            typename Lanes<R>::type* y, typename Lanes<R>::type* below,
                                            typename Lanes<R>::type* top_updates, const int* top_slot) {
    sweep<R>(is_forward, f, supernodes, y, below, top_updates, top_slot);
}
#endif

bool has_avx2() {
#if defined(__x86_64__) || defined(__i386__)
    static const bool available = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return available;
#else
    return false;
#endif
}

// n rows, aligned for the widest vector loads (std::vector would align a 256-bit vector type to
// only 16 bytes when the file is compiled for the baseline); zeroed unless told otherwise.
constexpr std::align_val_t kRowAlignment{32};
template <typename Row>
auto aligned_rows(size_t n, bool zeroed = true) {
    auto release = [](Row* rows) { ::operator delete[](rows, kRowAlignment); };
    std::unique_ptr<Row[], decltype(release)> rows(static_cast<Row*>(::operator new[](n * sizeof(Row), kRowAlignment)),
                                                   release);
    if (zeroed) std::fill(rows.get(), rows.get() + n, Row{});
    return rows;
}

template <int R>
void run_sweep(bool is_forward, const SupernodalLayout& f, const std::vector<int>& supernodes, typename Lanes<R>::type* y,
               typename Lanes<R>::type* below, typename Lanes<R>::type* top_updates = nullptr,
               const int* top_slot = nullptr) {
#if defined(__x86_64__) || defined(__i386__)
    if (has_avx2()) return sweep_avx2<R>(is_forward, f, supernodes, y, below, top_updates, top_slot);
#endif
    sweep<R>(is_forward, f, supernodes, y, below, top_updates, top_slot);
}

// Solves for `count` ≤ R columns of B starting at `first`; missing lanes stay zero.
template <int R>
void solve_group(const cholmod_factor& factor, const SolvePlan& plan, const Eigen::Ref<const Eigen::MatrixXd>& B,
                 Eigen::Ref<Eigen::MatrixXd> X, Eigen::Index first, int count) {
    using Row = typename Lanes<R>::type;
    const SupernodalLayout f(factor);
    const auto n = static_cast<Eigen::Index>(factor.n);
    const auto* perm = static_cast<const int*>(factor.Perm);
    const auto y = aligned_rows<Row>(static_cast<size_t>(n), count < R);  // every lane is written when count = R
    const size_t below_size = std::max<size_t>(factor.maxesize, 1);
    const auto below = aligned_rows<Row>(2 * below_size);
    const auto top_updates = aligned_rows<Row>(static_cast<size_t>(std::max(plan.top_columns, 1)));
    auto lane = [](Row& row, int c) -> double& { return reinterpret_cast<double*>(&row)[c]; };

    // Forward: the two parts side by side (the second keeps its updates of top rows apart), then
    // the top; backward: the top, then the two parts. The permutations (random reads of B, random
    // writes of X) are shared out too: four columns on igea 49.8 → 46.0 ms, and nefertiti's
    // eigenpairs (k = 50) 0.33 → 0.32 s.
    const bool split = !plan.parts[0].empty();
    const int threads = std::min(2, omp_get_max_threads());
#pragma omp parallel num_threads(threads) if (split)
    {
#pragma omp for schedule(static)
        for (Eigen::Index i = 0; i < n; ++i)  // y = P b
            for (int c = 0; c < count; ++c) lane(y[i], c) = B(perm[i], first + c);
#pragma omp for schedule(static, 1)
        for (int part = 0; part < 2; ++part)
            run_sweep<R>(true, f, plan.parts[part], y.get(), below.get() + part * below_size,
                         part == 1 ? top_updates.get() : nullptr, plan.top_slot.data());
    }
    if (split) {
        int slot = 0;
        for (const int s : plan.top)
            for (int column = f.super[s]; column < f.super[s + 1]; ++column) y[column] -= top_updates[slot++];
    }
    run_sweep<R>(true, f, plan.top, y.get(), below.get());
    run_sweep<R>(false, f, plan.top, y.get(), below.get());
#pragma omp parallel num_threads(threads) if (split)
    {
#pragma omp for schedule(static, 1)
        for (int part = 0; part < 2; ++part)
            run_sweep<R>(false, f, plan.parts[part], y.get(), below.get() + part * below_size);
#pragma omp for schedule(static)
        for (Eigen::Index i = 0; i < n; ++i)  // x = Pᵀ w
            for (int c = 0; c < count; ++c) X(perm[i], first + c) = lane(y[i], c);
    }
}

// Below this many factor entries a solve takes tens of microseconds, and a second thread would
// cost as much to start as it saves.
constexpr long kMinSplitEntries = 200000;
// The plan stops cutting once the parts differ by this fraction of the factor's entries.
constexpr double kBalanced = 0.02;
// A bound on the cuts, for trees that never balance (a chain, a star of tiny subtrees).
constexpr int kMaxCuts = 256;

}  // namespace

std::vector<int> supernode_of_columns(const cholmod_factor& factor) {
    const SupernodalLayout f(factor);
    std::vector<int> supernode_of(factor.n);
    for (int s = 0; s < static_cast<int>(factor.nsuper); ++s)
        std::fill(supernode_of.begin() + f.super[s], supernode_of.begin() + f.super[s + 1], s);
    return supernode_of;
}

SolvePlan plan_solve(const cholmod_factor& factor) {
    if (!factor.is_super) throw NumericalError("Cholesky: the factor is not supernodal");
    const SupernodalLayout f(factor);
    const auto supernodes = static_cast<int>(factor.nsuper);
    const auto n = static_cast<int>(factor.n);
    SolvePlan plan;

    // The supernodal elimination tree: a supernode's parent holds the first row below its block.
    // Parents come after their children. Work is counted in factor entries.
    const std::vector<int> supernode_of = supernode_of_columns(factor);
    std::vector<int> parent(static_cast<size_t>(supernodes), -1), child_count(static_cast<size_t>(supernodes) + 1, 0);
    std::vector<long> work(static_cast<size_t>(supernodes)), subtree(static_cast<size_t>(supernodes));
    long total = 0;
    for (int s = 0; s < supernodes; ++s) {
        const int columns = f.columns(s), height = f.height(s);
        if (height > columns) parent[s] = supernode_of[f.rows[f.row_start[s] + columns]];
        work[s] = static_cast<long>(columns) * height;
        total += work[s];
    }
    for (int s = 0; s < supernodes; ++s) {
        subtree[s] += work[s];
        if (parent[s] >= 0) {
            subtree[parent[s]] += subtree[s];
            ++child_count[parent[s] + 1];
        }
    }
    if (total < kMinSplitEntries) {
        plan.top.resize(static_cast<size_t>(supernodes));
        for (int s = 0; s < supernodes; ++s) plan.top[s] = s;
        return plan;
    }
    // Children lists (compressed), ascending.
    for (int s = 0; s < supernodes; ++s) child_count[s + 1] += child_count[s];
    std::vector<int> children(static_cast<size_t>(child_count[supernodes]));
    std::vector<int> next(child_count.begin(), child_count.end() - 1);
    for (int s = 0; s < supernodes; ++s)
        if (parent[s] >= 0) children[next[parent[s]]++] = s;

    // Cut the heaviest subtree below the cut (its root moves to the top) until the two parts
    // balance, dealing the subtrees heaviest first to the lighter part; keep the cut with the
    // least time (top + the heavier part).
    std::vector<int> frontier;
    for (int s = 0; s < supernodes; ++s)
        if (parent[s] < 0) frontier.push_back(s);
    std::vector<int> best_frontier, best_assignment;
    long best_cost = total, top_work = 0;
    std::vector<int> assignment;
    for (int cut = 0; cut < kMaxCuts && !frontier.empty(); ++cut) {
        std::sort(frontier.begin(), frontier.end(), [&](int a, int b) {
            return subtree[a] != subtree[b] ? subtree[a] > subtree[b] : a < b;
        });
        long load[2] = {0, 0};
        assignment.assign(frontier.size(), 0);
        for (size_t i = 0; i < frontier.size(); ++i) {
            const int part = load[1] < load[0] ? 1 : 0;
            assignment[i] = part;
            load[part] += subtree[frontier[i]];
        }
        const long cost = top_work + std::max(load[0], load[1]);
        if (cost < best_cost) {
            best_cost = cost;
            best_frontier = frontier;
            best_assignment = assignment;
        }
        if (static_cast<double>(std::abs(load[0] - load[1])) <= kBalanced * static_cast<double>(total)) break;
        const int heaviest = frontier.front();
        frontier.erase(frontier.begin());
        top_work += work[heaviest];
        frontier.insert(frontier.end(), children.begin() + child_count[heaviest],
                        children.begin() + child_count[heaviest + 1]);
    }

    // Owners, parents before children: a subtree root's part, else its parent's part, else top.
    std::vector<signed char> owner(static_cast<size_t>(supernodes), -1);
    for (size_t i = 0; i < best_frontier.size(); ++i)
        owner[best_frontier[i]] = static_cast<signed char>(best_assignment[i] + 2);
    for (int s = supernodes - 1; s >= 0; --s) {
        if (owner[s] >= 2)
            owner[s] -= 2;
        else if (parent[s] >= 0 && owner[parent[s]] >= 0)
            owner[s] = owner[parent[s]];
    }
    plan.top_slot.assign(static_cast<size_t>(n), -1);
    for (int s = 0; s < supernodes; ++s) {
        if (owner[s] >= 0) {
            plan.parts[owner[s]].push_back(s);
            continue;
        }
        plan.top.push_back(s);
        for (int column = f.super[s]; column < f.super[s + 1]; ++column) plan.top_slot[column] = plan.top_columns++;
    }
    return plan;
}

void supernodal_solve(const cholmod_factor& factor, const SolvePlan& plan, const Eigen::Ref<const Eigen::MatrixXd>& B,
                      Eigen::Ref<Eigen::MatrixXd> X) {
    if (!factor.is_super || !factor.is_ll || factor.xtype != CHOLMOD_REAL || factor.itype != CHOLMOD_INT)
        throw NumericalError("Cholesky: the factor is not a real supernodal LLᵀ factor with int indices");
    for (Eigen::Index first = 0; first < B.cols(); first += 4) {
        const int count = static_cast<int>(std::min<Eigen::Index>(4, B.cols() - first));
        if (count == 1)
            solve_group<1>(factor, plan, B, X, first, count);
        else if (count == 2)
            solve_group<2>(factor, plan, B, X, first, count);
        else
            solve_group<4>(factor, plan, B, X, first, count);
    }
}

}  // namespace sdmesh::detail
