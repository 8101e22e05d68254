#include "sdmesh/validate.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <queue>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "prefault.hpp"
#include "union_find.hpp"

namespace sdmesh {
namespace {

// representative[v] = the smallest-index vertex among those with exactly v's position, for the
// vertices in `mask` with finite coordinates; v itself otherwise.
std::vector<int> coincident_representatives(const Eigen::MatrixX3d& V,
                                            const std::vector<char>& mask) {
    // Sorted as copies packed per vertex: comparisons that read V (stored column by column) at
    // random cost three cache misses each.
    struct Point {
        std::array<double, 3> x;
        int v;
    };
    std::vector<Point> points;
    points.reserve(static_cast<size_t>(V.rows()));
    detail::prefault(points.data(), points.capacity() * sizeof(Point));
    for (int v = 0; v < V.rows(); ++v)
        if (mask[v] && V.row(v).allFinite()) points.push_back({{V(v, 0), V(v, 1), V(v, 2)}, v});
    std::sort(points.begin(), points.end(), [](const Point& a, const Point& b) {
        for (int i = 0; i < 3; ++i)
            if (a.x[i] != b.x[i]) return a.x[i] < b.x[i];
        return a.v < b.v;
    });
    std::vector<int> representative(V.rows());
    std::iota(representative.begin(), representative.end(), 0);
    for (size_t i = 1; i < points.size(); ++i)
        if (points[i].x == points[i - 1].x) representative[points[i].v] = representative[points[i - 1].v];
    return representative;
}

// Whether face f (with three distinct indices) has zero area: at most 1e-12 of its longest side
// squared. The area is the cross product of two sides scaled by the longest (no overflow at
// 1e150). From the side lengths, a cap 8e8 long whose apex lay 1e-9 of that off the long side
// came out as exactly 0 (its short sides summed to the long one in rounding), and repair flipped
// it, moving the surface. Returns its side lengths, side k opposite corner k, in `sides`.
bool has_zero_area(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, int f, double (&sides)[3]) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = V.row(F(f, k)).transpose();
    for (int k = 0; k < 3; ++k) sides[k] = distance(p[(k + 1) % 3], p[(k + 2) % 3]);
    const double longest = std::max({sides[0], sides[1], sides[2]});
    if (!std::isfinite(longest)) return false;
    if (longest == 0) return true;
    const Eigen::Vector3d u = (p[1] - p[0]) / longest, v = (p[2] - p[0]) / longest;
    return 0.5 * u.cross(v).norm() <= 1e-12;
}

// A zero-area face whose shortest side is below kNeedleSide of its longest is a needle: two of its
// vertices nearly coincide, so no flip mends it (its ends are merged instead); any other is a cap,
// with a vertex inside its longest side.
constexpr double kNeedleSide = 1e-6;

// Whether a zero-area face with these sides is a needle.
bool is_needle(const double (&sides)[3]) {
    return *std::min_element(sides, sides + 3) < kNeedleSide * *std::max_element(sides, sides + 3);
}

// The corner opposite the short side of face f if it is a needle, else -1.
int needle_corner(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, int f) {
    double sides[3];
    if (!has_zero_area(V, F, f, sides) || !is_needle(sides)) return -1;
    return static_cast<int>(std::min_element(sides, sides + 3) - sides);
}

struct Merges {
    std::vector<int> representative;  ///< the smallest-index vertex each vertex is merged with
    int needle_sides = 0;             ///< merges that only needles asked for
};

// With `coincident`, merges the vertices at exactly one position (among `mask`), and the two ends
// of a face side shorter than kRoundingSide of the bounding-box diagonal of those vertices, which
// are one point up to an exporter's rounding (0 and 5.7e-16); with `needles`, the two ends of
// each needle's short side.
Merges merge_representatives(const TriangleMesh& mesh, const std::vector<char>& mask, bool coincident, bool needles) {
    constexpr double kRoundingSide = 1e-12;
    Merges merges;
    std::vector<int>& representative = merges.representative;
    if (coincident) {
        representative = coincident_representatives(mesh.V, mask);
    } else {
        representative.resize(static_cast<size_t>(mesh.num_vertices()));
        std::iota(representative.begin(), representative.end(), 0);
    }
    Eigen::RowVector3d low = Eigen::RowVector3d::Constant(HUGE_VAL), high = -low;
    for (int v = 0; v < mesh.num_vertices(); ++v)
        if (mask[v] && mesh.V.row(v).allFinite()) {
            low = low.cwiseMin(mesh.V.row(v));
            high = high.cwiseMax(mesh.V.row(v));
        }
    const double shortest = kRoundingSide * (high - low).stableNorm();
    const bool rounding = coincident && shortest > 0 && std::isfinite(shortest);
    UnionFind sets(mesh.num_vertices());
    bool merged = false;
    if (rounding)
        for (int f = 0; f < mesh.num_faces(); ++f)
            for (int k = 0; k < 3; ++k) {
                const int a = representative[mesh.F(f, k)], b = representative[mesh.F(f, (k + 1) % 3)];
                if (a != b && (mesh.V.row(a) - mesh.V.row(b)).norm() <= shortest) merged |= sets.unite(a, b);
            }
    if (needles) {
        std::vector<signed char> corner(static_cast<size_t>(mesh.num_faces()));
#pragma omp parallel for schedule(static)
        for (int f = 0; f < mesh.num_faces(); ++f) corner[f] = static_cast<signed char>(needle_corner(mesh.V, mesh.F, f));
        for (int f = 0; f < mesh.num_faces(); ++f) {
            const int k = corner[f];
            if (k >= 0 && sets.unite(representative[mesh.F(f, (k + 1) % 3)], representative[mesh.F(f, (k + 2) % 3)])) {
                merged = true;
                ++merges.needle_sides;
            }
        }
    }
    if (!merged) return merges;
    std::vector<int> smallest(representative.size(), INT_MAX);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
        int& s = smallest[static_cast<size_t>(sets.find(representative[v]))];
        s = std::min(s, v);
    }
    for (int v = 0; v < mesh.num_vertices(); ++v) representative[v] = smallest[static_cast<size_t>(sets.find(representative[v]))];
    return merges;
}

