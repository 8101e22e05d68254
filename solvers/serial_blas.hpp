#pragma once
// Private to sdmesh::solvers: running BLAS calls on one thread.

#include <omp.h>

namespace sdmesh::detail {

// CHOLMOD's supernodal kernels and block Lanczos's products call BLAS, which (OpenBLAS's OpenMP
// build, what setup installs) runs each call on all OpenMP threads. On the 2-core VMs measured
// that never made a factorization or solve faster, and with libgomp's default spinning it made the igea geodesic
// precomputation 2.5× slower (21.8 s against 8.5 s). One thread also makes the factors
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

}  // namespace sdmesh::detail
