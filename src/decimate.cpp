#include "sdmesh/decimate.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <queue>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "sdmesh/distance.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh {
namespace {

using Clock = std::chrono::steady_clock;
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

// n·x >= c.
struct HalfSpace {
    Vec3 n;
    double c;
};

// How the new vertex of a collapse may move.
enum class Placement { free, on_edge, fixed };

enum class Verdict { accepted, topology, not_delaunay, normal_flip, max_error };

// A queued collapse of [u, w]; valid while both vertices keep the version they had when queued.
struct Candidate {
    double key;
    int u, w;
    unsigned version_u, version_w;
    int checked;  // -1: key is a lower bound; else key is the cost at the placement checked_[checked]

    bool operator>(const Candidate& o) const {
        if (key != o.key) return key > o.key;
        return u != o.u ? u > o.u : w > o.w;
    }
};

// A face of the star after the collapse, (v, a, b) counter-clockwise, and the face it was.
struct StarFace {
    int face, a, b;
    int before = -1;     // the star face (v, c, a) sharing spoke v-a, -1 if that spoke is on the boundary
    int after = -1;      // the star face (v, b, d) sharing spoke v-b, -1 if that spoke is on the boundary
    int across = -1;     // the face on the other side of a-b, -1 on the boundary
    int w = -1;          // its vertex opposite a-b
    // What the checks of every placement share: the old normal, |ab| and the angle at w as
    // 4·area and cosine numerator of (a, b, w).
    Vec3 normal = Vec3::Zero();
    double ab = 0, across_area4 = 0, across_cosine = 0;
};

// Per star face and placement x: |xa|, |xb|, and the triangle (x, a, b) as 4·area and the cosine
// numerators of its angles at x, a and b — each computed once, though the spoke and link tests
// use them several times.
struct StarTriangle {
    double xa, xb, area4, cosine_x, cosine_a, cosine_b;
};

// The weight of a collapse's removed positions against its quadric, where a face plane weighs 1
// (see collapse_cost): with 1, 3 and 10, boot's Hausdorff at 20 % was 1.20x, 1.07x and 1.11x the
// reference's.
constexpr double kRemovalWeight = 3;

// A boundary edge's plane weighs as much as this many face planes, so that the outline holds
// (with 1, mushroom's Hausdorff at 20 % was 1.56x the reference, with 4 0.85x).
constexpr double kBoundaryPlaneWeight = 4;

class Decimator {
public:
    Decimator(const TriangleMesh& mesh, const EdgeTable& edges, const DecimateOptions& options)
        : options_(options) {
        const int nv = mesh.num_vertices(), nf = mesh.num_faces();
        P_.resize(static_cast<size_t>(nv));
        for (int v = 0; v < nv; ++v) P_[v] = mesh.V.row(v).transpose();
        corner_.resize(static_cast<size_t>(nf));
        face_alive_.assign(static_cast<size_t>(nf), 1);
        vertex_faces_.resize(static_cast<size_t>(nv));
        quadric_.resize(static_cast<size_t>(nv));
        for (int f = 0; f < nf; ++f) {
            for (int k = 0; k < 3; ++k) {
                corner_[f][k] = mesh.F(f, k);
                vertex_faces_[mesh.F(f, k)].push_back(f);
            }
            // Every face's plane weighs the same: weighted by area, the small faces of thin
            // features (and those the conversion adds) were cheap to collapse away (boot: Hausdorff
            // 1.69x the reference at 20 %, 1.39x unweighted).
            const Vec3 normal = face_normal(f);
            if (normal.norm() > 0)
                for (int k = 0; k < 3; ++k) quadric_[corner_[f][k]].add_plane(normal.normalized(), P_[corner_[f][0]], 1);
        }
        twin_.assign(3 * static_cast<size_t>(nf), -1);
        for (int e = 0; e < edges.num_edges(); ++e)
            if (edges.face_count[e] == 2) {
                twin_[edges.edge_halfedges(e, 0)] = edges.edge_halfedges(e, 1);
                twin_[edges.edge_halfedges(e, 1)] = edges.edge_halfedges(e, 0);
            }
        on_boundary_.assign(static_cast<size_t>(nv), 0);
        for (int e = 0; e < edges.num_edges(); ++e) {
            if (edges.face_count[e] != 1) continue;
            const int a = edges.E(e, 0), b = edges.E(e, 1);
            on_boundary_[a] = on_boundary_[b] = 1;
            // A plane through the boundary edge, perpendicular to its face, keeps the outline.
            const int f = edges.edge_halfedges(e, 0) / 3;
            const Vec3 along = P_[b] - P_[a];
            const Vec3 across = along.cross(face_normal(f)).normalized();
            if (across.allFinite())
                for (int v : {a, b}) quadric_[v].add_plane(across, P_[a], kBoundaryPlaneWeight);
        }
        alive_.assign(static_cast<size_t>(nv), 0);
        for (int v = 0; v < nv; ++v) alive_[v] = !vertex_faces_[v].empty();
        live_vertices_ = std::count(alive_.begin(), alive_.end(), 1);
        version_.assign(static_cast<size_t>(nv), 0);
        mark_.assign(static_cast<size_t>(nv), 0);
        slot_.assign(static_cast<size_t>(nv), -1);
        touched_.assign(static_cast<size_t>(nv), 0);
        refused_.resize(static_cast<size_t>(nv));
        if (options_.max_error > 0) init_error_tracking(mesh);
    }

    [[nodiscard]] long long live_vertices() const { return live_vertices_; }

