// Local search's relocation: a point among folds taken out while the points around it move until
// every piece is locally Delaunay again (min-conflicts on the split model).
#include "convert/converter.hpp"

#include <cstdint>
#include <optional>
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

}  // namespace

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
    // f's other edges (but `leaving_out`'s).
    std::vector<Eigen::Vector3d> apexes;
    auto gather = [&](int f, int g, std::vector<Eigen::Vector3d>& out, int leaving_out = -1) {
        out.clear();
        for (int k = 0; k < 3; ++k) {
            const int side = input_edges_.face_edge(f, k);
            if (side == g)
                out.push_back(P_[input_.F(f, k)]);
            else if (side != leaving_out)
                for (const double t : at[side]) out.push_back(position(side, t));
        }
    };
    // The ends of g's pieces, along g.
    auto piece_ends = [&](int g, std::vector<Eigen::Vector3d>& out) {
        out.assign(1, P_[input_edges_.E(g, 0)]);
        for (const double t : at[g]) out.push_back(position(g, t));
        out.push_back(P_[input_edges_.E(g, 1)]);
    };
    // The apex cotangents of g's pieces, along g, among `seen_from` (null: a boundary edge's
    // missing face, whose apex counts as a right angle).
    std::vector<Eigen::Vector3d> ends;
    auto piece_cotangents = [&](int g, const std::vector<Eigen::Vector3d>* seen_from, std::vector<double>& out) {
        piece_ends(g, ends);
        out.clear();
        for (size_t i = 0; i + 1 < ends.size(); ++i)
            out.push_back(seen_from ? apex_cotangent(*seen_from, ends[i], ends[i + 1]) : 0.0);
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
    std::vector<std::vector<double>> away, toward_g;
    std::vector<std::vector<Eigen::Vector3d>> ends_of;
    std::vector<Eigen::Vector3d> points_of_g;
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
                // What moving g's points leaves as it is: the apexes of g's pieces; the other
                // edges' pieces, their apex cotangents in their faces away from g, and those in
                // their faces toward g among the points off g.
                for (int side = 0; side < 2; ++side)
                    if (const int f = input_face(g, side); f >= 0) gather(f, g, apexes_of_g[side]);
                away.resize(affected.size());
                toward_g.resize(affected.size());
                ends_of.resize(affected.size());
                away_side.resize(affected.size());
                for (size_t k = 1; k < affected.size(); ++k) {
                    const int h = affected[k], f = input_face(h, 0);
                    away_side[k] = f >= 0 && (f == input_face(g, 0) || f == input_face(g, 1)) ? 1 : 0;
                    cotangents_in(h, away_side[k], away[k]);
                    gather(input_face(h, 1 - away_side[k]), h, apexes, g);
                    piece_cotangents(h, &apexes, toward_g[k]);
                    piece_ends(h, ends_of[k]);
                }
                auto excess_after_move = [&] {
                    double total = 0;
                    if (counts(g)) {
                        for (int side = 0; side < 2; ++side)
                            piece_cotangents(g, input_face(g, side) >= 0 ? &apexes_of_g[side] : nullptr,
                                             cotangents[side]);
                        total += excess_of(cotangents[0], cotangents[1]);
                    }
                    points_of_g.clear();
                    for (const double t : at[g]) points_of_g.push_back(position(g, t));
                    for (size_t k = 1; k < affected.size(); ++k) {
                        if (!counts(affected[k])) continue;
                        const int toward = 1 - away_side[k];
                        std::vector<double>& seen = cotangents[toward];
                        seen = toward_g[k];
                        for (size_t piece = 0; piece < seen.size(); ++piece)
                            seen[piece] = std::min(seen[piece], apex_cotangent(points_of_g, ends_of[k][piece],
                                                                               ends_of[k][piece + 1]));
                        total += toward == 0 ? excess_of(seen, away[k]) : excess_of(away[k], seen);
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
