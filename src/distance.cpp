#include "sdmesh/distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <string>

#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"

// Determinism: each sample's distance depends only on the sample and the tree; the parallel loops
// combine them with max (order-independent) and per-face sums that are added serially in face
// order. So reports are bit-identical for any number of threads.

namespace sdmesh {
namespace {

using Eigen::Vector3d;

constexpr int kLeafSize = 4;
// Subtrees of more faces than this are built as tasks of their own.
constexpr int kParallelFaces = 1 << 14;
// A median split halves the faces, so the depth is at most log2(2^31) = 31 and a traversal stack
// holds at most depth + 1 entries.
constexpr int kMaxStack = 64;
// The cross product of two edges carries a rounding error of about ε·longest², so below this
// fraction of longest² (the height relative to the longest edge) the normal is not trusted:
// 1e-8 ≈ √ε balances the error of projecting on a noisy normal (ε·longest²/|n|) against that of
// ignoring the interior (the height).
constexpr double kSliver = 1e-8;

// Unit normal of abc, or zero when the triangle is too thin for a normal (see kSliver).
Vector3d trusted_normal(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
    const Vector3d n = (b - a).cross(c - a);
    const double longest2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    const double length = n.norm();
    if (length <= kSliver * longest2) return Vector3d::Zero();
    return n / length;
}

// Closest point of segment se to p. Its end points are returned exactly, and a zero-length
// segment (along = 0) is its point s.
Vector3d nearest_on_segment(const Vector3d& p, const Vector3d& s, const Vector3d& e) {
    const Vector3d se = e - s;
    const double along = se.dot(p - s), length2 = se.squaredNorm();
    if (along <= 0) return s;
    if (along >= length2) return e;
    return s + (along / length2) * se;
}

// Closest point of a triangle to p. When p projects outside, the nearest point lies on an edge
// whose line separates p from the triangle (one edge, or two near a vertex); otherwise it is the
// projection. A zero normal marks a thin triangle, reduced to its three edges.
Vector3d nearest_on_triangle(const Vector3d& p, const std::array<Vector3d, 3>& corner, const Vector3d& normal) {
    const bool thin = normal == Vector3d::Zero();
    Vector3d best;
    double best_d2 = std::numeric_limits<double>::infinity();
    bool outside = false;
    for (int k = 0; k < 3; ++k) {
        const Vector3d& s = corner[k];
        const Vector3d& e = corner[(k + 1) % 3];
        // Signed area of (p, s, e) along the normal: the opposite corner makes it positive.
        if (!thin && normal.dot((s - p).cross(e - s)) >= 0) continue;
        outside = true;
        const Vector3d x = nearest_on_segment(p, s, e);
        const double d2 = (x - p).squaredNorm();
        if (d2 < best_d2) {
            best = x;
            best_d2 = d2;
        }
    }
    if (outside) return best;
    return p - normal * normal.dot(p - corner[0]);
}

}  // namespace

Vector3d closest_point_on_triangle(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
    return nearest_on_triangle(p, {a, b, c}, trusted_normal(a, b, c));
}

// ---- TriangleTree -------------------------------------------------------------------------------

TriangleTree::TriangleTree(const TriangleMesh& mesh) {
    const int nf = mesh.num_faces();
    if (nf == 0) throw InvalidMeshError("distance: the mesh has no faces");
    require_indices_in_range(mesh);
    require_finite_positions(mesh);

    std::vector<Vector3d> centroid(nf);
#pragma omp parallel for schedule(static)
    for (int f = 0; f < nf; ++f)
        centroid[f] = (mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)) + mesh.V.row(mesh.F(f, 2))).transpose() / 3.0;
    std::vector<int> order(nf);
    std::iota(order.begin(), order.end(), 0);
    nodes_.resize(subtree_nodes(nf));
#pragma omp parallel
#pragma omp single
    build(order, centroid, 0, nf, 0);

    face_ = std::move(order);
    slot_.resize(nf);
    triangles_.resize(nf);
