#include "decimate/flat_flips.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sdmesh/delaunay.hpp"
#include "sdmesh/geometry.hpp"

namespace sdmesh::decimation {
namespace {

// Normals at most this far apart (radians) count as one plane: the conversion's coplanar tolerance.
constexpr double kFlatAngle = 1e-10;
// Flips per collapse; a collapse that needs more is refused.
constexpr int kMaxFlips = 64;

int index_of(const std::array<int, 3>& corners, int v) {
    return corners[0] == v ? 0 : corners[1] == v ? 1 : corners[2] == v ? 2 : -1;
}

}  // namespace

bool inside_a_plane(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    // The angle between the normals is at most kFlatAngle ≈ its tangent; no arctangent, since
    // every failed LD test of a collapse asks.
    const Vec3 n1 = (b - a).cross(c - a), n2 = (a - b).cross(d - b);
    const double cosine = n1.dot(n2);
    return cosine > 0 && n1.cross(n2).squaredNorm() <= kFlatAngle * kFlatAngle * cosine * cosine;
}

int FlatFlips::face_with_side(int from, int to) {
    for (int i = 0; i < static_cast<int>(faces_.size()); ++i) {
        const int k = index_of(faces_[i].v, from);
        if (k >= 0 && faces_[i].v[(k + 1) % 3] == to) return i;
    }
    if (from == p_ || to == p_) return -1;  // every face around p is in the patch
    for (int f : mesh_->vertex_faces[from]) {
        if (!mesh_->face_alive[f] || std::find(removed_->begin(), removed_->end(), f) != removed_->end() ||
            std::any_of(faces_.begin(), faces_.end(), [&](const Face& g) { return g.id == f; }))
            continue;
        const auto& c = mesh_->corner[f];
        if (c[(index_of(c, from) + 1) % 3] != to) continue;
        if (half_ >= 0 && std::any_of(c.begin(), c.end(), [&](int v) { return mesh_->owner[v] != half_; })) {
            outside_half_ = true;
            return -1;
        }
        faces_.push_back({f, c, c});
        return static_cast<int>(faces_.size()) - 1;
    }
    return -1;
}

bool FlatFlips::locally_delaunay(int a, int b, int c, int d, double tan_tolerance) const {
    const double ab = distance(position(a), position(b));
    const double ac = distance(position(a), position(c)), bc = distance(position(b), position(c));
    const double ad = distance(position(a), position(d)), bd = distance(position(b), position(d));
    const double area4_c = 4.0 * triangle_area(ab, ac, bc), area4_d = 4.0 * triangle_area(ab, ad, bd);
    return area4_c > 0 && area4_d > 0 &&
           is_locally_delaunay_scaled(area4_c, cosine_numerator(ab, ac, bc), area4_d, cosine_numerator(ab, ad, bd),
                                      tan_tolerance);
}

bool FlatFlips::has_edge(int a, int b) const {
    if (std::any_of(faces_.begin(), faces_.end(),
                    [&](const Face& f) { return index_of(f.v, a) >= 0 && index_of(f.v, b) >= 0; }))
        return true;
    if (a == p_ || b == p_) return false;
    return std::any_of(mesh_->vertex_faces[a].begin(), mesh_->vertex_faces[a].end(), [&](int f) {
        return mesh_->face_alive[f] && std::find(removed_->begin(), removed_->end(), f) == removed_->end() &&
               std::none_of(faces_.begin(), faces_.end(), [&](const Face& g) { return g.id == f; }) &&
               MeshState::has_corner(mesh_->corner[f], b);
    });
}

FlatFlips::Outcome FlatFlips::run(const MeshState& mesh, int p, int q, const Vec3& x, const std::vector<int>& star_faces,
                                  const std::vector<int>& removed_faces, BoundaryPolicy boundary, double tolerance,
                                  int half) {
    mesh_ = &mesh;
    p_ = p, half_ = half, x_ = x;
    removed_ = &removed_faces;
    faces_.clear();
    flipped_in_.clear();
    flipped_out_.clear();
    pending_.clear();
    flips_ = 0;
    outside_half_ = false;
    for (int f : star_faces) {
        std::array<int, 3> c = mesh.corner[f];
        for (int& v : c)
            if (v == q) v = p;
        faces_.push_back({f, c, c});
    }
    for (const Face& f : faces_)
        for (int k = 0; k < 3; ++k) pending_.emplace_back(f.v[k], f.v[(k + 1) % 3]);
    const double tan_tolerance = std::tan(tolerance);
    while (!pending_.empty()) {
        const auto [a, b] = pending_.back();
        pending_.pop_back();
        const int i = face_with_side(a, b), j = face_with_side(b, a);
        if (outside_half_) return Outcome::outside_half;
        if (i < 0 && j < 0) continue;  // flipped away
        const auto opposite = [&](int face, int from) { return faces_[face].v[(index_of(faces_[face].v, from) + 2) % 3]; };
        const double ab = distance(position(a), position(b));
        if (i < 0 || j < 0) {
            const int face = i >= 0 ? i : j;
            const int c = opposite(face, i >= 0 ? a : b);
            const double ac = distance(position(a), position(c)), bc = distance(position(b), position(c));
            if (boundary == BoundaryPolicy::strict &&
                boundary_margin_scaled(4.0 * triangle_area(ab, ac, bc), cosine_numerator(ab, ac, bc)) < -tolerance)
                return Outcome::not_delaunay;
            continue;
        }
        const int c = opposite(i, a), d = opposite(j, b);
        if (locally_delaunay(a, b, c, d, tan_tolerance)) continue;
        // Faces (a, b, c) and (b, a, d) become (a, d, c) and (d, b, c): only inside a plane, for a
        // convex quad whose other diagonal is not an edge yet.
        if (!inside_a_plane(position(a), position(b), position(c), position(d)) || c == d || has_edge(c, d))
            return Outcome::not_delaunay;
        const double ac = distance(position(a), position(c)), bc = distance(position(b), position(c));
        const double ad = distance(position(a), position(d)), bd = distance(position(b), position(d));
        const double at_a = corner_angle(bc, ab, ac) + corner_angle(bd, ab, ad);
        const double at_b = corner_angle(ac, ab, bc) + corner_angle(ad, ab, bd);
        if (!(at_a < std::numbers::pi - 1e-9 && at_b < std::numbers::pi - 1e-9) || ++flips_ > kMaxFlips)
            return Outcome::not_delaunay;
        // In exact arithmetic the other diagonal of a quad is LD when this one is not; in a nearly
        // co-circular quad of long thin faces both verdicts are rounding (margins of ±1e-9 at
        // aspect 1e7), so it is judged too, as the certificate will judge it.
        if (!locally_delaunay(c, d, b, a, tan_tolerance)) return Outcome::not_delaunay;
        faces_[i].v = {a, d, c};
        faces_[j].v = {d, b, c};
        flipped_in_.emplace_back(std::min(c, d), std::max(c, d));
        flipped_out_.emplace_back(std::min(a, b), std::max(a, b));
        for (const auto& side : {std::pair{a, d}, std::pair{d, b}, std::pair{b, c}, std::pair{c, a}}) pending_.push_back(side);
    }
    return Outcome::delaunay;
}

void FlatFlips::apply(MeshState& mesh, std::vector<std::pair<int, int>>& flipped_in,
                      std::vector<std::pair<int, int>>& flipped_out, std::vector<int>& changed) const {
    flipped_in = flipped_in_;
    flipped_out = flipped_out_;
    changed.clear();
    for (const Face& f : faces_) {
        if (f.v == f.before) continue;
        for (int v : f.before) mesh.vertex_faces[v].erase(f.id);
        mesh.corner[f.id] = f.v;
        for (int v : f.v) mesh.vertex_faces[v].push_back(f.id);
        changed.insert(changed.end(), f.before.begin(), f.before.end());
        changed.insert(changed.end(), f.v.begin(), f.v.end());
    }
    std::sort(changed.begin(), changed.end());
    changed.erase(std::unique(changed.begin(), changed.end()), changed.end());
    for (int v : changed) std::sort(mesh.vertex_faces[v].begin(), mesh.vertex_faces[v].end());
    // The sides of the changed faces and their twins.
    for (const Face& f : faces_) {
        if (f.v == f.before) continue;
        for (int k = 0; k < 3; ++k) {
            const int from = f.v[(k + 1) % 3], to = f.v[(k + 2) % 3];
            int twin = -1;
            for (int g : mesh.vertex_faces[to]) {
                const auto& c = mesh.corner[g];
                const int j = index_of(c, to);
                if (g != f.id && c[(j + 1) % 3] == from) twin = 3 * g + (j + 2) % 3;
            }
            mesh.twin[3 * f.id + k] = twin;
            if (twin >= 0) mesh.twin[twin] = 3 * f.id + k;
        }
    }
}

}  // namespace sdmesh::decimation
