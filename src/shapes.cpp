#include "sdmesh/shapes.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include "sdmesh/error.hpp"

namespace sdmesh {

TriangleMesh make_icosphere(int subdivisions) {
    if (subdivisions < 0 || subdivisions > 9)
        throw InvalidArgumentError("make_icosphere: subdivisions must be in [0, 9]");
    const double t = (1.0 + std::sqrt(5.0)) / 2.0;
    std::vector<Eigen::Vector3d> points = {
        {-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
        {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<Eigen::Vector3i> faces = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (auto& p : points) p.normalize();
    for (int level = 0; level < subdivisions; ++level) {
        std::map<std::pair<int, int>, int> midpoint;
        auto middle = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            const auto [it, inserted] = midpoint.try_emplace(key, static_cast<int>(points.size()));
            if (inserted) points.push_back((points[a] + points[b]).normalized());
            return it->second;
        };
        std::vector<Eigen::Vector3i> finer;
        finer.reserve(4 * faces.size());
        for (const auto& f : faces) {
            const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
            finer.emplace_back(f[0], ab, ca);
            finer.emplace_back(f[1], bc, ab);
            finer.emplace_back(f[2], ca, bc);
            finer.emplace_back(ab, bc, ca);
        }
        faces = std::move(finer);
    }
    TriangleMesh mesh;
    mesh.V.resize(static_cast<Eigen::Index>(points.size()), 3);
    mesh.F.resize(static_cast<Eigen::Index>(faces.size()), 3);
    for (size_t i = 0; i < points.size(); ++i) mesh.V.row(static_cast<Eigen::Index>(i)) = points[i];
    for (size_t i = 0; i < faces.size(); ++i) mesh.F.row(static_cast<Eigen::Index>(i)) = faces[i];
    return mesh;
}

namespace {

// Faces of an nx × ny quad grid whose vertex (i, j) has index j·(nx+1) + i; the index wraps
// around in i when `periodic` (a cylinder), each quad split along (i, j)-(i+1, j+1).
Eigen::MatrixX3i quad_grid_faces(int nx, int ny, bool periodic) {
    const int row = periodic ? nx : nx + 1;
    Eigen::MatrixX3i F(2 * nx * ny, 3);
    int f = 0;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const int i1 = periodic ? (i + 1) % nx : i + 1;
            const int a = j * row + i, b = j * row + i1, c = (j + 1) * row + i1, d = (j + 1) * row + i;
            F.row(f++) << a, b, c;
            F.row(f++) << a, c, d;
        }
    return F;
}

}  // namespace

TriangleMesh make_grid(int nx, int ny, double width, double height, double shear) {
    if (nx < 1 || ny < 1) throw InvalidArgumentError("make_grid: nx and ny must be >= 1");
    TriangleMesh mesh;
    mesh.V.resize((nx + 1) * (ny + 1), 3);
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) {
            const double y = height * j / ny;
            mesh.V.row(j * (nx + 1) + i) << width * i / nx + shear * y, y, 0.0;
        }
    mesh.F = quad_grid_faces(nx, ny, false);
    return mesh;
}

TriangleMesh make_cylinder(int segments, int rings, double radius, double height) {
    if (segments < 3 || rings < 1)
        throw InvalidArgumentError("make_cylinder: segments must be >= 3 and rings >= 1");
    TriangleMesh mesh;
    mesh.V.resize(segments * (rings + 1), 3);
    for (int j = 0; j <= rings; ++j)
        for (int i = 0; i < segments; ++i) {
            const double angle = 2.0 * std::numbers::pi * i / segments;
            mesh.V.row(j * segments + i) << radius * std::cos(angle), radius * std::sin(angle),
                height * j / rings;
        }
    mesh.F = quad_grid_faces(segments, rings, true);
    return mesh;
}

}  // namespace sdmesh