#pragma omp parallel for schedule(static)
    for (int i = 0; i < nf; ++i) {
        slot_[face_[i]] = i;
        Triangle& t = triangles_[i];
        for (int k = 0; k < 3; ++k) t.corner[k] = mesh.V.row(mesh.F(face_[i], k)).transpose();
        t.normal = trusted_normal(t.corner[0], t.corner[1], t.corner[2]);
    }
    // Children follow their parent in nodes_, so one backward pass fills the boxes bottom-up.
    for (int index = static_cast<int>(nodes_.size()) - 1; index >= 0; --index) {
        Node& node = nodes_[index];
        if (node.count > 0) {
            for (int i = node.first; i < node.first + node.count; ++i)
                for (const Vector3d& x : triangles_[i].corner) node.box.extend(x);
        } else {
            node.box = nodes_[index + 1].box.merged(nodes_[node.first].box);
        }
    }
}

int TriangleTree::subtree_nodes(int faces) {
    // The nodes at depth d hold ⌊faces / 2^d⌋ or ⌈faces / 2^d⌉ faces: two sizes a level.
    struct Sizes {
        int size[2] = {0, 0}, count[2] = {0, 0};
        void add(int n, int times) {
            const int slot = count[0] == 0 || size[0] == n ? 0 : 1;
            size[slot] = n, count[slot] += times;
        }
    };
    int nodes = 0;
    Sizes level;
    level.add(faces, 1);
    while (level.count[0] + level.count[1] > 0) {
        Sizes below;
        for (int slot = 0; slot < 2; ++slot) {
            nodes += level.count[slot];
            if (level.count[slot] == 0 || level.size[slot] <= kLeafSize) continue;
            below.add(level.size[slot] / 2, level.count[slot]);
            below.add(level.size[slot] - level.size[slot] / 2, level.count[slot]);
        }
        level = below;
    }
    return nodes;
}

void TriangleTree::build(std::vector<int>& order, const std::vector<Vector3d>& centroid, int begin, int end,
                         int index) {
    if (end - begin <= kLeafSize) {
        nodes_[index].first = begin;
        nodes_[index].count = end - begin;
        return;
    }
    Eigen::AlignedBox3d spread;
    for (int i = begin; i < end; ++i) spread.extend(centroid[order[i]]);
    int axis = 0;
    spread.sizes().maxCoeff(&axis);
    // Ties broken by face index: the split, hence the tree, is the same with any standard library.
    const auto before = [&](int f, int g) {
        return centroid[f][axis] < centroid[g][axis] || (centroid[f][axis] == centroid[g][axis] && f < g);
    };
    const int mid = begin + (end - begin) / 2;
    std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end, before);
    // Each subtree has its place in nodes_ (depth-first), so the halves are built side by side.
    const int right = index + 1 + subtree_nodes(mid - begin);
    nodes_[index].first = right;
#pragma omp task default(shared) if (end - begin > kParallelFaces)
    build(order, centroid, begin, mid, index + 1);
    build(order, centroid, mid, end, right);
#pragma omp taskwait
}

ClosestPoint TriangleTree::closest_point(const Vector3d& query) const {
    return search(query, {std::numeric_limits<double>::infinity(), Vector3d::Zero(), -1});
}

ClosestPoint TriangleTree::closest_point(const Vector3d& query, int near_face) const {
    return closest_point_beyond(query, near_face, -1);
}

ClosestPoint TriangleTree::closest_point_beyond(const Vector3d& query, int near_face, double squared_radius) const {
    const Triangle& t = triangles_[slot_[near_face]];
    const Vector3d x = nearest_on_triangle(query, t.corner, t.normal);
    // The same value the traversal computes for this face, so the minimum is the same.
    return search(query, {(x - query).squaredNorm(), x, near_face}, squared_radius);
}

