#include "sdmesh/mesh.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "sdmesh/error.hpp"

namespace sdmesh {

void require_indices_in_range(const TriangleMesh& mesh) {
    const int n = mesh.num_vertices();
    for (int f = 0; f < mesh.num_faces(); ++f)
        for (int k = 0; k < 3; ++k)
            if (mesh.F(f, k) < 0 || mesh.F(f, k) >= n)
                throw InvalidMeshError("face " + std::to_string(f) + " references vertex " +
                                       std::to_string(mesh.F(f, k)) + ", but the mesh has " +
                                       std::to_string(n) + " vertices");
}

void require_finite_positions(const TriangleMesh& mesh) {
    for (int v = 0; v < mesh.num_vertices(); ++v)
        if (!mesh.V.row(v).allFinite())
            throw InvalidMeshError("vertex " + std::to_string(v) +
                                   " has a coordinate that is not finite");
}

std::vector<char> referenced_vertices(const TriangleMesh& mesh) {
    std::vector<char> referenced(static_cast<size_t>(mesh.num_vertices()), 0);
    for (int k = 0; k < 3; ++k)
        for (int f = 0; f < mesh.num_faces(); ++f)
            if (const int v = mesh.F(f, k); v >= 0 && v < mesh.num_vertices()) referenced[v] = 1;
    return referenced;
}

double bounding_box_diagonal(const TriangleMesh& mesh) {
    // Unreferenced vertices are not part of the surface and must not set the scale at which its
    // lengths are judged: one far away made every face tiny, where products of lengths underflow.
    std::vector<char> counted = referenced_vertices(mesh);
    if (mesh.num_faces() == 0) counted.assign(counted.size(), 1);
    Eigen::RowVector3d low = Eigen::RowVector3d::Constant(HUGE_VAL), high = -low;
    bool any = false;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
        if (!counted[v]) continue;
        if (!mesh.V.row(v).allFinite()) return std::numeric_limits<double>::quiet_NaN();
        low = low.cwiseMin(mesh.V.row(v)), high = high.cwiseMax(mesh.V.row(v)), any = true;
    }
    // stableNorm: the squares of extents below 1e-154 or above 1e154 would leave the double range.
    return any ? (high - low).stableNorm() : 0.0;
}

double require_supported_extent(const TriangleMesh& mesh) {
    const double diagonal = bounding_box_diagonal(mesh);
    const double largest = std::ldexp(1.0, kMaxExtentExponent), smallest = std::ldexp(1.0, -kMaxExtentExponent);
    // NaN is left for require_finite_positions, which names the vertex.
    if (std::isnan(diagonal) || (diagonal <= largest && (diagonal == 0 || diagonal >= smallest))) return diagonal;
    const bool large = diagonal > largest;
    char message[200];
    std::snprintf(message, sizeof message,
                  "coordinates too %s: the bounding-box diagonal is %.3g, %s %.3g (squared lengths and areas would "
                  "leave the normal doubles); rescale the mesh",
                  large ? "large" : "small", diagonal, large ? "above" : "below", large ? largest : smallest);
    throw InvalidMeshError(message);
}

TriangleMesh scaled_by_power_of_two(const TriangleMesh& mesh, int exponent) {
    return {mesh.V.unaryExpr([exponent](double x) { return std::ldexp(x, exponent); }), mesh.F};
}

}  // namespace sdmesh