// Faces whose vertex set equals that of an earlier face. The faces are bucketed by their
// smallest vertex (a counting sort), and each small bucket is sorted by the other two packed in
// one 64-bit key: several times faster than sorting all the triples.
std::vector<char> duplicate_faces(const Eigen::MatrixX3i& F, int num_vertices) {
    const int num_faces = static_cast<int>(F.rows());
    const auto sorted = [&F](int f) {
        std::array<int, 3> key = {F(f, 0), F(f, 1), F(f, 2)};
        std::sort(key.begin(), key.end());
        return key;
    };
    std::vector<int> bucket_start(static_cast<size_t>(num_vertices) + 1, 0);
    for (int f = 0; f < num_faces; ++f) ++bucket_start[sorted(f)[0] + 1];
    std::partial_sum(bucket_start.begin(), bucket_start.end(), bucket_start.begin());
    std::vector<std::pair<std::uint64_t, int>> keys;
    detail::prefaulted_assign(keys, static_cast<size_t>(num_faces), {});
    std::vector<int> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (int f = 0; f < num_faces; ++f) {
        const auto [a, b, c] = sorted(f);
        keys[fill[a]++] = {(std::uint64_t(std::uint32_t(b)) << 32) | std::uint32_t(c), f};
    }
    std::vector<char> duplicate(static_cast<size_t>(num_faces), 0);
#pragma omp parallel for schedule(dynamic, 4096)
    for (int v = 0; v < num_vertices; ++v) {
        const auto begin = keys.begin() + bucket_start[v], end = keys.begin() + bucket_start[v + 1];
        std::sort(begin, end);
        for (auto i = begin; i != end; ++i)
            if (i != begin && i->first == (i - 1)->first) duplicate[i->second] = 1;
    }
    return duplicate;
}

// True when the two halfedges of an interior edge run the same way (inconsistent orientation).
bool same_direction(const Eigen::MatrixX3i& F, int h0, int h1) {
    auto tail = [&F](int h) { return F(h / 3, (h % 3 + 1) % 3); };
    return tail(h0) == tail(h1);
}

struct Orientation {
    std::vector<char> flip;  ///< faces to re-wind for a consistent orientation
    int non_orientable_components = 0;
};