    void run(long long target, const std::vector<int>& input_vertex, DecimateReport& report,
             std::vector<TriangleMesh>& levels) {
        for (int u = 0; u < static_cast<int>(P_.size()); ++u) {
            if (!alive_[u]) continue;
            neighbours(u, ring_);
            for (int w : ring_)
                if (w > u) push(u, w);
        }
        size_t next_level = 0;
        auto last_progress = Clock::now();
        long long collapses_before_round = 0;
        while (live_vertices_ > target) {
            // Collapses refused too often wait for the next round, which starts when the queue
            // runs dry; a round without a collapse means that nothing allowable is left.
            if (queue_.empty()) {
                if (collapses_ == collapses_before_round || deferred_.empty()) {
                    report.status = DecimateStatus::stalled;
                    break;
                }
                collapses_before_round = collapses_;
                for (const auto& [u, w] : deferred_)
                    if (alive_[u] && alive_[w] && adjacent(u, w)) push(u, w);
                deferred_.clear();
                continue;
            }
            const Candidate top = queue_.top();
            queue_.pop();
            std::optional<Checked> checked;
            if (top.checked >= 0) checked = checked_[top.checked], free_checked_.push_back(top.checked);
            if (!alive_[top.u] || !alive_[top.w] || version_[top.u] != top.version_u ||
                version_[top.w] != top.version_w)
                continue;
            const auto [keep, drop] = survivor(top.u, top.w);
            Vec3 x = Vec3::Zero();
            double cost = 0;
            // Without a collapse near it since the check, the checked placement still passes (its
            // check is rerun only for the state collapse() takes from it); else evaluate afresh.
            const bool unchanged = checked && topology_allows(keep, drop) && untouched_since(keep, drop, checked->collapses);
            if (unchanged) x = checked->x;
            const Verdict verdict = unchanged ? check(keep, drop, x) : evaluate(keep, drop, x, cost);
            if (verdict != Verdict::accepted) {
                count_rejection(verdict, report.rejected);
                refuse(top.u, top.w);
                continue;
            }
            // The queue key was a lower bound (or the cost of a placement checked before the
            // neighbourhood changed); let a cheaper collapse go first.
            if (!unchanged && !queue_.empty() && cost > queue_.top().key) {
                queue_.push({cost, top.u, top.w, top.version_u, top.version_w, store_checked({x, collapses_})});
                continue;
            }
            collapse(keep, drop, x);
            report.collapses = collapses_;
            while (next_level < options_.levels.size() && live_vertices_ <= options_.levels[next_level]) {
                levels.push_back(result(input_vertex));
                ++next_level;
            }
            if (options_.progress && Clock::now() - last_progress > std::chrono::seconds(1)) {
                last_progress = Clock::now();
                std::fprintf(stderr, "decimate: %lld vertices, %lld collapses, %zu queued\n", live_vertices_,
                             collapses_, queue_.size());
            }
        }
    }

    /// The current mesh; survivors keep the order of `input_vertex` (their index in the caller's mesh).
    [[nodiscard]] TriangleMesh result(const std::vector<int>& input_vertex) const {
        std::vector<int> survivors;
        for (size_t v = 0; v < P_.size(); ++v)
            if (alive_[v]) survivors.push_back(static_cast<int>(v));
        std::sort(survivors.begin(), survivors.end(), [&](int a, int b) { return input_vertex[a] < input_vertex[b]; });
        std::vector<int> index(P_.size(), -1);
        TriangleMesh out;
        out.V.resize(static_cast<Eigen::Index>(survivors.size()), 3);
        for (int i = 0; i < static_cast<int>(survivors.size()); ++i) {
            index[survivors[i]] = i;
            out.V.row(i) = P_[survivors[i]].transpose();
        }
        out.F.resize(std::count(face_alive_.begin(), face_alive_.end(), 1), 3);
        int row = 0;
        for (size_t f = 0; f < corner_.size(); ++f) {
            if (!face_alive_[f]) continue;
            for (int k = 0; k < 3; ++k) out.F(row, k) = index[corner_[f][k]];
            ++row;
        }
        return out;
    }

private:
    // ---- connectivity -------------------------------------------------------------------------

    Vec3 face_normal(int f) const {
        const auto& c = corner_[f];
        return (P_[c[1]] - P_[c[0]]).cross(P_[c[2]] - P_[c[0]]);
    }

    static bool has_corner(const std::array<int, 3>& face, int v) {
        return face[0] == v || face[1] == v || face[2] == v;
    }

    // The neighbours of u, sorted, into out.
    void neighbours(int u, std::vector<int>& out) const {
        out.clear();
        for (int f : vertex_faces_[u])
            for (int v : corner_[f])
                if (v != u) out.push_back(v);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
    }

    // Which end stays: a boundary vertex keeps its place; otherwise the lower index (determinism).
    std::pair<int, int> survivor(int u, int w) const {
        if (on_boundary_[w] && !on_boundary_[u]) return {w, u};
        return {u, w};
    }

    // ---- evaluation ---------------------------------------------------------------------------

