#include "sdmesh/delaunay.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <omp.h>

#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "number_text.hpp"
#include "prefault.hpp"

namespace sdmesh {
namespace {

// A cheap stand-in for m.radians() with the same order, for finding the least margin: one
// division instead of an arctangent. In [-2, 2]; ±0 and ±2 where atan2 gives ±0 and ±π.
double pseudo_angle(const ScaledMargin& m) {
    const double q = m.y / std::max(std::abs(m.x) + std::abs(m.y), std::numeric_limits<double>::min());
    // x < 0 or x = -0, as copysign rather than signbit, which SIMD lanes lack.
    return std::copysign(1.0, m.x) < 0 ? std::copysign(2.0, m.y) - q : q;
}

// A face seen from one of its sides, of length l: the other two sides b, c and the angle α
// opposite l (as 4·area = 2bc·sin α and cosine numerator b² + c² - l² = 2bc·cos α).
struct Wing {
    double b2, c2, b, c, area4, cosine;
};

// Always inlined: GCC vectorizes no loop that calls a function.
[[gnu::always_inline]] inline Wing wing(double l, double b2, double c2) {
    const double b = std::sqrt(b2), c = std::sqrt(c2);
    return {.b2 = b2,
            .c2 = c2,
            .b = b,
            .c = c,
            .area4 = 4.0 * triangle_area(l, b, c),
            .cosine = cosine_numerator(l, b, c)};
}

// Edges are certified a block at a time, in two loops: one gathers the hinges' squared lengths
// (random reads of memory, requested ahead), the other judges them (arithmetic only, on as many
// SIMD lanes as the compiler finds: no branch, one array per quantity). There is no per-face
// array: on a virtual machine the first write to fresh memory (~1.4 ms/MB even prefaulted) costs
// more than recomputing each face from both of its edges. Both get the same bits, since squared
// lengths, area and cosine numerator are symmetric in the sides.
constexpr int kBlock = 1024;

// The six squared lengths of a hinge ij with apexes o (first face) and p (second face): every
// verdict on an interior edge is a function of these.
struct Hinge {
    double ij, oi, oj, pi, pj, op;
};

// The hinges of a block, one array per length.
struct HingeLengths {
    double ij[kBlock], oi[kBlock], oj[kBlock], pi[kBlock], pj[kBlock], op[kBlock];

