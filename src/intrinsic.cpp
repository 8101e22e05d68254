#include "sdmesh/intrinsic.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "flip_queue.hpp"
#include "halfedge.hpp"
#include "prefault.hpp"
#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"

namespace sdmesh {
namespace {

// Factors that keep a clamped length a few ulps inside the triangle inequality, so that Kahan's
// area of the new faces stays positive (Triangulation::check() requires it).
constexpr double kBelow = 1 - 32 * std::numeric_limits<double>::epsilon();
constexpr double kAbove = 1 + 32 * std::numeric_limits<double>::epsilon();

// How many pops ahead the flip loop requests face records.
constexpr size_t kLookahead = 4;

// Length of the new diagonal r-s of the hinge p, q, r, s (notation of ALGORITHMS.md §1:
// l = |pq|, a = |rp|, b = |rq|, c = |sp|, d = |sq|). The hinge is laid out in the plane with p at
// the origin, q at (l, 0), r = (x_r, y_r) above and s = (x_s, -y_s) below the axis, where
// x_r = (l² + a² - b²)/(2l) and y_r = 2·area(l, a, b)/l (likewise s with c, d). Then
//   |rs|² = (x_r - x_s)² + (y_r + y_s)²,  x_r - x_s = ((a - b)(a + b) - (c - d)(c + d)) / (2l):
// l² cancels exactly in the difference, each product is accurate, and the y-term adds two
// positive Kahan areas, so nothing cancels catastrophically beyond what the data dictate.
// A non-LD hinge is a strictly convex quadrilateral, so the exact |rs| lies strictly inside the
// triangle inequalities of the new faces (r, p, s) and (s, q, r); when its angle at p or q is
// within ~1e-8 of π, rounding can push the computed value onto or past a bound, and the clamp
// below moves it back by a few ulps (a rounding-level change of the metric). No length fits
// when the bounds cross, which a hinge flat within rounding allows (both faces of nearly zero
// area, its four vertices nearly on a line): the flip would make a face of zero area, and the
// edge is left as it is (nullopt). Two such slivers of an unseen mesh (speaker3.obj) were
// flipped into one of zero area, whose cotangents came out infinite.
std::optional<double> flipped_length(double l, double a, double b, double c, double d) {
    const double dx = ((a - b) * (a + b) - (c - d) * (c + d)) / (2 * l);
    const double dy = 2 * (triangle_area(l, a, b) + triangle_area(l, c, d)) / l;
    const double lower = std::max(std::abs(a - c), std::abs(b - d)) * kAbove;
    const double upper = std::min(a + c, b + d) * kBelow;
    if (lower > upper) return std::nullopt;
    return std::min(std::max(std::sqrt(dx * dx + dy * dy), lower), upper);
}

// The hinge of an edge: h runs p -> q in face (r, p, q), its twin q -> p in (s, q, p); l = |pq|,
// a = |rp|, b = |qr|, c = |ps|, d = |sq|.
struct Hinge {
    int h = -1, tw = -1;
    double l = 0, a = 0, b = 0, c = 0, d = 0;
};

// Whether edge e is interior and not LD within the tolerance, with its hinge. An edge whose two
// sides lie in one face never is: its opposite angles are two corners of one triangle.
bool needs_flip(const HalfedgeMesh& mesh, int e, double tolerance, Hinge& hinge) {
    const int h = mesh.halfedge(e), tw = mesh.twin(h);
    if (tw < 0 || HalfedgeMesh::face(h) == HalfedgeMesh::face(tw)) return false;
    hinge = {h,
             tw,
             mesh.side_length(h),
             mesh.side_length(HalfedgeMesh::prev(h)),
             mesh.side_length(HalfedgeMesh::next(h)),
             mesh.side_length(HalfedgeMesh::next(tw)),
             mesh.side_length(HalfedgeMesh::prev(tw))};
    // Two non-obtuse opposite angles make the edge LD (the cheap test first).
    if (cosine_numerator(hinge.l, hinge.a, hinge.b) >= 0 && cosine_numerator(hinge.l, hinge.c, hinge.d) >= 0)
        return false;
    return !is_locally_delaunay(hinge.l, hinge.a, hinge.b, hinge.c, hinge.d, tolerance);
}

// The two faces of every interior edge must run along it in opposite directions, i.e. its
// face_edge_sign entries sum to 0 (a self-edge cannot tell, and needs no check): flips rely on it.
// Summed in one sequential pass over the faces, since random access to the signs is slow.
void require_oriented(const Triangulation& t) {
    std::vector<signed char> sign_sum(t.num_edges(), 0);
    for (int k = 0; k < 3; ++k)
        for (int f = 0; f < t.num_faces(); ++f) {
            signed char& sum = sign_sum[t.face_edge(f, k)];
            sum = static_cast<signed char>(sum + t.face_edge_sign(f, k));
        }
    for (int e = 0; e < t.num_edges(); ++e) {
        const int h0 = t.edge_halfedges(e, 0), h1 = t.edge_halfedges(e, 1);
        if (h1 >= 0 && t.E(e, 0) != t.E(e, 1) && sign_sum[e] != 0)
            throw InvalidMeshError("intrinsic_delaunay: faces " + std::to_string(h0 / 3) + " and " +
                                   std::to_string(h1 / 3) + " run along edge " + std::to_string(e) + " (" +
                                   std::to_string(t.E(e, 0)) + ", " + std::to_string(t.E(e, 1)) +
                                   ") in the same direction; the triangulation is not consistently oriented");
    }
}

// Self-edges and repeated edges (non-self edges joining the same two vertices as an edge of
// smaller id) in O(|V| + |E|): edges bucketed by their lower end, in id order, then each bucket
// scanned with a per-vertex stamp of the last bucket that reached it.
void count_improper_edges(const Triangulation& t, IntrinsicReport& report) {
    const int nv = t.num_vertices, ne = t.num_edges();
    std::vector<int> begin(static_cast<size_t>(nv) + 1, 0);
    for (int e = 0; e < ne; ++e) ++begin[t.E(e, 0) + 1];
    for (int v = 0; v < nv; ++v) begin[v + 1] += begin[v];
    std::vector<int> bucket(ne), cursor(begin.begin(), begin.end() - 1);
    for (int e = 0; e < ne; ++e) bucket[cursor[t.E(e, 0)]++] = e;
    std::vector<int> stamp(nv, -1);
    for (int v = 0; v < nv; ++v)
        for (int i = begin[v]; i < begin[v + 1]; ++i) {
            const int w = t.E(bucket[i], 1);
            if (w == v) ++report.self_edges;
            else if (stamp[w] == v) ++report.repeated_edges;
            else stamp[w] = v;
        }
    report.proper = report.self_edges == 0 && report.repeated_edges == 0;
}

}  // namespace

IntrinsicResult intrinsic_delaunay(const Triangulation& t, const IntrinsicOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    require_delaunay_tolerance(options.tolerance, "intrinsic_delaunay");
    t.check();
    require_oriented(t);

    HalfedgeMesh mesh(t);
    // Flips run at a unit mean edge length, reached by a power of two (exact both ways): the LD
    // test multiplies four lengths, which overflowed from lengths of about 1e75 on (the bunny at
    // 2^450 made 1.55 million flips, at 2^-460 none).
    const int exponent = t.num_edges() > 0 ? unit_exponent(t.length.mean()) : 0;
    const double to_unit = std::ldexp(1.0, -exponent);
    Eigen::VectorXd length = to_unit * t.length;
    double* const len = length.data();
    const int ne = t.num_edges();
    const long long budget = options.max_flips >= 0 ? options.max_flips : 100LL * ne + 1'000'000;
    const double tolerance = options.tolerance;

    const auto loop_start = std::chrono::steady_clock::now();
    // Lawson's loop on a FlipQueue of candidate edges; `queued` keeps an edge on it at most
    // once. The initial candidates are the edges facing an obtuse corner: with both opposite
    // angles <= π/2 an edge is LD, and it can only lose that when a flip changes its hinge,
    // which pushes it. They are stacked so that they pop in id order; after a flip the four
    // outer edges of its hinge are pushed and so tested next, while they are still in cache.
    std::vector<char> queued;
    detail::prefaulted_assign(queued, static_cast<size_t>(ne), char{0});
    std::vector<char> flat_hinge(static_cast<size_t>(ne), 0);  // left unflipped (flipped_length)
    // The same pass copies the edge lengths onto the sides of the mesh, so that a hinge test
    // reads two face records instead of five scattered edge lengths.
    for (int f = 0; f < t.num_faces(); ++f) {
        detail::prefetch_sides_ahead(t, f);
        for (int k = 0; k < 3; ++k) {
            mesh.set_side_length(3 * f + k, to_unit * t.side(f, k));
            if (cosine_numerator(t.side(f, k), t.side(f, (k + 1) % 3), t.side(f, (k + 2) % 3)) < 0)
                queued[t.face_edge(f, k)] = 1;
        }
    }
    detail::FlipQueue queue;
    const auto length_of = [len](int e) { return len[e]; };
    for (int e = ne - 1; e >= 0; --e)
        if (queued[e]) queue.push(e, length_of);
    auto push = [&](int e) {
        if (!queued[e]) queued[e] = 1, queue.push(e, length_of);
    };
    long long flips = 0;
    const long long longest_first_from = detail::kFlipsPerEdgeBeforeLongestFirst * ne;
    bool exhausted = false;
    while (!queue.empty()) {
        if (flips > longest_first_from) queue.longest_first(length_of);
        const int e = queue.pop();
        queued[e] = 0;
        // A test waits on two random face records; request those of the candidates a few pops
        // down the stack, in two steps since the second face is read from the first.
        const std::vector<int>& stack = queue.stack();
        const size_t n = stack.size();
        if (n > 2 * kLookahead) mesh.prefetch(mesh.halfedge(stack[n - 1 - 2 * kLookahead]));
        if (n > kLookahead) mesh.prefetch(mesh.twin(mesh.halfedge(stack[n - 1 - kLookahead])));
        Hinge hinge;
        if (!needs_flip(mesh, e, tolerance, hinge)) continue;
        if (flips == budget) {
            exhausted = true;
            break;
        }
        const std::optional<double> flipped = flipped_length(hinge.l, hinge.a, hinge.b, hinge.c, hinge.d);
        if (!flipped) {
            flat_hinge[e] = 1;  // counted at the end, unless a later flip makes it LD
            continue;
        }
        const int h = hinge.h, tw = hinge.tw;
        const int h_qr = HalfedgeMesh::next(h), h_rp = HalfedgeMesh::prev(h);
        const int h_ps = HalfedgeMesh::next(tw), h_sq = HalfedgeMesh::prev(tw);
        const int e_rp = mesh.edge(h_rp), e_qr = mesh.edge(h_qr);
        const int e_ps = mesh.edge(h_ps), e_sq = mesh.edge(h_sq);
        const double rs = *flipped;
        len[e] = rs;
        mesh.flip(e);
        mesh.set_side_length(mesh.halfedge(e), rs);  // both sides of e, now s->r and r->s
        mesh.set_side_length(mesh.twin(mesh.halfedge(e)), rs);
        // The outer edges are tested next, each needing the face across it.
        const int f = HalfedgeMesh::face(h), g = HalfedgeMesh::face(tw);
        for (const int side : {3 * f, 3 * f + 2, 3 * g, 3 * g + 2}) mesh.prefetch(mesh.twin(side));
        ++flips;
        push(e_rp), push(e_qr), push(e_ps), push(e_sq);
    }
    const auto loop_end = std::chrono::steady_clock::now();

    length *= std::ldexp(1.0, exponent);
    IntrinsicResult result{mesh.to_triangulation(std::move(length)), {}};
    IntrinsicReport& report = result.report;
    report.flip_seconds = std::chrono::duration<double>(loop_end - loop_start).count();
    report.flips = flips;
    for (int e = 0; e < ne; ++e) {
        Hinge hinge;
        if (flat_hinge[e] && needs_flip(mesh, e, tolerance, hinge)) ++report.unflippable_edges;
    }
    report.status = exhausted                      ? "flip_budget_exhausted"
                    : report.unflippable_edges > 0 ? "unflippable_edges"
                                                   : "delaunay";
    count_improper_edges(result.triangulation, report);
    report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace sdmesh