    // Link condition and the neighbourhood rules; fills shared_ (faces on the edge) and star_.
    bool topology_allows(int p, int q) {
        shared_.clear();
        for (int f : vertex_faces_[p])
            if (has_corner(corner_[f], q)) shared_.push_back(f);
        if (shared_.empty() || shared_.size() > 2) return false;
        const bool boundary_edge = shared_.size() == 1;
        if (!boundary_edge && on_boundary_[p] && on_boundary_[q]) return false;  // would pinch
        // Link condition: the common neighbours of p and q are exactly the opposite vertices.
        const unsigned of_p = ++stamp_, common = ++stamp_;
        for (int f : vertex_faces_[p])
            for (int v : corner_[f]) mark_[v] = of_p;
        int common_count = 0;
        for (int f : vertex_faces_[q])
            for (int v : corner_[f])
                if (v != p && v != q && mark_[v] == of_p) mark_[v] = common, ++common_count;
        if (common_count != static_cast<int>(shared_.size())) return false;
        for (int f : shared_)
            for (int o : corner_[f]) {
                if (o == p || o == q) continue;
                if (mark_[o] != common) return false;
                // o loses a neighbour; it keeps three (two on the boundary).
                const int degree = static_cast<int>(vertex_faces_[o].size()) + on_boundary_[o];
                if (degree - 1 < (on_boundary_[o] ? 2 : 3)) return false;
            }
        // The new star: every face of p or q but the shared ones, turned to start at p or q.
        star_.clear();
        for (int end : {p, q})
            for (int f : vertex_faces_[end]) {
                if (std::find(shared_.begin(), shared_.end(), f) != shared_.end()) continue;
                const auto& c = corner_[f];
                const int k = c[0] == end ? 0 : c[1] == end ? 1 : 2;
                StarFace& s = star_.emplace_back(StarFace{.face = f, .a = c[(k + 1) % 3], .b = c[(k + 2) % 3]});
                // The side a-b is opposite the corner at `end`; its twin lies in the face across.
                const int twin = twin_[3 * f + k];
                if (twin >= 0) s.across = twin / 3, s.w = corner_[twin / 3][twin % 3];
            }
        // Neighbouring star faces through per-vertex slots: the face ending at a vertex, then
        // the face starting at it.
        const unsigned ends = ++stamp_;
        for (int j = 0; j < static_cast<int>(star_.size()); ++j) mark_[star_[j].b] = ends, slot_[star_[j].b] = j;
        for (StarFace& s : star_)
            if (mark_[s.a] == ends) s.before = slot_[s.a];
        const unsigned starts = ++stamp_;
        for (int j = 0; j < static_cast<int>(star_.size()); ++j) mark_[star_[j].a] = starts, slot_[star_[j].a] = j;
        for (StarFace& s : star_) {
            if (mark_[s.b] == starts) s.after = slot_[s.b];
            s.normal = face_normal(s.face);
            s.ab = distance(P_[s.a], P_[s.b]);
            if (s.across >= 0) {
                const double wa = distance(P_[s.w], P_[s.a]), wb = distance(P_[s.w], P_[s.b]);
                s.across_area4 = 4.0 * triangle_area(s.ab, wa, wb);
                s.across_cosine = cosine_numerator(s.ab, wa, wb);
            }
        }
        return !star_.empty();
    }

    Placement placement(int p, int q) const {
        if (shared_.size() == 1) return Placement::on_edge;
        if (on_boundary_[p] || on_boundary_[q]) return Placement::fixed;  // survivor() keeps it at p
        return Placement::free;
    }

    // The linearised allowable region of ALGORITHMS.md §4 for the star_ of collapsing p, q.
    void allowable_region(int p, int q, std::vector<HalfSpace>& region) const {
        region.clear();
        const Vec3 inside = 0.5 * (P_[p] + P_[q]);
        for (const StarFace& s : star_) {
            const Vec3 &a = P_[s.a], &b = P_[s.b];
            const Vec3 ab = b - a;
            // The angles at a and b of (v, a, b) stay <= π/2, so both spokes see LD angles there.
            region.push_back({ab, ab.dot(a)});
            region.push_back({-ab, -ab.dot(b)});
            // The link edge ab stays LD if v sees it at an angle <= π - γ (γ: the angle across it),
            // which holds outside the ball of radius (l/2)·max(1, tan(γ/2)) around its midpoint.
            double radius_factor = 1;
            if (s.across < 0) {
                if (options_.boundary == BoundaryPolicy::free) continue;
            } else {
                // tan(γ/2) = 4·area / ((wa + wb)² - ab²).
                const double l = ab.norm(), wa = distance(P_[s.w], a), wb = distance(P_[s.w], b);
                radius_factor = std::max(1.0, 4 * triangle_area(l, wa, wb) / ((wa + wb - l) * (wa + wb + l)));
            }
            const Vec3 mid = 0.5 * (a + b);
            const Vec3 unit_ab = ab.normalized();
            Vec3 toward = inside - mid;
            toward -= toward.dot(unit_ab) * unit_ab;
            if (!(toward.norm() > 0) || !std::isfinite(radius_factor)) {
                region.push_back({Vec3::Zero(), 1});  // empty: v cannot reach the safe side
                continue;
            }
            toward.normalize();
            region.push_back({toward, toward.dot(mid) + 0.5 * ab.norm() * radius_factor});
        }
    }

    static bool inside(const std::vector<HalfSpace>& region, const Vec3& x, double slack) {
        return std::all_of(region.begin(), region.end(), [&](const HalfSpace& h) { return h.n.dot(x) >= h.c - slack; });
    }

    // The quadric with a slight pull towards the edge's midpoint, so that flat and cylindrical
    // neighbourhoods (singular A) have a unique optimum.
    static Quadric regularised(const Quadric& q, const Vec3& mid) {
        Quadric r = q;
        const double weight = 1e-6 * std::max(q.A.trace(), std::numeric_limits<double>::min());
        r.A += weight * Eigen::Matrix3d::Identity();
        r.b -= weight * mid;
        r.c += weight * mid.squaredNorm();
        return r;
    }

