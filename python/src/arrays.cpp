#include "arrays.hpp"

#include <cstdint>
#include <limits>

#include "sdmesh/error.hpp"

namespace sdmesh::python {
namespace {

std::string shape_text(const py::array& array) { return py::str(array.attr("shape")).cast<std::string>(); }

// np.asarray(object) with its dtype kind checked: 'f' (float), 'i', 'u' (integers).
py::array numeric_array(py::handle object, const char* name, bool integers_only) {
    const auto array = py::array::ensure(py::module_::import("numpy").attr("asarray")(object));
    const char kind = array.dtype().kind();
    const bool accepted = kind == 'i' || kind == 'u' || (!integers_only && kind == 'f');
    if (!accepted)
        throw py::type_error(std::string(name) + " must be an array of " + (integers_only ? "integers" : "real numbers") +
                             ", got dtype " + py::str(array.dtype()).cast<std::string>());
    return array;
}

void require_shape(const py::array& array, const char* name, int columns, const char* expected) {
    const bool ok = columns > 0 ? array.ndim() == 2 && array.shape(1) == columns : array.ndim() == 1;
    if (!ok) throw InvalidArgumentError(std::string(name) + " must have shape " + expected + ", got " + shape_text(array));
}

// The array as float64, converted (a copy) only when it has another dtype.
py::array_t<double> as_float64(const py::array& array) {
    return array.attr("astype")("float64", py::arg("copy") = false).cast<py::array_t<double>>();
}

// The array as int32, converted only when it has another dtype, after checking that every value fits.
py::array_t<std::int32_t> as_int32(const py::array& array, const char* name) {
    if (array.dtype().is(py::dtype::of<std::int32_t>())) return array.cast<py::array_t<std::int32_t>>();
    if (array.size() > 0) {
        const auto low = array.attr("min")().cast<long double>(), high = array.attr("max")().cast<long double>();
        if (low < std::numeric_limits<std::int32_t>::min() || high > std::numeric_limits<std::int32_t>::max())
            throw InvalidArgumentError(std::string(name) + " has values outside the int32 range");
    }
    return array.attr("astype")("int32").cast<py::array_t<std::int32_t>>();
}

}  // namespace

TriangleMesh mesh_from_arrays(py::handle V, py::handle F) {
    const py::array positions = numeric_array(V, "V", false), faces = numeric_array(F, "F", true);
    require_shape(positions, "V", 3, "(n, 3)");
    require_shape(faces, "F", 3, "(m, 3)");
    const auto positions64 = as_float64(positions);  // named: the views below need them alive
    const auto faces32 = as_int32(faces, "F");
    const auto v = positions64.unchecked<2>();
    const auto f = faces32.unchecked<2>();
    TriangleMesh mesh;
    mesh.V.resize(v.shape(0), 3);
    mesh.F.resize(f.shape(0), 3);
    for (py::ssize_t i = 0; i < v.shape(0); ++i)
        for (py::ssize_t k = 0; k < 3; ++k) mesh.V(i, k) = v(i, k);
    for (py::ssize_t i = 0; i < f.shape(0); ++i)
        for (py::ssize_t k = 0; k < 3; ++k) mesh.F(i, k) = f(i, k);
    return mesh;
}

Eigen::VectorXd vector_from_array(py::handle values, const char* name, Eigen::Index size) {
    const py::array array = numeric_array(values, name, false);
    const std::string expected = size < 0 ? "(n,)" : "(" + std::to_string(size) + ",)";
    require_shape(array, name, 0, expected.c_str());
    if (size >= 0 && array.shape(0) != size)
        throw InvalidArgumentError(std::string(name) + " must have shape " + expected + ", got " + shape_text(array));
    const auto values64 = as_float64(array);
    const auto x = values64.unchecked<1>();
    Eigen::VectorXd vector(x.shape(0));
    for (py::ssize_t i = 0; i < x.shape(0); ++i) vector[i] = x(i);
    return vector;
}

std::vector<int> indices_from_array(py::handle indices, const char* name) {
    const py::array array = numeric_array(indices, name, true);
    require_shape(array, name, 0, "(n,)");
    const auto indices32 = as_int32(array, name);
    const auto x = indices32.unchecked<1>();
    std::vector<int> list(static_cast<size_t>(x.shape(0)));
    for (py::ssize_t i = 0; i < x.shape(0); ++i) list[static_cast<size_t>(i)] = x(i);
    return list;
}

bool is_sparse(py::handle object) {
    return py::module_::import("scipy.sparse").attr("issparse")(object).cast<bool>();
}

Eigen::SparseMatrix<double> sparse_from_scipy(py::handle matrix, const char* name) {
    if (!is_sparse(matrix))
        throw py::type_error(std::string(name) + " must be a scipy.sparse matrix, got " +
                             py::str(py::type::of(matrix)).cast<std::string>());
    py::object csc = matrix.attr("tocsc")();
    if (!csc.attr("has_canonical_format").cast<bool>()) {  // Eigen wants sorted, unique row indices
        csc = csc.attr("copy")();
        csc.attr("sum_duplicates")();
    }
    const auto shape = csc.attr("shape").cast<std::pair<Eigen::Index, Eigen::Index>>();
    const auto data = as_float64(numeric_array(csc.attr("data"), name, false));
    const auto rows = as_int32(py::array::ensure(csc.attr("indices")), name);
    const auto starts = as_int32(py::array::ensure(csc.attr("indptr")), name);
    const Eigen::Map<const Eigen::SparseMatrix<double>> view(
        shape.first, shape.second, starts.at(shape.second), starts.data(), rows.data(), data.data());
    return Eigen::SparseMatrix<double>(view);
}

py::object to_csc(Eigen::SparseMatrix<double>&& matrix) {
    matrix.makeCompressed();
    const auto rows = static_cast<py::ssize_t>(matrix.rows()), cols = static_cast<py::ssize_t>(matrix.cols());
    const auto nnz = static_cast<py::ssize_t>(matrix.nonZeros());
    auto* owner = new Eigen::SparseMatrix<double>(std::move(matrix));
    const py::capsule base(owner, [](void* p) { delete static_cast<Eigen::SparseMatrix<double>*>(p); });
    const py::array_t<double> data({nnz}, {py::ssize_t(sizeof(double))}, owner->valuePtr(), base);
    const py::array_t<int> inner({nnz}, {py::ssize_t(sizeof(int))}, owner->innerIndexPtr(), base);
    const py::array_t<int> outer({cols + 1}, {py::ssize_t(sizeof(int))}, owner->outerIndexPtr(), base);
    return py::module_::import("scipy.sparse")
        .attr("csc_matrix")(py::make_tuple(data, inner, outer), py::arg("shape") = py::make_tuple(rows, cols));
}

py::dict to_dict(const cli::JsonObject& json) {
    return py::module_::import("json").attr("loads")(json.str(0)).cast<py::dict>();
}

}  // namespace sdmesh::python
