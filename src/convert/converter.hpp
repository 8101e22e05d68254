#pragma once
// The converter behind convert() (internal, not installed): one Converter per call, with the
// working mesh, the split points and the queues. Its member functions are grouped by stage:
//   convert.cpp      the loop (run, drain) and the edits of the mesh (split, flip, undo_split);
//   placement.cpp    where a split point goes on its edge (intervals, look-ahead, shells);
//   cascades.cpp     splits decided together: strip cuts, cascade trials, joint splits;
//   improvement.cpp  after the loop: point removal, the fewest points per edge, local search;
//   piece_reach.cpp  (no member) how far a piece of an edge stays locally Delaunay, for the above;
//   relocation.cpp   local search's moves of the points among folds (min-conflicts);
//   lower_bound.cpp  ConversionReport::added_vertices_lower_bound.

#include "sdmesh/convert.hpp"

#include <algorithm>
#include <array>
#include <bit>
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
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include "flip_queue.hpp"
#include "halfedge.hpp"
#include "prefault.hpp"
#include "progress_clock.hpp"
#include "union_find.hpp"
#include "sdmesh/distance.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "sdmesh/validate.hpp"

namespace sdmesh::conversion {

using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;
// Pieces of an input edge shorter than this fraction of it, with one end at an input vertex, are
// split on Ruppert's shells (see split_distance).
constexpr double kShellPieceFraction = 0.25;
// Pieces this much shorter than their input edge, with one end at an input vertex, are a cascade
// converging on that vertex: they always take the shells, which end it (see split_distance).
constexpr double kConvergingPieceFraction = 1.0 / 64;
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
// Point removal lets at most this many points go together (see remove_unneeded_points), stops a
// chain once it has tested this many apexes, and grows no more chains once the pass's tests
// outnumber its split points kChainWork times. Cheese needs 256 (128: 85 more vertices); a
// coffee table of Sweet Home 3D, whose 358 faces hold 31,000 points, took 11 s instead of 0.2 s
// without this budget (16 % fewer vertices), 0.6 s with it (1.4 % fewer).
constexpr size_t kChainPoints = 64, kChainTests = size_t{1} << 14, kChainWork = 256;
// relocate_points gives up on a point after this many moves, trying this many points for each
// at this many positions each. Measured with --local-search 1 (vertices added on elk / mushroom
// / boot, seconds on boot): 24 moves of 6 × 8: 1,255 / 1,263 / 15,951, 4.8 s; 40 of 3 × 8:
// 1,264 / 1,271 / 15,950, 6.1 s; 40 of 6 × 8: 1,245 / 1,252 / 15,842, 6.7 s (6 × 12 alike, 9 s);
// 80 of 3 × 8: 1,254 / 1,250 / 15,849, 10.9 s. Without the moves: 1,288 / 1,316 / 16,299, 1.0 s.
// Since moves are scored on what they change, 40 of 6 × 8 take 3.6 s on boot; 80 of 6 × 8: 1,232 /
// 1,241 / 15,748 in 6.0 s.
constexpr int kRelocationMoves = 40, kRelocationCandidates = 6, kRelocationPositions = 8;
// ... and leaves points where the faces around hold more than this many (fans of needles with
// hundreds of points each: a move's cost grows with the square of them).
constexpr size_t kRelocationMaxPoints = 64;

// fewest_points_per_edge places points where the cotangent sums of the pieces they touch are
// at least this, so that rounding does not undo them: far from the origin (the skewed grid
// moved by 10^6) a margin of 1e-9 lost two thirds of the points it saves near it.
constexpr double kPlacementMargin = 1e-6;
// ... and sweeps the edges this many times, alternately placing from either end: moving a
// point without saving one can make room on the edges beside it.
constexpr int kFewestPointsPasses = 4;
// ... and leaves edges whose two faces hold more points than this many pairs: each point placed
// tests its piece against them all (a warped fan of 500 needles with 176 points each takes 4.4 s
// without the cap, 0.8 s with it, for the same output; of the corpus's conversions, only
// occt_head's with the shell rule has such edges).
constexpr size_t kFewestPointsMaxPairs = 16384;
// ... and edges where testing each piece of the sides beside them against the points of the face
// across that side takes more tests than this (chairWithCushion, 10 k vertices, spent 19 of its
// 31 s in such tests, up to 1.8e7 for one edge; the corpus needs at most 25 k).
constexpr size_t kFewestPointsMaxSideTests = size_t{1} << 18;
// The lower bound takes an edge for broken only where its margin is below minus the
// locally-Delaunay tolerance by more than this (rounding of the margin, ~1e-15).
constexpr double kBoundRounding = 1e-12;
// An input edge with a face corner below this at one end (and none at the other) is a needle of
// a fan: all its split points follow shells around that end (see split_distance).
constexpr double kNeedleCorner = std::numbers::pi / 180;
// A face with a corner below this is a thin face of a strip, which a split carries its cut
// across (see split_across_strips; 5° measured best: 3° misses couplingdown's strips, 10°
// costs boot and koala 1-2 %), unless the corner's vertex has more such input corners than
// kMaxStripCorners, or is a spike's tip (an interior vertex whose corners sum to less than
// kSpikeCone): the apex of a fan, whose needles take shells.
constexpr double kThinCorner = 5 * std::numbers::pi / 180;
inline const double kThinCornerTangent = std::tan(kThinCorner);  // for corner_below
constexpr int kMaxStripCorners = 3;
// Split points at equal fractions of the needles round a spike's tip (of unequal lengths) made
// rings out of step by the same angle at every scale, down to 1e-15 of the needles: Scopia's
// bush (tips of 5°) and tulips (petals' tips of 56-79°, two corners thin). Shells end them.
constexpr double kSpikeCone = std::numbers::pi / 2;

// Cotangent of the angle under which y sees p-q (+inf where y is on their line): the apex tests
// of point removal and placement, which compare sums of these with 0.
inline double cotangent_seen_from(const Eigen::Vector3d& y, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    const Eigen::Vector3d a = p - y, b = q - y;
    const double sine = a.cross(b).norm();
    return sine > 0 ? a.dot(b) / sine : std::numeric_limits<double>::infinity();
}

// Cotangent of the widest angle under which a point of `face` sees u-v (+inf for none).
inline double apex_cotangent(const std::vector<Eigen::Vector3d>& face, const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
    double smallest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& p : face) smallest = std::min(smallest, cotangent_seen_from(p, u, v));
    return smallest;
}