// Breadth-first 2-colouring of the faces across interior edges: a face is flipped relative to
// its neighbour when they traverse the shared edge the same way. A contradiction marks the
// component non-orientable (its faces are left as they are). The first face of each component keeps its orientation.
Orientation orient_faces(const Eigen::MatrixX3i& F, const EdgeTable& edges) {
    const int num_faces = static_cast<int>(F.rows());
    Orientation result;
    result.flip.assign(num_faces, 0);
    std::vector<int> component(num_faces, -1);
    std::vector<int> members;
    for (int seed = 0; seed < num_faces; ++seed) {
        if (component[seed] >= 0 || has_repeated_index(F, seed)) continue;
        bool orientable = true;
        members.clear();
        std::queue<int> queue;
        queue.push(seed);
        component[seed] = seed;
        while (!queue.empty()) {
            const int f = queue.front();
            queue.pop();
            members.push_back(f);
            for (int k = 0; k < 3; ++k) {
                const int e = edges.face_edge(f, k);
                if (edges.face_count[e] != 2) continue;
                const int h0 = edges.edge_halfedges(e, 0), h1 = edges.edge_halfedges(e, 1);
                const int g = (h0 / 3 == f) ? h1 / 3 : h0 / 3;
                const char wanted = result.flip[f] ^ static_cast<char>(same_direction(F, h0, h1));
                if (component[g] < 0) {
                    component[g] = seed;
                    result.flip[g] = wanted;
                    queue.push(g);
                } else if (result.flip[g] != wanted) {
                    orientable = false;
                }
            }
        }
        if (!orientable) {
            ++result.non_orientable_components;
            for (int f : members) result.flip[f] = 0;
        }
    }
    return result;
}

// The edge u-v of the table, -1 if there is none (the rows are sorted; a plain bisection, since
// clang 14, which builds the fuzzers, cannot compile libstdc++ 12's ranges).
int find_edge(const EdgeTable& table, int u, int v) {
    const Eigen::Vector2i key(std::min(u, v), std::max(u, v));
    int lo = 0, hi = table.num_edges();
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        const Eigen::Vector2i row = table.E.row(mid).transpose();
        if (row[0] < key[0] || (row[0] == key[0] && row[1] < key[1])) lo = mid + 1;
        else hi = mid;
    }
    return lo < table.num_edges() && table.E(lo, 0) == key[0] && table.E(lo, 1) == key[1] ? lo : -1;
}

// Removes the rows of F marked in `drop`, keeping the order of the others.
void drop_faces(Eigen::MatrixX3i& F, const std::vector<char>& drop) {
    if (std::find(drop.begin(), drop.end(), 1) == drop.end()) return;
    Eigen::MatrixX3i kept(F.rows() - std::count(drop.begin(), drop.end(), 1), 3);
    for (int f = 0, row = 0; f < F.rows(); ++f)
        if (!drop[f]) kept.row(row++) = F.row(f);
    F = std::move(kept);
}

// A cap is a zero-area face whose third vertex c lies inside its longest side a-b, away from both
// ends (it is not a needle: its shorter sides are at least kNeedleSide of a-b, far longer than its
// height). With the face a-b-d across that side, the cap and that face become c-a-d and b-c-d,
// which tile a-b-d: the surface moves by no more than the cap's height (1e-12 of a-b at most). A
// cap whose side a-b is on the boundary is dropped: a-c and c-b take a-b's place on the boundary,
// along the same line. When c is a boundary vertex inside the cap's fan, that tears c's fan in two
// (`may_tear`: the caller gives each part its own copy of c). Consistently oriented faces expected.
struct MendedCaps {
    int flipped = 0;
    int dropped = 0;
    int torn = 0;  ///< of the dropped, those that tore their c's fan
    int left = 0;  ///< zero-area faces left
};

// The faces on each edge while caps are mended: the edge table of the faces before, with the
// edges that mending changed kept aside (few: about three per cap).
class CapEdges {
public:
    struct Faces {
        int count = 0;                ///< 1 = boundary, 2 = interior, more = non-manifold
        std::array<int, 2> face{-1, -1};  ///< the first two
    };

