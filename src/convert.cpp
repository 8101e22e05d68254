#include "sdmesh/convert.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <limits>
#include <numeric>
#include <numbers>
#include <optional>
#include <queue>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "halfedge.hpp"
#include "union_find.hpp"
#include "sdmesh/distance.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;
// Pieces of an input edge shorter than this fraction of it, with one end at an input vertex, are
// split on Ruppert's shells (see split_distance).
constexpr double kShellPieceFraction = 0.25;
// Split points next to a plane with more points than this are not removed (quadratic work).
constexpr int kMaxPlanePoints = 2048;
// Interval points stay this fraction of the piece away from its ends, so that piece lengths
// stay bounded below, unless a point closer to an end keeps every physical outer side locally
// Delaunay; then kNearEnd (0.1 % to 1 % measured alike).
constexpr double kEndClearance = 0.1, kNearEnd = 0.003;
// Split points at dyadic fractions of their input edge use at most this many bits (see
// split_distance; 3 to 20 bits measured, 4-6 best).
constexpr int kDyadicBits = 6;
// Where a split must break a physical side, this many dyadic positions of each range are tried
// besides the usual one (see least_cascading; 3, 8 and 20 measured: 8 about as good as 20).
constexpr int kCascadeDyadics = 8;
// A physical hinge's place in the queue is its length, made up to kLittleRoomFirst longer the
// less room its halves leave for the split point, and kCleanFirst longer if a split point can
// keep every physical outer side (measured: 0.35-0.45 best for the first, 0.1 and 0.25 0.1-0.7 %
// more vertices, 0.5 and more cheese 12.1 -> 14.4; 0.15-0.5 alike for the second).
constexpr double kLittleRoomFirst = 0.35, kCleanFirst = 0.3;
// A trial of a split position follows the cascade it starts for this many splits (8 and 40
// measured: about as good; 40 worse on couplingdown) and at most this many flips.
constexpr long long kTrialSplits = 16, kTrialFlips = 1000;
// No more trials are made once their splits outnumber the real ones this many times (plus an
// eighth of the input's vertices). The corpus meshes take 0.8-7 times; trials that each ran a
// ring of strip cuts around a cylinder took 19 times (2 cut koala's and elk's gains by half).
constexpr long long kTrialWork = 8;
// Local search places again at most this many split points at once: more (dense fans of
// needles) cost time that grows with them and rarely pay (16, 32 and unlimited measured alike).
constexpr size_t kLocalSearchPoints = 16;

// fewest_points_per_edge places points where the cotangent sums of the pieces they touch are
// at least this, so that rounding does not undo them: far from the origin (the skewed grid
// moved by 10^6) a margin of 1e-9 lost two thirds of the points it saves near it.
constexpr double kPlacementMargin = 1e-6;
// ... and sweeps the edges this many times, alternately placing from either end: moving a
// point without saving one can make room on the edges beside it.
constexpr int kFewestPointsPasses = 4;
// The lower bound takes an edge for broken only where its margin is below minus the
// locally-Delaunay tolerance by more than this (rounding of the margin, ~1e-15).
constexpr double kBoundRounding = 1e-12;
// An input edge with a face corner below this at one end (and none at the other) is a needle of
// a fan: all its split points follow shells around that end (see split_distance).
constexpr double kNeedleCorner = std::numbers::pi / 180;
// A face with a corner below this is a thin face of a strip, which a split carries its cut
// across (see split_across_strips; 5° measured best: 3° misses couplingdown's strips, 10°
// costs boot and koala 1-2 %), unless the corner's vertex has more such input corners than
// kMaxStripCorners: the apex of a fan, whose needles take shells.
constexpr double kThinCorner = 5 * std::numbers::pi / 180;
constexpr int kMaxStripCorners = 3;

// The hinge of an edge seen from halfedge h = (a -> b) with apex r, and its twin's apex s
// (s = -1 on the boundary).
struct Hinge {
    int h, a, b, r, s;
};

// The items 0..count-1 grouped by key(item) in [0, keys) (-1: left out), each group in
// increasing order (counting sort).
class Buckets {
public:
    template <class Key>
    Buckets(int keys, int count, Key key) : start_(static_cast<size_t>(keys) + 1, 0) {
        for (int i = 0; i < count; ++i)
            if (key(i) >= 0) ++start_[key(i) + 1];
        for (int k = 0; k < keys; ++k) start_[k + 1] += start_[k];
        items_.resize(static_cast<size_t>(start_[keys]));
        std::vector<int> next(start_.begin(), start_.end() - 1);
        for (int i = 0; i < count; ++i)
            if (key(i) >= 0) items_[next[key(i)]++] = i;
    }
    std::span<const int> operator[](int key) const {
        return {items_.data() + start_[key], static_cast<size_t>(start_[key + 1] - start_[key])};
    }

private:
    std::vector<int> start_, items_;
};

// Lawson-style conversion on a HalfedgeMesh with positions; one instance per convert() call.
class Converter {
public:
    // \pre `edges` is the edge table of the mesh, which is manifold.
    Converter(const TriangleMesh& mesh, const EdgeTable& edges, const ConvertOptions& options)
        : options_(options),
          input_(mesh),
          input_edges_(edges),
          mesh_(mesh.F, edges.face_edge, edges.edge_halfedges, mesh.num_vertices()),
          input_vertices_(mesh.num_vertices()),
          flat_angle_(flat_angle(options)),
          coplanar_angle_(options.coplanar_tolerance),
          tan_tolerance_(std::tan(options.tolerance)) {
        const double diagonal = bounding_box_diagonal(mesh);  // in the supported range (convert checks)
        // The work is done at the scale of a unit diagonal, by a power of two (exact both ways):
        // far from it, the products of lengths in the tests overflow or underflow (the bunny
        // scaled by 1e150 took every hinge for flat and split on to its vertex budget), and any
        // power-of-two scaling of the input gives the same output.
        scale_exponent_ = unit_exponent(diagonal);
        P_.resize(static_cast<size_t>(mesh.num_vertices()));
        for (int v = 0; v < mesh.num_vertices(); ++v)
            for (int i = 0; i < 3; ++i) P_[v][i] = std::ldexp(mesh.V(v, i), -scale_exponent_);
        shell_unit_ = std::exp2(std::floor(std::log2(std::ldexp(diagonal, -scale_exponent_))) - 40.0);
        input_edge_.resize(static_cast<size_t>(mesh_.num_edges()));
        for (int e = 0; e < mesh_.num_edges(); ++e) input_edge_[e] = e;
        in_plane_.assign(static_cast<size_t>(mesh_.num_edges()), 0);
        input_length_.resize(static_cast<size_t>(mesh_.num_edges()));
        input_flat_.resize(static_cast<size_t>(mesh_.num_edges()));
#pragma omp parallel for schedule(static)
        for (int e = 0; e < mesh_.num_edges(); ++e) {
            const int h = mesh_.halfedge(e);
            input_length_[e] = distance(P_[mesh_.tail(h)], P_[mesh_.head(h)]);
        }
        queued_.assign(static_cast<size_t>(mesh_.num_edges()), 0);
    }

    void run(ConversionReport& report) {
        // Each edge's tests read only its hinge, so they run in parallel; the queue is filled in
        // edge order. keys: NaN for a locally Delaunay edge, else as for enqueue().
        const int edges = mesh_.num_edges();
        std::vector<double> keys(static_cast<size_t>(edges));
        needs_point_.assign(static_cast<size_t>(edges), 0);
#pragma omp parallel for schedule(static)
        for (int e = 0; e < edges; ++e) {
            input_flat_[e] = is_flat(e, coplanar_angle_);
            keys[e] = is_delaunay(e) ? std::numeric_limits<double>::quiet_NaN() : queue_key(e);
        }
        for (int e = 0; e < edges; ++e) {
            if (std::isnan(keys[e])) continue;
            ++report.input_non_delaunay_edges;
            needs_point_[e] = !input_flat_[e];
            report.input_nonflat_non_delaunay_edges += needs_point_[e];
            enqueue(e, keys[e]);
        }
        if (options_.method == ConvertMethod::split && options_.lower_bound)
            report.added_vertices_lower_bound = added_vertices_lower_bound();
        vertex_budget_ = options_.max_vertices > 0 ? options_.max_vertices : 10LL * input_vertices_ + 100000;
        flip_budget_ = options_.max_flips > 0 ? options_.max_flips : 100LL * mesh_.num_edges() + 1'000'000;
        if (options_.method != ConvertMethod::flip) count_thin_corners();
        if (options_.method != ConvertMethod::flip && options_.split_rule == SplitRule::interval) split_together(report);
        drain(report);
        if (options_.method == ConvertMethod::split && report.status == ConvertStatus::certified &&
            report.vertices_inside_faces == 0) {
            remove_unneeded_points(report);
            // What the edges' new points changed may let other points go; elsewhere none can.
            if (const std::vector<char> respaced = fewest_points_per_edge(report); !respaced.empty())
                remove_unneeded_points(report, &respaced);
            if (options_.local_search > 0) {
                // What the search changed may let other points go; elsewhere none can.
                const std::vector<char> changed = local_search(report);
                remove_unneeded_points(report, &changed);
            }
        }
    }