// Whether both halves of a-b, split at x, are locally Delaunay with apexes y and z (z null: a
// boundary edge), by kPlacementMargin in their cotangent sums. On a long thin piece a comfortable
// margin in angle spans a long stretch of the edge, which an inset of I0 along it misses.
inline bool halves_keep_margin(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& x,
                               const Eigen::Vector3d& y, const Eigen::Vector3d* z) {
    for (const Eigen::Vector3d* end : {&a, &b}) {
        double cotangents = cotangent_seen_from(y, *end, x);
        if (z) cotangents += cotangent_seen_from(*z, *end, x);
        if (!(cotangents >= kPlacementMargin)) return false;
    }
    return true;
}

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
    // \pre `edges` is the edge table of the mesh, which is manifold; `diagonal` is its
    //      bounding-box diagonal, in the supported range (require_supported_extent).
    Converter(const TriangleMesh& mesh, const EdgeTable& edges, double diagonal, const ConvertOptions& options)
        : options_(options),
          input_(mesh),
          input_edges_(edges),
          mesh_(mesh.F, edges.face_edge, edges.edge_halfedges, mesh.num_vertices(), spare_splits(mesh)),
          input_vertices_(mesh.num_vertices()),
          flat_angle_(flat_angle(options)),
          coplanar_angle_(options.coplanar_tolerance),
          tan_tolerance_(std::tan(options.tolerance)),
          tracks_moves_(options.method != ConvertMethod::split) {
        // The work is done at the scale of a unit diagonal, by a power of two (exact both ways):
        // far from it, the products of lengths in the tests overflow or underflow (the bunny
        // scaled by 1e150 took every hinge for flat and split on to its vertex budget), and any
        // power-of-two scaling of the input gives the same output.
        scale_exponent_ = unit_exponent(diagonal);
        const auto vertices = static_cast<size_t>(mesh.num_vertices()),
                   num_edges = static_cast<size_t>(mesh_.num_edges()), splits = static_cast<size_t>(spare_splits(mesh));
        detail::prefaulted_assign(P_, vertices, Eigen::Vector3d::Zero().eval(), vertices + splits);
        for (int v = 0; v < mesh.num_vertices(); ++v)
            for (int i = 0; i < 3; ++i) P_[v][i] = std::ldexp(mesh.V(v, i), -scale_exponent_);
        shell_unit_ = std::exp2(std::floor(std::log2(std::ldexp(diagonal, -scale_exponent_))) - 40.0);
        detail::prefaulted_assign(input_edge_, num_edges, 0, num_edges + 3 * splits);
        std::iota(input_edge_.begin(), input_edge_.end(), 0);
        detail::prefaulted_assign(in_plane_, num_edges, char{0}, num_edges + 3 * splits);
        detail::prefaulted_assign(queued_, num_edges, char{0}, num_edges + 3 * splits);
        vertex_input_edge_.reserve(splits), removed_.reserve(splits), pieces_.reserve(splits);
        if (tracks_moves_) moved_.assign(static_cast<size_t>(mesh_.num_faces()), 0);
        detail::prefaulted_assign(input_length_, num_edges, 0.0);
        detail::prefaulted_assign(input_flat_, num_edges, char{0});
#pragma omp parallel for schedule(static)
        for (int e = 0; e < mesh_.num_edges(); ++e) input_length_[e] = dist(edges.E(e, 0), edges.E(e, 1));
    }

    void run(ConversionReport& report);

    TriangleMesh result() const;
    // Where flips across folds moved the surface, for hausdorff_distance_of_edit.
    // \pre not the split method (whose faces never move and are not tracked).
    SurfaceEdit surface_edit() const;