    CapEdges(const Eigen::MatrixX3i& F, int num_vertices)
        : table_(build_edge_table(F, num_vertices, NonmanifoldVertices::skip)),
          on_boundary_(static_cast<size_t>(num_vertices), 0) {
        for (int e = 0; e < table_.num_edges(); ++e)
            if (table_.face_count[e] == 1) on_boundary_[table_.E(e, 0)] = on_boundary_[table_.E(e, 1)] = 1;
    }

    [[nodiscard]] Faces at(int u, int v) const {
        if (const auto it = changed_.find(key(u, v)); it != changed_.end()) return it->second;
        const int e = find_edge(table_, u, v);
        if (e < 0) return {};
        return {table_.face_count[e], {table_.edge_halfedges(e, 0) / 3, table_.edge_halfedges(e, 1) / 3}};
    }
    void set(int u, int v, const Faces& faces) {
        changed_[key(u, v)] = faces;
        if (faces.count == 1) on_boundary_[u] = on_boundary_[v] = 1;
    }
    /// Edge u-v, which has faces `from` and another, has `to` instead of `from`.
    void replace(int u, int v, int from, int to) {
        Faces faces = at(u, v);
        faces.face[faces.face[0] == from ? 0 : 1] = to;
        set(u, v, faces);
    }
    /// Edge u-v loses face f (one of its two).
    void remove(int u, int v, int f) {
        Faces faces = at(u, v);
        if (faces.face[0] == f) std::swap(faces.face[0], faces.face[1]);
        faces.face[1] = -1;
        --faces.count;
        set(u, v, faces);
    }
    [[nodiscard]] bool on_boundary(int v) const { return on_boundary_[v] != 0; }

private:
    static std::uint64_t key(int u, int v) {
        return static_cast<std::uint64_t>(std::min(u, v)) << 32 | static_cast<std::uint32_t>(std::max(u, v));
    }
    EdgeTable table_;
    std::unordered_map<std::uint64_t, Faces> changed_;
    std::vector<char> on_boundary_;
};

// Mends caps from a work list: a flip can leave a new cap (if d lies on a-b too), and a chain of
// caps sharing their long sides (a fan of collinear vertices) mends one cap after the other. A cap
// that cannot be mended yet is tried again after each round that changed something; the flips
// are bounded, since on collinear vertices they need not end.
MendedCaps mend_caps(const Eigen::MatrixX3d& V, Eigen::MatrixX3i& F, bool may_tear) {
    std::vector<int> caps;
    for (int f = 0; f < F.rows(); ++f) {
        double sides[3];
        if (!has_repeated_index(F, f) && has_zero_area(V, F, f, sides)) caps.push_back(f);
    }
    MendedCaps mended;
    if (caps.empty()) return mended;
    CapEdges edges(F, static_cast<int>(V.rows()));
    std::vector<char> dropped(static_cast<size_t>(F.rows()), 0);
    const long long max_changes = 8 * static_cast<long long>(caps.size()) + 64;
    long long changes = 0;
    // Mends face f if it is a cap that can be mended now, adding the faces that changed around
    // it to `changed`; false for a cap that cannot be mended yet.
    auto mend = [&](int f, std::vector<int>& changed) {
        double sides[3];
        if (dropped[f] || !has_zero_area(V, F, f, sides)) return true;
        const int corner = static_cast<int>(std::max_element(sides, sides + 3) - sides);
        if (is_needle(sides)) return true;
        const int c = F(f, corner), a = F(f, (corner + 1) % 3), b = F(f, (corner + 2) % 3);
        const CapEdges::Faces long_side = edges.at(a, b), ca = edges.at(c, a), cb = edges.at(c, b);
        if (long_side.count == 1) {
            const bool tears = ca.count == 2 && cb.count == 2 && edges.on_boundary(c);
            if ((tears && !may_tear) || ca.count > 2 || cb.count > 2) return false;
            mended.torn += tears;
            dropped[f] = 1;
            edges.remove(a, b, f);
            for (const auto& [u, side] : {std::pair{a, ca}, std::pair{b, cb}}) {
                edges.remove(c, u, f);
                if (side.count == 2) changed.push_back(side.face[0] == f ? side.face[1] : side.face[0]);
            }
            ++mended.dropped;
            return true;
        }
        if (long_side.count != 2) return true;
        const int g = long_side.face[0] == f ? long_side.face[1] : long_side.face[0];
        const int k = F(g, 0) != a && F(g, 0) != b ? 0 : F(g, 1) != a && F(g, 1) != b ? 1 : 2;
        const int d = F(g, k);
        if (g == f || d == c || edges.at(c, d).count > 0 || edges.at(a, d).count > 2 || cb.count > 2) return false;
        F.row(f) << c, a, d;
        F.row(g) << b, c, d;
        edges.set(a, b, {});
        edges.set(c, d, {2, {f, g}});
        edges.replace(a, d, g, f);
        edges.replace(c, b, f, g);
        changed.push_back(f);
        changed.push_back(g);
        ++mended.flipped;
        return true;
    };
    std::vector<int> waiting;  // caps that could not be mended yet
    while (!caps.empty() && changes < max_changes) {
        const int before = mended.flipped + mended.dropped;
        std::vector<int> next;
        for (size_t i = 0; i < caps.size() && changes < max_changes; ++i) {
            const int f = caps[i];
            if (!mend(f, next)) waiting.push_back(f);
            changes = mended.flipped + mended.dropped;
        }
        if (changes == before) break;  // nothing left that can be mended
        next.insert(next.end(), waiting.begin(), waiting.end());
        waiting.clear();
        std::sort(next.begin(), next.end());
        next.erase(std::unique(next.begin(), next.end()), next.end());
        caps = std::move(next);
    }
    drop_faces(F, dropped);
    for (int f = 0; f < F.rows(); ++f) {
        double sides[3];
        mended.left += !has_repeated_index(F, f) && has_zero_area(V, F, f, sides);
    }
    return mended;
}