    // The minimiser of q on segment p + t(d), t in [lo, hi].
    static Vec3 segment_minimum(const Quadric& q, const Vec3& p, const Vec3& d, double lo, double hi) {
        const double curvature = d.dot(q.A * d), slope = d.dot(q.A * p + q.b);
        double t = curvature > 0 ? -slope / curvature : 0.5 * (lo + hi);
        return p + std::clamp(t, lo, hi) * d;
    }

    // The quadric's minimum in the region for a free vertex: the unconstrained optimum if it is
    // inside, else the best feasible optimum on one or two planes of the constraints it violates.
    std::optional<Vec3> region_minimum(const Quadric& q, const Eigen::Matrix3d& inverse, const Vec3& optimum,
                                       const std::vector<HalfSpace>& region, double slack) {
        if (inside(region, optimum, slack)) return optimum;
        std::vector<int>& violated = violated_;
        violated.clear();
        for (int i = 0; i < static_cast<int>(region.size()); ++i)
            if (region[i].n.dot(optimum) < region[i].c - slack) violated.push_back(i);
        std::optional<Vec3> best;
        double best_cost = std::numeric_limits<double>::infinity();
        auto consider = [&](const Vec3& x) {
            if (!x.allFinite() || !inside(region, x, slack)) return;
            const double cost = q(x);
            if (cost < best_cost) best_cost = cost, best = x;
        };
        // Minimise q subject to n_iᵀx = c_i (i active): x = x* + A⁻¹Nλ, (NᵀA⁻¹N)λ = c - Nᵀx*.
        for (int i : violated) {
            const HalfSpace& h = region[i];
            const Vec3 An = inverse * h.n;
            const double s = h.n.dot(An);
            if (s > 0) consider(optimum + An * ((h.c - h.n.dot(optimum)) / s));
        }
        // Pairs only for a few violations: many mean v is far from the region anyway.
        if (best || violated.size() > 6) return best;
        for (size_t i = 0; i < violated.size(); ++i)
            for (size_t j = i + 1; j < violated.size(); ++j) {
                const HalfSpace &g = region[violated[i]], &h = region[violated[j]];
                Eigen::Matrix<double, 3, 2> N;
                N << g.n, h.n;
                const Eigen::Matrix<double, 3, 2> AN = inverse * N;
                const Eigen::Matrix2d S = N.transpose() * AN;
                const double det = S.determinant();
                if (!(det > 1e-14 * S.trace() * S.trace())) continue;
                const Eigen::Vector2d rhs(g.c - g.n.dot(optimum), h.c - h.n.dot(optimum));
                consider(optimum + AN * (S.inverse() * rhs));
            }
        return best;
    }

    // Where v may go, best first: the quadric optimum in the allowable region, then (with
    // search_candidates) the unconstrained optimum, the midpoint and the ends.
    // Into out (placements_), with extra_ and order_ as scratch.
    void placements(int p, int q, const Quadric& quadric) {
        std::vector<Vec3>& out = placements_;
        std::vector<Vec3>& extra = extra_;
        out.clear();
        extra.clear();
        const Placement mode = placement(p, q);
        if (mode == Placement::fixed) {
            out.push_back(P_[p]);
            return;
        }
        const Vec3 mid = 0.5 * (P_[p] + P_[q]);
        std::vector<HalfSpace>& region = region_;
        allowable_region(p, q, region);
        const double slack = 1e-9 * distance(P_[p], P_[q]);
        if (mode == Placement::on_edge) {
            const Vec3 d = P_[q] - P_[p];
            double lo = 0, hi = 1;
            for (const HalfSpace& h : region) {
                const double rate = h.n.dot(d), need = h.c - h.n.dot(P_[p]);
                if (rate > 0) lo = std::max(lo, need / rate);
                else if (rate < 0) hi = std::min(hi, need / rate);
                else if (need > slack) lo = 2;  // unreachable
            }
            const Quadric r = regularised(quadric, mid);
            if (lo <= hi) out.push_back(segment_minimum(r, P_[p], d, lo, hi));
            extra.push_back(segment_minimum(r, P_[p], d, 0, 1));
        } else {
            const Quadric r = regularised(quadric, mid);
            const Eigen::Matrix3d inverse = r.A.inverse();
            const Vec3 optimum = -(inverse * r.b);
            if (optimum.allFinite()) {
                if (auto x = region_minimum(r, inverse, optimum, region, slack)) out.push_back(*x);
                extra.push_back(optimum);
            }
            extra.push_back(segment_minimum(r, P_[p], P_[q] - P_[p], 0, 1));
        }
        // A nearly singular quadric can put its optimum far away, where the new faces would make a
        // spike that no local test sees: v stays within an edge length of the edge's midpoint.
        const double reach2 = (P_[q] - P_[p]).squaredNorm();
        const auto near_edge = [&](const Vec3& y) { return (y - mid).squaredNorm() <= reach2; };
        if (!options_.search_candidates) {
            std::erase_if(out, [&](const Vec3& y) { return !near_edge(y); });
            return;
        }
        // All candidates by quadric cost (the region's point first on ties): the linearised
        // region is conservative, and an end of the edge outside it may pass the exact test at a
        // lower cost — removing a split vertex exactly, for one.
        extra.insert(extra.begin(), out.begin(), out.end());
        extra.insert(extra.end(), {mid, P_[p], P_[q]});
        std::vector<std::pair<double, int>>& order = order_;
        order.clear();
        for (int i = 0; i < static_cast<int>(extra.size()); ++i) order.emplace_back(quadric(extra[i]), i);
        std::sort(order.begin(), order.end());
        out.clear();
        for (const auto& [cost, i] : order)
            if (near_edge(extra[i]) && std::find(out.begin(), out.end(), extra[i]) == out.end()) out.push_back(extra[i]);
    }

