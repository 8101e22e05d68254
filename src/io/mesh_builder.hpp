#pragma once
// Collects what a reader finds (vertices, polygons) and turns it into a TriangleMesh.
//
// Shared by every format so that polygon triangulation and the ReadReport counts are done the
// same way everywhere. Index validation stays with the readers: only they know where in the file
// an index came from, which the error message must say.

#include <algorithm>
#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "io/memory_budget.hpp"
#include "sdmesh/io.hpp"
#include "sdmesh/mesh.hpp"

namespace sdmesh::io {

class MeshBuilder {
public:
    /// `file` names the input in the IoError thrown when what is read would take more than
    /// max_bytes (memory_budget.hpp).
    explicit MeshBuilder(std::string_view file, std::size_t max_bytes = max_mesh_bytes())
        : file_(file), max_bytes_(max_bytes) {}

    /// Callers bound these by what the remaining bytes can hold, never by header counts alone;
    /// the budget bounds them too.
    void reserve_vertices(std::size_t vertices) { xyz_.reserve(3 * std::min(vertices, max_bytes_ / kVertexBytes)); }
    void reserve_triangles(std::size_t triangles) {
        triangles_.reserve(3 * std::min(triangles, max_bytes_ / kTriangleBytes));
    }

    void add_vertex(double x, double y, double z) {
        take(kVertexBytes);
        xyz_.push_back(x);
        xyz_.push_back(y);
        xyz_.push_back(z);
    }

    /// Counts memory a reader holds beside the mesh (STL's table of welded corners) against the
    /// same budget.
    void take(std::size_t bytes) {
        if (bytes > max_bytes_ - bytes_) throw_too_large(file_, "its vertices and faces take", MemoryUse::mesh, max_bytes_);
        bytes_ += bytes;
    }

    /// Adds a face. One with more than 3 corners is kept as its fan (0, i, i+1) until finish()
    /// knows every position and triangulates it (io.hpp says how). Corners are kept as they are
    /// (repeated indices included). Returns false, adding nothing, for a face with fewer than 3
    /// corners: the caller reports that with its own location.
    [[nodiscard]] bool add_face(std::span<const int> corners) {
        if (corners.size() < 3) return false;
        take((corners.size() - 2) * kTriangleBytes + (corners.size() > 3 ? sizeof(PolygonFan) : 0));
        if (corners.size() > 3) polygon_fans_.push_back({triangles_.size() / 3, corners.size()});
        for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
            triangles_.push_back(corners[0]);
            triangles_.push_back(corners[i]);
            triangles_.push_back(corners[i + 1]);
        }
        ++faces_;
        if (corners.size() > 3) {
            ++polygons_;
            polygon_triangles_ += static_cast<long long>(corners.size()) - 2;
        }
        return true;
    }

    [[nodiscard]] long long num_vertices() const { return static_cast<long long>(xyz_.size() / 3); }

    /// The mesh; fills file_vertices (= vertices added), file_faces, polygons, polygon_triangles,
    /// ear_clipped_polygons. Every index must be a vertex by now.
    TriangleMesh finish(ReadReport& report) const;

private:
    struct PolygonFan {
        std::size_t first_triangle;
        std::size_t corners;
    };
    static constexpr std::size_t kVertexBytes = 3 * sizeof(double);
    static constexpr std::size_t kTriangleBytes = 3 * sizeof(int);

    std::string_view file_;
    std::size_t max_bytes_;
    std::size_t bytes_ = 0;  // taken from max_bytes_ so far

    std::vector<double> xyz_;    // x0 y0 z0 x1 ...
    std::vector<int> triangles_; // a0 b0 c0 a1 ...
    long long faces_ = 0;
    long long polygons_ = 0;
    long long polygon_triangles_ = 0;
    std::vector<PolygonFan> polygon_fans_;
};

}  // namespace sdmesh::io
