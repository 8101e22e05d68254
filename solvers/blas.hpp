#pragma once
// Private to sdmesh::solvers: the system BLAS and LAPACK (OpenBLAS after setup), on one thread.

#include <algorithm>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <cblas.h>
#include <omp.h>

#include "sdmesh/error.hpp"

extern "C" {
// LAPACK's symmetric eigensolver by divide and conquer (Fortran interface).
void dsyevd_(const char* jobz, const char* uplo, const int* n, double* a, const int* lda, double* w, double* work,
             const int* lwork, int* iwork, const int* liwork, int* info);
}

namespace sdmesh::detail {

// The factorization's large updates and block Lanczos's products call BLAS, which (OpenBLAS's OpenMP
// build, what setup installs) runs each call on all OpenMP threads. On the 2-core VMs measured
// that never made a factorization or solve faster, and with libgomp's default spinning it made
// the igea geodesic precomputation 2.5× slower (21.8 s against 8.5 s). One thread also makes the factors
// independent of the thread count. Scoped: the caller's thread count is restored.
class SerialBlas {
public:
    SerialBlas() : saved_(omp_get_max_threads()) { omp_set_num_threads(1); }
    ~SerialBlas() { omp_set_num_threads(saved_); }
    SerialBlas(const SerialBlas&) = delete;
    SerialBlas& operator=(const SerialBlas&) = delete;

private:
    int saved_;
};

// One dgemm call: C ← alpha · op(A) · B + beta · C with op(A) = Aᵀ or A, on this thread.
inline void dgemm(bool transpose_a, double alpha, const Eigen::Ref<const Eigen::MatrixXd>& A,
                  const Eigen::Ref<const Eigen::MatrixXd>& B, double beta, Eigen::Ref<Eigen::MatrixXd> C) {
    const SerialBlas serial;
    cblas_dgemm(CblasColMajor, transpose_a ? CblasTrans : CblasNoTrans, CblasNoTrans, static_cast<int>(C.rows()),
                static_cast<int>(C.cols()), static_cast<int>(B.rows()), alpha, A.data(),
                static_cast<int>(A.outerStride()), B.data(), static_cast<int>(B.outerStride()), beta, C.data(),
                static_cast<int>(C.outerStride()));
}

// C ← alpha · op(A) · B + beta · C with op(A) = Aᵀ or A, by the system BLAS. OpenBLAS picks
// AVX-512 kernels at run time, which Eigen, compiled for baseline x86-64, lacks: on the n x k
// products of the eigensolver it was 1.7× faster in all. Products over tall matrices (C's rows,
// or the sum over B's rows for Aᵀ) are split into two fixed halves run side by side (eigenpairs:
// igea 21 → 17.4 s, nefertiti 1.36 → 1.05 s on two cores); the split does not depend on the
// thread count, so neither do the results. (Solving two halves of a block side by side gained
// nothing: 117 against 128 ms.)
inline void multiply(bool transpose_a, double alpha, const Eigen::Ref<const Eigen::MatrixXd>& A,
                     const Eigen::Ref<const Eigen::MatrixXd>& B, double beta, Eigen::Ref<Eigen::MatrixXd> C) {
    constexpr Eigen::Index kSplitRows = 1 << 14;
    const Eigen::Index rows = transpose_a ? B.rows() : C.rows();
    if (rows < kSplitRows) {
        dgemm(transpose_a, alpha, A, B, beta, C);
        return;
    }
    const Eigen::Index half = rows / 2;
    Eigen::MatrixXd second_half;  // the second half's sum for Aᵀ B, added after
    if (transpose_a) second_half.resize(C.rows(), C.cols());
#pragma omp parallel for num_threads(2) schedule(static, 1)
    for (int part = 0; part < 2; ++part) {
        const Eigen::Index first = part == 0 ? 0 : half, count = part == 0 ? half : rows - half;
        if (transpose_a)
            dgemm(true, alpha, A.middleRows(first, count), B.middleRows(first, count), part == 0 ? beta : 0.0,
                  part == 0 ? C : Eigen::Ref<Eigen::MatrixXd>(second_half));
        else
            dgemm(false, alpha, A.middleRows(first, count), B, beta, C.middleRows(first, count));
    }
    if (transpose_a) C += second_half;
}

// The `count` largest eigenvalues of the symmetric matrix A (ascending) and their orthonormal
// eigenvectors, by LAPACK's divide and conquer (dsyevd) on one thread. Only A's lower triangle is
// read. Block Lanczos's Ritz pairs, whose O(m³) cost grows with k: at k = 200 on nefertiti,
// Eigen's solver took a quarter of the time (7.4 → 5.3 s with dsyevd, residuals and ΦᵀMΦ − I as
// small or smaller). dsyevr for just `count` pairs was slower (it bisects for a subset), MRRR
// (dstemr) on the tridiagonal form for just these pairs about as fast, with 10× larger residuals.
struct LargestEigenpairs {
    Eigen::VectorXd values;
    Eigen::MatrixXd vectors;
};
inline LargestEigenpairs largest_eigenpairs(const Eigen::Ref<const Eigen::MatrixXd>& A, int count) {
    const SerialBlas serial;
    const int n = static_cast<int>(A.rows()), query = -1;
    Eigen::MatrixXd a = A;
    Eigen::VectorXd values(n);
    int info = 0, iwork_size = 0;
    double work_size = 0;
    dsyevd_("V", "L", &n, a.data(), &n, values.data(), &work_size, &query, &iwork_size, &query, &info);
    const int lwork = static_cast<int>(work_size), liwork = iwork_size;
    std::vector<double> work(static_cast<size_t>(std::max(lwork, 1)));
    std::vector<int> iwork(static_cast<size_t>(std::max(liwork, 1)));
    dsyevd_("V", "L", &n, a.data(), &n, values.data(), work.data(), &lwork, iwork.data(), &liwork, &info);
    if (info != 0)
        throw NumericalError("eigenpairs: LAPACK dsyevd failed on the Lanczos matrix (info " + std::to_string(info) + ")");
    return {values.tail(count), a.rightCols(count)};
}

}  // namespace sdmesh::detail