    // What a collapse of q into p at x costs: the quadric, plus kRemovalWeight times the squared
    // distance of the farther of the two old positions from the new star. The quadric alone
    // misses what the collapse of a thin fold's tip cuts away (the fold's planes nearly contain
    // the tip's path): on boot, one such tip made the Hausdorff distance at 20 % 1.93x the
    // reference's; with the term it is 1.07x, and every corpus mesh is within 1.10x at 20 % and 10 %.
    double collapse_cost(const Quadric& quadric, int p, int q, const Vec3& x) const {
        double removed2 = 0;
        for (int v : {p, q}) {
            if (P_[v] == x) continue;
            double nearest2 = std::numeric_limits<double>::infinity();
            for (const StarFace& s : star_)
                nearest2 = std::min(nearest2, (closest_point_on_triangle(P_[v], x, P_[s.a], P_[s.b]) - P_[v]).squaredNorm());
            removed2 = std::max(removed2, nearest2);
        }
        return quadric(x) + kRemovalWeight * removed2;
    }

    // The lower bound the queue is keyed on: the quadric at the unconstrained placement.
    double lower_bound(int p, int q) const {
        const Quadric quadric = quadric_[p] + quadric_[q];
        const Vec3 mid = 0.5 * (P_[p] + P_[q]);
        const Quadric r = regularised(quadric, mid);
        const bool boundary_edge = on_boundary_[p] && on_boundary_[q];
        if (on_boundary_[p] != on_boundary_[q]) return quadric(on_boundary_[p] ? P_[p] : P_[q]);
        if (boundary_edge) return quadric(segment_minimum(r, P_[p], P_[q] - P_[p], 0, 1));
        const Vec3 optimum = r.A.ldlt().solve(-r.b);
        return optimum.allFinite() ? quadric(optimum) : quadric(mid);
    }

    // The exact checks of a collapse of q into p at x: normals, then LD of every spoke and link
    // edge, then the error bound.
    Verdict check(int p, int q, const Vec3& x) {
        const int n = static_cast<int>(star_.size());
        std::vector<StarTriangle>& t = star_triangles_;
        t.resize(star_.size());
        for (int i = 0; i < n; ++i) t[i].xa = distance(x, P_[star_[i].a]);
        for (int i = 0; i < n; ++i) t[i].xb = star_[i].after >= 0 ? t[star_[i].after].xa : distance(x, P_[star_[i].b]);
        for (int i = 0; i < n; ++i) {
            const StarFace& s = star_[i];
            const Vec3 after = (P_[s.a] - x).cross(P_[s.b] - x);
            const double longest = std::max({t[i].xa, t[i].xb, s.ab});
            if (!(after.dot(s.normal) > 0) || 0.5 * after.norm() <= 1e-12 * longest * longest) return Verdict::normal_flip;
        }
        for (int i = 0; i < n; ++i) {
            StarTriangle& ti = t[i];
            const double ab = star_[i].ab;
            ti.area4 = 4.0 * triangle_area(ti.xa, ti.xb, ab);
            ti.cosine_x = cosine_numerator(ab, ti.xa, ti.xb);
            ti.cosine_a = cosine_numerator(ti.xb, ti.xa, ab);
            ti.cosine_b = cosine_numerator(ti.xa, ti.xb, ab);
        }
        const double tol = options_.tolerance;
        const bool strict = options_.boundary == BoundaryPolicy::strict;
        const auto obtuse = [&](double area4, double cosine) { return strict && boundary_margin_scaled(area4, cosine) < -tol; };
        for (int i = 0; i < n; ++i) {
            const StarFace& s = star_[i];
            const StarTriangle& ti = t[i];
            // Spoke v-a: its angles are at b in this face (v, a, b) and at c in the star face
            // (v, c, a) before it, if any.
            if (s.before >= 0) {
                const StarTriangle& tc = t[s.before];
                if (!is_locally_delaunay_scaled(ti.area4, ti.cosine_b, tc.area4, tc.cosine_a, tan_tolerance_))
                    return Verdict::not_delaunay;
            } else if (obtuse(ti.area4, ti.cosine_b)) {
                return Verdict::not_delaunay;
            }
            // Spoke v-b on the boundary (no star face after it).
            if (s.after < 0 && obtuse(ti.area4, ti.cosine_a)) return Verdict::not_delaunay;
            // Link edge a-b: the angle at v against the angle at w across it.
            if (s.across < 0) {
                if (obtuse(ti.area4, ti.cosine_x)) return Verdict::not_delaunay;
                continue;
            }
            if (!is_locally_delaunay_scaled(ti.area4, ti.cosine_x, s.across_area4, s.across_cosine, tan_tolerance_))
                return Verdict::not_delaunay;
        }
        if (options_.max_error > 0 && !within_error(p, q, x)) return Verdict::max_error;
        return Verdict::accepted;
    }

    Verdict evaluate(int p, int q, Vec3& x, double& cost) {
        if (!topology_allows(p, q)) return Verdict::topology;
        const Quadric quadric = quadric_[p] + quadric_[q];
        placements(p, q, quadric);
        const std::vector<Vec3>& options = placements_;
        if (options.empty()) return Verdict::not_delaunay;
        // The reason reported: the bound, if it alone refused some candidate (the collapse was
        // allowable otherwise), else the first candidate's.
        std::optional<Verdict> reason;
        for (const Vec3& candidate : options) {
            const Verdict v = check(p, q, candidate);
            if (v == Verdict::accepted) {
                x = candidate;
                cost = collapse_cost(quadric, p, q, candidate);
                return v;
            }
            if (!reason || v == Verdict::max_error) reason = v;
        }
        return *reason;
    }

