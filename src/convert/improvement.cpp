// After the loop: split points removed again, the fewest points per input edge, local search.
#include "convert/converter.hpp"

#include <cstdint>
#include <unordered_map>

namespace sdmesh::conversion {
namespace {

// SplitMix64: the same numbers on every platform (the standard library's distributions are
// free to differ), so that relocate_points is deterministic.
class Random {
public:
    explicit Random(std::uint64_t seed) : state_(seed) {}
    std::uint64_t next() {
        std::uint64_t z = state_ += 0x9e3779b97f4a7c15ull;
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
        return z ^ (z >> 31);
    }
    double uniform() { return static_cast<double>(next() >> 11) * 0x1p-53; }  // in [0, 1)
    size_t below(size_t n) { return static_cast<size_t>(next() % n); }

private:
    std::uint64_t state_;
};

// Cotangent of the widest angle under which a point of `face` sees u-v (+inf for none).
double apex_cotangent(const std::vector<Eigen::Vector3d>& face, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& p : face) smallest = std::min(smallest, cotangent_seen_from(p, u, v));
    return smallest;
}

}  // namespace

void Converter::remove_unneeded_points(ConversionReport& report, const std::vector<char>* changed) {
    const int input_faces = static_cast<int>(input_.F.rows()), edges = input_edges_.num_edges();
    auto faces_of = [&](int e) { return std::array<int, 2>{input_face(e, 0), input_face(e, 1)}; };
    const bool any_flat = std::find(input_flat_.begin(), input_flat_.end(), 1) != input_flat_.end();
    const std::vector<int> plane_of = any_flat ? input_planes() : std::vector<int>{};
    const Buckets plane_faces(any_flat ? input_faces : 0, any_flat ? input_faces : 0,
                              [&](int f) { return plane_of[f]; });
    auto for_each_face_in_plane_of = [&](int f, auto&& visit) {
        if (!any_flat) return visit(f);
        for (const int face : plane_faces[plane_of[f]]) visit(face);
    };
    // The split points on each input edge (removed ones are skipped when read).
    const int split_points = static_cast<int>(P_.size());
    const Buckets on_edge(edges, split_points - input_vertices_, [&](int i) { return vertex_input_edge_[i]; });
    // Calls visit(y, input edge) for the points on the edges of the plane of face f.
    auto for_each_point_in_plane_of = [&](int f, auto&& visit) {
        for_each_face_in_plane_of(f, [&](int face) {
            for (int k = 0; k < 3; ++k) {
                const int edge = input_edges_.face_edge(face, k);
                visit(input_.F(face, (k + 1) % 3), edge);
                for (const int i : on_edge[edge]) visit(input_vertices_ + i, edge);
                for (int y = split_points; y < static_cast<int>(P_.size()); ++y)  // added while removing
                    if (vertex_input_edge_[y - input_vertices_] == edge) visit(y, edge);
            }
        });
    };
    // Points next to a plane of more than kMaxPlanePoints points stay: each try scans both
    // planes, and a removal retries their points (the corpus's largest plane has 1,269).
    std::vector<char> plane_too_big(any_flat ? input_faces : 0, 0);
    if (any_flat) {
        std::vector<int> points(input_faces, 0);
        for (int f = 0; f < input_faces; ++f) {
            int& n = points[plane_of[f]];
            for (int k = 0; k < 3; ++k) n += 1 + static_cast<int>(on_edge[input_edges_.face_edge(f, k)].size());
            if (n > kMaxPlanePoints) plane_too_big[plane_of[f]] = 1;
        }
    }
    auto is_too_big = [&](int f) { return f >= 0 && any_flat && plane_too_big[plane_of[f]]; };
    // cotangent_seen_from, by vertex ids.
    auto cotangent = [&](int y, int p, int q) { return cotangent_seen_from(P_[y], P_[p], P_[q]); };
    // Cotangent of the widest angle under which a point of the plane of face f, off edge e,
    // sees p-q.
    auto apex_cotangent = [&](int f, int p, int q, int e) {
        double smallest = std::numeric_limits<double>::infinity();
        for_each_point_in_plane_of(f, [&](int y, int edge) {
            if (edge == e || y == p || y == q || (y >= input_vertices_ && removed_[y - input_vertices_])) return;
            smallest = std::min(smallest, cotangent(y, p, q));
        });
        return smallest;
    };
    // Every split point is tried; a removal makes the points of its two planes worth trying
    // again, so that at the end no point can go alone.
    std::deque<int> to_try;
    std::vector<char> waiting(static_cast<size_t>(split_points - input_vertices_), 0);
    auto try_later = [&](int x, int) {
        if (x < input_vertices_ || x >= split_points || waiting[x - input_vertices_] || removed_[x - input_vertices_])
            return;
        waiting[x - input_vertices_] = 1;
        to_try.push_back(x);
    };
    if (!changed)
        for (int x = input_vertices_; x < split_points; ++x) try_later(x, -1);
    else
        for (int e = 0; e < edges; ++e)
            if ((*changed)[e])
                for (const int f : faces_of(e))
                    if (f >= 0) for_each_point_in_plane_of(f, try_later);
    while (!to_try.empty() && report.status == ConvertStatus::certified) {
        const int x = to_try.front();
        to_try.pop_front();
        waiting[x - input_vertices_] = 0;
        const int e = vertex_input_edge_[x - input_vertices_];
        if (e < 0 || input_flat_[e] || removed_[x - input_vertices_]) continue;
        const auto [f, g] = faces_of(e);
        if (is_too_big(f) || is_too_big(g)) continue;
        const int p = other_end(pieces_[x - input_vertices_][0], x), q = other_end(pieces_[x - input_vertices_][1], x);
        // Locally Delaunay: cot α + cot β >= 0 inside, cot α >= 0 on a strict boundary. The
        // apexes of x's piece to p, one in each plane, settle most points at once.
        const Hinge k = hinge(pieces_[x - input_vertices_][0]);
        const double first_apexes = k.s >= 0 ? cotangent(k.r, p, q) + cotangent(k.s, p, q)
                                    : options_.boundary == BoundaryPolicy::strict ? cotangent(k.r, p, q)
                                                                                 : 0.0;
        if (!(first_apexes >= 0)) continue;
        const double margin = g >= 0 ? apex_cotangent(f, p, q, e) + apex_cotangent(g, p, q, e)
                             : options_.boundary == BoundaryPolicy::strict ? apex_cotangent(f, p, q, e)
                                                                          : 0.0;
        if (!(margin >= 0)) continue;
        if (undo_split(x, report) >= 0) {
            ++report.removed_points;
            for_each_point_in_plane_of(f, try_later);
            if (g >= 0) for_each_point_in_plane_of(g, try_later);
        }
        drain(report);
    }
}

