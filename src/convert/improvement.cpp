// After the loop: split points removed again, the fewest points per input edge, local search
// (whose moves of points are in relocation.cpp).
#include "convert/converter.hpp"
#include "convert/piece_reach.hpp"

#include <bitset>
#include <unordered_map>

namespace sdmesh::conversion {

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
    // The split points on each input edge (removed ones are skipped when read), and those that
    // drains add while removing.
    const int split_points = static_cast<int>(P_.size());
    const Buckets on_edge(edges, split_points - input_vertices_, [&](int i) { return vertex_input_edge_[i]; });
    std::unordered_map<int, std::vector<int>> added_on_edge;
    // The points of each plane, each once, packed in a row when the plane is first read (and
    // extended with the points that drains add, and rid of those removed): the scans below are
    // most of the pass's time, and read from scattered positions they mostly waited on memory.
    struct PlanePoint {
        Eigen::Vector3d position;
        int y, edge;  // edge: the input edge of a split point, -1 for an input vertex
    };
    auto plane_id = [&](int f) { return any_flat ? plane_of[f] : f; };
    std::vector<int> packed_index(static_cast<size_t>(input_faces), -1);  // by plane id
    std::vector<std::vector<PlanePoint>> packed;
    size_t packed_until = P_.size();
    std::vector<int> corners, plane_edges;
    auto points_in_plane_of = [&](int f) -> std::span<const PlanePoint> {
        for (; packed_until < P_.size(); ++packed_until) {
            const int y = static_cast<int>(packed_until), edge = vertex_input_edge_[y - input_vertices_];
            if (edge < 0) continue;
            added_on_edge[edge].push_back(y);
            const auto [one, other] = faces_of(edge);
            for (const int face : {one, other})
                if (face >= 0 && (face == one || plane_id(face) != plane_id(one)))
                    if (const int index = packed_index[plane_id(face)]; index >= 0)
                        packed[index].push_back({P_[y], y, edge});
        }
        int& index = packed_index[plane_id(f)];
        if (index >= 0) return packed[index];
        corners.clear(), plane_edges.clear();
        for_each_face_in_plane_of(f, [&](int face) {
            for (int k = 0; k < 3; ++k) {
                corners.push_back(input_.F(face, k));
                plane_edges.push_back(input_edges_.face_edge(face, k));
            }
        });
        for (std::vector<int>* ids : {&corners, &plane_edges}) {
            std::sort(ids->begin(), ids->end());
            ids->erase(std::unique(ids->begin(), ids->end()), ids->end());
        }
        index = static_cast<int>(packed.size());
        std::vector<PlanePoint>& points = packed.emplace_back();
        for (const int v : corners) points.push_back({P_[v], v, -1});
        for (const int edge : plane_edges) {
            for (const int i : on_edge[edge])
                if (!removed_[i]) points.push_back({P_[input_vertices_ + i], input_vertices_ + i, edge});
            if (const auto added = added_on_edge.find(edge); added != added_on_edge.end())
                for (const int y : added->second)
                    if (!removed_[y - input_vertices_]) points.push_back({P_[y], y, edge});
        }
        return points;
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
    // A removed point leaves the packed lists of its edge's planes (those packed so far), so the
    // scans need not ask whether a point is still there.
    auto drop_from_planes = [&](int y) {
        for (const int f : faces_of(vertex_input_edge_[y - input_vertices_]))
            if (f >= 0)
                if (const int index = packed_index[plane_id(f)]; index >= 0)
                    if (const auto it = std::find_if(packed[index].begin(), packed[index].end(),
                                                     [&](const PlanePoint& point) { return point.y == y; });
                        it != packed[index].end())
                        packed[index].erase(it);  // in place: the order of the plane's tries stays
    };
    // The points of the chain being gathered, by split point (grown as the drain adds points),
    // behind a filter of their ids modulo 4096: a plane scan asks about every point of the
    // plane, and the filter answers nearly all of them without a scattered read.
    std::vector<int> chain;
    std::vector<char> in_chain;
    std::bitset<4096> chain_filter;
    auto in_filter = [](int y) { return static_cast<size_t>(y) % 4096; };
    auto is_in_chain = [&](int y) {
        return y >= input_vertices_ && chain_filter[in_filter(y)] && in_chain[y - input_vertices_];
    };
    auto join_chain = [&](int y) {
        in_chain[y - input_vertices_] = 1;
        chain_filter.set(in_filter(y));
        chain.push_back(y);
    };
    // A point that may go with the chain: a split point on a fold (one on a flat edge, inside a
    // plane, stays like the input vertices).
    auto goes_with_edge = [&](int edge) { return edge >= 0 && !input_flat_[edge]; };
    auto may_go = [&](int y) { return y >= input_vertices_ && goes_with_edge(vertex_input_edge_[y - input_vertices_]); };
    // The apexes of a piece p-q on one side, as cotangents of the angles under which they see
    // it: the widest of the points that stay, and the points that may go and see it wider.
    constexpr double kNone = std::numeric_limits<double>::infinity();  // no apex
    struct Apexes {
        double staying = kNone, widest_going = kNone;
        // Those that may go and see the piece wider than `staying`: after heap(), a heap whose
        // top is the widest (seldom needed: widest() settles most pieces).
        std::vector<std::pair<double, int>> going;
        void add(double cotangent, int y, bool stays) {
            if (stays) {
                staying = std::min(staying, cotangent);
            } else if (cotangent < staying) {
                going.emplace_back(cotangent, y);
                widest_going = std::min(widest_going, cotangent);
            }
        }
        void clear() {
            staying = widest_going = kNone;
            going.clear();  // keeping its room: this runs for every try
        }
        double widest() const { return std::min(staying, widest_going); }
        void heap() {
            std::erase_if(going, [&](const auto& apex) { return !(apex.first < staying); });
            std::make_heap(going.begin(), going.end(), std::greater<>{});
        }
        double widest_left() const { return going.empty() ? staying : going.front().first; }
        int pop_widest() {
            std::pop_heap(going.begin(), going.end(), std::greater<>{});
            const int y = going.back().second;
            going.pop_back();
            return y;
        }
    };
    size_t apex_tests = 0;
    // Those of the points of the plane of face f, off edge e.
    auto plane_apexes = [&](int f, int p, int q, int e, Apexes& found) {
        found.clear();
        const Eigen::Vector3d from = P_[p], to = P_[q];
        for (const PlanePoint& point : points_in_plane_of(f)) {
            if (point.edge == e || point.y == p || point.y == q || is_in_chain(point.y)) continue;
            ++apex_tests;
            found.add(cotangent_seen_from(point.position, from, to), point.y, !goes_with_edge(point.edge));
        }
    };
    // Those of x's neighbours from its piece `into` round to `last`; false where x has no face on
    // that side (a boundary line).
    auto neighbour_apexes = [&](int x, int into, int last, int p, int q, Apexes& found) {
        found.clear();
        const int h = side_into(into, x);
        if (h < 0) return false;
        for (int out = HalfedgeMesh::next(h); mesh_.head(out) != last; out = HalfedgeMesh::next(mesh_.twin(out)))
            if (const int y = mesh_.head(out); y != p && y != q && !is_in_chain(y)) {
                ++apex_tests;
                found.add(cotangent_seen_from(P_[y], P_[p], P_[q]), y, !may_go(y));
            }
        return true;
    };
    // The end of x's piece `piece` beyond the points of the chain.
    auto beyond_chain = [&](int x, int piece) {
        for (int z = other_end(piece, x);; z = other_end(piece, x)) {
            if (!is_in_chain(z)) return z;
            const auto [one, other] = pieces_[z - input_vertices_];
            piece = one == piece ? other : one;
            x = z;
        }
    };
    const bool strict = options_.boundary == BoundaryPolicy::strict;
    // What is left of the pass's budget of apex tests for chains (see kChainWork).
    size_t chain_work = kChainWork * static_cast<size_t>(split_points - input_vertices_);
    // The points that must go with x gather in `chain`: while the piece that a point of the
    // chain leaves (joined across the chain's points beside it on its edge) is not locally
    // Delaunay, its widest apex that may go joins the chain. The chain fails if apexes that stay
    // break such a piece, or it grows past kChainPoints, kChainTests or the budget. It grows
    // first from the neighbours of its points, which cost little to read and settle most
    // points, then from the planes on their sides, where every apex of the pieces left lies.
    Apexes sides[2];
    auto grow_chain = [&](bool whole_planes) {
        for (size_t i = 0; i < chain.size(); ++i) {
            const int y = chain[i], e = vertex_input_edge_[y - input_vertices_];
            const auto [f, g] = faces_of(e);
            if (is_too_big(f) || is_too_big(g)) return false;
            const auto [to_p, to_q] = pieces_[y - input_vertices_];
            const int p = beyond_chain(y, to_p), q = beyond_chain(y, to_q);
            bool two_sides = g >= 0;
            if (whole_planes) {
                plane_apexes(f, p, q, e, sides[0]);
                if (two_sides) plane_apexes(g, p, q, e, sides[1]);
            } else {
                const int next_p = other_end(to_p, y), next_q = other_end(to_q, y);
                const bool one = neighbour_apexes(y, to_p, next_q, p, q, sides[0]);
                const bool other = neighbour_apexes(y, to_q, next_p, p, q, sides[1]);
                if (!one) std::swap(sides[0], sides[1]);
                two_sides = one && other;
            }
            if (!two_sides) {
                if (!strict) continue;  // a free boundary line
                sides[1].clear();  // a strict one: cot α >= 0
                sides[1].staying = 0;
            }
            // Locally Delaunay: cot α + cot β >= 0.
            if (sides[0].widest() + sides[1].widest() >= 0) continue;
            if (!(sides[0].staying + sides[1].staying >= 0)) return false;
            sides[0].heap(), sides[1].heap();
            while (sides[0].widest_left() + sides[1].widest_left() < 0) {
                // The staying ones sum to >= 0, so one side's widest may go.
                const bool first = sides[1].going.empty() ||
                                   (!sides[0].going.empty() && sides[0].widest_left() <= sides[1].widest_left());
                const int z = sides[first ? 0 : 1].pop_widest();
                if (is_in_chain(z)) continue;  // a point of both planes
                if (chain.size() >= kChainPoints || apex_tests >= std::min(kChainTests, chain_work)) return false;
                join_chain(z);
            }
        }
        return true;
    };
    auto gather_chain = [&](int x) {
        in_chain.resize(P_.size() - input_vertices_, 0);
        chain.clear();
        join_chain(x);
        apex_tests = 0;
        const bool goes = grow_chain(false) && grow_chain(true);
        chain_work -= std::min(chain_work, apex_tests);
        for (const int y : chain) in_chain[y - input_vertices_] = 0, chain_filter.reset(in_filter(y));
        return goes;
    };
    // Every split point is tried; a removal makes the points of the planes around it worth
    // trying again, so that at the end no point can go, alone or with a chain.
    std::deque<int> to_try;
    std::vector<char> waiting(static_cast<size_t>(split_points - input_vertices_), 0);
    auto try_later = [&](int x) {
        if (x < input_vertices_ || x >= split_points || waiting[x - input_vertices_] || removed_[x - input_vertices_])
            return;
        waiting[x - input_vertices_] = 1;
        to_try.push_back(x);
    };
    auto try_points_of_plane = [&](int f) {
        for (const PlanePoint& point : points_in_plane_of(f)) try_later(point.y);
    };
    if (!changed)
        for (int x = input_vertices_; x < split_points; ++x) try_later(x);
    else
        for (int e = 0; e < edges; ++e)
            if ((*changed)[e])
                for (const int f : faces_of(e))
                    if (f >= 0) try_points_of_plane(f);
    const long long removed_before = report.removed_points;
    while (!to_try.empty() && report.status == ConvertStatus::certified) {
        if (progress_due())
            std::fprintf(stderr, "convert: removing the points no longer needed, %lld removed, %zu to try\n",
                         report.removed_points - removed_before, to_try.size());
        const int x = to_try.front();
        to_try.pop_front();
        waiting[x - input_vertices_] = 0;
        if (removed_[x - input_vertices_] || !may_go(x) || !gather_chain(x)) continue;
        for (const int y : chain) {
            if (undo_split(y, report) < 0) break;  // what the rest left non-Delaunay is split again
            ++report.removed_points;
            drop_from_planes(y);
            for (const int f : faces_of(vertex_input_edge_[y - input_vertices_]))
                if (f >= 0) try_points_of_plane(f);
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
        if (!split(rest, from_near ? t - done : dist(k.a, k.b) - (t - done))) return false;
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
    std::vector<UnfoldedPoint> unfolded[2];
    std::vector<double> on_line;
    PieceReach reach_across;
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
        for (int side = 0; side < sides; ++side) gather(input_face(e, side), e, points[side]);
        // reach() pairs the points across e, once for each point placed.
        if (sides == 2 && points[0].size() * points[1].size() > kFewestPointsMaxPairs) return std::nullopt;
        forbidden.clear();
        size_t side_tests = 0;
        for (int side = 0; side < sides; ++side) {
            const int f = input_face(e, side);
            for (int k = 0; k < 3; ++k) {
                const int g = input_edges_.face_edge(f, k);
                if (g == e) continue;
                const int across = input_face(g, 0) == f ? input_face(g, 1) : input_face(g, 0);
                if (across < 0 && !strict) continue;
                if (across >= 0) gather(across, g, others);
                const Eigen::Vector3d& w = P_[input_.F(f, k)];  // the corner of f off g, on e
                pieces_of(g);
                if (across >= 0) side_tests += others.size() * (chain.size() - 1);
                if (side_tests > kFewestPointsMaxSideTests) return std::nullopt;
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
        std::sort(forbidden.begin(), forbidden.end());
        // Each face's points unfolded. Across e, reach() pairs the points off e's line; those
        // on it bound a piece only at their own place, from side 1.
        on_line.clear();
        for (int side = 0; side < sides; ++side) {
            unfolded[side].clear();
            for (const Eigen::Vector3d& p : points[side]) {
                const double x = (p - A).dot(along), y = (p - A).cross(along).norm();
                if (y > 0 || sides == 1)
                    unfolded[side].push_back({x, y, 1 / y});
                else if (side == 1 && y == 0)  // (a NaN bounds nothing)
                    on_line.push_back(x);
            }
        }
        // The piece from s to t is locally Delaunay against both faces' points, with a margin.
        auto delaunay = [&](double s, double t) {
            const Eigen::Vector3d u = A + s * along, v = A + t * along;
            if (sides == 1) return !strict || apex_cotangent(points[0], u, v) >= kPlacementMargin;
            // Each apex of the larger side can only lower the sum: the first that breaks it decides.
            const bool larger = points[1].size() > points[0].size();
            const double smaller_side = apex_cotangent(points[larger ? 0 : 1], u, v);
            double larger_side = std::numeric_limits<double>::infinity();
            for (const Eigen::Vector3d& p : points[larger ? 1 : 0]) {
                larger_side = std::min(larger_side, cotangent_seen_from(p, u, v));
                if (smaller_side + larger_side < kPlacementMargin) return false;
            }
            return smaller_side + larger_side >= kPlacementMargin;
        };
        // Where the piece from s stops being locally Delaunay.
        auto reach = [&](double s) {
            if (sides == 2) return reach_across(unfolded[0], unfolded[1], on_line, s);
            double t = std::numeric_limits<double>::infinity();
            if (strict)
                for (const UnfoldedPoint& p : unfolded[0]) t = std::min(t, pair_reach(p, p, 0, s));
            return t;
        };
        const size_t has = on_edge[e].size();
        placed.clear();
        for (double s = 0; !delaunay(s, l);) {
            if (placed.size() + 1 > has) return std::nullopt;
            // Just short of the reach, where the margin holds (else where bisection finds it).
            // x only moves down from here, so it fails as soon as it must end below `nearest`.
            const double nearest = s + kNearEnd * l;
            double x = std::min(s + (reach(s) - s) * (1 - kPlacementMargin), l * (1 - kNearEnd));
            if (x < nearest) return std::nullopt;
            if (!delaunay(s, x)) {
                double beyond = x;
                x = s;
                for (int i = 0; i < 50 && !(beyond < nearest); ++i) {
                    const double t = (x + beyond) / 2;
                    (delaunay(s, t) ? x : beyond) = t;
                }
            }
            for (auto it = forbidden.rbegin(); it != forbidden.rend(); ++it)
                if (it->first < x && x < it->second) x = it->first;  // by lo, downwards: x only moves down
            if (!(x >= nearest)) return std::nullopt;  // NaN too, from a degenerate face
            placed.push_back(x);
            s = x;
        }
        if (from == 1) {
            for (double& t : placed) t = l - t;
            std::reverse(placed.begin(), placed.end());
        }
        return placed;
    };
    // Two passes in a row that place nothing leave the mesh as it was: each pass after them
    // would repeat the one before last.
    for (int pass = 0, idle_passes = 0; pass < kFewestPointsPasses && idle_passes < 2; ++pass) {
        ++idle_passes;
        for (size_t i = 0; i < candidates.size(); ++i) {
            if (report.status != ConvertStatus::certified) break;
            if (!trial_ && progress_due())
                std::fprintf(stderr, "convert: the fewest points per input edge, pass %d of %d, %.0f %% of the edges tried, "
                             "%lld vertices saved\n", pass + 1, kFewestPointsPasses, 100.0 * static_cast<double>(i) / static_cast<double>(candidates.size()),
                             report.fewest_points_saved);
            const int e = candidates[i];
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
                idle_passes = 0;
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

}  // namespace sdmesh::conversion
