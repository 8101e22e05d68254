#include "sdmesh/delaunay.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <omp.h>

#include "sdmesh/error.hpp"
#include "sdmesh/geometry.hpp"
#include "prefault.hpp"

namespace sdmesh {
namespace {

// Margin π - (α + β) from the scaled sines s = 4·area = 2ab·sin α and cosines
// c = a² + b² - l² = 2ab·cos α of the two opposite angles (the common factors 2ab and 2cd are
// positive, so they do not change the atan2).
double margin_from_scaled(double s_alpha, double c_alpha, double s_beta, double c_beta) {
    return std::atan2(s_alpha * c_beta + c_alpha * s_beta, s_alpha * s_beta - c_alpha * c_beta);
}

}  // namespace

double delaunay_margin(double l, double a, double b, double c, double d) {
    return margin_from_scaled(4.0 * triangle_area(l, a, b), cosine_numerator(l, a, b),
                              4.0 * triangle_area(l, c, d), cosine_numerator(l, c, d));
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
    // prefaulted) costs more than this arithmetic. The bits are those of a per-face pass: a side
    // length is the distance of the same two points whichever face asks, area and cosine
    // numerator are symmetric in the sides, and the circumcentre takes the corners in the face's
    // own order.
    struct Wing {                        // face of halfedge h, seen from its side (l, b, c)
        const Eigen::Vector3d* corner[3];  // the face's corners in its own order
        double area4, cosine;              // 4·area, b² + c² - l²
    };
    const auto wing = [&](int h, int i, int j, double l) {
        const int f = h / 3, k = h % 3;
        const Eigen::Vector3d& o = P[F(f, k)];
        const bool forward = F(f, (k + 1) % 3) == i;  // the side runs from i to j
        Wing w;
        w.corner[k] = &o;
        w.corner[(k + 1) % 3] = &P[forward ? i : j];
        w.corner[(k + 2) % 3] = &P[forward ? j : i];
        const double b = distance(o, P[i]), c = distance(o, P[j]);
        w.area4 = 4.0 * triangle_area(l, b, c);
        w.cosine = cosine_numerator(l, b, c);
        return w;
    };
    const auto opposite = [](const Wing& w, int h) -> const Eigen::Vector3d& { return *w.corner[h % 3]; };
    // Circumsphere test of the Gabriel property: is p strictly inside (beyond the tolerance)?
    const double shrink = 1.0 - 2.0 * tol;
    const auto inside = [shrink](const Wing& w, const Eigen::Vector3d& p) {
        const Eigen::Vector3d center = circumcenter(*w.corner[0], *w.corner[1], *w.corner[2]);
        return (p - center).squaredNorm() < shrink * (center - *w.corner[0]).squaredNorm();
    };

    DelaunayCertificate cert;
    cert.edge_margin.resize(num_edges);
    detail::prefault(cert.edge_margin);
    cert.dual_area = detail::prefaulted_constant<Eigen::VectorXd>(num_vertices, 1, 0.0);
    auto dual_magnitude = detail::prefaulted_constant<Eigen::VectorXd>(num_vertices, 1, 0.0);

    // Per edge of [begin, end): margin, dual-area term l²(cot α + cot β)/8 (into term[e - begin])
    // and Gabriel test. The counts are integer sums, the same for any split of the edges.
    struct Counts {
        int interior = 0, boundary = 0, nonmanifold = 0, non_delaunay = 0, obtuse = 0, gabriel = 0;
    };
    // The random reads (face corners, then positions) of a later edge are requested ahead, in
    // two stages: without this the loop waits on memory most of the time.
    constexpr int kAhead = 16;
    const auto judge = [&](int begin, int end, double* term, Counts& n) {
        for (int e = begin; e < end; ++e) {
            if (e + 2 * kAhead < num_edges)
                for (const int h : H.row(e + 2 * kAhead))
                    if (h >= 0) __builtin_prefetch(&F(h / 3, h % 3)), __builtin_prefetch(&F(h / 3, (h + 1) % 3));
            if (e + kAhead < num_edges) {
                for (const int h : H.row(e + kAhead))
                    if (h >= 0) __builtin_prefetch(&P[F(h / 3, h % 3)]);
                __builtin_prefetch(&P[E(e + kAhead, 1)]);
            }
            const int count = edges.face_count[e];
            if (count > 2) {
                ++n.nonmanifold;
                cert.edge_margin[e] = std::numeric_limits<double>::quiet_NaN();
                term[e - begin] = 0;
                continue;
            }
            const int i = E(e, 0), j = E(e, 1), h0 = H(e, 0);
            const double l = distance(P[j], P[i]);
            const Wing w0 = wing(h0, i, j, l);
            double margin, cot_sum;
            if (count == 2) {
                ++n.interior;
                const int h1 = H(e, 1);
                const Wing w1 = wing(h1, i, j, l);
                margin = margin_from_scaled(w0.area4, w0.cosine, w1.area4, w1.cosine);
                cot_sum = w0.cosine / w0.area4 + w1.cosine / w1.area4;
                n.non_delaunay += margin < -tol;
                n.gabriel += inside(w0, opposite(w1, h1)) || inside(w1, opposite(w0, h0));
            } else {
                ++n.boundary;
                margin = std::atan2(w0.cosine, w0.area4);
                cot_sum = w0.cosine / w0.area4;
                n.obtuse += margin < -tol;
            }
            cert.edge_margin[e] = margin;
            term[e - begin] = l * l * cot_sum / 8.0;
        }
    };
    // The smallest interior margin (first edge on ties) and the dual areas, taken in edge order
    // so that they are bit-identical for any thread count.
    const auto add = [&](int begin, int end, const double* term) {
        for (int e = begin; e < end; ++e) {
            if (edges.face_count[e] == 2 && cert.edge_margin[e] < cert.min_delaunay_margin) {
                cert.min_delaunay_margin = cert.edge_margin[e];
                cert.worst_edge = e;
            }
            for (int side = 0; side < 2; ++side) {
                cert.dual_area[E(e, side)] += term[e - begin];
                dual_magnitude[E(e, side)] += std::abs(term[e - begin]);
            }
        }
    };

    constexpr int kBlock = 2048;
    const int num_blocks = (num_edges + kBlock - 1) / kBlock;
    Counts n;
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
            Counts local;
#pragma omp for schedule(static)
            for (int block = 0; block < num_blocks; ++block) {
                const int begin = block * kBlock, end = std::min(begin + kBlock, num_edges);
                judge(begin, end, &term[begin], local);
            }
#pragma omp critical
            {
                n.interior += local.interior, n.boundary += local.boundary;
                n.nonmanifold += local.nonmanifold, n.non_delaunay += local.non_delaunay;
                n.obtuse += local.obtuse, n.gabriel += local.gabriel;
            }
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