bool Converter::among_folds(int e) const {
    auto all_folds = [&](int f) {
        for (int k = 0; k < 3; ++k)
            if (input_flat_[input_edges_.face_edge(f, k)]) return false;
        return true;
    };
    for (int side = 0; side < 2; ++side)
        if (const int f = input_face(e, side); f >= 0)
            for (int k = 0; k < 3; ++k)
                for (int g_side = 0; g_side < 2; ++g_side)
                    if (const int g = input_face(input_edges_.face_edge(f, k), g_side); g >= 0 && !all_folds(g))
                        return false;
    return true;
}

bool Converter::place_points_again(int e, const std::vector<int>& old_points, const std::vector<double>& positions,
                                   ConversionReport& report) {
    int whole = -1;
    for (const int y : old_points) {
        whole = undo_split(y, report);
        if (whole < 0) return false;
        ++report.removed_points;
    }
    // Split the rest of e, from its first end, at each position in turn.
    int rest = whole, near = input_edges_.E(e, 0);
    double done = 0;
    for (const double t : positions) {
        const Hinge k = hinge(rest);
        const bool from_near = k.a == near;
        split(rest, from_near ? t - done : dist(k.a, k.b) - (t - done));
        ++report.splits;
        near = static_cast<int>(P_.size()) - 1;
        rest = pieces_[near - input_vertices_][from_near ? 1 : 0];
        done = t;
    }
    return true;
}

