#pragma once
// Private to sdmesh::solvers: the system BLAS (OpenBLAS after setup), on one thread.

#include <Eigen/Core>
#include <cblas.h>
#include <omp.h>

namespace sdmesh::detail {

// CHOLMOD's supernodal kernels and block Lanczos's products call BLAS, which (OpenBLAS's OpenMP
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

}  // namespace sdmesh::detail
