// Splits decided together: cuts carried across strips of thin faces, cascade trials, and the
// joint splits of non-Delaunay edges that share only outer sides.
#include "convert/converter.hpp"

namespace sdmesh::conversion {

void Converter::classify_input_vertices() {
    // Each face's corners are judged in parallel (4.8M on the skull took 0.43 s with an
    // arctangent each, on one thread), then counted by vertex in order. The corners' positions
    // lie anywhere: those of a later face are requested ahead.
    const int faces = input_.num_faces();
    std::vector<std::uint8_t> thin(static_cast<size_t>(faces));
#pragma omp parallel for schedule(static)
    for (int f = 0; f < faces; ++f) {
        if (const int ahead = f + detail::kPrefetchDistance; ahead < faces)
            for (int c = 0; c < 3; ++c) __builtin_prefetch(&P_[input_.F(ahead, c)]);
        const int u = input_.F(f, 0), v = input_.F(f, 1), w = input_.F(f, 2);
        const double opposite[3] = {dist(v, w), dist(w, u), dist(u, v)};
        std::uint8_t corners = 0;
        for (int c = 0; c < 3; ++c)
            if (corner_below(opposite[c], opposite[(c + 1) % 3], opposite[(c + 2) % 3], kThinCornerTangent))
                corners |= static_cast<std::uint8_t>(1u << c);
        thin[f] = corners;
    }
    const size_t vertices = static_cast<size_t>(input_vertices_);
    std::vector<int> thin_corners(vertices, 0);
    for (int f = 0; f < faces; ++f)
        for (int c = 0; c < 3; ++c) thin_corners[input_.F(f, c)] += thin[f] >> c & 1u;
    // The cone angles of the vertices with thin corners (few: no arctangent elsewhere).
    std::vector<double> cone(vertices, 0);
    for (int f = 0; f < faces; ++f) {
        const int u = input_.F(f, 0), v = input_.F(f, 1), w = input_.F(f, 2);
        if (thin_corners[u] + thin_corners[v] + thin_corners[w] == 0) continue;
        const double opposite[3] = {dist(v, w), dist(w, u), dist(u, v)};
        for (int c = 0; c < 3; ++c)
            if (thin_corners[input_.F(f, c)] > 0)
                cone[input_.F(f, c)] += corner_angle(opposite[c], opposite[(c + 1) % 3], opposite[(c + 2) % 3]);
    }
    std::vector<char> on_boundary(vertices, 0);
    shortest_edge_.assign(vertices, std::numeric_limits<double>::infinity());
    for (int e = 0; e < input_edges_.num_edges(); ++e)
        for (const int end : {input_edges_.E(e, 0), input_edges_.E(e, 1)}) {
            shortest_edge_[end] = std::min(shortest_edge_[end], input_length_[e]);
            on_boundary[end] |= static_cast<char>(input_edges_.edge_halfedges(e, 1) < 0);
        }
    fan_apex_.assign(vertices, 0);
    for (size_t v = 0; v < vertices; ++v)
        fan_apex_[v] =
            thin_corners[v] > kMaxStripCorners || (thin_corners[v] > 0 && !on_boundary[v] && cone[v] < kSpikeCone);
}

void Converter::split_across_strips(int first, ConversionReport& report, bool look_ahead, double at) {
    struct Cut {
        int edge;
        double at;  // distance from the edge's hinge's a; < 0: where split_distance says
        bool across_strip;
    };
    std::vector<Cut> cuts{{first, at, false}};
    while (!cuts.empty() && mesh_.num_vertices() < vertex_budget_) {
        const Cut cut = cuts.back();
        cuts.pop_back();
        if (cut.across_strip && is_delaunay(cut.edge)) continue;
        const Hinge k = hinge(cut.edge);
        const double l = dist(k.a, k.b);
        const OuterHalfedges outer = outer_halfedges(k);
        std::array<StripSide, 4> sides;
        for (int i = 0; i < outer.count; ++i) {
            const int g = outer.h[i], shared = i % 2 == 0 ? k.a : k.b;
            sides[i] = {mesh_.edge(g), shared, mesh_.tail(g) == shared ? mesh_.head(g) : mesh_.tail(g),
                        shared == k.a ? k.b : k.a};
        }
        double position = cut.at;
        if (position < 0) {
            const bool trials = look_ahead && options_.cascade_trials > 1 &&
                                trial_splits_ < kTrialWork * (report.splits + input_vertices_ / 8);
            position = split_distance(k, l, trials ? &alternatives_ : nullptr);
            if (trials && alternatives_.size() > 1) position = fewest_splits_after(cut.edge, alternatives_);
        }
        if (!split(cut.edge, position)) {
            ++report.skipped_splits;
            continue;
        }
        ++report.splits;
        for (int i = 0; i < outer.count; ++i)
            if (const std::optional<double> across = strip_cut(sides[i]); across)
                cuts.push_back({sides[i].edge, *across, true});
    }
}

double Converter::fewest_splits_after(int e, const std::vector<double>& positions) {
    double chosen = positions.front();
    long long fewest = std::numeric_limits<long long>::max();
    for (const double t : positions) {
        if (const long long cost = splits_after(e, t, fewest); cost < fewest) fewest = cost, chosen = t;
        if (fewest <= 2) break;  // itself and one broken side: what nearly every position costs
    }
    return chosen;
}

long long Converter::splits_after(int e, double t, long long at_most) {
    auto flat_waiting = std::move(flat_queue_);
    auto physical_waiting = std::move(physical_queue_);
    flat_queue_ = {};
    physical_queue_ = {};
    begin_trial();
    ConversionReport trial;
    split_across_strips(e, trial, false, t);
    const bool refused = trial.splits == 0;  // skipped: every point fell on a vertex
    for (long long flips = 0; !refused && trial.splits < kTrialSplits && trial.splits < at_most && flips < kTrialFlips;) {
        const int g = pop();
        if (g < 0 || mesh_.num_vertices() >= vertex_budget_) break;
        if (mesh_.is_removed_edge(g) || is_delaunay(g)) continue;
        if (heals_by_flip(g)) {
            flip(g);
            ++flips;
        } else {
            split_across_strips(g, trial, false);
        }
    }
    trial_splits_ += trial.splits;
    long long cost = refused ? std::numeric_limits<long long>::max() / 2 : trial.splits;
    auto still_to_split = [&](int g) {
        return !mesh_.is_removed_edge(g) && !is_delaunay(g) && !heals_by_flip(g);
    };
    for (int g = pop(); g >= 0; g = pop()) cost += still_to_split(g);  // entries may have healed
    rollback();
    flat_queue_ = std::move(flat_waiting);
    physical_queue_ = std::move(physical_waiting);
    return cost;
}

std::optional<double> Converter::strip_cut(const StripSide& side) const {
    const int c = side.shared, d = side.far, e = side.split_end, x = mesh_.num_vertices() - 1;
    if (is_flat(side.edge, flat_angle_) || is_delaunay(side.edge)) return std::nullopt;
    if (c < input_vertices_ && fan_apex_[c]) return std::nullopt;
    if (!corner_below(dist(e, d), dist(c, e), dist(c, d), kThinCornerTangent)) return std::nullopt;
    int beyond = mesh_.halfedge(side.edge);  // the side's face without x
    if (mesh_.opposite_vertex(beyond) == x) beyond = mesh_.twin(beyond);
    if (beyond < 0) return std::nullopt;
    const int w = mesh_.opposite_vertex(beyond);
    const double fraction = dist(c, x) / dist(c, e);
    Eigen::Vector3d exit;  // where the cut leaves the face beyond
    if (corner_below(dist(d, w), dist(c, d), dist(c, w), kThinCornerTangent))
        exit = P_[c] + fraction * (P_[w] - P_[c]);
    else if (corner_below(dist(c, w), dist(c, d), dist(d, w), kThinCornerTangent))
        exit = P_[d] + (1 - fraction) * (P_[w] - P_[d]);
    else
        return std::nullopt;
    const Hinge k = hinge(side.edge);
    const double l = dist(k.a, k.b);
    const double t = distance(P_[c] + fraction * (P_[d] - P_[c]), P_[k.a]);
    const Interval halves = away_from_ends(halves_interval(l, dist(k.a, x), dist(k.b, x), distance(P_[k.a], exit),
                                                           distance(P_[k.b], exit)),
                                           l, kNearEnd);
    if (!(t >= halves.lo && t <= halves.hi)) return std::nullopt;
    return t;
}

void Converter::split_together(ConversionReport& report) {
    struct Side {
        int h, from, to;
        bool from_b;
        int partner;  // the edge across whose point is the apex there, -1: none
    };
    struct Edge {
        int e;
        Hinge k;
        double l;
        Interval room;
        std::array<Side, 4> sides;
        int count = 0;
        bool left_out = true;  // until it has a partner
    };
    const int edges = mesh_.num_edges();
    auto needs_split = [&](int e) { return queued_[e] && !is_flat(e, flat_angle_); };
    std::vector<Edge> group;  // by increasing edge id
    for (int e = 0; e < edges; ++e) {
        if (!needs_split(e)) continue;
        // Alone in its faces, with no flat side, and not a needle (needles take shells).
        bool alone = true;
        for (const int h : {mesh_.halfedge(e), mesh_.twin(mesh_.halfedge(e))})
            if (h >= 0)
                for (const int side : {mesh_.edge(HalfedgeMesh::next(h)), mesh_.edge(HalfedgeMesh::prev(h))})
                    alone = alone && !needs_split(side) && !is_flat(side, flat_angle_);
        if (!alone || needle_end(input_edge_[e]) >= 0) continue;
        const Hinge k = hinge(e);
        Edge& edge = group.emplace_back();
        edge.e = e, edge.k = k, edge.l = dist(k.a, k.b);
        edge.room = away_from_ends(delaunay_halves_interval(k, edge.l), edge.l, kEndClearance);
    }
    for (Edge& edge : group) {  // an edge without partners gains nothing here
        const OuterHalfedges outer = outer_halfedges(edge.k);
        for (int i = 0; i < outer.count; ++i) {
            const bool from_b = i % 2 == 1;
            Side side{outer.h[i], from_b ? edge.k.b : edge.k.a, from_b ? edge.k.a : edge.k.b, from_b, -1};
            if (const int across = mesh_.twin(side.h); across >= 0)
                for (const int g : {HalfedgeMesh::next(across), HalfedgeMesh::prev(across)})
                    if (const auto it = std::lower_bound(group.begin(), group.end(), mesh_.edge(g),
                                                         [](const Edge& x, int e) { return x.e < e; });
                        it != group.end() && it->e == mesh_.edge(g))
                        side.partner = static_cast<int>(it - group.begin());
            edge.sides[edge.count++] = side;
            edge.left_out = edge.left_out && side.partner < 0;
        }
    }
    auto point_at = [&](const Edge& edge, double t) -> Eigen::Vector3d {
        return P_[edge.k.a] + (t / edge.l) * (P_[edge.k.b] - P_[edge.k.a]);
    };
    // Narrows edge's room by each side; true if it changed.
    auto narrow = [&](Edge& edge) {
        Interval room = edge.room;
        for (int i = 0; i < edge.count && room.lo <= room.hi; ++i) {
            const Side& side = edge.sides[i];
            Interval keeps;
            if (side.partner < 0 || group[side.partner].left_out) {
                keeps = outer_side_interval(side.h, side.from, side.to, edge.l, side.from_b);
            } else {
                // The partner's point that sees the side under the narrowest angle.
                const Edge& partner = group[side.partner];
                const Eigen::Vector3d u = P_[mesh_.tail(side.h)], w = P_[mesh_.head(side.h)];
                auto cosine = [&](const Eigen::Vector3d& y) {
                    return (u - y).normalized().dot((w - y).normalized());
                };
                const Eigen::Vector3d lo = point_at(partner, partner.room.lo);
                const Eigen::Vector3d hi = point_at(partner, partner.room.hi);
                const Across future{mesh_.edge(side.h), cosine(lo) >= cosine(hi) ? lo : hi};
                keeps = outer_side_interval(side.h, side.from, side.to, edge.l, side.from_b, &future);
            }
            room = {std::max(room.lo, keeps.lo), std::min(room.hi, keeps.hi)};
        }
        const bool changed = room.lo != edge.room.lo || room.hi != edge.room.hi;
        edge.room = room;
        edge.left_out = !(room.lo <= room.hi);
        return changed;
    };
    std::deque<int> work;
    std::vector<char> waiting(group.size(), 0);
    auto wake_partners = [&](const Edge& edge) {
        for (int i = 0; i < edge.count; ++i)
            if (const int p = edge.sides[i].partner; p >= 0 && !group[p].left_out && !waiting[p])
                waiting[p] = 1, work.push_back(p);
    };
    auto settle = [&] {
        while (!work.empty()) {
            const int i = work.front();
            work.pop_front();
            waiting[i] = 0;
            if (!group[i].left_out && narrow(group[i])) wake_partners(group[i]);
        }
    };
    for (size_t i = 0; i < group.size(); ++i) waiting[i] = 1, work.push_back(static_cast<int>(i));
    settle();
    std::vector<double> position(group.size(), -1);
    for (size_t i = 0; i < group.size(); ++i) {
        Edge& edge = group[i];
        if (edge.left_out) continue;
        // Off the interval's ends, which are co-circular with a side's apexes.
        const double inset = 1e-3 * (edge.room.hi - edge.room.lo);
        const Interval inside{edge.room.lo + inset, edge.room.hi - inset};
        const double t = sparing_neighbours(edge.k, edge.l, inside, input_edge_[edge.e]);
        position[i] = std::clamp(t, inside.lo, inside.hi);
        edge.room = {position[i], position[i]};
        wake_partners(edge);
        settle();
    }
    for (size_t i = 0; i < group.size() && mesh_.num_vertices() < vertex_budget_; ++i) {
        if (group[i].left_out) continue;
        const bool same_way = hinge(group[i].e).a == group[i].k.a;
        if (split(group[i].e, same_way ? position[i] : group[i].l - position[i]))
            ++report.splits;
        else
            ++report.skipped_splits;
    }
}

}  // namespace sdmesh::conversion
