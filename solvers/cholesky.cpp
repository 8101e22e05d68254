#include "sdmesh/cholesky.hpp"

#include <cholmod.h>

#include <cstdlib>
#include <mutex>
#include <string>
#include <vector>

#include "sdmesh/error.hpp"

#include "prefault.hpp"
#include "supernodal_factor.hpp"
#include "supernodal_solve.hpp"

namespace sdmesh {
namespace {

// CHOLMOD allocates the factor's values (~250 MB for 500k mesh vertices), which the factorization
// then writes in full; on a virtual machine taking those pages one fault at a time cost about
// 1 s per factorization. Only replaces the standard malloc, never a user's own allocator.
void* prefaulted_malloc(size_t bytes) {
    void* block = std::malloc(bytes);
    detail::prefault(block, bytes);
    return block;
}

void use_prefaulted_malloc() {
    static std::once_flag once;
    std::call_once(once, [] {
        if (SuiteSparse_config.malloc_func == &std::malloc) SuiteSparse_config.malloc_func = &prefaulted_malloc;
    });
}

}  // namespace

struct CholeskySolver::Impl {
    cholmod_common common{};
    cholmod_factor* factor = nullptr;
    detail::SolvePlan solve_plan;    // of the analysed structure
    detail::FactorPlan factor_plan;  // of the analysed structure and pattern
    int size = 0;
    bool factorized = false;

    Impl() {
        use_prefaulted_malloc();
        cholmod_start(&common);
        reset_options();
    }
    // CHOLMOD's defaults (they try AMD, then METIS when its fill is high), supernodal, silent.
    void reset_options() {
        cholmod_defaults(&common);
        common.supernodal = CHOLMOD_SUPERNODAL;
        common.print = 0;  // errors become exceptions here, not text on stderr
        common.error_handler = nullptr;
    }
    ~Impl() {
        if (factor) cholmod_free_factor(&factor, &common);
        cholmod_finish(&common);
    }
    Impl(const Impl&) = delete;
    Impl& operator=(const Impl&) = delete;