    static void count_rejection(Verdict v, DecimateRejections& r) {
        switch (v) {
            case Verdict::topology: ++r.topology; break;
            case Verdict::not_delaunay: ++r.not_delaunay; break;
            case Verdict::normal_flip: ++r.normal_flip; break;
            case Verdict::max_error: ++r.max_error; break;
            case Verdict::accepted: break;
        }
    }

    // ---- the collapse -------------------------------------------------------------------------

    void collapse(int p, int q, const Vec3& x) {
        if (options_.max_error > 0) commit_error_tracking();
        for (int f : shared_) {
            // The sides o-q and p-o of the removed face (p, q, o) become one edge p-o: glue the
            // faces across them.
            const auto& c = corner_[f];
            const int at_p = 3 * f + (c[0] == p ? 0 : c[1] == p ? 1 : 2), at_q = 3 * f + (c[0] == q ? 0 : c[1] == q ? 1 : 2);
            const int across_p = twin_[at_p], across_q = twin_[at_q];
            if (across_p >= 0) twin_[across_p] = across_q;
            if (across_q >= 0) twin_[across_q] = across_p;
            face_alive_[f] = 0;
            for (int v : corner_[f]) std::erase(vertex_faces_[v], f);
        }
        for (int f : vertex_faces_[q]) {
            for (int& v : corner_[f])
                if (v == q) v = p;
            vertex_faces_[p].push_back(f);
        }
        std::sort(vertex_faces_[p].begin(), vertex_faces_[p].end());
        vertex_faces_[q].clear();
        alive_[q] = 0;
        --live_vertices_;
        P_[p] = x;
        quadric_[p] = quadric_[p] + quadric_[q];
        ++version_[p];
        neighbours(p, ring_);
        const std::vector<int>& ring = ring_;
        ++collapses_;
        touched_[p] = collapses_;
        for (int a : ring) touched_[a] = collapses_;
        for (int a : ring) push(std::min(p, a), std::max(p, a));
        // Collapses refused next to the changed star may be allowed now: retried at once (they
        // keep the greedy order), a few times; after that they wait for the next round.
        refused_[q].clear();
        refused_[p].clear();  // its edges are all queued afresh
        const unsigned in_ring = ++stamp_;
        for (int a : ring) mark_[a] = in_ring;
        for (int a : ring) {
            std::erase_if(refused_[a], [&](const Refusal& r) { return !alive_[r.other] || r.other == p; });
            for (const Refusal& r : refused_[a])
                if (mark_[r.other] != in_ring || a < r.other) push(std::min(a, r.other), std::max(a, r.other));
        }
    }

    struct Refusal {
        int other;  // the other end of the refused edge
        int count;  // how often it was refused
    };
    static constexpr int kImmediateRetries = 3;

    // Recorded at both ends, with the same count.
    void refuse(int u, int w) {
        auto find = [&](int at, int other) {
            auto& list = refused_[at];
            return std::find_if(list.begin(), list.end(), [&](const Refusal& r) { return r.other == other; });
        };
        const auto at_u = find(u, w);
        if (at_u == refused_[u].end()) {
            refused_[u].push_back({w, 1});
            refused_[w].push_back({u, 1});
            return;
        }
        const auto at_w = find(w, u);
        if (++at_u->count <= kImmediateRetries) {
            ++at_w->count;
            return;
        }
        refused_[u].erase(at_u);
        refused_[w].erase(at_w);
        deferred_.emplace_back(u, w);
    }

    bool adjacent(int u, int w) const {
        return std::any_of(vertex_faces_[u].begin(), vertex_faces_[u].end(),
                           [&](int f) { return has_corner(corner_[f], w); });
    }

    void push(int u, int w) {
        queue_.push({lower_bound(u, w), u, w, version_[u], version_[w], -1});
    }

    // A placement that passed the checks, and the number of collapses done then.
    struct Checked {
        Vec3 x;
        long long collapses;
    };

    // Whether the checks of collapsing q into p read only what no collapse after the first
    // `collapses` changed (star_ as topology_allows left it). A collapse into v changes the faces
    // around v, hence the stars of v and its ring, the twins across the faces it removed (whose
    // sides join v and ring vertices) and v's position; it marks v and its ring as touched.
    bool untouched_since(int p, int q, long long collapses) const {
        if (touched_[p] > collapses || touched_[q] > collapses) return false;
        return std::none_of(star_.begin(), star_.end(), [&](const StarFace& s) {
            return touched_[s.a] > collapses || touched_[s.b] > collapses || (s.w >= 0 && touched_[s.w] > collapses);
        });
    }

    int store_checked(const Checked& c) {
        if (free_checked_.empty()) {
            checked_.push_back(c);
            return static_cast<int>(checked_.size()) - 1;
        }
        const int slot = free_checked_.back();
        free_checked_.pop_back();
        checked_[slot] = c;
        return slot;
    }

    // ---- the error bound ----------------------------------------------------------------------
    // Forward: the input's vertices and face centroids, each kept with a face of the current mesh
    // it is within the bound of; a collapse re-homes the points of the old star on the new star.
    // Backward: v and the centroids of the new faces must be within the bound of the input.