// Gives each fan of faces around a non-manifold vertex its own copy of the vertex (at the same
// position), the fan with the smallest corner keeping the original: faces of a fan are joined
// through edges with exactly two faces, so the sheets that meet at an edge with more faces come
// apart along it, each with a boundary there. Faces with a repeated index are left out. With
// `unmerged` (F before this pass merged coincident vertices, row for row), a fan whose corners
// all had one vertex at exactly this position gets that vertex back instead of a copy: merging
// vertices that the split parts again changes nothing, so a repaired mesh repairs to itself.
struct SplitVertices {
    int copies = 0;
    int restored = 0;  ///< merged vertices given back to their fans
};

SplitVertices split_nonmanifold_vertices(TriangleMesh& mesh, const Eigen::MatrixX3i* unmerged = nullptr) {
    const EdgeTable table = build_edge_table(mesh.F, mesh.num_vertices());
    if (table.nonmanifold_vertices.empty()) return {};
    Eigen::MatrixX3i& F = mesh.F;
    const int corners = static_cast<int>(3 * F.rows());
    UnionFind fans(corners);  // corner 3f + k: vertex F(f, k) in face f
    auto corner_of = [&F](int f, int v) {
        const int k = F(f, 0) == v ? 0 : F(f, 1) == v ? 1 : 2;
        return 3 * f + k;
    };
    for (int e = 0; e < table.num_edges(); ++e) {
        if (table.face_count[e] != 2) continue;
        const int f0 = table.edge_halfedges(e, 0) / 3, f1 = table.edge_halfedges(e, 1) / 3;
        for (int end = 0; end < 2; ++end) fans.unite(corner_of(f0, table.E(e, end)), corner_of(f1, table.E(e, end)));
    }
    std::vector<char> nonmanifold(static_cast<size_t>(mesh.num_vertices()), 0);
    for (const int v : table.nonmanifold_vertices) nonmanifold[v] = 1;
    auto in_a_fan = [&](int c) { return nonmanifold[F(c / 3, c % 3)] && !has_repeated_index(F, c / 3); };
    // By fan root: the vertex all its corners had before the merge, -2 if they had several.
    std::vector<int> fan_origin;
    if (unmerged) {
        fan_origin.assign(static_cast<size_t>(corners), -1);
        for (int c = 0; c < corners; ++c) {
            if (!in_a_fan(c)) continue;
            int& origin = fan_origin[fans.find(c)];
            const int before = (*unmerged)(c / 3, c % 3);
            origin = origin == -1 || origin == before ? before : -2;
        }
    }
    // By fan root: the vertex that fan's corners get, once its first corner has been seen.
    std::vector<int> fan_vertex(static_cast<size_t>(corners), -1);
    std::vector<char> taken(static_cast<size_t>(mesh.num_vertices()), 0);  // by a fan
    std::vector<int> copied_from;
    SplitVertices split;
    for (int c = 0; c < corners; ++c) {
        if (!in_a_fan(c)) continue;
        const int f = c / 3, v = F(f, c % 3), root = fans.find(c);
        int& vertex = fan_vertex[root];
        if (vertex < 0) {
            const int origin = unmerged ? fan_origin[root] : -1;
            const int wanted = origin >= 0 && mesh.V.row(origin) == mesh.V.row(v) ? origin : v;
            if (!taken[wanted]) {
                vertex = wanted, taken[wanted] = 1;
                split.restored += wanted != v;
            } else {
                vertex = mesh.num_vertices() + static_cast<int>(copied_from.size());
                copied_from.push_back(v);
            }
        }
        F(f, c % 3) = vertex;
    }
    const int old_count = mesh.num_vertices();
    mesh.V.conservativeResize(old_count + static_cast<Eigen::Index>(copied_from.size()), 3);
    for (size_t i = 0; i < copied_from.size(); ++i) mesh.V.row(old_count + static_cast<int>(i)) = mesh.V.row(copied_from[i]);
    split.copies = static_cast<int>(copied_from.size());
    return split;
}

}  // namespace

