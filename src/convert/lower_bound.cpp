// ConversionReport::added_vertices_lower_bound.
#include "convert/converter.hpp"

namespace sdmesh::conversion {

long long Converter::added_vertices_lower_bound() const {
    const int edges = mesh_.num_edges();
    std::vector<std::uint16_t> requirements(static_cast<size_t>(edges), 0);
#pragma omp parallel for schedule(static)
    for (int e = 0; e < edges; ++e)
        if (!input_flat_[e]) requirements[e] = side_requirements(e);
    std::vector<char> gets_point(static_cast<size_t>(edges), 0);
    std::vector<int> reached;
    for (int e = 0; e < edges; ++e)
        if (needs_point_[e]) gets_point[e] = 1, reached.push_back(e);
    long long bound = static_cast<long long>(reached.size());
    while (!reached.empty()) {
        const int e = reached.back();
        reached.pop_back();
        const OuterHalfedges sides = outer_halfedges(hinge(e));
        for (int i = 0; i < sides.count; ++i)
            if (const int side = mesh_.edge(sides.h[i]); (requirements[e] >> i & 1u) && !gets_point[side])
                gets_point[side] = 1, reached.push_back(side), ++bound;
    }
    std::vector<char> matched(static_cast<size_t>(edges), 0);
    for (int e = 0; e < edges; ++e) {
        if (!gets_point[e] || requirements[e] < 16) continue;
        const OuterHalfedges sides = outer_halfedges(hinge(e));
        for (int i = 0, pair = 4; i < sides.count; ++i)
            for (int j = i + 1; j < sides.count; ++j, ++pair) {
                const int u = mesh_.edge(sides.h[i]), w = mesh_.edge(sides.h[j]);
                if ((requirements[e] >> pair & 1u) && !gets_point[u] && !gets_point[w] && !matched[u] &&
                    !matched[w])
                    matched[u] = matched[w] = 1, ++bound;
            }
    }
    return bound;
}

std::uint16_t Converter::side_requirements(int e) const {
    const Hinge k = hinge(e);
    const double l = dist(k.a, k.b);
    const bool free_boundary = k.s < 0 && options_.boundary == BoundaryPolicy::free;
    const Interval halves = free_boundary ? Interval{0, l} : delaunay_halves_interval(k, l);
    const OuterSides sides = outer_sides(k, l);
    const double broken = -options_.tolerance - kBoundRounding;
    auto point = [&](double t) -> Eigen::Vector3d { return P_[k.a] + (t / l) * (P_[k.b] - P_[k.a]); };
    // Whether side i (0 a-r, 1 b-r, 2 a-s, 3 b-s) is broken by the point at distance t from a.
    auto breaks_side = [&](int i, double t) {
        const Eigen::Vector3d x = point(t);
        const int end = i % 2 == 0 ? k.a : k.b, apex = i < 2 ? k.r : k.s;
        const double length = dist(end, apex), end_x = distance(P_[end], x), apex_x = distance(P_[apex], x);
        const int across = mesh_.twin(sides.halfedge[i]);
        if (across < 0) return boundary_margin(length, end_x, apex_x) < broken;  // strict: free keeps all
        const int w = mesh_.opposite_vertex(across);
        return delaunay_margin(length, end_x, apex_x, dist(end, w), dist(apex, w)) < broken;
    };
    // Whether the piece from a (or b) to the point at distance t from a is broken.
    auto breaks_half = [&](bool from_a, double t) {
        if (free_boundary) return false;
        const Eigen::Vector3d x = point(t);
        const int end = from_a ? k.a : k.b;
        const double piece = from_a ? t : l - t, end_r = dist(end, k.r), x_r = distance(P_[k.r], x);
        if (k.s < 0) return boundary_margin(piece, end_r, x_r) < broken;
        return delaunay_margin(piece, end_r, x_r, dist(end, k.s), distance(P_[k.s], x)) < broken;
    };
    unsigned found = 0;
    for (int i = 0; i < sides.count; ++i) {
        if (!(sides.physical >> i & 1u)) continue;
        const Interval keeps = sides.keeps[i];  // [D, l] for a side at a, [0, l - D] at b
        // The first point lies within I0's bound from a, the last within the one from b.
        bool implied;
        if (i % 2 == 0) {
            const double t = std::min(0.5 * (halves.hi + keeps.lo), l);
            implied = keeps.lo > halves.hi && breaks_side(i, t) && (t >= l || breaks_half(true, t));
        } else {
            const double t = std::max(0.5 * (keeps.hi + halves.lo), 0.0);
            implied = keeps.hi < halves.lo && breaks_side(i, t) && (t <= 0 || breaks_half(false, t));
        }
        if (implied) found |= 1u << i;
    }
    for (int i = 0, pair = 4; i < sides.count; ++i)
        for (int j = i + 1; j < sides.count; ++j, ++pair) {
            // Sides at the same end both keep the far end: only opposite ends exclude each other.
            if (!(sides.physical >> i & sides.physical >> j & 1u) || (found >> i | found >> j) & 1u ||
                i % 2 == j % 2)
                continue;
            const int at_a = i % 2 == 0 ? i : j, at_b = i % 2 == 0 ? j : i;
            if (!(sides.keeps[at_a].lo > sides.keeps[at_b].hi)) continue;
            const double t = std::clamp(0.5 * (sides.keeps[at_a].lo + sides.keeps[at_b].hi), 0.0, l);
            if (breaks_side(at_a, t) && breaks_side(at_b, t)) found |= 1u << pair;
        }
    return static_cast<std::uint16_t>(found);
}

}  // namespace sdmesh::conversion