    // The points of face abc that the report's hausdorff_distance samples (with samples_per_face
    // 4 or 1): edge midpoints, the centroids of its 2 × 2 subdivision, its centroid; computed as
    // it does, from the first corner, so that the bound holds for the reported value.
    static void face_samples(const Vec3& a, const Vec3& b, const Vec3& c, std::vector<Vec3>& out) {
        const Vec3 ab = b - a, ac = c - a;
        const auto at = [&](double v, double w) { out.push_back(a + v * ab + w * ac); };
        at(0.5, 0.0), at(0.0, 0.5), at(0.5, 0.5);
        at(1.0 / 3, 1.0 / 3);
        for (int i = 0; i < 2; ++i)
            for (int j = 0; i + j < 2; ++j) {
                at((i + 1.0 / 3) / 2, (j + 1.0 / 3) / 2);
                if (i + j + 1 < 2) at((i + 2.0 / 3) / 2, (j + 2.0 / 3) / 2);
            }
    }

    void init_error_tracking(const TriangleMesh& mesh) {
        tree_ = std::make_unique<TriangleTree>(mesh);
        bound_ = options_.max_error * tree_->bounds().diagonal().norm();
        face_points_.resize(corner_.size());
        for (size_t f = 0; f < corner_.size(); ++f) {
            const auto& c = corner_[f];
            const size_t first = points_.size();
            face_samples(P_[c[0]], P_[c[1]], P_[c[2]], points_);
            for (size_t i = first; i < points_.size(); ++i) face_points_[f].push_back(static_cast<int>(i));
        }
        for (size_t v = 0; v < P_.size(); ++v) {
            if (vertex_faces_[v].empty()) continue;
            points_.push_back(P_[v]);
            face_points_[vertex_faces_[v].front()].push_back(static_cast<int>(points_.size()) - 1);
        }
    }

    bool within_error(int p, int q, const Vec3& x) {
        const double bound2 = bound_ * bound_;
        if (tree_->closest_point(x).squared_distance > bound2) return false;
        for (const StarFace& s : star_) {
            samples_.clear();
            const auto& c = corner_[s.face];
            const auto corner = [&](int k) -> const Vec3& { return c[k] == p || c[k] == q ? x : P_[c[k]]; };
            face_samples(corner(0), corner(1), corner(2), samples_);
            for (const Vec3& y : samples_)
                if (tree_->closest_point(y).squared_distance > bound2) return false;
        }
        rehomed_.clear();
        auto rehome = [&](int f) {
            for (int point : face_points_[f]) {
                int best = -1;
                double best2 = bound2;
                for (const StarFace& s : star_) {
                    const double d2 = (closest_point_on_triangle(points_[point], x, P_[s.a], P_[s.b]) - points_[point]).squaredNorm();
                    if (d2 <= best2) best2 = d2, best = s.face;
                }
                if (best < 0) return false;
                rehomed_.emplace_back(point, best);
            }
            return true;
        };
        for (int f : shared_)
            if (!rehome(f)) return false;
        for (const StarFace& s : star_)
            if (!rehome(s.face)) return false;
        return true;
    }

    void commit_error_tracking() {
        for (int f : shared_) face_points_[f].clear();
        for (const StarFace& s : star_) face_points_[s.face].clear();
        for (const auto& [point, face] : rehomed_) face_points_[face].push_back(point);
    }