    // A view of A's compressed columns for CHOLMOD, no copy; stype -1: only the lower triangle
    // is read, so a full symmetric matrix can be passed as it is.
    static cholmod_sparse view(const Eigen::SparseMatrix<double>& A) {
        cholmod_sparse s{};
        s.nrow = static_cast<size_t>(A.rows());
        s.ncol = static_cast<size_t>(A.cols());
        s.nzmax = static_cast<size_t>(A.nonZeros());
        s.p = const_cast<int*>(A.outerIndexPtr());
        s.i = const_cast<int*>(A.innerIndexPtr());
        s.x = const_cast<double*>(A.valuePtr());
        s.stype = -1;
        s.itype = CHOLMOD_INT;
        s.xtype = CHOLMOD_REAL;
        s.dtype = CHOLMOD_DOUBLE;
        s.sorted = 1;
        s.packed = 1;
        return s;
    }
};

CholeskySolver::CholeskySolver() : impl_(std::make_unique<Impl>()) {}
CholeskySolver::CholeskySolver(const Eigen::SparseMatrix<double>& A, const CholeskyOptions& options)
    : CholeskySolver() {
    analyze(A, options);
    factorize(A);
}
CholeskySolver::~CholeskySolver() = default;
CholeskySolver::CholeskySolver(CholeskySolver&&) noexcept = default;
CholeskySolver& CholeskySolver::operator=(CholeskySolver&&) noexcept = default;

void CholeskySolver::analyze(const Eigen::SparseMatrix<double>& A, const CholeskyOptions& options) {
    if (A.rows() != A.cols())
        throw InvalidArgumentError("Cholesky: the matrix is " + std::to_string(A.rows()) + " x " +
                                   std::to_string(A.cols()) + ", not square");
    if (!A.isCompressed()) throw InvalidArgumentError("Cholesky: the matrix must be compressed");
    const Impl* other = options.same_ordering_as ? options.same_ordering_as->impl_.get() : nullptr;
    if (options.same_ordering_as && (!other->factor || other->size != A.rows()))
        throw InvalidArgumentError("Cholesky: same_ordering_as must be analysed for a matrix of the same size");
    // A copy, because same_ordering_as may be this solver, whose factor is freed next.
    std::vector<int> perm;
    if (other) perm.assign(static_cast<const int*>(other->factor->Perm), static_cast<const int*>(other->factor->Perm) + other->size);
    Impl& m = *impl_;
    if (m.factor) cholmod_free_factor(&m.factor, &m.common);
    cholmod_sparse a = Impl::view(A);
    m.reset_options();
    if (other) {
        // The given permutation is already postordered for its pattern; postordering again
        // could only reorder it for a different pattern.
        m.common.nmethods = 1;
        m.common.method[0].ordering = CHOLMOD_GIVEN;
        m.common.postorder = 0;
        m.factor = cholmod_analyze_p(&a, perm.data(), nullptr, 0, &m.common);
    } else {
        m.common.nmethods = options.ordering == CholeskyOrdering::automatic ? 0 : 1;
        switch (options.ordering) {
            case CholeskyOrdering::automatic: break;
            case CholeskyOrdering::amd: m.common.method[0].ordering = CHOLMOD_AMD; break;
            case CholeskyOrdering::metis: m.common.method[0].ordering = CHOLMOD_METIS; break;
            case CholeskyOrdering::nested_dissection: m.common.method[0].ordering = CHOLMOD_NESDIS; break;
            case CholeskyOrdering::coarse_nested_dissection:
                m.common.method[0].ordering = CHOLMOD_NESDIS;
                m.common.method[0].nd_small = 20000;
                break;
        }
        m.factor = cholmod_analyze(&a, &m.common);
    }
    if (!m.factor) throw NumericalError("Cholesky: symbolic analysis failed (CHOLMOD status " +
                                        std::to_string(m.common.status) + ")");
    m.solve_plan = detail::plan_solve(*m.factor);
    m.factor_plan = detail::plan_factor(*m.factor, m.solve_plan, A);
    m.size = static_cast<int>(A.rows());
    m.factorized = false;
}

void CholeskySolver::factorize(const Eigen::SparseMatrix<double>& A) {
    Impl& m = *impl_;
    if (!m.factor) throw InvalidArgumentError("Cholesky: factorize before analyze");
    if (A.rows() != m.size || A.cols() != m.size || !A.isCompressed())
        throw InvalidArgumentError("Cholesky: the matrix does not have the analysed pattern");
    m.factorized = false;
    const int failed = detail::factorize_supernodal(*m.factor, m.solve_plan, m.factor_plan, A, m.common);
    if (failed >= 0) {
        // The factor's column, in the matrix's own numbering (a mesh's vertex).
        const auto* perm = static_cast<const int*>(m.factor->Perm);
        const int row = perm != nullptr ? perm[failed] : failed;
        throw NumericalError("Cholesky: the matrix is not positive definite within rounding (the pivot of row " +
                             std::to_string(row) + " is not positive)");
    }
    m.factorized = true;
}

Eigen::MatrixXd CholeskySolver::solve_columns(const Eigen::MatrixXd& b) const {
    const Impl& m = *impl_;
    if (!m.factorized) throw InvalidArgumentError("Cholesky: solve before a successful factorize");
    if (b.rows() != m.size)
        throw InvalidArgumentError("Cholesky: right-hand side has " + std::to_string(b.rows()) + " rows, expected " +
                                   std::to_string(m.size));
    Eigen::MatrixXd x(b.rows(), b.cols());
    detail::supernodal_solve(*m.factor, m.solve_plan, b, x);
    return x;
}

Eigen::VectorXd CholeskySolver::solve(const Eigen::VectorXd& b) const {
    return solve_columns(b);
}

int CholeskySolver::rows() const { return impl_->size; }

}  // namespace sdmesh