std::vector<char> Converter::fewest_points_per_edge(ConversionReport& report) {
    const int edges = input_edges_.num_edges();
    // The edges with two or more points, from the points' edges sorted (no array by edge: on the
    // skull few edges qualify, and 4.8 M counters would be the pass's largest cost).
    std::vector<int> candidates;
    for (size_t y = input_vertices_; y < P_.size(); ++y)
        if (const int ie = vertex_input_edge_[y - input_vertices_]; ie >= 0 && !removed_[y - input_vertices_])
            candidates.push_back(ie);
    std::sort(candidates.begin(), candidates.end());
    size_t kept = 0;
    for (size_t i = 0; i < candidates.size();) {
        size_t j = i;
        while (j < candidates.size() && candidates[j] == candidates[i]) ++j;
        if (const int e = candidates[i]; j - i >= 2 && !input_flat_[e] && among_folds(e)) candidates[kept++] = e;
        i = j;
    }
    candidates.resize(kept);
    if (candidates.empty()) return {};
    std::unordered_map<int, std::vector<int>> on_edge;  // by input edge, those with points or read
    auto index_points = [&](size_t from) {
        for (size_t y = from; y < P_.size(); ++y)
            if (const int ie = vertex_input_edge_[y - input_vertices_]; ie >= 0 && !removed_[y - input_vertices_])
                on_edge[ie].push_back(static_cast<int>(y));
    };
    index_points(static_cast<size_t>(input_vertices_));
    std::vector<Eigen::Vector3d> points[2], others;
    std::vector<Eigen::Vector2d> unfolded[2];
    // The corners of face f and the points on its edges but e.
    auto gather = [&](int f, int e, std::vector<Eigen::Vector3d>& out) {
        out.clear();
        for (int k = 0; k < 3; ++k) {
            out.push_back(P_[input_.F(f, k)]);
            if (const int g = input_edges_.face_edge(f, k); g != e)
                for (const int y : on_edge[g])
                    if (!removed_[y - input_vertices_]) out.push_back(P_[y]);
        }
    };
    const bool strict = options_.boundary == BoundaryPolicy::strict;
    std::vector<char> changed(static_cast<size_t>(edges), 0);
    std::vector<std::pair<double, double>> forbidden;
    std::vector<double> placed;
    std::vector<int> chain;
    // The pieces of input edge g in order from its first endpoint, as point ids.
    auto pieces_of = [&](int g) {
        chain.assign(on_edge[g].begin(), on_edge[g].end());
        std::erase_if(chain, [&](int y) { return removed_[y - input_vertices_] != 0; });
        const Eigen::Vector3d& start = P_[input_edges_.E(g, 0)];
        std::sort(chain.begin(), chain.end(),
                  [&](int p, int q) { return (P_[p] - start).squaredNorm() < (P_[q] - start).squaredNorm(); });
        chain.insert(chain.begin(), input_edges_.E(g, 0));
        chain.push_back(input_edges_.E(g, 1));
    };
    // The distances from E(e, 0) of the fewest points e needs, placed from E(e, `from`);
    // none if that is more than it has.
    auto fewest = [&](int e, int from) -> std::optional<std::vector<double>> {
        const int a = input_edges_.E(e, from), b = input_edges_.E(e, 1 - from);
        const Eigen::Vector3d& A = P_[a];
        const double l = distance(A, P_[b]);
        const Eigen::Vector3d along = (P_[b] - A) / l;
        const int sides = input_face(e, 1) < 0 ? 1 : 2;
        forbidden.clear();
        for (int side = 0; side < sides; ++side) {
            const int f = input_face(e, side);
            gather(f, e, points[side]);
            for (int k = 0; k < 3; ++k) {
                const int g = input_edges_.face_edge(f, k);
                if (g == e) continue;
                const int across = input_face(g, 0) == f ? input_face(g, 1) : input_face(g, 0);
                if (across < 0 && !strict) continue;
                if (across >= 0) gather(across, g, others);
                const Eigen::Vector3d& w = P_[input_.F(f, k)];  // the corner of f off g, on e
                pieces_of(g);
                for (size_t j = 0; j + 1 < chain.size(); ++j) {
                    const Eigen::Vector3d &u = P_[chain[j]], &v = P_[chain[j + 1]];
                    // x on e breaks u-v where it sees it under a cotangent below c: inside
                    // the circle through u and v on w's side whose inscribed angle has it.
                    const double c = kPlacementMargin - (across < 0 ? 0.0 : apex_cotangent(others, u, v));
                    const Eigen::Vector3d middle = (u + v) / 2, chord = v - u;
                    Eigen::Vector3d normal = w - middle;
                    normal -= normal.dot(chord) / chord.squaredNorm() * chord;
                    const double half = chord.norm() / 2;
                    const Eigen::Vector3d center = middle + normal.normalized() * (half * c);
                    const double t0 = (center - A).dot(along);
                    const double room = half * half * (1 + c * c) - ((center - A).squaredNorm() - t0 * t0);
                    if (room > 0) forbidden.emplace_back(t0 - std::sqrt(room), t0 + std::sqrt(room));
                }
            }
        }
        // reach() pairs the points across e, once for each point placed.
        if (sides == 2 && points[0].size() * points[1].size() > kFewestPointsMaxPairs) return std::nullopt;
        std::sort(forbidden.begin(), forbidden.end());
        // Each face's points unfolded: distance along e from a, and from e's line.
        for (int side = 0; side < sides; ++side) {
            unfolded[side].clear();
            for (const Eigen::Vector3d& p : points[side])
                unfolded[side].emplace_back((p - A).dot(along), (p - A).cross(along).norm());
        }
        // The piece from s to t is locally Delaunay against both faces' points, with a margin.
        auto delaunay = [&](double s, double t) {
            const Eigen::Vector3d u = A + s * along, v = A + t * along;
            if (sides == 1) return !strict || apex_cotangent(points[0], u, v) >= kPlacementMargin;
            return apex_cotangent(points[0], u, v) + apex_cotangent(points[1], u, v) >= kPlacementMargin;
        };
        // Where the piece from s stops being locally Delaunay. Across e, p and q (at heights
        // p.y and -q.y) see s-t under angles summing to π where q lies on the circle through
        // s, t and p: (q.x - s)(q.x - t) + q.y² + κ((p.x - s)(p.x - t) + p.y²) = 0, κ = q.y / p.y,
        // linear in t. On a strict boundary p sees it under π/2 where κ = 0 and q = p.
        auto reach = [&](double s) {
            double t = std::numeric_limits<double>::infinity();
            auto bound = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& q, double kappa) {
                const double slope = (q.x() - s) + kappa * (p.x() - s);
                const double rest = q.x() * (q.x() - s) + q.y() * q.y() + kappa * (p.x() * (p.x() - s) + p.y() * p.y());
                if (slope > 0) t = std::min(t, rest / slope);
            };
            if (sides == 1) {
                if (strict)
                    for (const Eigen::Vector2d& p : unfolded[0]) bound(p, p, 0);
            } else {
                for (const Eigen::Vector2d& p : unfolded[0])
                    if (p.y() > 0)
                        for (const Eigen::Vector2d& q : unfolded[1]) bound(p, q, q.y() / p.y());
            }
            return t;
        };
        const size_t has = on_edge[e].size();
        placed.clear();
        for (double s = 0; !delaunay(s, l);) {
            if (placed.size() + 1 > has) return std::nullopt;
            // Just short of the reach, where the margin holds (else where bisection finds it).
            double x = std::min(s + (reach(s) - s) * (1 - kPlacementMargin), l * (1 - kNearEnd));
            if (!delaunay(s, x)) {
                double beyond = x;
                x = s;
                for (int i = 0; i < 50; ++i) {
                    const double t = (x + beyond) / 2;
                    (delaunay(s, t) ? x : beyond) = t;
                }
            }
            for (auto it = forbidden.rbegin(); it != forbidden.rend(); ++it)
                if (it->first < x && x < it->second) x = it->first;  // by lo, downwards: x only moves down
            if (!(x >= s + kNearEnd * l)) return std::nullopt;  // NaN too, from a degenerate face
            placed.push_back(x);
            s = x;
        }
        if (from == 1) {
            for (double& t : placed) t = l - t;
            std::reverse(placed.begin(), placed.end());
        }
        return placed;
    };
    for (int pass = 0; pass < kFewestPointsPasses; ++pass) {
        for (const int e : candidates) {
            if (report.status != ConvertStatus::certified) break;
            std::erase_if(on_edge[e], [&](int y) { return removed_[y - input_vertices_] != 0; });
            if (on_edge[e].size() < 2) continue;
            const auto positions = fewest(e, pass % 2);
            if (!positions) continue;
            const std::vector<int> old_points = on_edge[e];
            if (positions->size() == old_points.size() && std::all_of(old_points.begin(), old_points.end(), [&](int y) {
                    return std::any_of(positions->begin(), positions->end(), [&](double t) {
                        return std::abs(distance(P_[input_edges_.E(e, 0)], P_[y]) - t) <= 1e-12 * input_length_[e];
                    });
                }))
                continue;  // where they are
            if (mesh_.num_vertices() + static_cast<long long>(positions->size()) > vertex_budget_) continue;
            const ConversionReport before = report;
            begin_trial();
            const bool placed_again = place_points_again(e, old_points, *positions, report);
            // A drain that has to split stops one split beyond as many as it took.
            if (placed_again) drain(report, before.splits + static_cast<long long>(old_points.size()) + 1);
            const long long added = report.splits - report.removed_points;
            if (placed_again && report.status == ConvertStatus::certified && report.vertices_inside_faces == 0 &&
                added <= before.splits - before.removed_points) {
                const size_t first_new = trial_->points;
                commit();
                changed[e] = 1;
                for (size_t y = first_new; y < P_.size(); ++y)
                    if (const int ie = vertex_input_edge_[y - input_vertices_]; ie >= 0) changed[ie] = 1;
                on_edge[e].clear();
                index_points(first_new);
                report.fewest_points_saved += before.splits - before.removed_points - added;
                continue;
            }
            rollback();
            report = before;
        }
    }
    if (std::find(changed.begin(), changed.end(), 1) == changed.end()) return {};
    return changed;
}

