#pragma once
// Fresh large buffers get their pages from the kernel one fault at a time on first write; on a
// virtual machine each fault is a trap to the hypervisor and filling 100 MB this way costs ~10×
// the writes themselves. prefault() maps all pages of a block in one system call instead
// (MADV_POPULATE_WRITE, Linux >= 5.14). Small blocks, other systems and older kernels: no-op.

#include <algorithm>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "sdmesh/triangulation.hpp"

namespace sdmesh::detail {

void prefault(void* data, std::size_t bytes);

/// Prefaults the storage of a freshly sized contiguous container (Eigen dense, std::vector).
template <class Container>
void prefault(Container& c) {
    prefault(static_cast<void*>(c.data()), static_cast<std::size_t>(c.size()) * sizeof(*c.data()));
}

/// Resizes an empty std::vector to n copies of `value`, its pages mapped first, with room for
/// `capacity` elements (the pages beyond n are mapped only when used).
template <class T>
void prefaulted_assign(std::vector<T>& v, std::size_t n, const T& value, std::size_t capacity = 0) {
    v.reserve(std::max(n, capacity));
    prefault(static_cast<void*>(v.data()), n * sizeof(T));
    v.assign(n, value);
}

/// The side lengths of a face are random reads into the edge array: a loop over the faces calls
/// this for face f to request those of face f + kPrefetchDistance, which hides most of the latency.
inline constexpr int kPrefetchDistance = 16;
inline void prefetch_sides_ahead(const Triangulation& t, int f) {
    if (f + kPrefetchDistance < t.num_faces())
        for (int k = 0; k < 3; ++k) __builtin_prefetch(&t.length[t.face_edge(f + kPrefetchDistance, k)]);
}

/// A dense matrix of the given size, its pages mapped, every entry set to `value`.
template <class Matrix>
Matrix prefaulted_constant(Eigen::Index rows, Eigen::Index cols, typename Matrix::Scalar value) {
    Matrix m(rows, cols);
    prefault(m);
    m.setConstant(value);
    return m;
}

}  // namespace sdmesh::detail