ClosestPoint TriangleTree::search(const Vector3d& query, ClosestPoint best, double enough) const {
    if (best.squared_distance <= enough) return best;
    struct Pending {
        int node;
        double box_d2;
    };
    std::array<Pending, kMaxStack> stack;
    int top = 0;
    stack[top++] = {0, nodes_[0].box.squaredExteriorDistance(query)};
    while (top > 0) {
        const Pending pending = stack[--top];
        if (pending.box_d2 >= best.squared_distance) continue;  // best improved since the push
        const Node& node = nodes_[pending.node];
        if (node.count > 0) {
            for (int i = node.first; i < node.first + node.count; ++i) {
                const Triangle& t = triangles_[i];
                const Vector3d x = nearest_on_triangle(query, t.corner, t.normal);
                const double d2 = (x - query).squaredNorm();
                if (d2 < best.squared_distance) best = {d2, x, face_[i]};
            }
            if (best.squared_distance <= enough) return best;
            continue;
        }
        Pending near{pending.node + 1, nodes_[pending.node + 1].box.squaredExteriorDistance(query)};
        Pending far{node.first, nodes_[node.first].box.squaredExteriorDistance(query)};
        if (far.box_d2 < near.box_d2) std::swap(near, far);
        // The nearer child goes on top, so it is searched first and tightens the bound for the other.
        if (far.box_d2 < best.squared_distance) stack[top++] = far;
        if (near.box_d2 < best.squared_distance) stack[top++] = near;
    }
    return best;
}

// ---- Hausdorff distance -------------------------------------------------------------------------