MeshInfo validate(const TriangleMesh& mesh) {
    require_indices_in_range(mesh);
    return validate(mesh, build_edge_table(mesh.F, mesh.num_vertices()));
}

MeshInfo validate(const TriangleMesh& mesh, const EdgeTable& edges, ValidateScope scope) {
    require_indices_in_range(mesh);
    const auto& V = mesh.V;
    const auto& F = mesh.F;
    const int num_vertices = mesh.num_vertices();
    MeshInfo info;
    info.faces = mesh.num_faces();
    info.edges = edges.num_edges();

    const std::vector<char> referenced = referenced_vertices(mesh);
    for (int v = 0; v < num_vertices; ++v) {
        info.vertices += referenced[v];
        if (!V.row(v).allFinite()) {
            ++info.non_finite_vertices;
            if (info.first_non_finite_vertex < 0) info.first_non_finite_vertex = v;
        }
    }
    info.unreferenced_vertices = num_vertices - info.vertices;
    const bool everything = scope == ValidateScope::everything;
    if (everything) {
        const std::vector<int> representative = coincident_representatives(V, referenced);
        for (int v = 0; v < num_vertices; ++v) info.duplicate_vertex_positions += representative[v] != v;
    }

    // Faces are independent: counted in parallel, the first of each kind by the smallest index.
    // Their corners' coordinates lie anywhere (a column each): those of a later face are
    // requested ahead.
    int repeated = 0, zero_area = 0, first_repeated = info.faces, first_zero_area = info.faces;
#pragma omp parallel for schedule(static) reduction(+ : repeated, zero_area) reduction(min : first_repeated, first_zero_area)
    for (int f = 0; f < info.faces; ++f) {
        if (const int ahead = f + detail::kPrefetchDistance; ahead < info.faces)
            for (int k = 0; k < 3; ++k)
                for (int i = 0; i < 3; ++i) __builtin_prefetch(&V(F(ahead, k), i));
        if (has_repeated_index(F, f)) {
            ++repeated;
            first_repeated = std::min(first_repeated, f);
            continue;
        }
        double sides[3];
        if (has_zero_area(V, F, f, sides)) {
            ++zero_area;
            first_zero_area = std::min(first_zero_area, f);
        }
    }
    info.repeated_index_faces = repeated;
    info.zero_area_faces = zero_area;
    if (repeated > 0) info.first_repeated_index_face = first_repeated;
    if (zero_area > 0) info.first_zero_area_face = first_zero_area;
    info.degenerate_faces = info.repeated_index_faces + info.zero_area_faces;
    if (everything) {
        const std::vector<char> duplicate = duplicate_faces(F, num_vertices);
        info.duplicate_faces = static_cast<int>(std::count(duplicate.begin(), duplicate.end(), 1));
    }

    int boundary = 0, interior = 0, conflicts = 0, nonmanifold = 0, first_nonmanifold = info.edges;
#pragma omp parallel for schedule(static) reduction(+ : boundary, interior, conflicts, nonmanifold) reduction(min : first_nonmanifold)
    for (int e = 0; e < info.edges; ++e) {
        const int count = edges.face_count[e];
        if (count == 1) {
            ++boundary;
        } else if (count == 2) {
            ++interior;
            conflicts += same_direction(F, edges.edge_halfedges(e, 0), edges.edge_halfedges(e, 1));
        } else {
            ++nonmanifold;
            first_nonmanifold = std::min(first_nonmanifold, e);
        }
    }
    info.boundary_edges = boundary, info.interior_edges = interior;
    info.orientation_conflicts = conflicts, info.nonmanifold_edges = nonmanifold;
    if (nonmanifold > 0) info.first_nonmanifold_edge = edges.E.row(first_nonmanifold).transpose();
    info.nonmanifold_vertices = static_cast<int>(edges.nonmanifold_vertices.size());
    if (info.nonmanifold_vertices > 0) info.first_nonmanifold_vertex = edges.nonmanifold_vertices.front();

    if (everything) {
        UnionFind boundary_graph(num_vertices);
        std::vector<char> on_boundary(num_vertices, 0);
        if (boundary > 0)
            for (int e = 0; e < info.edges; ++e)
                if (edges.face_count[e] == 1) {
                    boundary_graph.unite(edges.E(e, 0), edges.E(e, 1));
                    on_boundary[edges.E(e, 0)] = on_boundary[edges.E(e, 1)] = 1;
                }
        UnionFind connectivity(num_vertices);
        for (int f = 0; f < info.faces; ++f) {
            connectivity.unite(F(f, 0), F(f, 1));
            connectivity.unite(F(f, 0), F(f, 2));
        }
        for (int v = 0; v < num_vertices; ++v) {
            if (referenced[v] && connectivity.find(v) == v) ++info.components;
            if (on_boundary[v] && boundary_graph.find(v) == v) ++info.boundary_loops;
        }
    }

    // Without conflicts the faces are oriented consistently already.
    info.orientable = info.orientation_conflicts == 0 || orient_faces(F, edges).non_orientable_components == 0;
    info.euler_characteristic = info.vertices - info.edges + info.faces;
    if (everything && info.manifold() && info.orientable)
        info.genus = (2 * info.components - info.boundary_loops - info.euler_characteristic) / 2;
    return info;
}

