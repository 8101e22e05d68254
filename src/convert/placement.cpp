// Where a split point goes on its edge: the interval rule (ALGORITHMS.md §3) with the look-ahead
// of least_cascading, and the shells around input vertices.
#include "convert/converter.hpp"

namespace sdmesh::conversion {

double Converter::split_distance(const Hinge& k, double l, std::vector<double>* alternatives) const {
    if (alternatives) alternatives->clear();
    const int on_input_edge = input_edge_[mesh_.edge(k.h)];
    // The needles of a fan (a cone's, say) meet at their apex at tiny angles, and their other
    // ends lie anywhere: split points at the same distances from the apex, ignoring I0, make
    // rings that close. Interval points (or shells from either end) left rings out of step
    // that marched along the needles: a 90-needle cone took 51,328 vertices, 180 needles
    // more than the vertex budget; now 4,150 and 14,043. An end with at most kMaxStripCorners
    // thin corners is no fan's apex but a corner of a strip (in a band cut zigzag, each long
    // edge has the thin corners of both its faces at one end): there the interval rule and
    // the feet across planes keep the strip's rings in step, where shells took up to 12,600
    // vertices around a noisy zigzag drum (ConvertMethods.ANoisyZigzagDrumTakesRingsOfPoints),
    // and fewer points on the corpus (cheese 10.74 -> 10.52, skull 1.532 -> 1.526).
    const int input_end = (k.a < input_vertices_) == (k.b < input_vertices_) ? -1 : k.a < input_vertices_ ? k.a : k.b;
    const bool converging =
        input_end >= 0 && on_input_edge >= 0 && l < kConvergingPieceFraction * input_length_[on_input_edge];
    // A needle's points converging on its other end (far shorter than any input edge there)
    // take the shells around that end: the apex's left them out of step with the rings there
    // (the petals' tips of Scopia's tulips and its switch plate's rim: cascades to 1e-15 of
    // their needles). Far from the apex but not from that end, they keep the apex's shells,
    // which keep the fan's rings in step (a spike 2e8 long: 1,332 vertices, 3,014 with the
    // shells around every end).
    int needle_apex = on_input_edge >= 0 ? needle_end(on_input_edge) : -1;
    if (needle_apex >= 0 && input_end >= 0 && l < kConvergingPieceFraction * shortest_edge_[input_end])
        needle_apex = input_end;
    if (options_.split_rule == SplitRule::shell)
        return needle_apex >= 0 ? shell_distance_around(needle_apex, k, l) : shell_distance(k, l);
    if (needle_apex >= 0 && fan_apex_[needle_apex])
        return shell_distance_around(needle_apex, k, l);
    // Short pieces that end at a fan's apex follow the shells, unless an interval point keeps
    // every physical outer side locally Delaunay: input edges meeting there at small angles
    // would otherwise split each other ever finer. Longer ones take the interval rule, which
    // adds fewer vertices (a quarter of the input edge: measured on the corpus, shorter
    // thresholds gain nothing more), and so do short ones at other input vertices, as at a
    // strip's corners (shells at every input vertex: cheese 10.36 -> 10.52).
    const bool near_input_vertex =
        input_end >= 0 && (on_input_edge < 0 || l < kShellPieceFraction * input_length_[on_input_edge]);
    // Interval points can march towards an input vertex for ever, each out of step with the
    // last on the next edge (a pleated fan of 64 slightly noisy spokes, 5.6° apart: 55,336
    // vertices, the points 1e-15 from the apex); shells there close the rings.
    if (converging) return shell_distance(k, l);
    // Hard constraint: I0, where both halves are locally Delaunay.
    const Interval halves = delaunay_halves_interval(k, l);
    auto away_from_ends = [&](double clearance) { return Converter::away_from_ends(halves, l, clearance); };
    const OuterSides sides = outer_sides(k, l);
    const SideChoice best = sides.most_weight(away_from_ends(kEndClearance));
    if (best.weight < sides.total_weight) {
        // A point near an end can keep every physical side where the piece's middle cannot:
        // the two sides at that end see it under about π minus the faces' corners there
        // (wide ones can bear that), the far sides much as they saw the end. It then costs no
        // vertex beyond itself: cheese 19.3 -> 14.7 vertices added per non-Delaunay edge,
        // no corpus mesh more.
        const SideChoice near_end = sides.most_weight(away_from_ends(kNearEnd));
        if (near_end.keeps_physical && near_end.weight > best.weight)
            return 0.5 * (near_end.range.lo + near_end.range.hi);
    }
    if (near_input_vertex && !best.keeps_physical && fan_apex_[input_end])
        return shell_distance(k, l);
    if (best.weight < 0) return 0.5 * l;
    if (const std::optional<double> foot = foot_across_plane(k, l, sides, on_input_edge)) return *foot;
    if (!best.keeps_physical)
        return least_cascading(k, l, sides, away_from_ends(kEndClearance), on_input_edge, alternatives);
    return sparing_neighbours(k, l, best.range, on_input_edge);
}

double Converter::least_cascading(const Hinge& k, double l, const OuterSides& sides, Interval within, int on_input_edge,
                       std::vector<double>* alternatives) const {
    // The candidates, in order, without repeats: up to 16 choices of the 4 sides.
    constexpr int kMost = 16 * (1 + kCascadeDyadics);
    std::array<double, kMost> positions;
    int candidates = 0;
    auto candidate = [&](double t) {
        if (std::find(positions.begin(), positions.begin() + candidates, t) == positions.begin() + candidates)
            positions[candidates++] = t;
    };
    sides.for_each_choice(within, [&](Interval range, unsigned) { candidate(usual_position(k, l, range, on_input_edge)); });
    if (on_input_edge >= 0)
        sides.for_each_choice(within, [&](Interval range, unsigned) {
            for_each_dyadic(k, on_input_edge, range, kCascadeDyadics, candidate);
        });
    std::array<int, kMost> kept;  // by candidate: the weight of the sides it keeps
    int best = -1, best_score = std::numeric_limits<int>::min();
    const CleanNeighbours neighbours = clean_neighbours(k);
    const unsigned shared = sides_broken_anyway(sides);
    for (int c = 0; c < candidates; ++c) {
        const double t = positions[c];
        int score = 0;
        unsigned broken = 0;  // physical sides
        for (int i = 0; i < sides.count; ++i) {
            if ((t >= sides.keeps[i].lo && t <= sides.keeps[i].hi) || (shared >> i & 1u))
                score += sides.weight[i];
            else if (sides.physical >> i & 1u)
                broken |= 1u << i;
        }
        kept[c] = score;
        for (int i = 0; i < sides.count && score > best_score; ++i)
            if ((broken >> i & 1u) && !side_splits_cleanly(k, l, t, i, sides.halfedge[i])) --score;
        if (score > best_score) score -= spoiled(k, l, t, neighbours);
        if (score > best_score) best_score = score, best = c;
    }
    if (best < 0) return 0.5 * l;
    if (alternatives) {
        // The winner, then the others by the weight they keep (ranking them by their
        // complete scores instead costs their look-ahead and measured alike).
        std::array<int, kMost> order;
        std::iota(order.begin(), order.begin() + candidates, 0);
        std::stable_sort(order.begin(), order.begin() + candidates, [&](int x, int y) { return kept[x] > kept[y]; });
        alternatives->push_back(positions[best]);
        for (int i = 0; i < candidates && static_cast<int>(alternatives->size()) < options_.cascade_trials; ++i)
            if (order[i] != best) alternatives->push_back(positions[order[i]]);
    }
    return positions[best];
}

unsigned Converter::sides_broken_anyway(const OuterSides& sides) const {
    unsigned found = 0;
    for (int i = 0; i < sides.count; ++i) {
        const int across = mesh_.twin(sides.halfedge[i]);
        if (!(sides.physical >> i & 1u) || across < 0) continue;
        for (const int g : {HalfedgeMesh::next(across), HalfedgeMesh::prev(across)}) {
            const int e = mesh_.edge(g);
            if (queued_[e] && !is_flat(e, flat_angle_) && !is_delaunay(e) && !splits_cleanly(e)) found |= 1u << i;
        }
    }
    return found;
}

bool Converter::side_splits_cleanly(const Hinge& k, double l, double t, int i, int side) const {
    const Eigen::Vector3d x = P_[k.a] + (t / l) * (P_[k.b] - P_[k.a]);
    auto to_x = [&](int u) { return distance(x, P_[u]); };
    // The side's hinge after the split: end-apex with x on one side and w across.
    const int end = i % 2 == 0 ? k.a : k.b, apex = i < 2 ? k.r : k.s;
    const int far_apex = i < 2 ? k.s : k.r, far_end = end == k.a ? k.b : k.a;
    const double length = dist(end, apex), end_x = to_x(end), apex_x = to_x(apex);
    OuterSides sides;
    // The half end-x of the split edge, and the spoke apex-x inside the face.
    sides.add(far_apex < 0 ? side_interval(length, end_x, apex_x, -1, -1, false)
                           : side_interval(length, end_x, apex_x, dist(end, far_apex), to_x(far_apex), false),
              is_flat(mesh_.edge(k.h), flat_angle_), -1);
    sides.add(side_interval(length, apex_x, end_x, dist(apex, far_end), to_x(far_end), true), true, -1);
    const int across = mesh_.twin(side);
    Interval halves = halves_interval(length, end_x, apex_x, -1, -1);
    if (across >= 0) {
        const int w = mesh_.opposite_vertex(across);
        halves = halves_interval(length, end_x, apex_x, dist(end, w), dist(apex, w));
        for (const int g : {HalfedgeMesh::next(across), HalfedgeMesh::prev(across)}) {
            const bool at_end = mesh_.tail(g) == end || mesh_.head(g) == end;
            const int from = at_end ? end : apex, to = at_end ? apex : end;
            const int beyond = mesh_.twin(g) < 0 ? -1 : mesh_.opposite_vertex(mesh_.twin(g));
            sides.add(beyond < 0 ? side_interval(length, dist(from, w), dist(to, w), -1, -1, !at_end)
                                 : side_interval(length, dist(from, w), dist(to, w), dist(from, beyond),
                                                 dist(w, beyond), !at_end),
                      is_flat(mesh_.edge(g), flat_angle_), g);
        }
    }
    return has_clean_position(sides, halves, length);
}

Converter::CleanNeighbours Converter::clean_neighbours(const Hinge& k) const {
    CleanNeighbours found;
    for (const int h : {k.h, mesh_.twin(k.h)}) {
        if (h < 0) continue;
        for (const int side : {HalfedgeMesh::next(h), HalfedgeMesh::prev(h)}) {
            const int across = mesh_.twin(side);
            if (across < 0) continue;
            for (const int g : {HalfedgeMesh::next(across), HalfedgeMesh::prev(across)}) {
                const int e = mesh_.edge(g);
                if (queued_[e] && !is_flat(e, flat_angle_) && !is_delaunay(e) &&
                    !is_flat(mesh_.edge(side), flat_angle_) && splits_cleanly(e))
                    found.pending[found.count++] = {mesh_.edge(side), e};
            }
        }
    }
    return found;
}

int Converter::spoiled(const Hinge& k, double l, double t, const CleanNeighbours& neighbours) const {
    const Eigen::Vector3d x = P_[k.a] + (t / l) * (P_[k.b] - P_[k.a]);
    int count = 0;
    for (int i = 0; i < neighbours.count; ++i) {
        const Across future{neighbours.pending[i].first, x};
        count += !splits_cleanly(neighbours.pending[i].second, &future);
    }
    return count;
}

double Converter::sparing_neighbours(const Hinge& k, double l, Interval range, int on_input_edge) const {
    double chosen = usual_position(k, l, range, on_input_edge);
    const CleanNeighbours neighbours = clean_neighbours(k);
    if (neighbours.count == 0) return chosen;
    int fewest = spoiled(k, l, chosen, neighbours);
    if (fewest > 0 && on_input_edge >= 0)
        for_each_dyadic(k, on_input_edge, range, kCascadeDyadics, [&](double t) {
            if (fewest == 0) return;
            if (const int count = spoiled(k, l, t, neighbours); count < fewest) fewest = count, chosen = t;
        });
    return chosen;
}

double Converter::usual_position(const Hinge& k, double l, Interval range, int on_input_edge) const {
    const double ar = dist(k.a, k.r), br = dist(k.b, k.r);
    const int apex = k.s >= 0 && dist(k.a, k.s) + dist(k.b, k.s) < ar + br ? k.s : k.r;
    const double foot = (P_[apex] - P_[k.a]).dot(P_[k.b] - P_[k.a]) / l;
    if (foot >= range.lo && foot <= range.hi) return foot;
    double dyadic = -1;
    if (on_input_edge >= 0) for_each_dyadic(k, on_input_edge, range, 1, [&](double t) { dyadic = t; });
    return dyadic >= 0 ? dyadic : 0.5 * (range.lo + range.hi);
}

std::optional<double> Converter::foot_across_plane(const Hinge& k, double l, const OuterSides& sides,
                                                   int on_input_edge) const {
    if (on_input_edge < 0) return std::nullopt;
    for (const int y : {k.r, k.s}) {
        if (y < input_vertices_ || !lies_across_plane(y, on_input_edge)) continue;
        const double foot = (P_[y] - P_[k.a]).dot(P_[k.b] - P_[k.a]) / l;
        if (!(foot >= kNearEnd * l && foot <= (1 - kNearEnd) * l)) continue;
        // Judged by angles, not by I0 less its inset: the foot can lie 4e-5 of the piece from
        // I0's end with a margin of 0.5° in the halves' angles.
        const Eigen::Vector3d x = P_[k.a] + (foot / l) * (P_[k.b] - P_[k.a]);
        if (!halves_keep_margin(P_[k.a], P_[k.b], x, P_[k.r], k.s >= 0 ? &P_[k.s] : nullptr)) continue;
        bool carried = true;  // every physical side the foot breaks is cut on as a strip
        const unsigned broken = sides.physical_broken_at(foot);
        for (int i = 0; i < sides.count && carried; ++i) {
            if (!(broken >> i & 1u)) continue;
            const int end = i % 2 == 0 ? k.a : k.b, other = end == k.a ? k.b : k.a, apex = i < 2 ? k.r : k.s;
            carried = corner_below(dist(other, apex), dist(end, other), dist(end, apex), kThinCornerTangent);
        }
        if (carried) return foot;
    }
    return std::nullopt;
}

bool Converter::lies_across_plane(int y, int e) const {
    const int y_edge = vertex_input_edge_[y - input_vertices_];
    if (y_edge < 0) return false;
    for (int side = 0; side < 2; ++side)
        if (const int f = input_face(e, side); f >= 0)
            for (int j = 0; j < 3; ++j)
                if (input_edges_.face_edge(f, j) == y_edge) return false;
    return true;
}

Converter::OuterSides Converter::outer_sides(const Hinge& k, double l, const Across* future) const {
    OuterSides sides;
    const OuterHalfedges outer = outer_halfedges(k);
    for (int i = 0; i < outer.count; ++i) {
        const int side = outer.h[i];
        const bool from_b = i % 2 == 1;
        sides.add(outer_side_interval(side, from_b ? k.b : k.a, from_b ? k.a : k.b, l, from_b, future),
                  is_flat(mesh_.edge(side), flat_angle_), side);
    }
    return sides;
}

Converter::OuterHalfedges Converter::outer_halfedges(const Hinge& k) const {
    OuterHalfedges outer;
    for (const int h : {k.h, mesh_.twin(k.h)}) {
        if (h < 0) continue;
        outer.h[outer.count++] = h == k.h ? HalfedgeMesh::prev(h) : HalfedgeMesh::next(h);  // side a-apex
        outer.h[outer.count++] = h == k.h ? HalfedgeMesh::next(h) : HalfedgeMesh::prev(h);  // side b-apex
    }
    return outer;
}

Converter::Interval Converter::delaunay_halves_interval(const Hinge& k, double l) const {
    return k.s < 0 ? halves_interval(l, dist(k.a, k.r), dist(k.b, k.r), -1, -1)
                   : halves_interval(l, dist(k.a, k.r), dist(k.b, k.r), dist(k.a, k.s), dist(k.b, k.s));
}

Converter::Interval Converter::halves_interval(double l, double ar, double br, double as, double bs) {
    // ALGORITHMS.md §3's bounds without an angle: each face gives 4·area = 2·l·side·sine and
    // cosine numerators 2·l·side·cosine at a and b, and the factors of 2·l·side cancel.
    const double area_r = 4.0 * triangle_area(l, ar, br);
    const double cos_ar = cosine_numerator(br, l, ar), cos_br = cosine_numerator(ar, l, br);
    Interval range{0, l};
    if (as < 0) {  // |ax| ≤ |ar| / cos θ_a
        if (cos_ar > 0) range.hi = std::min(range.hi, 2 * l * ar * ar / cos_ar);
        if (cos_br > 0) range.lo = std::max(range.lo, l - 2 * l * br * br / cos_br);
        return range;
    }
    const double area_s = 4.0 * triangle_area(l, as, bs);
    const double cos_as = cosine_numerator(bs, l, as), cos_bs = cosine_numerator(as, l, bs);
    // Second intersection of the circle through a (b), r, s with the edge line:
    // (|ar|·sin φ_a + |as|·sin θ_a) / sin(θ_a + φ_a), where θ_a + φ_a < π.
    if (const double sine_a = area_r * cos_as + cos_ar * area_s; sine_a > 0)
        range.hi = std::min(range.hi, 2 * l * (ar * ar * area_s + as * as * area_r) / sine_a);
    if (const double sine_b = area_r * cos_bs + cos_br * area_s; sine_b > 0)
        range.lo = std::max(range.lo, l - 2 * l * (br * br * area_s + bs * bs * area_r) / sine_b);
    return range;
}

Converter::Interval Converter::outer_side_interval(int side, int from, int to, double l, bool from_b,
                             const Across* future) const {
    const int apex = mesh_.tail(side) == from ? mesh_.head(side) : mesh_.tail(side);
    const int across = mesh_.twin(side);
    if (across < 0) return side_interval(l, dist(from, apex), dist(to, apex), -1, -1, from_b);
    if (future && future->edge == mesh_.edge(side))
        return side_interval(l, dist(from, apex), dist(to, apex), distance(P_[from], future->point),
                             distance(P_[apex], future->point), from_b);
    const int w = mesh_.opposite_vertex(across);
    return side_interval(l, dist(from, apex), dist(to, apex), dist(from, w), dist(apex, w), from_b);
}

Converter::Interval Converter::side_interval(double l, double d_apex, double d_to_apex, double d_w, double d_apex_w,
                                             bool from_b) const {
    // With A the corner at `from` between `to` and apex: 2·l·d_apex·cos A.
    const double cos_from = cosine_numerator(d_to_apex, l, d_apex);
    double reach = 0;  // D
    if (d_w < 0) {
        if (options_.boundary == BoundaryPolicy::free) return {0, l};
        reach = cos_from / (2 * l);  // d_apex·cos A
    } else {
        // The circle through from, apex and w (unfolded) meets the edge line at
        // d_apex·sin(W - A) / sin W = d_apex·(cos A - sin A·cot W), W the corner at w.
        const double area_w = 4.0 * triangle_area(d_apex, d_w, d_apex_w);
        if (area_w <= 1e-14 * d_apex * d_w) return {0, l};  // circle degenerates to a line
        const double area_from = 4.0 * triangle_area(d_to_apex, l, d_apex);
        reach = (cos_from - area_from * cosine_numerator(d_apex, d_w, d_apex_w) / area_w) / (2 * l);
    }
    if (!(reach > 0)) return {0, l};
    return from_b ? Interval{0, l - reach} : Interval{reach, l};
}

double Converter::shell_distance_around(int c, const Hinge& k, double l) const {
    const double from_a = dist(c, k.a), from_b = dist(c, k.b);
    const double lo = std::min(from_a, from_b) + l / 3, hi = lo + l / 3;
    for (double step = shell_unit_ * std::exp2(std::floor(std::log2(hi / shell_unit_))); step >= shell_unit_;
         step *= 0.5) {
        const double d = std::ceil(lo / step) * step;
        if (d <= hi) return std::abs(d - from_a);
    }
    return 0.5 * l;
}

int Converter::needle_end(int e) const {
    const int a = input_edges_.E(e, 0), b = input_edges_.E(e, 1);
    const double l = input_length_[e];
    static const double tangent = std::tan(kNeedleCorner);
    bool at_a = false, at_b = false;
    for (const int side : {input_edges_.edge_halfedges(e, 0), input_edges_.edge_halfedges(e, 1)}) {
        if (side < 0) continue;
        const int r = input_.F(side / 3, side % 3);  // halfedge 3f + k lies opposite corner k
        const double ar = dist(a, r), br = dist(b, r);
        at_a = at_a || corner_below(br, l, ar, tangent);
        at_b = at_b || corner_below(ar, l, br, tangent);
    }
    if (at_a == at_b) return -1;
    return at_a ? a : b;
}

double Converter::shell_distance(const Hinge& k, double l) const {
    const bool a_input = k.a < input_vertices_, b_input = k.b < input_vertices_;
    if (a_input == b_input) return 0.5 * l;
    return shell_distance_around(a_input ? k.a : k.b, k, l);
}

double Converter::queue_key(int e) const {
    if (is_flat(e, flat_angle_)) return -1;
    const Hinge k = hinge(e);
    const double l = dist(k.a, k.b);
    const Interval halves = delaunay_halves_interval(k, l);
    // 0 for an empty I0, and for degenerate hinges (NaN bounds): keys must stay ordered.
    const double room = halves.hi > halves.lo ? std::min((halves.hi - halves.lo) / l, 1.0) : 0.0;
    const bool clean = outer_sides(k, l).most_weight(away_from_ends(halves, l, kEndClearance)).keeps_physical;
    return l * (1 + kLittleRoomFirst * (1 - room) + (clean ? kCleanFirst : 0));
}

}  // namespace sdmesh::conversion