namespace {

struct OneSided {
    double max = 0;
    double mean = 0;
    long long samples = 0;
};

TriangleTree tree_of(const TriangleMesh& mesh, const char* which) {
    try {
        return TriangleTree(mesh);
    } catch (const InvalidMeshError& e) {
        throw InvalidMeshError(std::string("hausdorff_distance: ") + which + " mesh: " + e.what());
    }
}

// The vertices of the faces flagged in `faces` (all faces when null), in order.
std::vector<int> referenced_vertices(const TriangleMesh& mesh, const std::vector<char>* faces) {
    std::vector<char> used(mesh.num_vertices(), 0);
    for (int f = 0; f < mesh.num_faces(); ++f)
        if (!faces || (*faces)[f])
            for (int k = 0; k < 3; ++k) used[mesh.F(f, k)] = 1;
    std::vector<int> vertices;
    for (int v = 0; v < mesh.num_vertices(); ++v)
        if (used[v]) vertices.push_back(v);
    return vertices;
}

// The largest k with k² <= samples_per_face whose total fits the budget, at least 1.
int face_resolution(long long num_vertices, long long num_faces, const HausdorffOptions& options) {
    int k = static_cast<int>(std::sqrt(static_cast<double>(options.samples_per_face)));
    while (k > 1 && num_vertices + num_faces * (static_cast<long long>(k) * k + 3) > options.max_samples) --k;
    return k;
}

// Distances from the samples of `from` to the surface held by `to`; only on the faces flagged in
// `faces` (and their vertices) when it is not null, the others counting as at distance 0. The
// density is that of the whole mesh either way. Without options.mean, the mean is NaN.
OneSided sample_distances(const TriangleMesh& from, const TriangleTree& to, const HausdorffOptions& options,
                          const std::vector<char>* faces) {
    const std::vector<int> all_vertices = referenced_vertices(from, nullptr);
    const std::vector<int> flagged_vertices = faces ? referenced_vertices(from, faces) : std::vector<int>{};
    const std::vector<int>& vertices = faces ? flagged_vertices : all_vertices;
    const int nv = static_cast<int>(vertices.size()), nf = from.num_faces();
    const int k = face_resolution(static_cast<long long>(all_vertices.size()), nf, options);

    // Each search starts from the face nearest to the previous sample of its thread, usually
    // next to it (files list neighbours near each other): the distance found is the same from any
    // start, only the search is shorter. Without the mean, a search stops at the first face within
    // its thread's maximum so far, as such a sample cannot raise it; a distance above the maximum
    // is exact, so each thread's maximum is the same as with full searches.
    double worst = 0;
    std::vector<double> face_mean(nf, 0.0), area(nf);
    long long sampled_faces = 0;
#pragma omp parallel
    {
        int near_face = -1;
        double thread_worst2 = 0;
        const auto sample = [&](const Vector3d& x) {
            const ClosestPoint hit = near_face < 0 ? to.closest_point(x)
                                     : options.mean ? to.closest_point(x, near_face)
                                                    : to.closest_point_beyond(x, near_face, thread_worst2);
            near_face = hit.face;
            thread_worst2 = std::max(thread_worst2, hit.squared_distance);
            return std::sqrt(hit.squared_distance);
        };
#pragma omp for schedule(dynamic, 256)
        for (int i = 0; i < nv; ++i) sample(from.V.row(vertices[i]).transpose());

        // Face f's samples are a + v·(b - a) + w·(c - a): the centroids of the k² sub-triangles of
        // a k-subdivision (weights for the mean) and the three edge midpoints.
#pragma omp for schedule(dynamic, 64) reduction(+ : sampled_faces)
        for (int f = 0; f < nf; ++f) {
            const Vector3d a = from.V.row(from.F(f, 0)).transpose();
            const Vector3d ab = from.V.row(from.F(f, 1)).transpose() - a;
            const Vector3d ac = from.V.row(from.F(f, 2)).transpose() - a;
            area[f] = 0.5 * ab.cross(ac).norm();
            if (faces && !(*faces)[f]) continue;
            ++sampled_faces;
            const auto at = [&](double v, double w) { return sample(a + v * ab + w * ac); };
            at(0.5, 0.0);
            at(0.0, 0.5);
            at(0.5, 0.5);
            double sum = 0;
            for (int i = 0; i < k; ++i)
                for (int j = 0; i + j < k; ++j) {
                    sum += at((i + 1.0 / 3) / k, (j + 1.0 / 3) / k);
                    if (i + j + 1 < k) sum += at((i + 2.0 / 3) / k, (j + 2.0 / 3) / k);
                }
            face_mean[f] = sum / (k * k);
        }
#pragma omp critical
        worst = std::max(worst, std::sqrt(thread_worst2));
    }
    const long long samples = nv + sampled_faces * (static_cast<long long>(k) * k + 3);
    if (!options.mean) return {worst, std::numeric_limits<double>::quiet_NaN(), samples};

    // A mesh of zero area weights its faces equally.
    const double total_area = std::accumulate(area.begin(), area.end(), 0.0);
    double weighted = 0;
    for (int f = 0; f < nf; ++f) weighted += (total_area > 0 ? area[f] : 1.0) * face_mean[f];
    return {worst, weighted / (total_area > 0 ? total_area : nf), samples};
}

// The faces of `mesh` that may meet a triangle of `replaced`: those with a triangle within their
// largest centroid-to-corner distance of their centroid (every point of a face is that close).
std::vector<char> faces_meeting(const TriangleMesh& mesh, const TriangleMesh& replaced) {
    std::vector<char> meets(mesh.num_faces(), 0);
    if (replaced.num_faces() == 0) return meets;
    const TriangleTree tree = tree_of(replaced, "replaced");
#pragma omp parallel for schedule(dynamic, 256)
    for (int f = 0; f < mesh.num_faces(); ++f) {
        Vector3d centroid = Vector3d::Zero();
        for (int k = 0; k < 3; ++k) centroid += mesh.V.row(mesh.F(f, k)).transpose() / 3.0;
        double radius2 = 0;
        for (int k = 0; k < 3; ++k)
            radius2 = std::max(radius2, (mesh.V.row(mesh.F(f, k)).transpose() - centroid).squaredNorm());
        // Rounding of the centroid and of the distance: a relative margin.
        meets[f] = tree.closest_point(centroid).squared_distance <= radius2 * (1 + 1e-9) ? 1 : 0;
    }
    return meets;
}

// Both directions, on the faces flagged in a_faces and b_faces (all when null); the sample
// density is that of the whole meshes.
HausdorffReport measure(const TriangleMesh& a, const TriangleMesh& b, const HausdorffOptions& options,
                        const TriangleTree& tree_a, const TriangleTree& tree_b, const std::vector<char>* a_faces,
                        const std::vector<char>* b_faces, int exponent) {
    const OneSided forward = sample_distances(a, tree_b, options, a_faces);
    const OneSided backward = sample_distances(b, tree_a, options, b_faces);

    const auto in_input_units = [exponent](double length) { return std::ldexp(length, exponent); };
    HausdorffReport report;
    report.forward = in_input_units(forward.max);
    report.backward = in_input_units(backward.max);
    report.hausdorff = std::max(report.forward, report.backward);
    report.diagonal = in_input_units(tree_a.bounds().diagonal().norm());
    report.hausdorff_rel = report.hausdorff == 0 ? 0 : std::max(forward.max, backward.max) / tree_a.bounds().diagonal().norm();
    report.mean_forward = in_input_units(forward.mean);
    report.samples = forward.samples + backward.samples;
    return report;
}

void check(const HausdorffOptions& options) {
    if (options.samples_per_face < 1 || options.max_samples < 1)
        throw InvalidArgumentError("hausdorff_distance: samples_per_face (" + std::to_string(options.samples_per_face) +
                                   ") and max_samples (" + std::to_string(options.max_samples) + ") must be >= 1");
}

// Both meshes are measured at the scale of a unit diagonal of the first, by a power of two
// (exact; copies only far from it): normals are cross products, whose squared norms overflow
// from coordinates of about 1e75 on (every face then looked too thin to have one).
struct AtUnitScale {
    explicit AtUnitScale(const TriangleMesh& reference) : exponent(far_unit_exponent(bounding_box_diagonal(reference))) {}
    const TriangleMesh& operator()(const TriangleMesh& mesh, std::optional<TriangleMesh>& copy) const {
        if (exponent == 0) return mesh;
        copy = scaled_by_power_of_two(mesh, -exponent);
        return *copy;
    }
    int exponent;
};

}  // namespace