    void set(int k, const Hinge& h) {
        ij[k] = h.ij, oi[k] = h.oi, oj[k] = h.oj, pi[k] = h.pi, pj[k] = h.pj, op[k] = h.op;
    }
};

// Flags are 0 or 1 in doubles, as wide as the lengths: SIMD lanes cannot narrow them.
struct HingeVerdicts {
    double term[kBlock];          // l²(cot α + cot β)/8, the edge's share of each end's dual cell
    double angle[kBlock];         // pseudo_angle of the margin
    double non_delaunay[kBlock];  // margin < -tolerance
    double gabriel[kBlock];       // an apex strictly inside the other face's circumsphere
    double collinear[kBlock];     // a face of the hinge has zero area: no angles
};

// Judges hinges [0, size) of a block as interior edges.
void judge_hinges(const HingeLengths& in, int size, double tan_tolerance, double tolerance, HingeVerdicts& out) {
    // Is apex p strictly inside (beyond the tolerance) the circumsphere of the face w, given
    // |p - i|², |p - j|² and |p - o|²? From lengths: with the circumcentre's barycentric
    // coordinates λ_k = a_k²·cos_k/(4·area)² (a_k the side opposite corner k, cos_k the cosine
    // numerator of its angle) and R² = l²b²c²/(4·area)², |p - centre|² = Σ_k λ_k·|p - k|² - R²,
    // so p is inside iff Σ_k a_k²·cos_k·|p - k|² < 2(1 - tol)·l²b²c². A count, not an angle: the
    // cosines at i and j from squared lengths are accurate enough. Zero-area faces have no
    // circumsphere.
    const double twice_shrink = 2.0 - 2.0 * tolerance;
    const auto inside = [twice_shrink](const Wing& w, double l2, double pi2, double pj2, double po2) {
        const double cosine_i = (w.b2 + l2) - w.c2, cosine_j = (w.c2 + l2) - w.b2;
        const double power = w.c2 * cosine_i * pi2 + w.b2 * cosine_j * pj2 + l2 * w.cosine * po2;
        return w.area4 > 0 && power < twice_shrink * l2 * w.b2 * w.c2;
    };
    for (int k = 0; k < size; ++k) {
        const double l2 = in.ij[k], l = std::sqrt(l2);
        const Wing w0 = wing(l, in.oi[k], in.oj[k]), w1 = wing(l, in.pi[k], in.pj[k]);
        const ScaledMargin margin = scaled_margin(w0.area4, w0.cosine, w1.area4, w1.cosine);
        out.non_delaunay[k] = margin.locally_delaunay(tan_tolerance) ? 0.0 : 1.0;
        out.angle[k] = pseudo_angle(margin);
        const double cot_sum = margin.y / (w0.area4 * w1.area4);  // sin(α + β) / (sin α sin β)
        out.term[k] = l2 * cot_sum / 8.0;
        out.gabriel[k] = inside(w0, l2, w1.b2, w1.c2, in.op[k]) || inside(w1, l2, w0.b2, w0.c2, in.op[k]) ? 1.0 : 0.0;
        out.collinear[k] = w0.area4 > 0 && w1.area4 > 0 ? 0.0 : 1.0;
    }
}

}  // namespace

void require_delaunay_tolerance(double tolerance, std::string_view who) {
    if (!(tolerance >= 0 && tolerance < std::numbers::pi / 2))
        throw InvalidArgumentError(std::string(who) + ": tolerance must be in [0, π/2) radians, got " +
                                   detail::number_text(tolerance));
}

double delaunay_margin(double l, double a, double b, double c, double d) {
    return scaled_margin(4.0 * triangle_area(l, a, b), cosine_numerator(l, a, b), 4.0 * triangle_area(l, c, d),
                         cosine_numerator(l, c, d))
        .radians();
}

bool is_locally_delaunay(double l, double a, double b, double c, double d, double tolerance) {
    return is_locally_delaunay_with_tangent(l, a, b, c, d, std::tan(tolerance));
}

bool is_locally_delaunay_with_tangent(double l, double a, double b, double c, double d, double tan_tolerance) {
    return is_locally_delaunay_scaled(4.0 * triangle_area(l, a, b), cosine_numerator(l, a, b),
                                      4.0 * triangle_area(l, c, d), cosine_numerator(l, c, d), tan_tolerance);
}

double boundary_margin(double l, double a, double b) {
    return boundary_margin_scaled(4.0 * triangle_area(l, a, b), cosine_numerator(l, a, b));
}

double cotan_weight(double l, double a, double b, double c, double d) {
    return 0.5 * (corner_cotangent(l, a, b) + corner_cotangent(l, c, d));
}

bool is_delaunay_sqrt_free(double l, double a, double b, double c, double d) {
    const double l2 = l * l;
    return (l2 - (a - b) * (a - b)) * (l2 - (c - d) * (c - d)) <=
           ((a + b) * (a + b) - l2) * ((c + d) * (c + d) - l2);
}

DelaunayCertificate certify(const TriangleMesh& mesh, const CertifyOptions& options) {
    require_indices_in_range(mesh);
    return certify(mesh, build_edge_table(mesh.F, mesh.num_vertices()), options);
}

DelaunayCertificate certify(const TriangleMesh& mesh, const EdgeTable& edges,
                            const CertifyOptions& options) {
    require_delaunay_tolerance(options.tolerance, "certify");
    if (edges.face_edge.rows() != mesh.F.rows())
        throw InvalidArgumentError("certify: the edge table was built for another mesh");
    require_indices_in_range(mesh);
    require_finite_positions(mesh);
    const auto& F = mesh.F;
    const auto& E = edges.E;
    const auto& H = edges.edge_halfedges;
    const int num_faces = mesh.num_faces();
    const int num_edges = edges.num_edges();
    const int num_vertices = mesh.num_vertices();
    const double tol = options.tolerance;

    // Positions packed per vertex (the loop below reads them in random order) and scaled by a
    // power of two that brings the largest coordinate near 1: exact in floating point, so the
    // verdicts are those of the input, while squared lengths of coordinates near the ends of the
    // double range (1e300, 1e-300) neither overflow nor underflow. Dual areas are scaled back.
    // Of the vertices that faces use: an unreferenced one far away made every hinge tiny, and
    // their products underflowed to a "locally Delaunay" verdict.
    const std::vector<char> referenced = referenced_vertices(mesh);
    double largest = 0;
    for (int v = 0; v < num_vertices; ++v)
        if (referenced[v]) largest = std::max(largest, mesh.V.row(v).cwiseAbs().maxCoeff());
    const int exponent = unit_exponent(largest);
    const double scale = std::ldexp(1.0, -exponent);
    std::vector<Eigen::Vector3d> P(num_vertices);
    detail::prefault(P);
    for (int v = 0; v < num_vertices; ++v) P[v] = scale * mesh.V.row(v).transpose();

    DelaunayCertificate cert;
    if (options.edge_margins) {
        cert.edge_margin.resize(num_edges);
        detail::prefault(cert.edge_margin);
    }
    cert.dual_area = detail::prefaulted_constant<Eigen::VectorXd>(num_vertices, 1, 0.0);
    auto dual_magnitude = detail::prefaulted_constant<Eigen::VectorXd>(num_vertices, 1, 0.0);

    const double tan_tol = std::tan(tol);
    // The counts are integer sums and the worst edge is the first one with the least margin:
    // the same for any split of the edges.
    struct Tally {
        int interior = 0, boundary = 0, nonmanifold = 0, non_delaunay = 0, obtuse = 0, gabriel = 0;
        int beside_collinear = 0;  // manifold edges with a zero-area face
        double worst_angle = std::numeric_limits<double>::infinity();  // pseudo_angle of the margin
        int worst_edge = -1;
        void add(const Tally& other) {
            interior += other.interior, boundary += other.boundary, nonmanifold += other.nonmanifold;
            non_delaunay += other.non_delaunay, obtuse += other.obtuse, gabriel += other.gabriel;
            beside_collinear += other.beside_collinear;
            if (other.worst_angle < worst_angle || (other.worst_angle == worst_angle && other.worst_edge < worst_edge))
                worst_angle = other.worst_angle, worst_edge = other.worst_edge;
        }
    };
    // The apexes of edge e: the corners opposite it in its first two faces (the first twice on a
    // boundary edge).
    const auto apexes = [&](int e) {
        const int h0 = H(e, 0), h1 = H(e, 1) >= 0 ? H(e, 1) : h0;
        return std::pair{F(h0 / 3, h0 % 3), F(h1 / 3, h1 % 3)};
    };
    const auto gather = [&](int e) {
        const auto [o, p] = apexes(e);
        const Eigen::Vector3d &Pi = P[E(e, 0)], &Pj = P[E(e, 1)];
        return Hinge{.ij = squared_distance(Pj, Pi),
                     .oi = squared_distance(P[o], Pi),
                     .oj = squared_distance(P[o], Pj),
                     .pi = squared_distance(P[p], Pi),
                     .pj = squared_distance(P[p], Pj),
                     .op = squared_distance(P[o], P[p])};
    };
    // Edges [begin, end): their dual-area terms into term[e - begin], their verdicts into n. The
    // random reads of a later edge (face corners, then positions) are requested ahead, in two
    // stages: without this the gathering waits on memory most of the time.
    constexpr int kAhead = 32;
    const auto judge = [&](int begin, int end, double* term, Tally& n) {
        HingeLengths hinge;
        for (int e = begin; e < end; ++e) {
            if (e + 2 * kAhead < num_edges)
                for (const int h : H.row(e + 2 * kAhead))
                    if (h >= 0) __builtin_prefetch(&F(h / 3, h % 3));
            if (e + kAhead < num_edges) {
                const auto [o, p] = apexes(e + kAhead);
                __builtin_prefetch(&P[o]), __builtin_prefetch(&P[p]);
                __builtin_prefetch(&P[E(e + kAhead, 0)]), __builtin_prefetch(&P[E(e + kAhead, 1)]);
            }
            hinge.set(e - begin, gather(e));
        }
        HingeVerdicts verdict;
        judge_hinges(hinge, end - begin, tan_tol, tol, verdict);
        for (int e = begin; e < end; ++e) {
            const int k = e - begin, count = edges.face_count[e];
            if (count == 2) {
                ++n.interior;
                n.non_delaunay += verdict.non_delaunay[k] != 0;
                n.gabriel += verdict.gabriel[k] != 0;
                n.beside_collinear += verdict.collinear[k] != 0;
                if (verdict.angle[k] < n.worst_angle) n.worst_angle = verdict.angle[k], n.worst_edge = e;
                term[k] = verdict.term[k];
            } else if (count == 1) {
                ++n.boundary;
                const Wing w = wing(std::sqrt(hinge.ij[k]), hinge.oi[k], hinge.oj[k]);
                n.obtuse += w.cosine < -tan_tol * w.area4;  // π/2 - α < -tol
                n.beside_collinear += !(w.area4 > 0);
                term[k] = hinge.ij[k] * (w.cosine / w.area4) / 8.0;
            } else {
                ++n.nonmanifold;
                term[k] = 0;
            }
        }
    };
    // Per-edge margins, on request: an arctangent each.
    const auto margin = [&](int e) {
        const Hinge hinge = gather(e);
        const double l = std::sqrt(hinge.ij);
        const Wing w0 = wing(l, hinge.oi, hinge.oj);
        switch (edges.face_count[e]) {
            case 1: return boundary_margin_scaled(w0.area4, w0.cosine);
            case 2: {
                const Wing w1 = wing(l, hinge.pi, hinge.pj);
                return scaled_margin(w0.area4, w0.cosine, w1.area4, w1.cosine).radians();
            }
            default: return std::numeric_limits<double>::quiet_NaN();
        }
    };
    // The dual areas, summed in edge order so that they are bit-identical for any thread count.
    const auto add = [&](int begin, int end, const double* term) {
        for (int e = begin; e < end; ++e) {
            if (e + kAhead < end) {
                const int far_end = E(e + kAhead, 1);  // the near ends are in edge order
                __builtin_prefetch(&cert.dual_area[far_end]), __builtin_prefetch(&dual_magnitude[far_end]);
            }
            for (int side = 0; side < 2; ++side) {
                cert.dual_area[E(e, side)] += term[e - begin];
                dual_magnitude[E(e, side)] += std::abs(term[e - begin]);
            }
        }
    };

    const int num_blocks = (num_edges + kBlock - 1) / kBlock;
    Tally n;
    if (omp_get_max_threads() == 1) {
        // One thread adds the terms of each block while they are in cache: no per-edge array.
        double term[kBlock];
        for (int block = 0; block < num_blocks; ++block) {
            const int begin = block * kBlock, end = std::min(begin + kBlock, num_edges);
            judge(begin, end, term, n);
            add(begin, end, term);
        }
    } else {
        // Several threads keep every term and one adds them after the loop. (Adding block after
        // block in an ordered section instead stalls the whole team whenever one thread is
        // descheduled: 2-6x slower on a busy 2-core machine.)
        Eigen::VectorXd term(num_edges);
        detail::prefault(term);
#pragma omp parallel
        {
            Tally local;
#pragma omp for schedule(static)
            for (int block = 0; block < num_blocks; ++block) {
                const int begin = block * kBlock, end = std::min(begin + kBlock, num_edges);
                judge(begin, end, &term[begin], local);
            }
#pragma omp critical
            n.add(local);
        }
        add(0, num_edges, term.data());
    }
    if (options.edge_margins) {
#pragma omp parallel for schedule(static)
        for (int e = 0; e < num_edges; ++e) cert.edge_margin[e] = margin(e);
    }
    cert.interior_edges = n.interior;
    cert.boundary_edges = n.boundary;
    cert.nonmanifold_edges = n.nonmanifold;
    cert.non_delaunay_edges = n.non_delaunay;
    cert.boundary_obtuse_edges = n.obtuse;
    cert.negative_cotan_weights = n.non_delaunay + n.obtuse;
    cert.gabriel_violations = n.gabriel;
    cert.worst_edge = n.worst_edge;
    if (n.worst_edge >= 0) cert.min_delaunay_margin = margin(n.worst_edge);

    for (int v = 0; v < num_vertices; ++v)
        if (dual_magnitude[v] > 0 || !std::isfinite(dual_magnitude[v]))
            cert.negative_dual_cells += !(cert.dual_area[v] >= -tol * dual_magnitude[v]);
    cert.dual_area *= std::ldexp(1.0, 2 * exponent);  // back to the input's units (may be ±inf or 0)

    cert.repeated_index_faces = 0;
    for (int f = 0; f < num_faces; ++f) cert.repeated_index_faces += has_repeated_index(F, f);
    // Faces are counted one by one only when the edges saw one (or could not: a face whose
    // edges are all non-manifold is not judged through them).
    if (n.beside_collinear > 0 || n.nonmanifold > 0) {
        int collinear = 0;
#pragma omp parallel for schedule(static) reduction(+ : collinear)
        for (int f = 0; f < num_faces; ++f) {
            const Eigen::Vector3d &p = P[F(f, 0)], &q = P[F(f, 1)], &r = P[F(f, 2)];
            collinear += !has_repeated_index(F, f) && !(triangle_area(distance(q, r), distance(r, p), distance(p, q)) > 0);
        }
        cert.collinear_faces = collinear;
    }
    cert.nonmanifold_vertices = static_cast<int>(edges.nonmanifold_vertices.size());
    const bool boundary_ok = options.boundary == BoundaryPolicy::free || cert.boundary_obtuse_edges == 0;
    cert.self_delaunay = cert.nonmanifold_edges == 0 && cert.nonmanifold_vertices == 0 &&
                         cert.repeated_index_faces == 0 && cert.collinear_faces == 0 && cert.non_delaunay_edges == 0 &&
                         boundary_ok;
    return cert;
}

}  // namespace sdmesh
