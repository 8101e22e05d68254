#pragma once
// Meshes made in code, for tests, experiments and examples.

#include "sdmesh/mesh.hpp"

namespace sdmesh {

/// Unit icosphere: the icosahedron, each face split 1:4 `subdivisions` times, vertices projected
/// onto the unit sphere. 10·4^s + 2 vertices, 20·4^s faces, outward orientation.
/// \throws InvalidArgumentError subdivisions < 0 or > 9.
TriangleMesh make_icosphere(int subdivisions);

/// Planar grid of nx × ny quads on [0, width] × [0, height] in the z = 0 plane, each quad cut by
/// its diagonal from (i, j) to (i+1, j+1); `shear` moves row j by shear·y in x (a skewed grid
/// whose triangles become obtuse when |shear| is large). Counter-clockwise seen from +z.
/// \throws InvalidArgumentError nx < 1 or ny < 1.
TriangleMesh make_grid(int nx, int ny, double width = 1.0, double height = 1.0, double shear = 0.0);

/// Open cylinder of radius r and height h around the z axis, `segments` around and `rings`
/// quads high, each quad cut by a diagonal; two boundary loops, outward orientation.
/// \throws InvalidArgumentError segments < 3 or rings < 1.
TriangleMesh make_cylinder(int segments, int rings, double radius = 1.0, double height = 1.0);

}  // namespace sdmesh
