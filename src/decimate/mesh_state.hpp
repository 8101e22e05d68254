#pragma once
// The mesh that decimation changes (internal, not installed): connectivity in a corner table,
// positions, quadrics and per-vertex bookkeeping, shared by the collapsers (collapser.hpp) and
// the queries they have in common. Collapsers of the two halves run side by side; each writes
// only what `owner` gives its half (see Collapser).

#include <algorithm>
#include <array>
#include <atomic>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "sdmesh/decimate.hpp"
#include "sdmesh/distance.hpp"
#include "sdmesh/topology.hpp"

namespace sdmesh::decimation {

using Vec3 = Eigen::Vector3d;

// Garland–Heckbert quadric: error(x) = xᵀAx + 2bᵀx + c.
struct Quadric {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Vec3 b = Vec3::Zero();
    double c = 0;

    void add_plane(const Vec3& unit_normal, const Vec3& point, double weight) {
        const double d = -unit_normal.dot(point);
        A += weight * unit_normal * unit_normal.transpose();
        b += weight * d * unit_normal;
        c += weight * d * d;
    }
    Quadric operator+(const Quadric& o) const { return {A + o.A, b + o.b, c + o.c}; }
    [[nodiscard]] double operator()(const Vec3& x) const { return x.dot(A * x) + 2 * b.dot(x) + c; }
};

// The quadric with a slight pull towards the edge's midpoint, so that flat and cylindrical
// neighbourhoods (singular A) have a unique optimum.
Quadric regularised(const Quadric& q, const Vec3& mid);

// The minimiser of q on segment p + t(d), t in [lo, hi].
Vec3 segment_minimum(const Quadric& q, const Vec3& p, const Vec3& d, double lo, double hi);

// The points of face abc that the report's hausdorff_distance samples (with samples_per_face
// 4 or 1): edge midpoints, the centroids of its 2 × 2 subdivision, its centroid; computed as
// it does, from the first corner, so that the error bound holds for the reported value.
void face_samples(const Vec3& a, const Vec3& b, const Vec3& c, std::vector<Vec3>& out);

// The faces around a vertex: up to kInline of them in place (a vertex has six on average), so
// that reading them costs one cache line rather than a second, scattered read; more on the heap.
class alignas(64) FaceRing {
public:
    [[nodiscard]] const int* begin() const { return size_ <= kInline ? inline_ : heap_.data(); }
    [[nodiscard]] const int* end() const { return begin() + size_; }
    [[nodiscard]] int* begin() { return size_ <= kInline ? inline_ : heap_.data(); }
    [[nodiscard]] int* end() { return begin() + size_; }
    [[nodiscard]] size_t size() const { return static_cast<size_t>(size_); }
    [[nodiscard]] bool empty() const { return size_ == 0; }
    [[nodiscard]] int front() const { return *begin(); }

    void push_back(int f) {
        if (size_ < kInline) {
            inline_[size_++] = f;
            return;
        }
        if (size_ == kInline) heap_.assign(inline_, inline_ + kInline);
        heap_.push_back(f);
        ++size_;
    }
    /// Removes every occurrence of f.
    void erase(int f) {
        int* const last = std::remove(begin(), end(), f);
        const int removed = static_cast<int>(end() - last);
        if (removed == 0) return;
        if (size_ > kInline) heap_.resize(heap_.size() - removed);
        const int before = size_;
        size_ -= removed;
        if (before > kInline && size_ <= kInline) {
            std::copy(heap_.begin(), heap_.end(), inline_);
            heap_.clear();
        }
    }
    void clear() {
        size_ = 0;
        heap_.clear();
    }

private:
    static constexpr int kInline = 9;  // with the size and the vector, one 64-byte line
    int size_ = 0;
    int inline_[kInline];
    std::vector<int> heap_;  // all the faces when there are more than kInline
};

// A refused collapse of one of a vertex's edges.
struct Refusal {
    int other;  // the other end of the refused edge
    int count;  // how often it was refused
};

struct MeshState {
    /// The state of `mesh` (manifold, oriented, no zero-area face); vertices below `split_at` form
    /// half 0 and the others half 1 (split_at = the vertex count: one half only). `mesh` is the
    /// input divided by 2^scale_exponent; result() multiplies back.
    MeshState(const TriangleMesh& mesh, const EdgeTable& edges, const DecimateOptions& options, int split_at,
              int scale_exponent);

    int scale_exponent;
    std::vector<Vec3> P;
    std::vector<std::array<int, 3>> corner;
    std::vector<int> twin;  // per side 3f + k (opposite corner k): the same edge's side in the face across, -1 on the boundary
    std::vector<char> face_alive;
    std::vector<FaceRing> vertex_faces;          // sorted face ids around each vertex
    std::vector<Quadric> quadric;
    std::vector<char> on_boundary;
    std::vector<char> alive;
    std::atomic<long long> live_vertices = 0;
    std::vector<unsigned> version;               // bumped when a collapse moves the vertex or gives it new edges
    std::vector<long long> touched;              // the clock of the last collapse that changed its star (Collapser::untouched_since)
    std::vector<std::vector<Refusal>> refused;   // per vertex: refused collapses of its edges, still retried

    // The halves: a vertex belongs to half 0 below `split`, else to half 1. Its owner is its half
    // if every face around it lies in that half, else -1 (it is on the seam).
    int split;
    std::vector<signed char> owner;

    // The error bound (max_error > 0). Forward: the input's vertices and sample points, each kept
    // with a face of the current mesh it is within the bound of; a collapse re-homes the points of
    // the old star on the new star. Backward: the new vertex and the samples of the new faces
    // must be within the bound of the input.
    std::unique_ptr<TriangleTree> tree;
    double bound = 0;
    std::vector<Vec3> points;
    std::vector<std::vector<int>> face_points;

    [[nodiscard]] int half_of(int v) const { return v < split ? 0 : 1; }
    // Sets v's owner from the faces around it now.
    void update_owner(int v);

    [[nodiscard]] Vec3 face_normal(int f) const {
        const auto& c = corner[f];
        return (P[c[1]] - P[c[0]]).cross(P[c[2]] - P[c[0]]);
    }
    static bool has_corner(const std::array<int, 3>& face, int v) {
        return face[0] == v || face[1] == v || face[2] == v;
    }
    // The neighbours of u, sorted, into out.
    void neighbours(int u, std::vector<int>& out) const;
    [[nodiscard]] bool adjacent(int u, int w) const;
    // Which end of an edge stays: a boundary vertex keeps its place; otherwise the lower index
    // (determinism).
    [[nodiscard]] std::pair<int, int> survivor(int u, int w) const {
        if (on_boundary[w] && !on_boundary[u]) return {w, u};
        return {u, w};
    }
    // The lower bound a collapse of [p, q] is queued with: the quadric at the unconstrained placement.
    [[nodiscard]] double lower_bound(int p, int q) const;

    /// The current mesh; survivors keep the order of `input_vertex` (their index in the caller's mesh).
    [[nodiscard]] TriangleMesh result(const std::vector<int>& input_vertex) const;

private:
    void init_error_tracking(const TriangleMesh& mesh, double max_error);
};

}  // namespace sdmesh::decimation