    const DecimateOptions& options_;
    const double tan_tolerance_ = std::tan(options_.tolerance);
    std::vector<Vec3> P_;
    std::vector<std::array<int, 3>> corner_;
    std::vector<int> twin_;  // per side 3f + k (opposite corner k): the same edge's side in the face across, -1 on the boundary
    std::vector<char> face_alive_;
    std::vector<std::vector<int>> vertex_faces_;  // sorted face ids around each vertex
    std::vector<Quadric> quadric_;
    std::vector<char> on_boundary_;
    std::vector<char> alive_;
    std::vector<unsigned> version_;
    std::vector<std::vector<Refusal>> refused_;  // per vertex: refused collapses of its edges, still retried
    std::vector<std::pair<int, int>> deferred_;  // refused too often: retried in the next round
    long long live_vertices_ = 0;
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<>> queue_;
    std::vector<Checked> checked_;   // of the queued candidates with checked >= 0
    long long collapses_ = 0;  // done so far; numbers the collapses for touched_
    std::vector<long long> touched_;  // per vertex: the last collapse that changed its star (see untouched_since)
    std::vector<int> free_checked_;  // unused entries of checked_
    // Scratch of the collapse being evaluated.
    std::vector<int> shared_;
    std::vector<StarFace> star_;
    std::vector<StarTriangle> star_triangles_;  // of check
    std::vector<HalfSpace> region_;
    std::vector<int> violated_;  // of region_minimum
    std::vector<Vec3> placements_, extra_;
    std::vector<std::pair<double, int>> order_;  // of placements
    std::vector<int> ring_;  // neighbours of a vertex
    std::vector<unsigned> mark_;  // vertex marks of the link condition, compared with stamp_
    std::vector<int> slot_;       // per vertex marked in mark_: a star face index
    unsigned stamp_ = 0;
    // Error bound.
    std::unique_ptr<TriangleTree> tree_;
    double bound_ = 0;
    std::vector<Vec3> points_;
    std::vector<std::vector<int>> face_points_;
    std::vector<std::pair<int, int>> rehomed_;
    std::vector<Vec3> samples_;
};

// The mesh with its vertices renumbered along a Morton curve of their positions and its faces
// sorted by their lowest new vertex, so that neighbourhoods are close in memory during the
// collapses; input_vertex maps the new vertex indices back.
struct SpatialOrder {
    TriangleMesh mesh;
    std::vector<int> input_vertex;
};

SpatialOrder spatial_order(const TriangleMesh& mesh) {
    const int nv = mesh.num_vertices(), nf = mesh.num_faces();
    if (nv == 0) return {mesh, {}};  // no bounding box
    const Eigen::RowVector3d low = mesh.V.colwise().minCoeff();
    const double extent = std::max((mesh.V.colwise().maxCoeff() - low).maxCoeff(), std::numeric_limits<double>::min());
    std::vector<std::pair<unsigned long long, int>> code(static_cast<size_t>(nv));
    for (int v = 0; v < nv; ++v) {
        unsigned long long key = 0;
        for (int axis = 0; axis < 3; ++axis) {
            const auto cell = static_cast<unsigned long long>((mesh.V(v, axis) - low[axis]) / extent * 2097151.0);
            for (int bit = 0; bit < 21; ++bit) key |= ((cell >> bit) & 1ULL) << (3 * bit + axis);
        }
        code[v] = {key, v};
    }
    std::sort(code.begin(), code.end());
    SpatialOrder out;
    out.input_vertex.resize(static_cast<size_t>(nv));
    std::vector<int> new_index(static_cast<size_t>(nv));
    out.mesh.V.resize(nv, 3);
    for (int i = 0; i < nv; ++i) {
        out.input_vertex[i] = code[i].second;
        new_index[code[i].second] = i;
        out.mesh.V.row(i) = mesh.V.row(code[i].second);
    }
    std::vector<std::pair<int, int>> face_order(static_cast<size_t>(nf));
    for (int f = 0; f < nf; ++f)
        face_order[f] = {std::min({new_index[mesh.F(f, 0)], new_index[mesh.F(f, 1)], new_index[mesh.F(f, 2)]}), f};
    std::sort(face_order.begin(), face_order.end());
    out.mesh.F.resize(nf, 3);
    for (int i = 0; i < nf; ++i)
        for (int k = 0; k < 3; ++k) out.mesh.F(i, k) = new_index[mesh.F(face_order[i].second, k)];
    return out;
}

void check_options(const DecimateOptions& o, long long input_vertices, long long target) {
    if (o.target_vertices < 0) throw InvalidArgumentError("decimate: target_vertices must be >= 0");
    if (o.target_vertices == 0 && !(o.target_ratio > 0 && o.target_ratio <= 1))
        throw InvalidArgumentError("decimate: target_ratio must be in (0, 1]");
    if (!(o.max_error >= 0)) throw InvalidArgumentError("decimate: max_error must be >= 0");
    if (!(o.tolerance >= 0 && o.tolerance < std::numbers::pi / 2))
        throw InvalidArgumentError("decimate: tolerance must be in [0, π/2)");
    for (size_t i = 0; i < o.levels.size(); ++i)
        if (o.levels[i] <= target || o.levels[i] >= input_vertices || (i > 0 && o.levels[i] >= o.levels[i - 1]))
            throw InvalidArgumentError("decimate: level " + std::to_string(i) + " (" + std::to_string(o.levels[i]) +
                                       " vertices) must lie between the target (" + std::to_string(target) +
                                       ") and the input's " + std::to_string(input_vertices) +
                                       " vertices, in decreasing order");
}

}  // namespace

DecimateResult decimate(const TriangleMesh& mesh, const DecimateOptions& options) {
    const auto start = Clock::now();
    require_indices_in_range(mesh);
    const EdgeTable edges = build_edge_table(mesh.F, mesh.num_vertices());
    const MeshInfo info = validate(mesh, edges);
    require_manifold(info, "decimate");
    if (info.orientation_conflicts > 0)
        throw InvalidMeshError("decimate: the faces are not consistently oriented (" +
                               std::to_string(info.orientation_conflicts) + " edges); run sdmesh repair");
    if (info.zero_area_faces > 0)
        throw InvalidMeshError("decimate: face " + std::to_string(info.first_zero_area_face) + " has zero area (" +
                               std::to_string(info.zero_area_faces) + " such faces)");
    const CertifyOptions certify_options{.boundary = options.boundary, .tolerance = options.tolerance};
    const long long input_vertices = info.vertices;
    const long long target = options.target_vertices > 0
                                 ? options.target_vertices
                                 : std::llround(options.target_ratio * static_cast<double>(input_vertices));
    check_options(options, input_vertices, target);
    const DelaunayCertificate input_certificate = certify(mesh, edges, certify_options);
    if (!input_certificate.self_delaunay)
        throw InvalidArgumentError(
            "decimate: the input is not self-Delaunay (" + std::to_string(input_certificate.non_delaunay_edges) +
            " non-Delaunay interior edges, " + std::to_string(input_certificate.boundary_obtuse_edges) +
            " obtuse boundary edges); convert it first (sdmesh convert, or sdmesh decimate --convert-first)");

    DecimateResult result;
    DecimateReport& report = result.report;
    report.input_vertices = input_vertices;
    report.input_faces = mesh.num_faces();
    report.target_vertices = target;
    const SpatialOrder ordered = spatial_order(mesh);
    Decimator decimator(ordered.mesh, build_edge_table(ordered.mesh.F, ordered.mesh.num_vertices()), options);
    decimator.run(target, ordered.input_vertex, report, result.levels);
    result.mesh = decimator.result(ordered.input_vertex);
    report.output_vertices = result.mesh.num_vertices();
    report.output_faces = result.mesh.num_faces();
    report.certificate = certify(result.mesh, certify_options);
    if (options.measure_hausdorff && report.collapses > 0)
        // A few samples per face of the input: the output's faces are larger, and sampled densely.
        report.hausdorff_rel =
            hausdorff_distance(mesh, result.mesh, {.samples_per_face = 4, .max_samples = 4'000'000}).hausdorff_rel;
    report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
}

std::string_view to_string(DecimateStatus status) {
    return status == DecimateStatus::stalled ? "stalled" : "reached_target";
}

}  // namespace sdmesh