std::string first_defect(const MeshInfo& info) {
    using std::to_string;
    if (info.non_finite_vertices > 0)
        return "vertex " + to_string(info.first_non_finite_vertex) + " has a coordinate that is not finite";
    if (info.repeated_index_faces > 0)
        return "face " + to_string(info.first_repeated_index_face) + " has a repeated vertex index";
    if (info.nonmanifold_edges > 0)
        return "edge (" + to_string(info.first_nonmanifold_edge[0]) + ", " +
               to_string(info.first_nonmanifold_edge[1]) + ") has more than two faces (" +
               to_string(info.nonmanifold_edges) + " such edges)";
    if (info.nonmanifold_vertices > 0)
        return "vertex " + to_string(info.first_nonmanifold_vertex) + " is non-manifold (" +
               to_string(info.nonmanifold_vertices) + " such vertices)";
    return {};
}

void require_manifold(const MeshInfo& info, const std::string& what) {
    if (const std::string defect = first_defect(info); !defect.empty())
        throw InvalidMeshError(what + ": " + defect);
}

void require_oriented_manifold(const MeshInfo& info, const std::string& what) {
    require_manifold(info, what);
    if (!info.orientable)
        throw InvalidMeshError(what + ": the surface is not orientable (a Möbius band or the like), which " + what +
                               " needs");
    if (info.orientation_conflicts > 0)
        throw InvalidMeshError(what + ": the faces are not consistently oriented (" +
                               std::to_string(info.orientation_conflicts) + " edges); run sdmesh repair");
    if (info.zero_area_faces > 0)
        throw InvalidMeshError(what + ": face " + std::to_string(info.first_zero_area_face) + " has zero area (" +
                               std::to_string(info.zero_area_faces) + " such faces)");
}