HausdorffReport hausdorff_distance(const TriangleMesh& a, const TriangleMesh& b, const HausdorffOptions& options) {
    check(options);
    const AtUnitScale unit(a);
    std::optional<TriangleMesh> copy_a, copy_b;
    const TriangleMesh& unit_a = unit(a, copy_a);
    const TriangleMesh& unit_b = unit(b, copy_b);
    return measure(unit_a, unit_b, options, tree_of(unit_a, "first"), tree_of(unit_b, "second"), nullptr, nullptr,
                   unit.exponent);
}

HausdorffReport hausdorff_distance_of_edit(const TriangleMesh& a, const TriangleMesh& b, const SurfaceEdit& edit,
                                           const HausdorffOptions& options) {
    check(options);
    auto require_flags = [](const std::vector<char>& flags, const TriangleMesh& mesh, const char* which) {
        if (static_cast<int>(flags.size()) != mesh.num_faces())
            throw InvalidArgumentError(std::string("hausdorff_distance_of_edit: ") + std::to_string(flags.size()) +
                                       " " + which + " flags for a mesh of " + std::to_string(mesh.num_faces()) +
                                       " faces");
    };
    require_flags(edit.changed_faces, b, "changed-face");
    if (!edit.replaced_faces.empty()) require_flags(edit.replaced_faces, a, "replaced-face");
    const AtUnitScale unit(a);
    std::optional<TriangleMesh> copy_a, copy_b, copy_replaced;
    const TriangleMesh& unit_a = unit(a, copy_a);
    const TriangleMesh& unit_b = unit(b, copy_b);
    std::vector<char> a_faces = faces_meeting(unit_a, unit(edit.replaced, copy_replaced));
    for (size_t f = 0; f < edit.replaced_faces.size(); ++f) a_faces[f] = a_faces[f] || edit.replaced_faces[f];
    return measure(unit_a, unit_b, options, tree_of(unit_a, "first"), tree_of(unit_b, "second"), &a_faces,
                   &edit.changed_faces, unit.exponent);
}

}  // namespace sdmesh
