#pragma once
// Edge collapses in cheapest-first order on a MeshState (internal, not installed): a queue of
// candidate collapses keyed by a lower bound of their cost, the evaluation of a candidate
// (ALGORITHMS.md §4: link condition, placement in the allowable region, exact LD tests, error
// bound) and the collapse itself.
//
// A collapser works on the whole mesh, or on one half of it: then it evaluates only collapses
// whose star lies inside its half (every vertex of the star owned by it, see MeshState::owner),
// and hands the others over. Such a collapse reads only faces of its half and vertices that no
// collapse of the other half changes, and writes only vertices it owns and faces of its half —
// so the collapsers of the two halves can run side by side, each with the same result as alone.

#include <optional>
#include <utility>
#include <vector>

#include "decimate/flat_flips.hpp"
#include "decimate/mesh_state.hpp"
#include "progress_clock.hpp"
#include "sdmesh/decimate.hpp"

namespace sdmesh::decimation {

class Collapser {
public:
    /// `half` 0 or 1 for a half's collapser, -1 for the whole mesh.
    Collapser(MeshState& mesh, const DecimateOptions& options, int half);

    [[nodiscard]] long long collapses() const { return collapses_; }
    [[nodiscard]] const DecimateRejections& rejected() const { return rejected_; }
    [[nodiscard]] size_t queued() const { return queue_.size(); }

    // The clock numbers collapses for MeshState::touched. Collapsers that take turns on the same
    // vertices are set to the latest clock of all before each turn; the halves' collapsers, side
    // by side, touch different vertices.
    [[nodiscard]] long long clock() const { return clock_; }
    void set_clock(long long clock) { clock_ = clock; }

    /// Queues the collapse of edge [u, w], u < w, keyed by its lower bound.
    void push(int u, int w);

    /// Collapses while the least key queued is at most `threshold`, at most `quota` times; a
    /// line on stderr when `progress` (null: none) says one is due.
    void collapse_below(double threshold, long long quota, ProgressClock* progress);

    /// Collapses `count` times; false when no allowable collapse is left first (collapses refused
    /// too often wait for the next round, which starts when the queue runs dry; a round without a
    /// collapse means that nothing allowable is left). A line on stderr when `progress` says one
    /// is due.
    bool collapse_count(long long count, ProgressClock& progress);

    /// The keys queued, appended to `out`.
    void append_keys(std::vector<double>& out) const;

    /// Queues the collapses this half's collapser handed over with `to`.
    void hand_over_to(Collapser& to);
    /// Moves everything queued, handed over or deferred to `to`.
    void move_all_to(Collapser& to);
    /// Moves the queued collapses of edges whose ends `to`'s half owns to `to`.
    void move_owned_to(Collapser& to);

private:
    // A placement that passed the checks, and the clock then.
    struct Checked {
        Vec3 x;
        long long clock;
    };

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
        int before = -1;  // the star face (v, c, a) sharing spoke v-a, -1 if that spoke is on the boundary
        int after = -1;   // the star face (v, b, d) sharing spoke v-b, -1 if that spoke is on the boundary
        int across = -1;  // the face on the other side of a-b, -1 on the boundary
        int w = -1;       // its vertex opposite a-b
        // What the checks and the allowable region of every placement share: the old normal, |ab|,
        // the angle at w as 4·area and cosine numerator of (a, b, w), and |wa| + |wb|.
        Vec3 normal = Vec3::Zero();
        double ab = 0, across_area4 = 0, across_cosine = 0, across_sides = 0;
    };

    // Per star face and placement x: |xa|, |xb|, and the triangle (x, a, b) as 4·area and the
    // cosine numerators of its angles at x, a and b — each computed once, though the spoke and
    // link tests use them several times.
    struct StarTriangle {
        double xa, xb, area4, cosine_x, cosine_a, cosine_b;
    };

    // n·x >= c.
    struct HalfSpace {
        Vec3 n;
        double c;
    };

    // How the new vertex of a collapse may move.
    enum class Placement { free, on_edge, fixed };

    // outside_half: only flips beyond the half would make the collapse allowable.
    enum class Verdict { accepted, topology, not_delaunay, normal_flip, max_error, outside_half };

    void step();
    void enqueue(const Candidate& c, const Checked* checked);
    Candidate pop();

    bool topology_allows(int p, int q);
    bool star_owned(int p, int q) const;
    static bool inside(const std::vector<HalfSpace>& region, const Vec3& x, double slack);
    Placement placement(int p, int q) const;
    void allowable_region(int p, int q, std::vector<HalfSpace>& region) const;
    std::optional<Vec3> region_minimum(const Quadric& q, const Eigen::Matrix3d& inverse, const Vec3& optimum,
                                       const std::vector<HalfSpace>& region, double slack);
    void placements(int p, int q, const Quadric& quadric);
    double collapse_cost(const Quadric& quadric, int p, int q, const Vec3& x) const;
    Verdict check(int p, int q, const Vec3& x);
    Verdict resolve_by_flips(int p, int q, const Vec3& x, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);
    Verdict evaluate(int p, int q, Vec3& x, double& cost);
    void count_rejection(Verdict v);
    void collapse(int p, int q, const Vec3& x);
    void refuse(int u, int w);
    bool untouched_since(int p, int q, long long clock) const;
    int store_checked(const Checked& c);
    bool within_error(int p, int q, const Vec3& x);
    void commit_error_tracking();

    MeshState& mesh_;
    const DecimateOptions& options_;
    const double tan_tolerance_;
    const int half_;
    std::vector<Candidate> queue_;  // a min-heap (std::greater)
    std::vector<Checked> checked_;  // of the queued candidates with checked >= 0
    std::vector<int> free_checked_;  // unused entries of checked_
    std::vector<std::pair<int, int>> deferred_;  // refused too often: retried in the next round
    std::vector<std::pair<int, int>> handed_over_;  // a half's collapses whose star leaves the half
    bool round_open_ = false;  // deferred collapses came from another collapser since this one's last round
    long long collapses_ = 0;
    long long collapses_before_round_ = 0;
    long long clock_ = 0;
    DecimateRejections rejected_;
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
    FlatFlips flat_flips_;
    bool flips_needed_ = false;  // the last accepted check needs flat_flips_
    std::vector<int> star_faces_, changed_;
    std::vector<std::pair<int, int>> flipped_in_, flipped_out_;  // edges the flips made and removed
    std::vector<std::pair<int, int>> rehomed_;  // of the error bound
    std::vector<Vec3> samples_;
};

}  // namespace sdmesh::decimation
