#pragma once
// Private to sdmesh::solvers: Cholesky factorizations whose NumericalError says which matrix was
// not positive definite, and what makes a mesh's matrices so.

#include <string>
#include <string_view>

#include "sdmesh/error.hpp"

namespace sdmesh::detail {

/// What makes the operators of a mesh indefinite within rounding.
inline constexpr std::string_view kIndefiniteMeshAdvice =
    "on a mesh that is not self-Delaunay, negative circumcentric cells and faces of nearly zero area do this, "
    "and a self-Delaunay mesh (sdmesh convert) avoids it";

/// factor(), a factorization of `matrix`; its NumericalError is rethrown as
/// "<matrix>: <its message>; <advice>".
template <class Factor>
decltype(auto) explained(std::string_view matrix, std::string_view advice, Factor&& factor) {
    try {
        return factor();
    } catch (const NumericalError& e) {
        throw NumericalError(std::string(matrix) + ": " + e.what() + "; " + std::string(advice));
    }
}

}  // namespace sdmesh::detail
