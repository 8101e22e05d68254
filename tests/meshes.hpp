#pragma once
// Small meshes built in code for the tests, beyond the generators of sdmesh/shapes.hpp.

#include <cmath>
#include <initializer_list>
#include <numbers>

#include <Eigen/Geometry>

#include "sdmesh/mesh.hpp"

namespace sdmesh::test {

inline TriangleMesh make_mesh(std::initializer_list<Eigen::RowVector3d> vertices,
                              std::initializer_list<Eigen::RowVector3i> faces) {
    TriangleMesh mesh;
    mesh.V.resize(static_cast<Eigen::Index>(vertices.size()), 3);
    mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
    Eigen::Index i = 0;
    for (const auto& v : vertices) mesh.V.row(i++) = v;
    i = 0;
    for (const auto& f : faces) mesh.F.row(i++) = f;
    return mesh;
}

/// Translates a copy of `b` by `shift` and appends it to `a` as another component.
inline TriangleMesh disjoint_union(const TriangleMesh& a, const TriangleMesh& b, double shift) {
    TriangleMesh mesh;
    mesh.V.resize(a.V.rows() + b.V.rows(), 3);
    mesh.V << a.V, b.V.rowwise() + Eigen::RowVector3d(shift, 0, 0);
    mesh.F.resize(a.F.rows() + b.F.rows(), 3);
    mesh.F << a.F, b.F.array() + a.num_vertices();
    return mesh;
}

/// Sum of the face areas.
inline double total_area(const TriangleMesh& mesh) {
    double area = 0;
    for (int f = 0; f < mesh.num_faces(); ++f) {
        const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                              c = mesh.V.row(mesh.F(f, 2));
        area += 0.5 * (b - a).cross(c - a).norm();
    }
    return area;
}

/// A planar fan around vertex 0 at the origin whose circumcentric dual cell has negative area:
/// its spokes face obtuse angles at the ring vertices.
inline TriangleMesh make_negative_dual_fan() {
    return make_mesh({{0, 0, 0}, {0, 0.2, 0}, {-0.3, 0.4, 0}, {-0.8, 0.6, 0}, {-0.3, 0, 0},
                      {-0.1, -0.1, 0}, {0.1, -0.1, 0}},
                     {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 6}, {0, 6, 1}});
}

/// A flat cap triangulated as a fan of n - 2 faces from one rim vertex, as CAD exporters do: the
/// rim is an unevenly sampled ellipse (on a circle every triangulation would be Delaunay).
inline TriangleMesh make_flat_fan(int n) {
    TriangleMesh fan;
    fan.V.resize(n, 3);
    for (int k = 0; k < n; ++k) {
        const double t = 2 * std::numbers::pi * (k + 0.4 * std::sin(7.3 * k)) / n;
        fan.V.row(k) << 3 * std::cos(t), std::sin(t), 0;
    }
    fan.F.resize(n - 2, 3);
    for (int k = 1; k < n - 1; ++k) fan.F.row(k - 1) << 0, k, k + 1;
    return fan;
}

}  // namespace sdmesh::test