    TriangleMesh result() const {
        // Input vertices keep their ids; points removed again leave no gap.
        std::vector<int> new_id(P_.size(), -1);
        int kept = 0;
        for (size_t v = 0; v < P_.size(); ++v)
            if (v < static_cast<size_t>(input_vertices_) || !removed_[v - input_vertices_]) new_id[v] = kept++;
        TriangleMesh out;
        out.V.resize(kept, 3);
        for (size_t v = 0; v < P_.size(); ++v)
            if (new_id[v] >= 0)
                for (int i = 0; i < 3; ++i) out.V(new_id[v], i) = std::ldexp(P_[v][i], scale_exponent_);
        out.F = mesh_.faces();
        for (int f = 0; f < out.F.rows(); ++f)
            for (int k = 0; k < 3; ++k) out.F(f, k) = new_id[out.F(f, k)];
        return out;
    }

private:
    // Pops until the queues are empty, a budget is reached, or the split that would make
    // report.splits exceed max_splits.
    void drain(ConversionReport& report, long long max_splits = std::numeric_limits<long long>::max()) {
        auto last_progress = Clock::now();
        while (true) {
            const int e = pop();
            if (e < 0) break;
            if (mesh_.is_removed_edge(e) || is_delaunay(e)) continue;
            if (is_flat(e, flat_angle_) && is_flippable(e)) {
                if (report.flips >= flip_budget_) {
                    report.status = ConvertStatus::budget_exhausted;
                    break;
                }
                flip(e);
                ++report.flips;
            } else if (options_.method == ConvertMethod::flip) {
                continue;  // left for the final certificate to count
            } else if (mesh_.num_vertices() >= vertex_budget_) {
                report.status = ConvertStatus::budget_exhausted;
                break;
            } else if (report.splits >= max_splits) {
                break;
            } else {
                if (input_edge_[e] < 0) ++report.vertices_inside_faces;
                split_across_strips(e, report, !trial_);
            }
            if (options_.progress && Clock::now() - last_progress > std::chrono::seconds(1)) {
                last_progress = Clock::now();
                std::fprintf(stderr, "convert: %lld splits, %lld flips, %zu queued, %d vertices\n", report.splits,
                             report.flips, flat_queue_.size() + physical_queue_.size(), mesh_.num_vertices());
            }
        }
    }