std::vector<char> Converter::local_search(ConversionReport& report) {
    // The split points on each input edge; ids taken back by a rollback may linger.
    std::vector<std::vector<int>> on_edge(static_cast<size_t>(input_edges_.num_edges()));
    size_t indexed = static_cast<size_t>(input_vertices_);
    std::vector<int> edges, victims;
    std::vector<char> changed(on_edge.size(), 0);
    for (int pass = 0; pass < options_.local_search; ++pass) {
        const int points = static_cast<int>(P_.size());
        if (options_.progress)
            std::fprintf(stderr, "convert: local search, pass %d of %d, %lld vertices added\n", pass + 1,
                         options_.local_search, report.splits - report.removed_points);
        for (int x = input_vertices_; x < points && report.status == ConvertStatus::certified; ++x) {
            if (progress_due())
                std::fprintf(stderr, "convert: local search, %.0f %% of the points tried, %lld vertices saved\n",
                             100.0 * (x - input_vertices_) / (points - input_vertices_), report.local_search_saved);
            if (x >= static_cast<int>(P_.size()) || removed_[x - input_vertices_]) continue;
            const int e = vertex_input_edge_[x - input_vertices_];
            if (e < 0 || input_flat_[e]) continue;
            for (; indexed < P_.size(); ++indexed)
                if (const int ie = vertex_input_edge_[indexed - input_vertices_]; ie >= 0)
                    on_edge[ie].push_back(static_cast<int>(indexed));
            edges.assign(1, e);
            for (int side = 0; side < 2; ++side)
                if (const int f = input_face(e, side); f >= 0)
                    for (int k = 0; k < 3; ++k) edges.push_back(input_edges_.face_edge(f, k));
            std::sort(edges.begin(), edges.end());
            edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
            victims.clear();
            for (const int ie : edges)
                for (const int y : on_edge[ie])
                    if (y < static_cast<int>(P_.size()) && vertex_input_edge_[y - input_vertices_] == ie &&
                        !removed_[y - input_vertices_])
                        victims.push_back(y);
            std::sort(victims.begin(), victims.end());
            victims.erase(std::unique(victims.begin(), victims.end()), victims.end());
            if (victims.size() > kLocalSearchPoints) continue;
            // A move saves nothing if each point it takes is the one an edge must keep.
            int kept_anyway = 0;
            for (const int ie : edges)
                kept_anyway += needs_point_[ie] && std::any_of(victims.begin(), victims.end(), [&](int y) {
                    return vertex_input_edge_[y - input_vertices_] == ie;
                });
            if (static_cast<int>(victims.size()) <= kept_anyway) continue;
            const ConversionReport before = report;
            begin_trial();
            for (const int y : victims) {
                if (undo_split(y, report) < 0) break;
                ++report.removed_points;
            }
            // It pays only with fewer points than it took: stop before as many are placed.
            drain(report, before.splits + (report.removed_points - before.removed_points));
            const long long added = report.splits - report.removed_points;
            if (report.status == ConvertStatus::certified && report.vertices_inside_faces == 0 &&
                added < before.splits - before.removed_points) {
                for (const int ie : edges) changed[ie] = 1;
                for (size_t y = trial_->points; y < P_.size(); ++y)
                    if (const int ie = vertex_input_edge_[y - input_vertices_]; ie >= 0) changed[ie] = 1;
                commit();
                report.local_search_saved += before.splits - before.removed_points - added;
                continue;
            }
            const bool out_of_budget = report.status == ConvertStatus::budget_exhausted;
            rollback();
            report = before;
            indexed = std::min(indexed, P_.size());
            if (out_of_budget) return changed;  // the next moves would run out too; the mesh is as before
        }
        const std::vector<char> relocated = relocate_points(report);
        for (size_t e = 0; e < changed.size(); ++e) changed[e] |= relocated[e];
    }
    return changed;
}