private:
    // Room reserved for this many splits in the arrays that splits grow, whose pages are mapped
    // only when used: growing them by doubling copied every element into pages mapped anew, one
    // fault at a time (the skull, which splits a tenth of its faces' count: 5.3 -> 4.7 s).
    static int spare_splits(const TriangleMesh& mesh) { return mesh.num_faces() / 4; }

    // Pops until the queues are empty, a budget is reached, or the split that would make
    // report.splits exceed max_splits.
    void drain(ConversionReport& report, long long max_splits = std::numeric_limits<long long>::max());

    // A --progress line as a phase starts: the phases after the queue's take seconds on large
    // meshes without a line of their own.
    void announce(const char* phase, const ConversionReport& report) const {
        if (options_.progress)
            std::fprintf(stderr, "convert: %s, %lld vertices added\n", phase, report.splits - report.removed_points);
    }

    // Whether a line of --progress is due, from whichever phase runs.
    bool progress_due() { return progress_.due(); }

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
    long long added_vertices_lower_bound() const;
    // What a point on physical edge e asks of its physical outer sides (see
    // added_vertices_lower_bound): bit i, side i must get a point; bit 4 + p, one of the p-th
    // pair of sides (0-1, 0-2, 0-3, 1-2, 1-3, 2-3) must. The keep intervals propose; margins
    // decide, at one position between the two ranges that cannot meet: a side's angle at x
    // shrinks as x moves away from the side's end on e, a half's apex angles grow with it, so a
    // margin broken there stays broken on the whole range beyond.
    std::uint16_t side_requirements(int e) const;

    // By input vertex: fan_apex_, whether it is the apex of a fan of thin faces or a spike's tip
    // (see kThinCorner), and shortest_edge_, its shortest input edge.
    void classify_input_vertices();

    // Splits e where split_distance says, and carries the cut on across the strips of thin faces
    // it enters, as a loop cut: a cylinder tessellated as a ring of long faces between two rims
    // (CAD meshes are full of them) is made Delaunay by one ring of points at one height, but
    // points placed one by one at heights of their own broke their neighbours ever further along
    // the strip (rims of 400 and 397 points, 199 non-Delaunay edges: 67,117 vertices added, now
    // 797; couplingdown 8.18 -> 4.50 per non-Delaunay edge, the other corpus meshes within 0.6 %).
    // With `look_ahead`, a split that must break a physical side is placed where a trial of the
    // cascade it starts costs the fewest splits (see fewest_splits_after); not inside a trial.
    // `at`: the first split's distance from its hinge's a; < 0: where split_distance says.
    void split_across_strips(int first, ConversionReport& report, bool look_ahead, double at = -1);
    // Of the positions (distances from the hinge's a) on e, the one whose split starts the
    // cheapest cascade; the first of equals. Each is tried and taken back (splits_after). The
    // scores of least_cascading see one step ahead; a trial sees how the broken sides' own
    // splits go. Measured against the first position alone: koala 2.41 -> 2.25 vertices added
    // per non-Delaunay edge, elk 2.33 -> 2.18, mushroom 2.39 -> 2.21, boot 2.11 -> 2.01,
    // couplingdown 4.50 -> 3.78, nefertiti 1.70 -> 1.66, cheese 12.15 -> 11.76.
    double fewest_splits_after(int e, const std::vector<double>& positions);
    // The splits that splitting e at distance t from its hinge's a costs: itself with the strip
    // cuts it carries on, then what the loop splits, followed for kTrialSplits splits (or until
    // at_most), plus the edges the trial left to split. A trial must make the strip cuts the
    // real split makes: without them, a split in a drum's band of 1,000 rim points looked
    // cheapest at a height where the ring that followed did not close the strips, and the
    // conversion ran into its vertex budget (118,018 vertices instead of one ring of 2,000).
    // The edges queued before wait outside the trial, which is taken back.
    long long splits_after(int e, double t, long long at_most);

    // An outer side c-d of a split edge c-e, before the split.
    struct StripSide {
        int edge, shared, far, split_end;  // c, d, e
    };
    // Where the cut through the newest split point x on c-e goes on across outer side c-d: at x's
    // fraction of the way from c (parallel to e-d, so the face's small triangle keeps its
    // angles), if the face c-e-d is thin at c, c is no fan's apex, c-d is a fold that x broke, and
    // the face beyond c-d is thin too, at c or d, and c-d's halves will be locally Delaunay once
    // the cut has crossed that face as well. Nothing otherwise.
    std::optional<double> strip_cut(const StripSide& side) const;

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
    void split_together(ConversionReport& report);

    // Split points that later points made unnecessary go again. A point x between p and q on a
    // non-flat input edge may go when the piece p-q would be locally Delaunay against every
    // point of the planes on its two sides (the apex of a piece in a plane's Delaunay
    // triangulation is one of them); removing a point only shrinks the angles that the other
    // pieces see, so they stay locally Delaunay. Where p-q is broken only by split points, they
    // may go with x, if the pieces they leave are locally Delaunay in turn (a chain, within
    // kChainPoints, kChainTests and kChainWork): a ring of points round a wall of thin strips
    // goes only whole. Each point's spokes are flipped away until one is left on each side, the
    // split is undone, and Lawson flips restore the planes' triangulations; anything they left
    // non-Delaunay would be split again by the same loop. With `changed` (by input edge), only
    // the points of the planes next to changed edges are tried first.
    void remove_unneeded_points(ConversionReport& report, const std::vector<char>* changed = nullptr);

    // Each input edge with two or more split points gets the fewest that suffice with the
    // points of every other edge in place: from one end, each point goes as far as the piece
    // before it stays locally Delaunay, and outside the circles where it would break a piece of
    // the other edges of its faces. Inside an input face whose edges are all folds, the apex of
    // a piece is the point of the face that sees it widest (its triangulation is the Delaunay
    // triangulation of points on a triangle's boundary), so both tests read point sets, and
    // this reach is optimal on the edge: a piece inside a locally Delaunay piece is locally
    // Delaunay. Edges next to coplanar faces, whose planes triangulate together, are left as
    // they are. Returns which input edges got or lost points (empty if none did).
    std::vector<char> fewest_points_per_edge(ConversionReport& report);
    // Whether the faces of input edge e's faces' edges are all single-face planes (every edge a
    // fold): then each of e's faces is triangulated alone, and the apex of a piece of e is the
    // point of the face that sees it widest.
    bool among_folds(int e) const;
    // Replaces split points `old_points` (all those of input edge e, at least one) by points at
    // `positions`, distances from e's first end in increasing order; false if a point could not
    // be undone.
    bool place_points_again(int e, const std::vector<int>& old_points, const std::vector<double>& positions,
                            ConversionReport& report);

    // By input face: its plane, the representative of the input faces joined to it across
    // input edges that are flat at the coplanar tolerance (itself when none is).
    std::vector<int> input_planes() const;

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
    // Marks face f as moved, keeping what it covered of the input surface.
    void set_moved(int f) {
        if (moved_[f]) return;
        replaced_.push_back({{mesh_.corner(f, 0), mesh_.corner(f, 1), mesh_.corner(f, 2)}, home_[f]});
        write(moved_, f, char{1}, trial_ ? trial_->faces : 0, trial_ ? &trial_->moved : nullptr);
    }
    void set_home(int f, int home) { write(home_, f, home, trial_ ? trial_->faces : 0, trial_ ? &trial_->home : nullptr); }
    int plane_of_home(int home) const { return home >= 0 ? input_plane_[home] : home == kSpansPlanes ? -1 : -2 - home; }
    // The home of the two faces a flip makes from faces at homes g and h.
    int merged_home(int g, int h) const {
        if (g == h) return g;
        const int plane = plane_of_home(g);
        return plane >= 0 && plane == plane_of_home(h) ? -2 - plane : kSpansPlanes;
    }

    void begin_trial() {
        trial_.emplace();
        trial_->points = P_.size();
        trial_->edges = static_cast<size_t>(mesh_.num_edges());
        trial_->faces = static_cast<size_t>(mesh_.num_faces());
        trial_->replaced = replaced_.size();
        mesh_.begin_trial();
    }
    void rollback() {
        while (pop() >= 0) {}  // what a stopped drain left queued
        auto undo = [](auto& array, auto& log) {
            for (auto it = log.rbegin(); it != log.rend(); ++it) array[it->first] = it->second;
        };
        undo(input_edge_, trial_->input_edge), undo(in_plane_, trial_->in_plane);
        undo(removed_, trial_->removed), undo(pieces_, trial_->pieces);
        undo(moved_, trial_->moved), undo(home_, trial_->home);
        const size_t points = trial_->points - input_vertices_, edges = trial_->edges;
        P_.resize(trial_->points);
        vertex_input_edge_.resize(points), removed_.resize(points), pieces_.resize(points);
        input_edge_.resize(edges), in_plane_.resize(edges), queued_.resize(edges);
        if (tracks_moves_) moved_.resize(trial_->faces), home_.resize(trial_->faces), replaced_.resize(trial_->replaced);
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
    std::vector<char> local_search(ConversionReport& report);
    // Local search's second move, for the points among folds (see among_folds): split point x
    // goes, and while a piece is not locally Delaunay, a point on an edge of its faces moves to
    // where the angles that stay too wide exceed π least (min-conflicts; a random move where no
    // move narrows them), for at most kRelocationMoves moves. It runs on the points' positions
    // alone; the mesh follows when every piece is locally Delaunay again, and the drain checks.
    // Greedy placement and local_search keep each point where its neighbours left room; this
    // moves the neighbours. Returns which input edges got or lost points.
    std::vector<char> relocate_points(ConversionReport& report);

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
    bool keep_one_spoke(int into, int x, int q, ConversionReport& report);

    // Removes split point x and returns the edge that joins its neighbours on the input edge;
    // -1 if its spokes could not be reduced to one per side.
    int undo_split(int x, ConversionReport& report);

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
    // The input face on side 0 or 1 of input edge e (-1: none, beyond the boundary).
    int input_face(int e, int side) const {
        const int h = input_edges_.edge_halfedges(e, side);
        return h < 0 ? -1 : h / 3;
    }

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
    // `bound` radians. In a split conversion (whose bound is the coplanar tolerance) an edge on
    // an input edge is flat exactly when its input edge is: nothing moves, so the verdict cannot
    // change, but the faces that flips made in a plane of input faces joined within the
    // tolerance can lean on a fold inside that plane by up to the plane's whole spread. Judged by
    // them, a piece of the skull's 1.16e-5 rad fold at a coplanar tolerance of 1e-5 looked flat
    // and was flipped: the surface moved, and point removal lost the piece and walked around its
    // point without end.
    bool is_flat(int e, const AngleBound& bound) const {
        if (in_plane_[e]) return true;
        if (options_.method == ConvertMethod::split && input_edge_[e] >= 0) return input_flat_[input_edge_[e]];
        return dihedral_within(e, bound);
    }

    // Whether the face normals at interior edge e differ by at most `bound` radians.
    bool dihedral_within(int e, const AngleBound& bound) const {
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
        if (k.r == k.s || mesh_.has_diagonal(k.h)) return false;
        const double l = dist(k.a, k.b), ar = dist(k.a, k.r), br = dist(k.b, k.r), as = dist(k.a, k.s),
                     bs = dist(k.b, k.s);
        const double area_r = 4.0 * triangle_area(l, ar, br), area_s = 4.0 * triangle_area(l, as, bs);
        // The two corners at an end sum below π - 1e-9: their sum's sine and cosine, times
        // 4·l²·|side r|·|side s|, from the faces' areas and cosine numerators.
        auto below_straight = [&](double cos_r, double cos_s, double side_r, double side_s) {
            const double sine = area_r * cos_s + cos_r * area_s, cosine = cos_r * cos_s - area_r * area_s;
            return cosine >= 0 ? sine >= 0 : sine > 1e-9 * 4 * l * l * side_r * side_s;
        };
        return below_straight(cosine_numerator(br, l, ar), cosine_numerator(bs, l, as), ar, as) &&
               below_straight(cosine_numerator(ar, l, br), cosine_numerator(as, l, bs), br, bs);
    }

    // Whether a flip fixes the non-LD edge e: e is flat (within flat_angle_), flippable, and the
    // other diagonal passes the LD test. In exact arithmetic it does whenever e fails; in a nearly
    // co-circular quad of needles both verdicts are rounding (±1e-9 rad), and a flip there would
    // leave a non-LD diagonal behind, so such an edge is split instead.
    bool heals_by_flip(int e) const {
        if (!is_flat(e, flat_angle_) || !is_flippable(e)) return false;
        const Hinge k = hinge(e);
        return is_locally_delaunay_with_tangent(dist(k.r, k.s), dist(k.a, k.r), dist(k.a, k.s), dist(k.b, k.r),
                                                dist(k.b, k.s), tan_tolerance_);
    }

    void flip(int e);

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

        // The physical sides (bit i: side i) that a point at distance t from a breaks.
        unsigned physical_broken_at(double t) const {
            unsigned broken = 0;
            for (int i = 0; i < count; ++i)
                if ((physical >> i & 1u) && (t < keeps[i].lo || t > keeps[i].hi)) broken |= 1u << i;
            return broken;
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
    double split_distance(const Hinge& k, double l, std::vector<double>* alternatives = nullptr) const;

    // Where every position of `within` breaks a physical outer side, which one breaks costs a
    // vertex at least; it costs more if that side's own split must break a physical side again
    // (a cascade). Among the usual position of each choice of sides and the simplest dyadic
    // fractions of its range, the one with the most weight kept less the broken physical sides
    // whose split would cascade and the clean neighbours it spoils; the first of equals.
    // Measured against the usual position of the choice of most weight: nefertiti 1.88 -> 1.76
    // vertices added per non-Delaunay edge, boot 2.42 -> 2.22, koala 2.78 -> 2.54. With
    // `alternatives`, the candidates to try as well (see split_distance).
    double least_cascading(const Hinge& k, double l, const OuterSides& sides, Interval within, int on_input_edge,
                           std::vector<double>* alternatives) const;

    // The physical outer sides (bit i: side i) across which waits a physical non-Delaunay edge
    // that cannot be split cleanly: its split will likely break a side, and if it breaks this one,
    // one point on it serves both. Breaking them costs nothing, keeping them gains nothing.
    // Measured against scoring them like other sides: mushroom 2.56 -> 2.47 vertices added per
    // non-Delaunay edge, elk 2.42 -> 2.35, koala 2.46 -> 2.43, cheese 12.58 -> 12.11.
    unsigned sides_broken_anyway(const OuterSides& sides) const;

    // Whether outer side i of hinge k (halfedge `side`: 0 a-r, 1 b-r, 2 a-s, 3 b-s), broken by a
    // split point x at distance t from k.a, could itself be split keeping its physical outer
    // sides locally Delaunay, as split_distance would judge it with x in the mesh.
    bool side_splits_cleanly(const Hinge& k, double l, double t, int i, int side) const;

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
    CleanNeighbours clean_neighbours(const Hinge& k) const;
    // How many of `neighbours` a split point of k at distance t from k.a leaves without a clean split.
    int spoiled(const Hinge& k, double l, double t, const CleanNeighbours& neighbours) const;
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
    double sparing_neighbours(const Hinge& k, double l, Interval range, int on_input_edge) const;

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
    double usual_position(const Hinge& k, double l, Interval range, int on_input_edge) const;
    // The foot of the perpendicular from an apex of k that is a split point across a plane
    // (lies_across_plane), if both halves are locally Delaunay there and every physical outer
    // side it breaks is a thin face's long side, across which split_across_strips carries the
    // cut on. Such a point breaks pieces of the plane's far sides, whose points then break pieces
    // near it, back and forth (cheese's flat sides); at its foot the two points make a right
    // angle, which ends that: cheese 11.6 -> 10.7 vertices added per non-Delaunay edge, the other
    // corpus meshes within 0.1 %. Around a shaft of planar and warped long rectangles, the feet
    // and the strip cuts make one ring at one height (ANoisyShaftTakesRingsOfPoints: 53-71
    // vertices where the interval rule's heights of their own took up to 14,000).
    std::optional<double> foot_across_plane(const Hinge& k, double l, const OuterSides& sides, int on_input_edge) const;
    // Whether split point y lies on none of the input edges of the faces beside input edge e:
    // as an apex of a piece of e, it sees it from across a plane of several input faces.
    bool lies_across_plane(int y, int e) const;

    OuterSides outer_sides(const Hinge& k, double l, const Across* future = nullptr) const;
    // The outer sides of hinge k as halfedges of its faces, in the order a-r, b-r, a-s, b-s
    // (the first two only on the boundary).
    struct OuterHalfedges {
        std::array<int, 4> h;
        int count = 0;
    };
    OuterHalfedges outer_halfedges(const Hinge& k) const;

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
    Interval delaunay_halves_interval(const Hinge& k, double l) const;
    // The same from the lengths a-r, b-r, a-s, b-s (as < 0: no s, a boundary edge).
    static Interval halves_interval(double l, double ar, double br, double as, double bs);

    // Positions x on the edge (distance from a) that keep the outer side `side` = from-apex of the
    // hinge locally Delaunay once x is its opposite vertex. Unfolded into the plane of the face
    // (from, to, apex): x must lie outside the circle through `from`, the apex and the vertex w
    // across the side, i.e. at least D = 2·(c - from)·u from `from` along u = (to - from)/l.
    // Boundary side: x must see it at an angle <= π/2 (strict policy), a circle with the side as
    // diameter. `from_b` mirrors the result for measuring from b. `future` may stand for w.
    Interval outer_side_interval(int side, int from, int to, double l, bool from_b,
                                 const Across* future = nullptr) const;
    // The same from the lengths from-apex, to-apex, from-w, apex-w (d_w < 0: a boundary side).
    Interval side_interval(double l, double d_apex, double d_to_apex, double d_w, double d_apex_w, bool from_b) const;

    // Shells around input vertex c on the edge line of hinge k: the distance from c on the
    // coarsest grid of power-of-two multiples of the shell unit that falls in the middle third
    // of the piece a-b (length l); returned as the distance from a.
    double shell_distance_around(int c, const Hinge& k, double l) const;

    // The end of input edge e with a corner below kNeedleCorner in one of e's input faces while
    // the other end has none; -1 if there is no such end.
    int needle_end(int e) const;

    // Ruppert's concentric shells: around the endpoint that is an input vertex, at the
    // power-of-two multiple of the shell unit in the middle third; the midpoint if none or both are.
    double shell_distance(const Hinge& k, double l) const;

    // Splits e at distance `at` from the tail of its halfedge, by default where split_distance
    // says, or elsewhere as split_point says; false, changing nothing, if it says nowhere.
    bool split(int e, std::optional<double> at = std::nullopt);

    // Where to split hinge k (edge length l) for a point at distance t from k.a: there if every
    // face made has angles (see keeps_angles), else at the middle or by the apex nearest an end
    // if that keeps them; else there if the point is on no vertex of the hinge; else nowhere.
    std::optional<Eigen::Vector3d> split_point(const Hinge& k, double l, double t) const;

    // Whether x has the coordinates of a vertex of hinge k, or, within rounding of its edge's
    // ends, of a split point placed within rounding of its own edge's ends.
    bool on_a_vertex(const Hinge& k, const Eigen::Vector3d& x) const;
    bool within_rounding_of_an_end(const Hinge& k, const Eigen::Vector3d& x) const;
    // The bits of a position, for points_by_position_.
    struct PositionKey {
        std::array<std::uint64_t, 3> bits;
        bool operator==(const PositionKey&) const = default;
    };
    struct PositionHash {
        size_t operator()(const PositionKey& p) const {
            return std::hash<std::uint64_t>()(p.bits[0] ^ (p.bits[1] * 0x9e3779b97f4a7c15ULL) ^
                                              (p.bits[2] * 0xc2b2ae3d27d4eb4fULL));
        }
    };
    static PositionKey position_key(const Eigen::Vector3d& x) {
        return {{std::bit_cast<std::uint64_t>(x[0]), std::bit_cast<std::uint64_t>(x[1]),
                 std::bit_cast<std::uint64_t>(x[2])}};
    }

    // Whether every face that splitting hinge k at x makes has angles: positive area from its
    // side lengths, as certify() judges faces.
    bool keeps_angles(const Hinge& k, const Eigen::Vector3d& x) const;

    // Flat candidates first (cheap flips; see FlipQueue), then physical ones by queue_key.
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
    double queue_key(int e) const;
    void enqueue(int e, double key) {
        queued_[e] = 1;
        if (key < 0)
            flat_queue_.push(e, [this](int f) { return edge_length(f); });
        else
            physical_queue_.emplace(key, e);
    }
    double edge_length(int e) const {
        const int h = mesh_.halfedge(e);
        return dist(mesh_.tail(h), mesh_.head(h));
    }

    int pop() {
        int e = -1;
        if (!flat_queue_.empty()) {
            e = flat_queue_.pop();
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
    std::vector<char> fan_apex_;  // by input vertex, see classify_input_vertices
    std::vector<double> shortest_edge_;  // by input vertex, see classify_input_vertices
    std::vector<int> vertex_input_edge_;  // by split point: the input edge it lies on, -1 inside a face
    std::vector<char> removed_;  // by split point: removed again
    // The split points placed within rounding of an end of their edge, by position (see
    // on_a_vertex); entries of points taken back or removed are left, and checked on reading.
    std::unordered_map<PositionKey, int, PositionHash> points_by_position_;
    long long vertex_budget_ = 0;
    // Lawson's flips end in exact arithmetic; rounding can make them cycle. Each split adds edges
    // that may want flips (placing an edge's points again undoes and redoes splits), so the
    // default grows with the mesh: a CAD mesh of 8,551 edges took 1.9 million flips in all.
    [[nodiscard]] long long flip_budget() const {
        return options_.max_flips > 0 ? options_.max_flips : 100LL * mesh_.num_edges() + 1'000'000;
    }
    std::vector<std::array<int, 2>> pieces_;  // by split point on an input edge: its two pieces
    // Only flips across folds (hybrid, flip) move faces; point removal, which merges faces,
    // runs only where none moves (split).
    const bool tracks_moves_;
    // By face: may have left the input surface (made by a flip across a fold, or from a face
    // that was); the others lie in it.
    std::vector<char> moved_;
    // By face, where it lies in the input surface: inside input face h >= 0, or in plane p (see
    // input_planes) as h = -2 - p, or kSpansPlanes when moved or made by a flip across two
    // planes (which rounding of the coplanar test allows). Set once the input is classified.
    static constexpr int kSpansPlanes = -1;
    std::vector<int> home_;
    std::vector<int> input_plane_;  // by input face: input_planes()
    // The faces that were in the input surface when they moved: they cover all of it that the
    // faces never moved leave uncovered.
    struct Replaced {
        std::array<int, 3> corners;
        int home;
    };
    std::vector<Replaced> replaced_;
    // By edge: in a queue. Every edge not locally Delaunay is, but the one being split.
    std::vector<char> queued_;
    // The open trial of local_search(): what to take back if it does not pay.
    struct Trial {
        size_t points, edges, faces, replaced;  // P_, mesh_'s edges and faces, replaced_ at its start
        std::vector<std::pair<int, int>> input_edge, home;
        std::vector<std::pair<int, char>> in_plane, removed, moved;
        std::vector<std::pair<int, std::array<int, 2>>> pieces;
    };
    std::optional<Trial> trial_;
    std::vector<double> alternatives_;  // split_distance's, for split_across_strips
    long long trial_splits_ = 0;  // made by trials, all taken back
    ProgressClock progress_{options_.progress};
    detail::FlipQueue flat_queue_;
    std::priority_queue<std::pair<double, int>> physical_queue_;
};

}  // namespace sdmesh::conversion
