#pragma once
// Conversions between NumPy / SciPy objects and the Eigen types of the C++ API.
//
// Inputs: the C++ API takes owning Eigen types (TriangleMesh, VectorXd, SparseMatrix), so every
// input is copied once into them, straight from the NumPy buffer whatever its strides. The dtype
// rule: real arrays (V, fields, right-hand sides) accept any integer or floating dtype and are
// read as float64; index arrays (F, sources, Dirichlet vertices) accept any integer dtype whose
// values fit in int32. Other dtypes raise TypeError; a wrong shape raises InvalidArgumentError (a
// ValueError) naming the shape received.
//
// Outputs are never copied: the Eigen result is moved to the heap and NumPy arrays view its
// buffers, kept alive by a capsule (Eigen stores column-major, so matrices come out in Fortran
// order); sparse results become scipy.sparse.csc_matrix over views of the data, inner index and
// outer index arrays.

#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "cli/json.hpp"
#include "sdmesh/mesh.hpp"

namespace sdmesh::python {

namespace py = pybind11;

/// V (n x 3, real) and F (m x 3, integer) as a mesh.
TriangleMesh mesh_from_arrays(py::handle V, py::handle F);

/// A 1-D real array of `size` entries (any size when size < 0) as float64.
Eigen::VectorXd vector_from_array(py::handle values, const char* name, Eigen::Index size = -1);

/// A 1-D integer array (or a Python sequence of ints) as int32 indices.
std::vector<int> indices_from_array(py::handle indices, const char* name);

/// True when `object` is a scipy.sparse matrix or array.
bool is_sparse(py::handle object);

/// A square or rectangular scipy.sparse matrix as a compressed column-major Eigen matrix.
Eigen::SparseMatrix<double> sparse_from_scipy(py::handle matrix, const char* name);

/// Takes ownership of `matrix` and returns a NumPy view of it (1-D for a vector).
template <class Matrix>
py::array to_numpy(Matrix&& matrix) {
    using Plain = std::decay_t<Matrix>;
    using Scalar = typename Plain::Scalar;
    static_assert(!Plain::IsRowMajor, "the strides below are column-major");
    auto* owner = new Plain(std::forward<Matrix>(matrix));
    const py::capsule base(owner, [](void* p) { delete static_cast<Plain*>(p); });
    const auto item = static_cast<py::ssize_t>(sizeof(Scalar));
    if constexpr (Plain::ColsAtCompileTime == 1)
        return py::array_t<Scalar>({static_cast<py::ssize_t>(owner->size())}, {item}, owner->data(), base);
    else
        return py::array_t<Scalar>({static_cast<py::ssize_t>(owner->rows()), static_cast<py::ssize_t>(owner->cols())},
                                   {item, item * static_cast<py::ssize_t>(owner->rows())}, owner->data(), base);
}

/// Takes ownership of `matrix` and returns it as a scipy.sparse.csc_matrix viewing its arrays.
py::object to_csc(Eigen::SparseMatrix<double>&& matrix);

/// A report as a dict, through the JSON text the CLI prints (same keys, same order; NaN and
/// infinities are None as in the JSON).
py::dict to_dict(const cli::JsonObject& json);

}  // namespace sdmesh::python