std::vector<char> Converter::relocate_points(ConversionReport& report) {
    const int edges = input_edges_.num_edges();
    const bool strict = options_.boundary == BoundaryPolicy::strict;
    std::vector<char> changed(static_cast<size_t>(edges), 0);

    // By input edge: its split points, and the model's positions of them (distances from its
    // first end, in increasing order).
    std::unordered_map<int, std::vector<int>> points_on;
    std::vector<std::vector<double>> at(static_cast<size_t>(edges));
    auto index_points = [&](size_t from) {
        for (size_t y = from; y < P_.size(); ++y)
            if (const int g = vertex_input_edge_[y - input_vertices_]; g >= 0 && !removed_[y - input_vertices_])
                points_on[g].push_back(static_cast<int>(y));
    };
    auto read_positions = [&](int g) {
        std::vector<double>& positions = at[g];
        positions.clear();
        for (const int y : points_on[g]) positions.push_back(dist(input_edges_.E(g, 0), y));
        std::sort(positions.begin(), positions.end());
    };
    index_points(static_cast<size_t>(input_vertices_));
    for (auto& [g, points] : points_on) read_positions(g);
    auto position = [&](int g, double t) -> Eigen::Vector3d {
        const Eigen::Vector3d &a = P_[input_edges_.E(g, 0)], &b = P_[input_edges_.E(g, 1)];
        return a + (t / input_length_[g]) * (b - a);
    };
    // The points of input face f off input edge g's line: the corner across g and the points on
    // f's other edges.
    std::vector<Eigen::Vector3d> apexes;
    auto gather = [&](int f, int g, std::vector<Eigen::Vector3d>& out) {
        out.clear();
        for (int k = 0; k < 3; ++k) {
            const int side = input_edges_.face_edge(f, k);
            if (side == g)
                out.push_back(P_[input_.F(f, k)]);
            else
                for (const double t : at[side]) out.push_back(position(side, t));
        }
    };
    // The apex cotangents of g's pieces, along g, among `seen_from` (null: a boundary edge's
    // missing face, whose apex counts as a right angle).
    auto piece_cotangents = [&](int g, const std::vector<Eigen::Vector3d>* seen_from, std::vector<double>& out) {
        out.clear();
        const std::vector<double>& cuts = at[g];
        Eigen::Vector3d u = P_[input_edges_.E(g, 0)];
        for (size_t i = 0; i <= cuts.size(); ++i) {
            const Eigen::Vector3d v = i < cuts.size() ? position(g, cuts[i]) : P_[input_edges_.E(g, 1)];
            out.push_back(seen_from ? apex_cotangent(*seen_from, u, v) : 0.0);
            u = v;
        }
    };
    // ... in g's face on `side` (0 or 1).
    auto cotangents_in = [&](int g, int side, std::vector<double>& out) {
        const int f = input_face(g, side);
        if (f >= 0) gather(f, g, apexes);
        piece_cotangents(g, f >= 0 ? &apexes : nullptr, out);
    };
    auto angle = [](double cotangent) { return std::atan2(1.0, cotangent); };
    // How far g is from locally Delaunay, from its pieces' apex cotangents in either face: the
    // sum over the pieces whose cotangents sum below kPlacementMargin (as fewest_points_per_edge
    // places points; on a strict boundary the one apex's) of their apex angles beyond π (π/2),
    // at least 1e-12 each; 0 for none. A free boundary never counts.
    auto counts = [&](int g) { return strict || input_face(g, 1) >= 0; };
    auto excess_of = [&](const std::vector<double>& first, const std::vector<double>& second) {
        double total = 0;
        for (size_t i = 0; i < first.size(); ++i)
            if (!(first[i] + second[i] >= kPlacementMargin))
                total += std::max(1e-12, angle(first[i]) + angle(second[i]) - kPi);
        return total;
    };
    std::vector<double> cotangents[2];
    auto excess = [&](int g) {
        if (!counts(g)) return 0.0;
        for (int side = 0; side < 2; ++side) cotangents_in(g, side, cotangents[side]);
        return excess_of(cotangents[0], cotangents[1]);
    };
    // Whether `count` points on g can make its pieces locally Delaunay against the corners across
    // g alone. Points on the other sides only widen the apex angles, so with fewer no move of
    // theirs repairs g. Greedy, each piece as long as its corners allow, which is optimal: a piece
    // that keeps within a longer one's ends is locally Delaunay if the longer one is.
    auto can_do_with = [&](int g, size_t count) {
        const int f = input_face(g, 0), across = input_face(g, 1);
        if (across < 0 && !strict) return true;
        auto corner = [&](int face) -> const Eigen::Vector3d& {
            int k = 0;
            while (input_edges_.face_edge(face, k) != g) ++k;
            return P_[input_.F(face, k)];
        };
        const Eigen::Vector3d& c = corner(f);
        auto keeps = [&](double from, double to) {
            const Eigen::Vector3d u = position(g, from), v = position(g, to);
            const double second = across >= 0 ? cotangent_seen_from(corner(across), u, v) : 0.0;  // π/2
            return cotangent_seen_from(c, u, v) + second >= kPlacementMargin;
        };
        const double l = input_length_[g];
        double from = 0;
        for (size_t piece = 0; piece <= count; ++piece) {
            if (keeps(from, l)) return true;
            double reached = from, broken = l;
            for (int halving = 0; halving < 64; ++halving) {
                const double middle = 0.5 * (reached + broken);
                (keeps(from, middle) ? reached : broken) = middle;
            }
            if (!(reached > from)) return false;  // no piece from here keeps: no count of points does
            from = reached;
        }
        return false;
    };
    // The input edges of g's faces, g among them: those whose excess g's points change.
    auto around = [&](int g, std::vector<int>& out) {
        out.assign(1, g);
        for (int side = 0; side < 2; ++side)
            if (const int f = input_face(g, side); f >= 0)
                for (int k = 0; k < 3; ++k)
                    if (const int h = input_edges_.face_edge(f, k); h != g) out.push_back(h);
    };
    // Whether the faces whose edges' excess g's points change hold more than
    // kRelocationMaxPoints points: each evaluation pairs their points with the pieces.
    auto crowded = [&](int g) {
        size_t count = 0;
        for (int side = 0; side < 2; ++side)
            if (const int f = input_face(g, side); f >= 0)
                for (int k = 0; k < 3; ++k)
                    for (int h_side = 0; h_side < 2; ++h_side)
                        if (const int h = input_face(input_edges_.face_edge(f, k), h_side); h >= 0)
                            for (int j = 0; j < 3; ++j)
                                count += at[input_edges_.face_edge(h, j)].size();
        return count > kRelocationMaxPoints;
    };
    auto movable = [&](int g) { return !input_flat_[g] && among_folds(g) && !crowded(g); };
    std::vector<std::pair<int, std::vector<double>>> before_move;  // the positions an attempt changed
    std::unordered_map<int, double> known_excess;  // by input edge, since its last change
    std::vector<int> region, violated, nearby, affected, replaced;
    std::vector<std::pair<int, size_t>> candidates;
    std::vector<Eigen::Vector3d> apexes_of_g[2];
    std::vector<std::vector<double>> away;
    std::vector<int> away_side;
    const int points = static_cast<int>(P_.size());
    for (int x = input_vertices_; x < points && report.status == ConvertStatus::certified; ++x) {
        if (progress_due())
            std::fprintf(stderr, "convert: local search, %.0f %% of the points moved, %lld vertices saved\n",
                         100.0 * (x - input_vertices_) / (points - input_vertices_), report.local_search_saved);
        if (removed_[x - input_vertices_]) continue;
        const int e = vertex_input_edge_[x - input_vertices_];
        if (e < 0 || !movable(e) || !can_do_with(e, at[e].size() - 1)) continue;
        Random random(static_cast<std::uint64_t>(x));
        before_move.clear();
        known_excess.clear();
        auto move = [&](int g, std::vector<double> positions) {
            if (std::none_of(before_move.begin(), before_move.end(), [g](const auto& m) { return m.first == g; }))
                before_move.emplace_back(g, at[g]);
            std::sort(positions.begin(), positions.end());
            at[g] = std::move(positions);
            around(g, nearby);
            for (const int h : nearby) known_excess.erase(h);
        };
        auto current_excess = [&](int g) {
            const auto [it, added] = known_excess.try_emplace(g, 0.0);
            if (added) it->second = excess(g);
            return it->second;
        };
        std::vector<double> without_x = at[e];
        const double x_at = dist(input_edges_.E(e, 0), x);
        without_x.erase(std::min_element(without_x.begin(), without_x.end(), [&](double p, double q) {
            return std::abs(p - x_at) < std::abs(q - x_at);
        }));
        move(e, std::move(without_x));
        around(e, region);
        bool repaired = false;
        for (int step = 0; step <= kRelocationMoves; ++step) {
            violated.clear();
            for (const int g : region)
                if (current_excess(g) > 0) violated.push_back(g);
            if (violated.empty()) {
                repaired = true;
                break;
            }
            if (step == kRelocationMoves) break;
            // A point on an edge of a broken edge's faces moves, where it narrows the angles most.
            around(violated[random.below(violated.size())], nearby);
            candidates.clear();
            for (const int g : nearby)
                if (movable(g))
                    for (size_t i = 0; i < at[g].size(); ++i) candidates.emplace_back(g, i);
            if (candidates.empty()) break;
            for (size_t i = 0; i + 1 < candidates.size(); ++i)
                std::swap(candidates[i], candidates[i + random.below(candidates.size() - i)]);
            candidates.resize(std::min<size_t>(candidates.size(), kRelocationCandidates));
            double best_gain = 0;
            std::optional<std::pair<int, std::vector<double>>> best;
            for (const auto& candidate : candidates) {
                const int g = candidate.first;  // a plain variable: clang 14 captures no structured binding
                const size_t i = candidate.second;
                around(g, affected);
                double now = 0;
                for (const int h : affected) now += current_excess(h);
                // What moving g's points leaves as it is: the apexes of g's pieces, and the apex
                // cotangents of the other edges' pieces in their faces away from g.
                for (int side = 0; side < 2; ++side)
                    if (const int f = input_face(g, side); f >= 0) gather(f, g, apexes_of_g[side]);
                away.resize(affected.size());
                away_side.resize(affected.size());
                for (size_t k = 1; k < affected.size(); ++k) {
                    const int h = affected[k], f = input_face(h, 0);
                    away_side[k] = f >= 0 && (f == input_face(g, 0) || f == input_face(g, 1)) ? 1 : 0;
                    cotangents_in(h, away_side[k], away[k]);
                }
                auto excess_after_move = [&] {
                    double total = 0;
                    if (counts(g)) {
                        for (int side = 0; side < 2; ++side)
                            piece_cotangents(g, input_face(g, side) >= 0 ? &apexes_of_g[side] : nullptr,
                                             cotangents[side]);
                        total += excess_of(cotangents[0], cotangents[1]);
                    }
                    for (size_t k = 1; k < affected.size(); ++k) {
                        if (!counts(affected[k])) continue;
                        const int toward = 1 - away_side[k];
                        cotangents_in(affected[k], toward, cotangents[toward]);
                        total += toward == 0 ? excess_of(cotangents[0], away[k]) : excess_of(away[k], cotangents[1]);
                    }
                    return total;
                };
                const double l = input_length_[g];
                const std::vector<double> current = at[g];
                for (int trial = 0; trial < kRelocationPositions; ++trial) {
                    // Mostly anywhere on the edge, once near where the point is.
                    const double t = trial == 0 ? current[i] + (random.uniform() - 0.5) * 0.1 * l : random.uniform() * l;
                    std::vector<double> positions = current;
                    positions[i] = t;
                    std::sort(positions.begin(), positions.end());
                    // Pieces stay at least kNearEnd of the edge long.
                    double previous = 0;
                    bool room = true;
                    for (const double p : positions) room = room && p - previous >= kNearEnd * l, previous = p;
                    if (!room || l - previous < kNearEnd * l) continue;
                    at[g] = positions;
                    if (const double gain = now - excess_after_move(); gain > best_gain)
                        best_gain = gain, best.emplace(g, std::move(positions));
                }
                at[g] = current;
            }
            if (!best) {  // nothing narrows them: a random move, to leave a local minimum
                const auto [g, i] = candidates[random.below(candidates.size())];
                const double l = input_length_[g];
                std::vector<double> positions = at[g];
                positions[i] = (kNearEnd + random.uniform() * (1 - 2 * kNearEnd)) * l;
                std::sort(positions.begin(), positions.end());
                if (std::adjacent_find(positions.begin(), positions.end(), [&](double p, double q) {
                        return q - p < kNearEnd * l;
                    }) != positions.end())
                    continue;
                best.emplace(g, std::move(positions));
            }
            move(best->first, std::move(best->second));
            around(best->first, nearby);
            for (const int g : nearby)
                if (std::find(region.begin(), region.end(), g) == region.end()) region.push_back(g);
        }
        auto restore = [&] {
            for (auto& [g, positions] : before_move) at[g] = std::move(positions);
        };
        if (!repaired) {
            restore();
            continue;
        }
        // The mesh follows; the drain takes it back if a piece still needs a point.
        const ConversionReport before = report;
        begin_trial();
        bool placed = true;
        replaced.clear();
        for (const auto& [g, positions] : before_move)
            if (placed && at[g] != positions) {
                placed = place_points_again(g, points_on[g], at[g], report);
                replaced.push_back(g);
            }
        // A drain that has to split leaves no saving: it stops at the first split.
        if (placed) drain(report, report.splits + 1);
        const long long added = report.splits - report.removed_points;
        if (placed && report.status == ConvertStatus::certified && report.vertices_inside_faces == 0 &&
            added < before.splits - before.removed_points) {
            const size_t first_new = trial_->points;
            commit();
            for (const int g : replaced) {
                changed[g] = 1;
                points_on[g].clear();
            }
            index_points(first_new);
            for (const int g : replaced) read_positions(g);
            report.local_search_saved += before.splits - before.removed_points - added;
            continue;
        }
        const bool out_of_budget = report.status == ConvertStatus::budget_exhausted;
        rollback();
        report = before;
        restore();
        if (out_of_budget) break;  // the next moves would run out too; the mesh is as before
    }
    return changed;
}

}  // namespace sdmesh::conversion