TriangleMesh repair(const TriangleMesh& mesh, const RepairOptions& options, RepairReport* report) {
    require_indices_in_range(mesh);
    RepairReport counts;
    TriangleMesh out = mesh;

    // Mending caps changes what the steps before it find: a flip can make a needle (its apex and
    // the vertex across its long side may be copies of one split vertex, or nearly one point) or
    // a face that duplicates one on a sheet the split parted, and a dropped cap can leave two such
    // sheets on an edge with two faces, to be joined again. So the steps run again after a pass
    // that mended caps and left none, or that left fewer zero-area faces than the pass before
    // (mending stops at a budget of flips).
    constexpr int kMaxPasses = 8;
    for (int pass = 0, zero_area_before = INT_MAX; pass < kMaxPasses; ++pass) {
        const bool coincident = options.merge_coincident_vertices;
        Eigen::MatrixX3i unmerged;  // F before this pass's merges, for the split to undo
        if (coincident || options.collapse_needles) {
            const Merges merges = merge_representatives(out, referenced_vertices(out), coincident, options.collapse_needles);
            const std::vector<int>& representative = merges.representative;
            for (int v = 0; v < out.num_vertices(); ++v) counts.merged_vertices += representative[v] != v;
            counts.collapsed_needles += merges.needle_sides;
            counts.merged_vertices -= merges.needle_sides;
            if (coincident) unmerged = out.F;
            for (int f = 0; f < out.num_faces(); ++f)
                for (int k = 0; k < 3; ++k) out.F(f, k) = representative[out.F(f, k)];
        }
        auto drop = [&](const std::vector<char>& faces) {
            drop_faces(out.F, faces);
            if (unmerged.rows() > 0) drop_faces(unmerged, faces);
        };

        if (options.drop_repeated_index_faces) {
            std::vector<char> faces(out.num_faces());
            for (int f = 0; f < out.num_faces(); ++f) faces[f] = has_repeated_index(out.F, f);
            counts.dropped_repeated_index_faces += static_cast<int>(std::count(faces.begin(), faces.end(), 1));
            drop(faces);
        }
        if (options.drop_duplicate_faces) {
            const std::vector<char> faces = duplicate_faces(out.F, out.num_vertices());
            counts.dropped_duplicate_faces += static_cast<int>(std::count(faces.begin(), faces.end(), 1));
            drop(faces);
        }
        if (options.split_nonmanifold_vertices) {
            const SplitVertices split = split_nonmanifold_vertices(out, unmerged.rows() > 0 ? &unmerged : nullptr);
            counts.split_vertices += split.copies;
            counts.merged_vertices -= split.restored;
        }
        if (options.orient) {
            const Orientation orientation = orient_faces(out.F, build_edge_table(out.F, out.num_vertices()));
            counts.non_orientable_components = orientation.non_orientable_components;
            for (int f = 0; f < out.num_faces(); ++f)
                if (orientation.flip[f]) {
                    std::swap(out.F(f, 1), out.F(f, 2));
                    ++counts.flipped_faces;
                }
        }
        if (!options.flip_caps || !options.orient || counts.non_orientable_components > 0) break;
        const MendedCaps mended = mend_caps(out.V, out.F, options.split_nonmanifold_vertices);
        counts.flipped_caps += mended.flipped;
        counts.dropped_caps += mended.dropped;
        if (mended.torn > 0) counts.split_vertices += split_nonmanifold_vertices(out).copies;
        const bool changed = mended.flipped + mended.dropped > 0;
        if (mended.left > 0 ? mended.left >= zero_area_before : !changed) break;
        zero_area_before = mended.left;
    }
    if (options.drop_unreferenced_vertices) {
        const std::vector<char> referenced = referenced_vertices(out);
        std::vector<int> new_index(out.num_vertices(), -1);
        int kept = 0;
        for (int v = 0; v < out.num_vertices(); ++v)
            if (referenced[v]) new_index[v] = kept++;
        counts.dropped_vertices = out.num_vertices() - kept;
        Eigen::MatrixX3d V(kept, 3);
        for (int v = 0; v < out.num_vertices(); ++v)
            if (referenced[v]) V.row(new_index[v]) = out.V.row(v);
        for (int f = 0; f < out.num_faces(); ++f)
            for (int k = 0; k < 3; ++k) out.F(f, k) = new_index[out.F(f, k)];
        out.V = std::move(V);
    }
    if (report) *report = counts;
    return out;
}

}  // namespace sdmesh
