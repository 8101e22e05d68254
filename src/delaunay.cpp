#include "sdmesh/delaunay.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cmath>
#include <limits>
#include <vector>

#include <omp.h>

#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "prefault.hpp"

namespace sdmesh {
namespace {

// A cheap stand-in for m.radians() with the same order, for finding the least margin: one
// division instead of an arctangent, and no branch (the signs of x come in no predictable order).
// In [-2, 2]; ±0 and ±2 where atan2 gives ±0 and ±π.
double pseudo_angle(const ScaledMargin& m) {
    const double q = m.y / std::max(std::abs(m.x) + std::abs(m.y), std::numeric_limits<double>::min());
    const double beyond_right_angle = std::copysign(2.0, m.y) - q;  // for x < 0 (or x = -0)
    const std::uint64_t take = std::signbit(m.x) ? ~std::uint64_t{0} : 0;
    return std::bit_cast<double>((std::bit_cast<std::uint64_t>(beyond_right_angle) & take) |
                                 (std::bit_cast<std::uint64_t>(q) & ~take));
}

}  // namespace

double delaunay_margin(double l, double a, double b, double c, double d) {
    return scaled_margin(4.0 * triangle_area(l, a, b), cosine_numerator(l, a, b), 4.0 * triangle_area(l, c, d),
                         cosine_numerator(l, c, d))
        .radians();
}

bool is_locally_delaunay(double l, double a, double b, double c, double d, double tolerance) {
    return is_locally_delaunay_scaled(4.0 * triangle_area(l, a, b), cosine_numerator(l, a, b),
                                      4.0 * triangle_area(l, c, d), cosine_numerator(l, c, d), std::tan(tolerance));
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
    if (!(options.tolerance >= 0)) throw InvalidArgumentError("certify: tolerance must be >= 0");
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
    const double largest = mesh.V.size() > 0 ? mesh.V.cwiseAbs().maxCoeff() : 0.0;
    const int exponent = largest > 0 ? std::ilogb(largest) : 0;
    const double scale = std::ldexp(1.0, -exponent);
    std::vector<Eigen::Vector3d> P(num_vertices);
    detail::prefault(P);
    for (int v = 0; v < num_vertices; ++v) P[v] = scale * mesh.V.row(v).transpose();

    // No per-face array: each edge recomputes what it needs of its faces from the four vertices
    // of its hinge, since on a virtual machine the first write to fresh memory (~1.4 ms/MB even
    // prefaulted) costs more than this arithmetic. A side length is the distance of the same two
    // points whichever face asks, and area and cosine numerator are symmetric in the sides, so
    // every face gets the same bits from both of its edges.
    struct Wing {           // face of halfedge h, seen from its side (l, b, c) = (ij, oi, oj)
        const Eigen::Vector3d* apex;  // o, the corner opposite the edge
        double b, c, b2, c2;          // |o - i|, |o - j| and their squares
        double area4, cosine;         // 4·area, b² + c² - l²
    };
    const auto wing = [&](int h, int i, int j, double l) {
        Wing w;
        w.apex = &P[F(h / 3, h % 3)];
        w.b2 = squared_distance(*w.apex, P[i]);
        w.c2 = squared_distance(*w.apex, P[j]);
        w.b = std::sqrt(w.b2), w.c = std::sqrt(w.c2);
        w.area4 = 4.0 * triangle_area(l, w.b, w.c);
        w.cosine = cosine_numerator(l, w.b, w.c);
        return w;
    };
    // Is the apex p of the other wing strictly inside (beyond the tolerance) the circumsphere of
    // w, given |p - i|², |p - j|² and |p - o|²? From lengths: with the circumcentre's barycentric
    // coordinates λ_k = a_k²·cos_k/(4·area)² (a_k the side opposite corner k, cos_k the cosine
    // numerator of its angle) and R² = l²b²c²/(4·area)², |p - centre|² = Σ_k λ_k·|p - k|² - R²,
    // so p is inside iff Σ_k a_k²·cos_k·|p - k|² < 2(1 - tol)·l²b²c². A count, not an angle: the
    // cosines at i and j from squared lengths are accurate enough. Zero-area faces have no
    // circumsphere.
    const double twice_shrink = 2.0 - 2.0 * tol;
    const auto inside = [twice_shrink](const Wing& w, double l2, double pi2, double pj2, double po2) {
        const double cosine_i = (w.b2 + l2) - w.c2, cosine_j = (w.c2 + l2) - w.b2;
        const double power = w.c2 * cosine_i * pi2 + w.b2 * cosine_j * pj2 + l2 * w.cosine * po2;
        return (w.area4 > 0) & (power < twice_shrink * l2 * w.b2 * w.c2);
    };
    const double tan_tol = std::tan(tol);

    DelaunayCertificate cert;
    if (options.edge_margins) {
        cert.edge_margin.resize(num_edges);
        detail::prefault(cert.edge_margin);
    }
    cert.dual_area = detail::prefaulted_constant<Eigen::VectorXd>(num_vertices, 1, 0.0);
    auto dual_magnitude = detail::prefaulted_constant<Eigen::VectorXd>(num_vertices, 1, 0.0);

    // Per edge of [begin, end): LD verdict, dual-area term l²(cot α + cot β)/8 (into
    // term[e - begin]) and Gabriel test. The counts are integer sums and the worst edge is the
    // first one with the least margin: the same for any split of the edges.
    struct Tally {
        int interior = 0, boundary = 0, nonmanifold = 0, non_delaunay = 0, obtuse = 0, gabriel = 0;
        double worst_angle = std::numeric_limits<double>::infinity();  // pseudo_angle of the margin
        int worst_edge = -1;
        void add(const Tally& other) {
            interior += other.interior, boundary += other.boundary, nonmanifold += other.nonmanifold;
            non_delaunay += other.non_delaunay, obtuse += other.obtuse, gabriel += other.gabriel;
            if (other.worst_angle < worst_angle || (other.worst_angle == worst_angle && other.worst_edge < worst_edge))
                worst_angle = other.worst_angle, worst_edge = other.worst_edge;
        }
    };
    // The random reads (face corners, then positions) of a later edge are requested ahead, in
    // two stages: without this the loop waits on memory most of the time.
    constexpr int kAhead = 16;
    const auto judge = [&](int begin, int end, double* term, Tally& n) {
        for (int e = begin; e < end; ++e) {
            if (e + 2 * kAhead < num_edges)
                for (const int h : H.row(e + 2 * kAhead))
                    if (h >= 0) __builtin_prefetch(&F(h / 3, h % 3));
            if (e + kAhead < num_edges) {
                for (const int h : H.row(e + kAhead))
                    if (h >= 0) __builtin_prefetch(&P[F(h / 3, h % 3)]);
                __builtin_prefetch(&P[E(e + kAhead, 0)]), __builtin_prefetch(&P[E(e + kAhead, 1)]);
            }
            const int count = edges.face_count[e];
            if (count > 2) {
                ++n.nonmanifold;
                if (options.edge_margins) cert.edge_margin[e] = std::numeric_limits<double>::quiet_NaN();
                term[e - begin] = 0;
                continue;
            }
            const int i = E(e, 0), j = E(e, 1);
            const double l2 = squared_distance(P[j], P[i]), l = std::sqrt(l2);
            const Wing w0 = wing(H(e, 0), i, j, l);
            double cot_sum;
            if (count == 2) {
                ++n.interior;
                const Wing w1 = wing(H(e, 1), i, j, l);
                const ScaledMargin margin = scaled_margin(w0.area4, w0.cosine, w1.area4, w1.cosine);
                n.non_delaunay += !margin.locally_delaunay(tan_tol);
                const double angle = pseudo_angle(margin);
                if (angle < n.worst_angle) n.worst_angle = angle, n.worst_edge = e;
                if (options.edge_margins) cert.edge_margin[e] = margin.radians();
                cot_sum = margin.y / (w0.area4 * w1.area4);  // cot α + cot β = sin(α + β) / (sin α sin β)
                const double apexes2 = squared_distance(*w0.apex, *w1.apex);
                n.gabriel += inside(w0, l2, w1.b2, w1.c2, apexes2) | inside(w1, l2, w0.b2, w0.c2, apexes2);
            } else {
                ++n.boundary;
                n.obtuse += w0.cosine < -tan_tol * w0.area4;  // π/2 - α < -tol
                if (options.edge_margins) cert.edge_margin[e] = boundary_margin_scaled(w0.area4, w0.cosine);
                cot_sum = w0.cosine / w0.area4;
            }
            term[e - begin] = l2 * cot_sum / 8.0;
        }
    };
    // The dual areas, summed in edge order so that they are bit-identical for any thread count.
    const auto add = [&](int begin, int end, const double* term) {
        for (int e = begin; e < end; ++e)
            for (int side = 0; side < 2; ++side) {
                cert.dual_area[E(e, side)] += term[e - begin];
                dual_magnitude[E(e, side)] += std::abs(term[e - begin]);
            }
    };

    constexpr int kBlock = 2048;
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
    cert.interior_edges = n.interior;
    cert.boundary_edges = n.boundary;
    cert.nonmanifold_edges = n.nonmanifold;
    cert.non_delaunay_edges = n.non_delaunay;
    cert.boundary_obtuse_edges = n.obtuse;
    cert.negative_cotan_weights = n.non_delaunay + n.obtuse;
    cert.gabriel_violations = n.gabriel;
    cert.worst_edge = n.worst_edge;
    if (n.worst_edge >= 0) {
        const int e = n.worst_edge, i = E(e, 0), j = E(e, 1);
        const double l = distance(P[i], P[j]);
        const Wing w0 = wing(H(e, 0), i, j, l), w1 = wing(H(e, 1), i, j, l);
        cert.min_delaunay_margin = scaled_margin(w0.area4, w0.cosine, w1.area4, w1.cosine).radians();
    }

    for (int v = 0; v < num_vertices; ++v)
        if (dual_magnitude[v] > 0 || !std::isfinite(dual_magnitude[v]))
            cert.negative_dual_cells += !(cert.dual_area[v] >= -tol * dual_magnitude[v]);
    cert.dual_area *= std::ldexp(1.0, 2 * exponent);  // back to the input's units (may be ±inf or 0)

    cert.repeated_index_faces = 0;
    for (int f = 0; f < num_faces; ++f) cert.repeated_index_faces += has_repeated_index(F, f);
    cert.nonmanifold_vertices = static_cast<int>(edges.nonmanifold_vertices.size());
    const bool boundary_ok = options.boundary == BoundaryPolicy::free || cert.boundary_obtuse_edges == 0;
    cert.self_delaunay = cert.nonmanifold_edges == 0 && cert.nonmanifold_vertices == 0 &&
                         cert.repeated_index_faces == 0 && cert.non_delaunay_edges == 0 && boundary_ok;
    return cert;
}

}  // namespace sdmesh