    // ConversionReport::added_vertices_lower_bound, from the input (before any split). Every
    // output vertex lies on an input edge, and the apexes of a piece of a physical edge see it
    // under angles no smaller than its input apexes do (more points only widen them). So a
    // physical edge e that gets points has its first one within I0's bound from a, its last
    // within the bound from b, and each physical outer side that gets none sees every point of
    // e from outside the circle through its ends and its input apex across (its keep interval).
    // A side whose interval misses either bound must get a point too (an implication); of two
    // sides with disjoint intervals, one must (a clause). The bound: the edges that the
    // non-Delaunay folds imply, transitively, plus a matching of the clauses they leave open
    // (each needs an edge of its own). Within 0.8 % of the exact optimum of these constraints
    // on the corpus meshes (an integer program, solved aside; experiments/README.md).
    long long added_vertices_lower_bound() const {
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
    // What a point on physical edge e asks of its physical outer sides (see
    // added_vertices_lower_bound): bit i, side i must get a point; bit 4 + p, one of the p-th
    // pair of sides (0-1, 0-2, 0-3, 1-2, 1-3, 2-3) must. The keep intervals propose; margins
    // decide, at one position between the two ranges that cannot meet: a side's angle at x
    // shrinks as x moves away from the side's end on e, a half's apex angles grow with it, so a
    // margin broken there stays broken on the whole range beyond.
    std::uint16_t side_requirements(int e) const {
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

    // thin_corners_: by input vertex, its input face corners below kThinCorner.
    void count_thin_corners() {
        thin_corners_.assign(static_cast<size_t>(input_vertices_), 0);
        for (int f = 0; f < input_.num_faces(); ++f)
            for (int c = 0; c < 3; ++c) {
                const int v = input_.F(f, c), p = input_.F(f, (c + 1) % 3), q = input_.F(f, (c + 2) % 3);
                if (corner_angle(dist(p, q), dist(v, p), dist(v, q)) < kThinCorner) ++thin_corners_[v];
            }
    }

    // Splits e where split_distance says, and carries the cut on across the strips of thin faces
    // it enters, as a loop cut: a cylinder tessellated as a ring of long faces between two rims
    // (CAD meshes are full of them) is made Delaunay by one ring of points at one height, but
    // points placed one by one at heights of their own broke their neighbours ever further along
    // the strip (rims of 400 and 397 points, 199 non-Delaunay edges: 67,117 vertices added, now
    // 797; couplingdown 8.18 -> 4.50 per non-Delaunay edge, the other corpus meshes within 0.6 %).
    // With `look_ahead`, a split that must break a physical side is placed where a trial of the
    // cascade it starts costs the fewest splits (see fewest_splits_after); not inside a trial.
    // `at`: the first split's distance from its hinge's a; < 0: where split_distance says.
    void split_across_strips(int first, ConversionReport& report, bool look_ahead, double at = -1) {
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
            split(cut.edge, position);
            ++report.splits;
            for (int i = 0; i < outer.count; ++i)
                if (const std::optional<double> across = strip_cut(sides[i]); across)
                    cuts.push_back({sides[i].edge, *across, true});
        }
    }
    // Of the positions (distances from the hinge's a) on e, the one whose split starts the
    // cheapest cascade; the first of equals. Each is tried and taken back (splits_after). The
    // scores of least_cascading see one step ahead; a trial sees how the broken sides' own
    // splits go. Measured against the first position alone: koala 2.41 -> 2.25 vertices added
    // per non-Delaunay edge, elk 2.33 -> 2.18, mushroom 2.39 -> 2.21, boot 2.11 -> 2.01,
    // couplingdown 4.50 -> 3.78, nefertiti 1.70 -> 1.66, cheese 12.15 -> 11.76.
    double fewest_splits_after(int e, const std::vector<double>& positions) {
        double chosen = positions.front();
        long long fewest = std::numeric_limits<long long>::max();
        for (const double t : positions) {
            if (const long long cost = splits_after(e, t, fewest); cost < fewest) fewest = cost, chosen = t;
            if (fewest <= 2) break;  // itself and one broken side: what nearly every position costs
        }
        return chosen;
    }
    // The splits that splitting e at distance t from its hinge's a costs: itself with the strip
    // cuts it carries on, then what the loop splits, followed for kTrialSplits splits (or until
    // at_most), plus the edges the trial left to split. A trial must make the strip cuts the
    // real split makes: without them, a split in a drum's band of 1,000 rim points looked
    // cheapest at a height where the ring that followed did not close the strips, and the
    // conversion ran into its vertex budget (118,018 vertices instead of one ring of 2,000).
    // The edges queued before wait outside the trial, which is taken back.
    long long splits_after(int e, double t, long long at_most) {
        std::vector<int> flat_waiting = std::move(flat_queue_);
        auto physical_waiting = std::move(physical_queue_);
        flat_queue_.clear();
        physical_queue_ = {};
        begin_trial();
        ConversionReport trial;
        split_across_strips(e, trial, false, t);
        for (long long flips = 0; trial.splits < kTrialSplits && trial.splits < at_most && flips < kTrialFlips;) {
            const int g = pop();
            if (g < 0 || mesh_.num_vertices() >= vertex_budget_) break;
            if (mesh_.is_removed_edge(g) || is_delaunay(g)) continue;
            if (is_flat(g, flat_angle_) && is_flippable(g)) {
                flip(g);
                ++flips;
            } else {
                split_across_strips(g, trial, false);
            }
        }
        trial_splits_ += trial.splits;
        long long cost = trial.splits;
        auto still_to_split = [&](int g) {
            return !mesh_.is_removed_edge(g) && !is_delaunay(g) && !(is_flat(g, flat_angle_) && is_flippable(g));
        };
        for (int g = pop(); g >= 0; g = pop()) cost += still_to_split(g);  // entries may have healed
        rollback();
        flat_queue_ = std::move(flat_waiting);
        physical_queue_ = std::move(physical_waiting);
        return cost;
    }

    // An outer side c-d of a split edge c-e, before the split.
    struct StripSide {
        int edge, shared, far, split_end;  // c, d, e
    };
    // Where the cut through the newest split point x on c-e goes on across outer side c-d: at x's
    // fraction of the way from c (parallel to e-d, so the face's small triangle keeps its
    // angles), if the face c-e-d is thin at c, c is no fan's apex, c-d is a fold that x broke, and
    // the face beyond c-d is thin too, at c or d, and c-d's halves will be locally Delaunay once
    // the cut has crossed that face as well. Nothing otherwise.
    std::optional<double> strip_cut(const StripSide& side) const {
        const int c = side.shared, d = side.far, e = side.split_end, x = mesh_.num_vertices() - 1;
        if (is_flat(side.edge, flat_angle_) || is_delaunay(side.edge)) return std::nullopt;
        if (c < input_vertices_ && thin_corners_[c] > kMaxStripCorners) return std::nullopt;
        if (corner_angle(dist(e, d), dist(c, e), dist(c, d)) >= kThinCorner) return std::nullopt;
        int beyond = mesh_.halfedge(side.edge);  // the side's face without x
        if (mesh_.opposite_vertex(beyond) == x) beyond = mesh_.twin(beyond);
        if (beyond < 0) return std::nullopt;
        const int w = mesh_.opposite_vertex(beyond);
        const double fraction = dist(c, x) / dist(c, e);
        Eigen::Vector3d exit;  // where the cut leaves the face beyond
        if (corner_angle(dist(d, w), dist(c, d), dist(c, w)) < kThinCorner)
            exit = P_[c] + fraction * (P_[w] - P_[c]);
        else if (corner_angle(dist(c, w), dist(c, d), dist(d, w)) < kThinCorner)
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

    // Physical non-Delaunay edges that need one split point each, placed together before the
    // queue runs. Greedy placement decides each point alone: on a terrain of valence-6 grid
    // cells, where the non-Delaunay diagonals of neighbouring cells share outer sides, the first
    // point takes the room a neighbour needed, and the neighbour's split then breaks a side. Here
    // each such edge gets an interval of positions: I0 less the ends, less the positions that
    // break a physical outer side. A side shared with another such edge's face (its partner)
    // constrains the two points together, monotonically (the nearer a point gets to the side, the
    // wider it sees it), so each interval is narrowed against the most permissive end of the
    // other's until none changes; then each point is fixed in turn where the queue would put it
    // inside its interval (sparing_neighbours), narrowing its partners'. An edge without
    // partners, or whose interval empties, is left to the queue (planning lone edges too: 0.2 %
    // more vertices), and so are edges next to planes (a plane's points all see its folds).
    // Measured against the queue alone: mountain 1.52 -> 1.37 vertices added per non-Delaunay
    // edge, a bumpy grid 1.02 -> 1.00.
    void split_together(ConversionReport& report) {
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
        // Nothing is split yet: the split method's flat edges are the input's.
        const bool flat_as_input = flat_angle_.angle == coplanar_angle_.angle;
        auto flat = [&](int e) { return flat_as_input ? input_flat_[e] != 0 : is_flat(e, flat_angle_); };
        auto needs_split = [&](int e) { return queued_[e] && !flat(e); };
        std::vector<Edge> group;  // by increasing edge id
        for (int e = 0; e < edges; ++e) {
            if (!needs_split(e)) continue;
            // Alone in its faces, with no flat side, and not a needle (needles take shells).
            bool alone = true;
            for (const int h : {mesh_.halfedge(e), mesh_.twin(mesh_.halfedge(e))})
                if (h >= 0)
                    for (const int side : {mesh_.edge(HalfedgeMesh::next(h)), mesh_.edge(HalfedgeMesh::prev(h))})
                        alone = alone && !needs_split(side) && !flat(side);
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
            split(group[i].e, same_way ? position[i] : group[i].l - position[i]);
            ++report.splits;
        }
    }

    // Split points that later points made unnecessary go again. A point x between p and q on a
    // non-flat input edge may go when the piece p-q would be locally Delaunay against every
    // point of the planes on its two sides (the apex of a piece in a plane's Delaunay
    // triangulation is one of them); removing a point only shrinks the angles that the other
    // pieces see, so they stay locally Delaunay. x's spokes are flipped away until one is left
    // on each side, the split is undone, and Lawson flips restore the planes' triangulations;
    // anything they left non-Delaunay would be split again by the same loop. With `changed`
    // (by input edge), only the points of the planes next to changed edges are tried first.
    void remove_unneeded_points(ConversionReport& report, const std::vector<char>* changed = nullptr) {
        const int input_faces = static_cast<int>(input_.F.rows()), edges = input_edges_.num_edges();
        auto faces_of = [&](int e) {
            const int g = input_edges_.edge_halfedges(e, 1);
            return std::array<int, 2>{input_edges_.edge_halfedges(e, 0) / 3, g < 0 ? -1 : g / 3};
        };
        // Planes: input faces joined across flat input edges (one face each without them).
        const bool any_flat = std::find(input_flat_.begin(), input_flat_.end(), 1) != input_flat_.end();
        std::vector<int> plane_of(any_flat ? input_faces : 0);  // by face: its plane's representative
        if (any_flat) {
            UnionFind planes(input_faces);
            for (int e = 0; e < edges; ++e)
                if (input_flat_[e]) planes.unite(faces_of(e)[0], faces_of(e)[1]);
            for (int f = 0; f < input_faces; ++f) plane_of[f] = planes.find(f);
        }
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
        // Cotangent of the angle under which y sees p-q (+inf on their line).
        auto cotangent = [&](int y, int p, int q) {
            const Eigen::Vector3d a = P_[p] - P_[y], b = P_[q] - P_[y];
            const double sine = a.cross(b).norm();
            return sine > 0 ? a.dot(b) / sine : std::numeric_limits<double>::infinity();
        };
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

    // Each input edge with two or more split points gets the fewest that suffice with the
    // points of every other edge in place: from one end, each point goes as far as the piece
    // before it stays locally Delaunay, and outside the circles where it would break a piece of
    // the other edges of its faces. Inside an input face whose edges are all folds, the apex of
    // a piece is the point of the face that sees it widest (its triangulation is the Delaunay
    // triangulation of points on a triangle's boundary), so both tests read point sets, and
    // this reach is optimal on the edge: a piece inside a locally Delaunay piece is locally
    // Delaunay. Edges next to coplanar faces, whose planes triangulate together, are left as
    // they are. Returns which input edges got or lost points (empty if none did).
    std::vector<char> fewest_points_per_edge(ConversionReport& report) {
        const int edges = input_edges_.num_edges();
        auto face_of = [&](int e, int side) {
            const int h = input_edges_.edge_halfedges(e, side);
            return h < 0 ? -1 : h / 3;
        };
        auto all_folds = [&](int f) {
            for (int k = 0; k < 3; ++k)
                if (input_flat_[input_edges_.face_edge(f, k)]) return false;
            return true;
        };
        // The faces of e's faces' edges must all be single-face planes.
        auto in_folds = [&](int e) {
            for (int side = 0; side < 2; ++side)
                if (const int f = face_of(e, side); f >= 0)
                    for (int k = 0; k < 3; ++k)
                        for (int g_side = 0; g_side < 2; ++g_side)
                            if (const int g = face_of(input_edges_.face_edge(f, k), g_side); g >= 0 && !all_folds(g))
                                return false;
            return true;
        };
        std::vector<int> count(static_cast<size_t>(edges), 0), candidates;
        for (size_t y = input_vertices_; y < P_.size(); ++y)
            if (const int ie = vertex_input_edge_[y - input_vertices_]; ie >= 0 && !removed_[y - input_vertices_]) ++count[ie];
        for (int e = 0; e < edges; ++e)
            if (count[e] >= 2 && !input_flat_[e] && in_folds(e)) candidates.push_back(e);
        if (candidates.empty()) return {};
        std::vector<std::vector<int>> on_edge(static_cast<size_t>(edges));
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
        // Cotangent of the widest angle under which a point of `face` sees u-v (+inf for none).
        auto apex_cotangent = [](const std::vector<Eigen::Vector3d>& face, const Eigen::Vector3d& u,
                                 const Eigen::Vector3d& v) {
            double smallest = std::numeric_limits<double>::infinity();
            for (const Eigen::Vector3d& p : face) {
                const Eigen::Vector3d a = u - p, b = v - p;
                const double sine = a.cross(b).norm();
                if (sine > 0) smallest = std::min(smallest, a.dot(b) / sine);
            }
            return smallest;
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
            const int sides = face_of(e, 1) < 0 ? 1 : 2;
            forbidden.clear();
            for (int side = 0; side < sides; ++side) {
                const int f = face_of(e, side);
                gather(f, e, points[side]);
                for (int k = 0; k < 3; ++k) {
                    const int g = input_edges_.face_edge(f, k);
                    if (g == e) continue;
                    const int across = face_of(g, 0) == f ? face_of(g, 1) : face_of(g, 0);
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
                if (x < s + kNearEnd * l) return std::nullopt;
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
                int whole = -1;
                for (const int y : old_points) {
                    whole = undo_split(y, report);
                    if (whole < 0) break;
                    ++report.removed_points;
                }
                if (whole >= 0) {
                    // Split the rest of e, from a's end, at each position in turn.
                    int rest = whole, near = input_edges_.E(e, 0);
                    double done = 0;
                    for (const double t : *positions) {
                        const Hinge k = hinge(rest);
                        const bool from_near = k.a == near;
                        split(rest, from_near ? t - done : dist(k.a, k.b) - (t - done));
                        ++report.splits;
                        near = static_cast<int>(P_.size()) - 1;
                        rest = pieces_[near - input_vertices_][from_near ? 1 : 0];
                        done = t;
                    }
                    // A drain that has to split stops one split beyond as many as it took.
                    drain(report, before.splits + static_cast<long long>(old_points.size()) + 1);
                }
                const long long added = report.splits - report.removed_points;
                if (whole >= 0 && report.status == ConvertStatus::certified && report.vertices_inside_faces == 0 &&
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

    // Inside a trial, writes to entries that existed before it are recorded first.
    template <class T>
    static void write(std::vector<T>& array, int i, T value, size_t existing, std::vector<std::pair<int, T>>* log) {
        if (log && static_cast<size_t>(i) < existing) log->emplace_back(i, array[i]);
        array[i] = value;
    }
    void set_input_edge(int e, int value) {
        write(input_edge_, e, value, trial_ ? trial_->edges : 0, trial_ ? &trial_->input_edge : nullptr);
    }
    void set_in_plane(int e, char value) {
        write(in_plane_, e, value, trial_ ? trial_->edges : 0, trial_ ? &trial_->in_plane : nullptr);
    }
    void set_removed(int point, char value) {
        write(removed_, point, value, trial_ ? trial_->points - input_vertices_ : 0, trial_ ? &trial_->removed : nullptr);
    }
    void set_pieces(int point, std::array<int, 2> value) {
        write(pieces_, point, value, trial_ ? trial_->points - input_vertices_ : 0, trial_ ? &trial_->pieces : nullptr);
    }

    void begin_trial() {
        trial_.emplace();
        trial_->points = P_.size();
        trial_->edges = static_cast<size_t>(mesh_.num_edges());
        mesh_.begin_trial();
    }
    void rollback() {
        while (pop() >= 0) {}  // what a stopped drain left queued
        auto undo = [](auto& array, auto& log) {
            for (auto it = log.rbegin(); it != log.rend(); ++it) array[it->first] = it->second;
        };
        undo(input_edge_, trial_->input_edge), undo(in_plane_, trial_->in_plane);
        undo(removed_, trial_->removed), undo(pieces_, trial_->pieces);
        const size_t points = trial_->points - input_vertices_, edges = trial_->edges;
        P_.resize(trial_->points);
        vertex_input_edge_.resize(points), removed_.resize(points), pieces_.resize(points);
        input_edge_.resize(edges), in_plane_.resize(edges), queued_.resize(edges);
        mesh_.rollback();
        trial_.reset();
    }
    void commit() {
        mesh_.commit();
        trial_.reset();
    }

    // Around each split point in turn, the split points on the (up to five) input edges of its
    // two input faces are removed and the loop places them again, with everything else in
    // place; the result is kept if it has fewer vertices, else taken back. Greedy placement
    // decides each point before its neighbours exist; here each is decided again after.
    // Returns which input edges got or lost points.
    std::vector<char> local_search(ConversionReport& report) {
        // The split points on each input edge; ids taken back by a rollback may linger.
        std::vector<std::vector<int>> on_edge(static_cast<size_t>(input_edges_.num_edges()));
        size_t indexed = static_cast<size_t>(input_vertices_);
        std::vector<int> edges, victims;
        std::vector<char> changed(on_edge.size(), 0);
        for (int pass = 0; pass < options_.local_search; ++pass) {
            const int points = static_cast<int>(P_.size());
            for (int x = input_vertices_; x < points && report.status == ConvertStatus::certified; ++x) {
                if (x >= static_cast<int>(P_.size()) || removed_[x - input_vertices_]) continue;
                const int e = vertex_input_edge_[x - input_vertices_];
                if (e < 0 || input_flat_[e]) continue;
                for (; indexed < P_.size(); ++indexed)
                    if (const int ie = vertex_input_edge_[indexed - input_vertices_]; ie >= 0)
                        on_edge[ie].push_back(static_cast<int>(indexed));
                edges.assign(1, e);
                for (int side = 0; side < 2; ++side)
                    if (const int h = input_edges_.edge_halfedges(e, side); h >= 0)
                        for (int k = 0; k < 3; ++k) edges.push_back(input_edges_.face_edge(h / 3, k));
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
        }
        return changed;
    }

    int other_end(int e, int v) const {
        const int h = mesh_.halfedge(e);
        return mesh_.tail(h) == v ? mesh_.head(h) : mesh_.tail(h);
    }
    // Split point v's piece `from` became `to`.
    void repoint_piece(int v, int from, int to) {
        if (v < input_vertices_) return;
        std::array<int, 2> pieces = pieces_[v - input_vertices_];
        for (int& piece : pieces)
            if (piece == from) piece = to;
        set_pieces(v - input_vertices_, pieces);
    }

    // The side of edge e that runs into vertex x, -1 if it has none (a boundary edge).
    int side_into(int e, int x) const {
        const int h = mesh_.halfedge(e);
        return mesh_.head(h) == x ? h : mesh_.twin(h);
    }

    // Flips the spokes of x on the side of `into` (an edge p-x) until one is left before the
    // piece x-q; false if none of them can be flipped.
    bool keep_one_spoke(int into, int x, int q, ConversionReport& report) {
        while (true) {
            const int h = side_into(into, x);
            std::vector<int> spokes;
            for (int out = HalfedgeMesh::next(h); mesh_.head(out) != q; out = HalfedgeMesh::next(mesh_.twin(out)))
                spokes.push_back(mesh_.edge(out));
            if (spokes.size() == 1) return true;
            const auto flippable = std::find_if(spokes.begin(), spokes.end(),
                                                [&](int s) { return is_flat(s, flat_angle_) && is_flippable(s); });
            if (flippable == spokes.end()) return false;
            flip(*flippable);
            ++report.flips;
        }
    }

    // Removes split point x and returns the edge that joins its neighbours on the input edge;
    // -1 if its spokes could not be reduced to one per side.
    int undo_split(int x, ConversionReport& report) {
        auto [piece, other] = pieces_[x - input_vertices_];
        if (side_into(piece, x) < 0) std::swap(piece, other);  // on a boundary line
        const int p = other_end(piece, x), q = other_end(other, x);
        if (!keep_one_spoke(piece, x, q, report)) return -1;
        if (side_into(other, x) >= 0 && !keep_one_spoke(other, x, p, report)) return -1;
        const int h = side_into(piece, x), t = mesh_.twin(h);
        mesh_.merge(h);
        set_removed(x - input_vertices_, 1);
        repoint_piece(q, other, piece);
        for (const int side : {h, t}) {
            if (side < 0) continue;
            push(mesh_.edge(HalfedgeMesh::next(side)));
            push(mesh_.edge(HalfedgeMesh::prev(side)));
        }
        push(piece);
        return piece;
    }

    // An angle bound for dihedral tests, with its tangent: below π/2 the test needs no arctangent.
    struct AngleBound {
        explicit AngleBound(double radians) : angle(radians), tangent(std::tan(radians)) {}
        double angle, tangent;
    };

    static double flat_angle(const ConvertOptions& o) {
        switch (o.method) {
            case ConvertMethod::flip: return kPi;  // every edge may be flipped
            case ConvertMethod::split: return o.coplanar_tolerance;
            case ConvertMethod::hybrid: return o.max_dihedral_deg * kPi / 180.0;
        }
        return 0;
    }

    Hinge hinge(int e) const {
        const int h = mesh_.halfedge(e), t = mesh_.twin(h);
        return {h, mesh_.tail(h), mesh_.head(h), mesh_.opposite_vertex(h), t < 0 ? -1 : mesh_.opposite_vertex(t)};
    }

    double dist(int u, int v) const { return distance(P_[u], P_[v]); }

    bool is_delaunay(int e) const {
        const Hinge k = hinge(e);
        const double l = dist(k.a, k.b);
        if (k.s < 0)
            return options_.boundary == BoundaryPolicy::free ||
                   boundary_margin(l, dist(k.a, k.r), dist(k.b, k.r)) >= -options_.tolerance;
        const double ar = dist(k.a, k.r), br = dist(k.b, k.r), as = dist(k.a, k.s), bs = dist(k.b, k.s);
        return is_locally_delaunay_with_tangent(l, ar, br, as, bs, tan_tolerance_);
    }

    // Interior edge known to lie inside a plane, or whose face normals differ by at most
    // `bound` radians.
    bool is_flat(int e, const AngleBound& bound) const {
        if (in_plane_[e]) return true;
        const Hinge k = hinge(e);
        if (k.s < 0) return false;
        const Eigen::Vector3d n1 = (P_[k.b] - P_[k.a]).cross(P_[k.r] - P_[k.a]);
        const Eigen::Vector3d n2 = (P_[k.a] - P_[k.b]).cross(P_[k.s] - P_[k.b]);
        const double cosine = n1.dot(n2), sine = n1.cross(n2).norm();
        if (bound.angle < kPi / 2) return cosine > 0 && sine <= bound.tangent * cosine;
        return std::atan2(sine, cosine) <= bound.angle;
    }

    // The new edge r-s must not exist already, and the hinge unfolded into the plane must be
    // strictly convex at a and b, so that both new faces have positive area and keep the
    // orientation.
    bool is_flippable(int e) const {
        const Hinge k = hinge(e);
        if (k.r == k.s || mesh_.has_edge_between(k.h, k.s)) return false;
        const double l = dist(k.a, k.b), ar = dist(k.a, k.r), br = dist(k.b, k.r), as = dist(k.a, k.s),
                     bs = dist(k.b, k.s);
        const double at_a = corner_angle(br, l, ar) + corner_angle(bs, l, as);
        const double at_b = corner_angle(ar, l, br) + corner_angle(as, l, bs);
        return at_a < kPi - 1e-9 && at_b < kPi - 1e-9;
    }

    void flip(int e) {
        const Hinge k = hinge(e);
        const int outer[4] = {mesh_.edge(HalfedgeMesh::next(k.h)), mesh_.edge(HalfedgeMesh::prev(k.h)),
                              mesh_.edge(HalfedgeMesh::next(mesh_.twin(k.h))),
                              mesh_.edge(HalfedgeMesh::prev(mesh_.twin(k.h)))};
        const bool planar_quad = is_flat(e, coplanar_angle_);
        mesh_.flip(e);
        set_input_edge(e, -1);  // the new diagonal crosses the input faces
        set_in_plane(e, static_cast<char>(planar_quad));
        for (int o : outer) {
            // A hybrid flip across a fold puts the outer sides next to faces of another plane.
            if (!planar_quad) set_in_plane(o, 0);
            push(o);
        }
    }

    struct Interval {
        double lo, hi;
    };

    // A point that is to become the apex across the outer side `edge` of a hinge (a split point
    // not made yet), in place of the vertex there now.
    struct Across {
        int edge;
        Eigen::Vector3d point;
    };

    // A range of split positions and the outer sides of the hinge that stay locally Delaunay
    // for all of it: their total weight (-1 for an empty range), and whether the physical
    // sides are all among them.
    struct SideChoice {
        Interval range;
        int weight;
        bool keeps_physical;
    };

    // Soft constraints: each outer side of the hinge stays locally Delaunay on a half-line of
    // positions. A physical side that breaks needs a new vertex, a flat one only a flip, so
    // physical sides weigh double.
    struct OuterSides {
        Interval keeps[4];
        int weight[4];
        int halfedge[4];
        int count = 0, total_weight = 0;
        unsigned physical = 0;  // bit i: side i is physical

        void add(Interval keep, bool flat, int h) {
            keeps[count] = keep;
            weight[count] = flat ? 1 : 2;
            halfedge[count] = h;
            if (!flat) physical |= 1u << count;
            total_weight += weight[count++];
        }

        // f(range, subset) for every subset of sides that some position inside `within` keeps.
        template <class F>
        void for_each_choice(Interval within, F f) const {
            if (within.lo > within.hi) return;
            for (unsigned subset = 0; subset < (1u << count); ++subset) {
                Interval candidate = within;
                for (int i = 0; i < count; ++i)
                    if (subset >> i & 1u) {
                        candidate.lo = std::max(candidate.lo, keeps[i].lo);
                        candidate.hi = std::min(candidate.hi, keeps[i].hi);
                    }
                if (candidate.lo <= candidate.hi) f(candidate, subset);
            }
        }

        // The feasible subset of most weight (the first found) inside `within`.
        SideChoice most_weight(Interval within) const {
            SideChoice best{within, -1, false};
            for_each_choice(within, [&](Interval range, unsigned subset) {
                int total = 0;
                for (int i = 0; i < count; ++i)
                    if (subset >> i & 1u) total += weight[i];
                if (total > best.weight) best = {range, total, (subset & physical) == physical};
            });
            return best;
        }
    };

    // Distance from a at which to split the edge a-b (length l) of hinge k.
    // With `alternatives`, where every position breaks a physical side, up to
    // options_.cascade_trials positions worth a trial go there, the chosen one first; it is left
    // empty otherwise.
    double split_distance(const Hinge& k, double l, std::vector<double>* alternatives = nullptr) const {
        if (alternatives) alternatives->clear();
        const int on_input_edge = input_edge_[mesh_.edge(k.h)];
        // The needles of a fan (a cone's, say) meet at their apex at tiny angles, and their other
        // ends lie anywhere: split points at the same distances from the apex, ignoring I0, make
        // rings that close. Interval points (or shells from either end) left rings out of step
        // that marched along the needles: a 90-needle cone took 51,328 vertices, 180 needles
        // more than the vertex budget; now 4,150 and 14,043.
        if (const int apex = on_input_edge >= 0 ? needle_end(on_input_edge) : -1; apex >= 0)
            return shell_distance_around(apex, k, l);
        if (options_.split_rule == SplitRule::shell) return shell_distance(k, l);
        // Short pieces that end at an input vertex follow the shells, unless an interval point
        // keeps every physical outer side locally Delaunay: two input edges meeting at a small
        // angle would otherwise split each other ever finer. Longer ones take the interval rule,
        // which adds fewer vertices (a quarter of the input edge: measured on the corpus,
        // shorter thresholds gain nothing more).
        const bool near_input_vertex =
            (k.a < input_vertices_) != (k.b < input_vertices_) &&
            (on_input_edge < 0 || l < kShellPieceFraction * input_length_[on_input_edge]);
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
        if (near_input_vertex && !best.keeps_physical) return shell_distance(k, l);
        if (best.weight < 0) return 0.5 * l;
        if (!best.keeps_physical)
            return least_cascading(k, l, sides, away_from_ends(kEndClearance), on_input_edge, alternatives);
        return sparing_neighbours(k, l, best.range, on_input_edge);
    }

    // Where every position of `within` breaks a physical outer side, which one breaks costs a
    // vertex at least; it costs more if that side's own split must break a physical side again
    // (a cascade). Among the usual position of each choice of sides and the simplest dyadic
    // fractions of its range, the one with the most weight kept less the broken physical sides
    // whose split would cascade and the clean neighbours it spoils; the first of equals.
    // Measured against the usual position of the choice of most weight: nefertiti 1.88 -> 1.76
    // vertices added per non-Delaunay edge, boot 2.42 -> 2.22, koala 2.78 -> 2.54. With
    // `alternatives`, the candidates to try as well (see split_distance).
    double least_cascading(const Hinge& k, double l, const OuterSides& sides, Interval within, int on_input_edge,
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

    // The physical outer sides (bit i: side i) across which waits a physical non-Delaunay edge
    // that cannot be split cleanly: its split will likely break a side, and if it breaks this one,
    // one point on it serves both. Breaking them costs nothing, keeping them gains nothing.
    // Measured against scoring them like other sides: mushroom 2.56 -> 2.47 vertices added per
    // non-Delaunay edge, elk 2.42 -> 2.35, koala 2.46 -> 2.43, cheese 12.58 -> 12.11.
    unsigned sides_broken_anyway(const OuterSides& sides) const {
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

    // Whether outer side i of hinge k (halfedge `side`: 0 a-r, 1 b-r, 2 a-s, 3 b-s), broken by a
    // split point x at distance t from k.a, could itself be split keeping its physical outer
    // sides locally Delaunay, as split_distance would judge it with x in the mesh.
    bool side_splits_cleanly(const Hinge& k, double l, double t, int i, int side) const {
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

    // Whether a split point in I0 (`halves`, on a piece of length l), in its middle or near an end,
    // keeps every physical outer side, as split_distance looks for one.
    static bool has_clean_position(const OuterSides& sides, Interval halves, double l) {
        return sides.most_weight(away_from_ends(halves, l, kEndClearance)).keeps_physical ||
               sides.most_weight(away_from_ends(halves, l, kNearEnd)).keeps_physical;
    }

    // Physical non-Delaunay edges across the physical outer sides of hinge k that could be split
    // cleanly now: (that side, the edge). A split point of k becomes their apex across the side.
    struct CleanNeighbours {
        std::array<std::pair<int, int>, 8> pending;
        int count = 0;
    };
    CleanNeighbours clean_neighbours(const Hinge& k) const {
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
    // How many of `neighbours` a split point of k at distance t from k.a leaves without a clean split.
    int spoiled(const Hinge& k, double l, double t, const CleanNeighbours& neighbours) const {
        const Eigen::Vector3d x = P_[k.a] + (t / l) * (P_[k.b] - P_[k.a]);
        int count = 0;
        for (int i = 0; i < neighbours.count; ++i) {
            const Across future{neighbours.pending[i].first, x};
            count += !splits_cleanly(neighbours.pending[i].second, &future);
        }
        return count;
    }
    // Whether physical edge e could be split keeping its physical outer sides locally Delaunay.
    bool splits_cleanly(int e, const Across* future = nullptr) const {
        const Hinge k = hinge(e);
        const double l = dist(k.a, k.b);
        return has_clean_position(outer_sides(k, l, future), delaunay_halves_interval(k, l), l);
    }

    // A split position in `range`, where every position keeps the physical outer sides of k: the
    // usual one, unless it leaves a neighbour across a side (see clean_neighbours) without a clean
    // split; then the first of the simplest dyadic fractions of the range that spoils fewest.
    // Measured against the usual position: mountain 1.56 -> 1.52 vertices added per
    // non-Delaunay edge, elk 2.44 -> 2.40, boot 2.17 -> 2.15, no corpus mesh more.
    double sparing_neighbours(const Hinge& k, double l, Interval range, int on_input_edge) const {
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

    // The positions of I0 (`halves`), shrunk by a little so that no half ends up exactly
    // co-circular, at least `clearance` of the piece (length l) away from its ends.
    static Interval away_from_ends(Interval halves, double l, double clearance) {
        const double inset = 1e-3 * (halves.hi - halves.lo);
        return {std::max(halves.lo + inset, clearance * l), std::min(halves.hi - inset, (1 - clearance) * l)};
    }

    // Inside a range of a choice of sides: the foot of the perpendicular from the apex with the
    // wider angle (the spoke is then perpendicular to the edge). Else the simplest dyadic
    // fraction of the input edge in the range: neighbouring edges of similar length then get
    // their points at the same fractions, and the pieces line up across the faces between them
    // (thin strips of faces need fewer points: couplingdown 10.96 -> 8.95 vertices added per
    // non-Delaunay edge). Else the middle of the range.
    double usual_position(const Hinge& k, double l, Interval range, int on_input_edge) const {
        const double ar = dist(k.a, k.r), br = dist(k.b, k.r);
        const int apex = k.s >= 0 && dist(k.a, k.s) + dist(k.b, k.s) < ar + br ? k.s : k.r;
        const double foot = (P_[apex] - P_[k.a]).dot(P_[k.b] - P_[k.a]) / l;
        if (foot >= range.lo && foot <= range.hi) return foot;
        double dyadic = -1;
        if (on_input_edge >= 0) for_each_dyadic(k, on_input_edge, range, 1, [&](double t) { dyadic = t; });
        return dyadic >= 0 ? dyadic : 0.5 * (range.lo + range.hi);
    }

    OuterSides outer_sides(const Hinge& k, double l, const Across* future = nullptr) const {
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
    // The outer sides of hinge k as halfedges of its faces, in the order a-r, b-r, a-s, b-s
    // (the first two only on the boundary).
    struct OuterHalfedges {
        std::array<int, 4> h;
        int count = 0;
    };
    OuterHalfedges outer_halfedges(const Hinge& k) const {
        OuterHalfedges outer;
        for (const int h : {k.h, mesh_.twin(k.h)}) {
            if (h < 0) continue;
            outer.h[outer.count++] = h == k.h ? HalfedgeMesh::prev(h) : HalfedgeMesh::next(h);  // side a-apex
            outer.h[outer.count++] = h == k.h ? HalfedgeMesh::next(h) : HalfedgeMesh::prev(h);  // side b-apex
        }
        return outer;
    }

    // f(position) for the first `count` positions in `range` (distances from k.a) whose parameter
    // along input edge ie (0 at one end, 1 at the other) is a dyadic fraction of at most
    // kDyadicBits bits, those with fewer bits first. The fractions are the same from either end.
    template <class F>
    void for_each_dyadic(const Hinge& k, int ie, Interval range, int count, F f) const {
        const int u = input_edges_.E(ie, 0), w = input_edges_.E(ie, 1);
        const double length = input_length_[ie];
        const Eigen::Vector3d along = (P_[w] - P_[u]) / (length * length);
        const double ta = (P_[k.a] - P_[u]).dot(along), tb = (P_[k.b] - P_[u]).dot(along);
        const double sign = tb > ta ? 1.0 : -1.0;  // the direction of a -> b in the parameter
        const double from_lo = ta + sign * range.lo / length, from_hi = ta + sign * range.hi / length;
        const double lo = std::min(from_lo, from_hi), hi = std::max(from_lo, from_hi);
        for (int bits = 1; bits <= kDyadicBits; ++bits) {
            const double step = std::ldexp(1.0, -bits);
            for (double t = std::ceil(lo / step) * step; t <= hi; t += step) {
                if (std::fmod(t / step, 2.0) == 0) continue;  // fewer bits: done already
                f(std::clamp(sign * (t - ta) * length, range.lo, range.hi));
                if (--count == 0) return;
            }
        }
    }

    // I0 of ALGORITHMS.md §3: positions x on a-b (distance from a) for which both halves are
    // locally Delaunay; on a boundary edge (strict policy) the opposite angle must stay <= π/2.
    Interval delaunay_halves_interval(const Hinge& k, double l) const {
        return k.s < 0 ? halves_interval(l, dist(k.a, k.r), dist(k.b, k.r), -1, -1)
                       : halves_interval(l, dist(k.a, k.r), dist(k.b, k.r), dist(k.a, k.s), dist(k.b, k.s));
    }
    // The same from the lengths a-r, b-r, a-s, b-s (as < 0: no s, a boundary edge).
    static Interval halves_interval(double l, double ar, double br, double as, double bs) {
        const double theta_a = corner_angle(br, l, ar), theta_b = corner_angle(ar, l, br);
        Interval range{0, l};
        if (as < 0) {
            if (std::cos(theta_a) > 0) range.hi = std::min(range.hi, ar / std::cos(theta_a));
            if (std::cos(theta_b) > 0) range.lo = std::max(range.lo, l - br / std::cos(theta_b));
            return range;
        }
        const double phi_a = corner_angle(bs, l, as), phi_b = corner_angle(as, l, bs);
        // Second intersection of the circle through a (b), r, s with the edge line.
        if (theta_a + phi_a < kPi)
            range.hi = std::min(range.hi, (ar * std::sin(phi_a) + as * std::sin(theta_a)) / std::sin(theta_a + phi_a));
        if (theta_b + phi_b < kPi)
            range.lo = std::max(range.lo, l - (br * std::sin(phi_b) + bs * std::sin(theta_b)) / std::sin(theta_b + phi_b));
        return range;
    }

    // Positions x on the edge (distance from a) that keep the outer side `side` = from-apex of the
    // hinge locally Delaunay once x is its opposite vertex. Unfolded into the plane of the face
    // (from, to, apex): x must lie outside the circle through `from`, the apex and the vertex w
    // across the side, i.e. at least D = 2·(c - from)·u from `from` along u = (to - from)/l.
    // Boundary side: x must see it at an angle <= π/2 (strict policy), a circle with the side as
    // diameter. `from_b` mirrors the result for measuring from b. `future` may stand for w.
    Interval outer_side_interval(int side, int from, int to, double l, bool from_b,
                                 const Across* future = nullptr) const {
        const int apex = mesh_.tail(side) == from ? mesh_.head(side) : mesh_.tail(side);
        const int across = mesh_.twin(side);
        if (across < 0) return side_interval(l, dist(from, apex), dist(to, apex), -1, -1, from_b);
        if (future && future->edge == mesh_.edge(side))
            return side_interval(l, dist(from, apex), dist(to, apex), distance(P_[from], future->point),
                                 distance(P_[apex], future->point), from_b);
        const int w = mesh_.opposite_vertex(across);
        return side_interval(l, dist(from, apex), dist(to, apex), dist(from, w), dist(apex, w), from_b);
    }
    // The same from the lengths from-apex, to-apex, from-w, apex-w (d_w < 0: a boundary side).
    Interval side_interval(double l, double d_apex, double d_to_apex, double d_w, double d_apex_w, bool from_b) const {
        const double angle = corner_angle(d_to_apex, l, d_apex);  // at `from`, between to and apex
        double reach = 0;  // D
        if (d_w < 0) {
            if (options_.boundary == BoundaryPolicy::free) return {0, l};
            reach = d_apex * std::cos(angle);
        } else {
            const double beyond = corner_angle(d_apex_w, d_apex, d_w);  // at `from`, apex to w
            const Eigen::Vector2d r = d_apex * Eigen::Vector2d(std::cos(angle), std::sin(angle));
            const Eigen::Vector2d q = d_w * Eigen::Vector2d(std::cos(angle + beyond), std::sin(angle + beyond));
            const double det = 2 * (r.x() * q.y() - r.y() * q.x());
            if (std::abs(det) <= 1e-14 * d_apex * d_w) return {0, l};  // circle degenerates to a line
            const double cx = (r.squaredNorm() * q.y() - q.squaredNorm() * r.y()) / det;
            reach = 2 * cx;
        }
        if (!(reach > 0)) return {0, l};
        return from_b ? Interval{0, l - reach} : Interval{reach, l};
    }

    // Shells around input vertex c on the edge line of hinge k: the distance from c on the
    // coarsest grid of power-of-two multiples of the shell unit that falls in the middle third
    // of the piece a-b (length l); returned as the distance from a.
    double shell_distance_around(int c, const Hinge& k, double l) const {
        const double from_a = dist(c, k.a), from_b = dist(c, k.b);
        const double lo = std::min(from_a, from_b) + l / 3, hi = lo + l / 3;
        for (double step = shell_unit_ * std::exp2(std::floor(std::log2(hi / shell_unit_))); step >= shell_unit_;
             step *= 0.5) {
            const double d = std::ceil(lo / step) * step;
            if (d <= hi) return std::abs(d - from_a);
        }
        return 0.5 * l;
    }

    // The end of input edge e with a corner below kNeedleCorner in one of e's input faces while
    // the other end has none; -1 if there is no such end.
    int needle_end(int e) const {
        const int a = input_edges_.E(e, 0), b = input_edges_.E(e, 1);
        const double l = input_length_[e];
        static const double tangent = std::tan(kNeedleCorner);
        // The corner between sides b and c opposite `opposite` is below kNeedleCorner: its
        // tangent, 4·area over the cosine numerator, is (no arctangent for 2.4M edges).
        auto needle_corner = [&](double opposite, double b_side, double c_side) {
            const double cosine = cosine_numerator(opposite, b_side, c_side);
            return cosine > 0 && 4.0 * triangle_area(opposite, b_side, c_side) < tangent * cosine;
        };
        bool at_a = false, at_b = false;
        for (const int side : {input_edges_.edge_halfedges(e, 0), input_edges_.edge_halfedges(e, 1)}) {
            if (side < 0) continue;
            const int r = input_.F(side / 3, side % 3);  // halfedge 3f + k lies opposite corner k
            const double ar = dist(a, r), br = dist(b, r);
            at_a = at_a || needle_corner(br, l, ar);
            at_b = at_b || needle_corner(ar, l, br);
        }
        if (at_a == at_b) return -1;
        return at_a ? a : b;
    }

    // Ruppert's concentric shells: around the endpoint that is an input vertex, at the
    // power-of-two multiple of the shell unit in the middle third; the midpoint if none or both are.
    double shell_distance(const Hinge& k, double l) const {
        const bool a_input = k.a < input_vertices_, b_input = k.b < input_vertices_;
        if (a_input == b_input) return 0.5 * l;
        return shell_distance_around(a_input ? k.a : k.b, k, l);
    }

    // Splits e at distance `at` from the tail of its halfedge, by default where split_distance says.
    void split(int e, std::optional<double> at = std::nullopt) {
        const Hinge k = hinge(e);
        const double l = dist(k.a, k.b);
        const double t = std::clamp(at ? *at : split_distance(k, l), 0.0, l);
        const Eigen::Vector3d x = P_[k.a] + (t / l) * (P_[k.b] - P_[k.a]);
        const int first_new_edge = mesh_.num_edges();
        std::vector<int> outer = {mesh_.edge(HalfedgeMesh::next(k.h)), mesh_.edge(HalfedgeMesh::prev(k.h))};
        if (k.s >= 0) {
            const int twin = mesh_.twin(k.h);
            outer.push_back(mesh_.edge(HalfedgeMesh::next(twin)));
            outer.push_back(mesh_.edge(HalfedgeMesh::prev(twin)));
        }
        mesh_.split(e);
        P_.push_back(x);
        vertex_input_edge_.push_back(input_edge_[e]);
        removed_.push_back(0);
        // The other half lies on the same input edge as e; the spokes inside faces, so they are
        // flat whatever the rounding of x says (a spoke taken for a fold would be split, with
        // a vertex inside the face, and the next spokes are as noisy: far from the origin that
        // ran away to the vertex budget).
        input_edge_.push_back(input_edge_[e]);
        in_plane_.push_back(in_plane_[e]);
        while (static_cast<int>(input_edge_.size()) < mesh_.num_edges()) {
            input_edge_.push_back(-1);
            in_plane_.push_back(1);
        }
        queued_.resize(static_cast<size_t>(mesh_.num_edges()), 0);
        if (input_edge_[e] >= 0) {  // e keeps the half at a, the new edge the one at b
            pieces_.push_back({e, first_new_edge});
            repoint_piece(k.b, e, first_new_edge);
        } else {
            pieces_.push_back({-1, -1});
        }
        push(e);
        for (int n = first_new_edge; n < mesh_.num_edges(); ++n) push(n);
        for (int o : outer) push(o);
    }

    // Flat candidates first (cheap flips), then physical ones, longest first.
    // Edges are pushed whenever their hinge changes, so one that is locally Delaunay then can
    // stay out (most are: 80 % of the pushes on the skull).
    void push(int e) {
        if (!queued_[e] && !is_delaunay(e)) enqueue(e, queue_key(e));
    }
    // -1 for a flat edge, else the physical queue's key: the length, counted longer when I0
    // (where both halves are locally Delaunay) is a small part of the edge, and when a split
    // point can keep every physical outer side. Among hinges of similar length, the one whose
    // split point has the least choice goes first and the others fit around it; one that can be
    // split cleanly is split before its neighbours' points take that away. Vertices added per
    // non-Delaunay edge, measured against the length alone: cheese 14.76 -> 12.58, mushroom
    // 2.84 -> 2.57, koala 2.54 -> 2.47, boot 2.22 -> 2.17.
    double queue_key(int e) const {
        if (is_flat(e, flat_angle_)) return -1;
        const Hinge k = hinge(e);
        const double l = dist(k.a, k.b);
        const Interval halves = delaunay_halves_interval(k, l);
        // 0 for an empty I0, and for degenerate hinges (NaN bounds): keys must stay ordered.
        const double room = halves.hi > halves.lo ? std::min((halves.hi - halves.lo) / l, 1.0) : 0.0;
        const bool clean = outer_sides(k, l).most_weight(away_from_ends(halves, l, kEndClearance)).keeps_physical;
        return l * (1 + kLittleRoomFirst * (1 - room) + (clean ? kCleanFirst : 0));
    }
    void enqueue(int e, double key) {
        queued_[e] = 1;
        if (key < 0)
            flat_queue_.push_back(e);
        else
            physical_queue_.emplace(key, e);
    }

    int pop() {
        int e = -1;
        if (!flat_queue_.empty()) {
            e = flat_queue_.back();
            flat_queue_.pop_back();
        } else if (!physical_queue_.empty()) {
            e = physical_queue_.top().second;
            physical_queue_.pop();
        }
        if (e >= 0) queued_[e] = 0;
        return e;
    }

    const ConvertOptions& options_;
    const TriangleMesh& input_;
    const EdgeTable& input_edges_;
    HalfedgeMesh mesh_;
    int input_vertices_;
    AngleBound flat_angle_, coplanar_angle_;
    double tan_tolerance_;  // of the locally Delaunay test
    int scale_exponent_ = 0;  // P_ = input coordinates · 2^-scale_exponent_
    double shell_unit_ = 1;
    std::vector<Eigen::Vector3d> P_;
    std::vector<int> input_edge_;  // the input edge an edge lies on, -1 inside an input face
    // Edges whose two faces lie in one plane by construction (within the coplanar tolerance).
    std::vector<char> in_plane_;
    std::vector<double> input_length_;  // by input edge
    std::vector<char> input_flat_;  // by input edge, at the coplanar tolerance
    // By input edge: a fold not locally Delaunay in the input. Whatever the split points
    // elsewhere, its apexes see it under angles at least the input's, so it keeps a point.
    std::vector<char> needs_point_;
    std::vector<int> thin_corners_;  // by input vertex, see count_thin_corners
    std::vector<int> vertex_input_edge_;  // by split point: the input edge it lies on, -1 inside a face
    std::vector<char> removed_;  // by split point: removed again
    long long vertex_budget_ = 0, flip_budget_ = 0;
    std::vector<std::array<int, 2>> pieces_;  // by split point on an input edge: its two pieces
    // By edge: in a queue. Every edge not locally Delaunay is, but the one being split.
    std::vector<char> queued_;
    // The open trial of local_search(): what to take back if it does not pay.
    struct Trial {
        size_t points, edges;  // P_.size(), mesh_.num_edges() at its start
        std::vector<std::pair<int, int>> input_edge;
        std::vector<std::pair<int, char>> in_plane, removed;
        std::vector<std::pair<int, std::array<int, 2>>> pieces;
    };
    std::optional<Trial> trial_;
    std::vector<double> alternatives_;  // split_distance's, for split_across_strips
    long long trial_splits_ = 0;  // made by trials, all taken back
    std::vector<int> flat_queue_;
    std::priority_queue<std::pair<double, int>> physical_queue_;
};

void check_options(const ConvertOptions& o) {
    if (!(o.tolerance >= 0 && o.tolerance < kPi / 2))
        throw InvalidArgumentError("convert: tolerance must be in [0, π/2)");
    if (!(o.max_dihedral_deg >= 0 && o.max_dihedral_deg <= 180))
        throw InvalidArgumentError("convert: max_dihedral_deg must be in [0, 180]");
    if (!(o.coplanar_tolerance >= 0)) throw InvalidArgumentError("convert: coplanar_tolerance must be >= 0");
    if (o.max_vertices < 0) throw InvalidArgumentError("convert: max_vertices must be >= 0");
    if (o.max_flips < 0) throw InvalidArgumentError("convert: max_flips must be >= 0");
    if (o.local_search < 0) throw InvalidArgumentError("convert: local_search must be >= 0");
    if (o.cascade_trials < 0) throw InvalidArgumentError("convert: cascade_trials must be >= 0");
}

}  // namespace

ConversionResult convert(const TriangleMesh& mesh, const ConvertOptions& options) {
    const auto start = Clock::now();
    check_options(options);
    require_indices_in_range(mesh);
    require_supported_extent(mesh);
    const EdgeTable edges = build_edge_table(mesh.F, mesh.num_vertices());
    const MeshInfo info = validate(mesh, edges);
    require_oriented_manifold(info, "convert");

    ConversionResult result;
    ConversionReport& report = result.report;
    report.input_vertices = mesh.num_vertices();
    report.input_faces = mesh.num_faces();
    {  // the converter's working memory is released before the output is certified
        Converter converter(mesh, edges, options);
        converter.run(report);
        result.mesh = converter.result();
    }
    report.output_vertices = result.mesh.num_vertices();
    report.output_faces = result.mesh.num_faces();
    report.certificate = certify(result.mesh, {.boundary = options.boundary, .tolerance = options.tolerance});
    if (report.status != ConvertStatus::budget_exhausted && !report.certificate.self_delaunay)
        report.status = ConvertStatus::not_certified;
    if (options.method == ConvertMethod::flip)
        report.unflippable_edges = report.certificate.non_delaunay_edges +
                                   (options.boundary == BoundaryPolicy::strict ? report.certificate.boundary_obtuse_edges : 0);
    if (options.measure_hausdorff && report.flips > 0 && options.method != ConvertMethod::split)
        // A few samples per face: the flips change the surface by a fraction of an edge length.
        report.hausdorff_rel =
            hausdorff_distance(mesh, result.mesh, {.samples_per_face = 4, .max_samples = 4'000'000}).hausdorff_rel;
    report.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return result;
}

std::string_view to_string(ConvertStatus status) {
    switch (status) {
        case ConvertStatus::certified: return "certified";
        case ConvertStatus::budget_exhausted: return "budget_exhausted";
        case ConvertStatus::not_certified: return "not_certified";
    }
    return "unknown";
}

std::string_view to_string(ConvertMethod method) {
    switch (method) {
        case ConvertMethod::flip: return "flip";
        case ConvertMethod::split: return "split";
        case ConvertMethod::hybrid: return "hybrid";
    }
    return "unknown";
}

std::string_view to_string(SplitRule rule) {
    return rule == SplitRule::shell ? "shell" : "interval";
}

}  // namespace sdmesh
