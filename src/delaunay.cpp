#include "sdmesh/delaunay.hpp"

#include <cmath>
#include <memory>
#include <vector>

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
    const int num_faces = mesh.num_faces();
    const int num_edges = edges.num_edges();
    const int num_vertices = mesh.num_vertices();
    const double tol = options.tolerance;

    // Positions packed per vertex (the loops below read them in random order) and scaled by a
    // power of two that brings the largest coordinate near 1: exact in floating point, so the
    // verdicts are those of the input, while squared lengths of coordinates near the ends of the
    // double range (1e300, 1e-300) neither overflow nor underflow. Dual areas are scaled back.
    const double largest = mesh.V.size() > 0 ? mesh.V.cwiseAbs().maxCoeff() : 0.0;
    const int exponent = largest > 0 ? std::ilogb(largest) : 0;
    const double scale = std::ldexp(1.0, -exponent);
    std::vector<Eigen::Vector3d> P(num_vertices);
    detail::prefault(P);
    for (int v = 0; v < num_vertices; ++v) P[v] = scale * mesh.V.row(v).transpose();

    // Per face, in one cache line: 4·area, the cosine numerators of the three corners and the
    // circumsphere. Side lengths come from positions, so both faces of an edge see the same bits.
    struct alignas(64) Face {
        double area4, cosine[3];
        Eigen::Vector3d center;
        double radius2;
    };
    const std::unique_ptr<Face[]> face(new Face[num_faces]);  // uninitialised: every entry is written
    detail::prefault(face.get(), sizeof(Face) * static_cast<std::size_t>(num_faces));
    // Both loops are bound by the latency of random reads (positions, faces); they request the
    // data of a later iteration ahead, which halves their time on large meshes.
    constexpr int kAhead = 16;
#pragma omp parallel for schedule(static)
    for (int f = 0; f < num_faces; ++f) {
        if (f + kAhead < num_faces)
            for (int k = 0; k < 3; ++k) __builtin_prefetch(&P[F(f + kAhead, k)]);
        Face& t = face[f];
        if (has_repeated_index(F, f)) {
            t = Face{0, {0, 0, 0}, Eigen::Vector3d::Zero(), 0};
            continue;
        }
        const Eigen::Vector3d &p = P[F(f, 0)], &q = P[F(f, 1)], &r = P[F(f, 2)];
        const double l[3] = {distance(r, q), distance(p, r), distance(q, p)};
        t.area4 = 4.0 * triangle_area(l[0], l[1], l[2]);
        for (int k = 0; k < 3; ++k) t.cosine[k] = cosine_numerator(l[k], l[(k + 1) % 3], l[(k + 2) % 3]);
        t.center = circumcenter(p, q, r);
        t.radius2 = (t.center - p).squaredNorm();
    }

    // Per edge: margin, dual-area term l²(cot α + cot β)/8, Gabriel test. Each edge is written by
    // one thread; counts are integer sums, so the result does not depend on the thread count.
    DelaunayCertificate cert;
    cert.edge_margin = detail::prefaulted_constant<Eigen::VectorXd>(num_edges, 1, std::numeric_limits<double>::quiet_NaN());
    Eigen::VectorXd dual_term(num_edges);
    detail::prefault(dual_term);
    const double shrink = 1.0 - 2.0 * tol;  // "strictly inside", beyond the tolerance
    int interior = 0, boundary = 0, nonmanifold = 0, non_delaunay = 0, obtuse = 0, gabriel = 0;
#pragma omp parallel for schedule(static) reduction(+ : interior, boundary, nonmanifold, non_delaunay, obtuse, gabriel)
    for (int e = 0; e < num_edges; ++e) {
        // Two stages: the faces of edge e + 2·kAhead, then the vertices of e + kAhead.
        if (e + 2 * kAhead < num_edges)
            for (const int h : edges.edge_halfedges.row(e + 2 * kAhead))
                if (h >= 0) __builtin_prefetch(&face[h / 3]), __builtin_prefetch(&F(h / 3, h % 3));
        if (e + kAhead < num_edges) {
            for (const int h : edges.edge_halfedges.row(e + kAhead))
                if (h >= 0) __builtin_prefetch(&P[F(h / 3, h % 3)]);
            __builtin_prefetch(&P[edges.E(e + kAhead, 1)]);
        }
        const int count = edges.face_count[e];
        const int h0 = edges.edge_halfedges(e, 0), h1 = edges.edge_halfedges(e, 1);
        const Face& t0 = face[h0 / 3];
        double margin, cot_sum;
        if (count == 2) {
            ++interior;
            const Face& t1 = face[h1 / 3];
            const double c0 = t0.cosine[h0 % 3], c1 = t1.cosine[h1 % 3];
            margin = margin_from_scaled(t0.area4, c0, t1.area4, c1);
            cot_sum = c0 / t0.area4 + c1 / t1.area4;
            non_delaunay += margin < -tol;
            const Eigen::Vector3d &r = P[F(h0 / 3, h0 % 3)], &s = P[F(h1 / 3, h1 % 3)];
            gabriel += (s - t0.center).squaredNorm() < shrink * t0.radius2 ||
                       (r - t1.center).squaredNorm() < shrink * t1.radius2;
        } else if (count == 1) {
            ++boundary;
            margin = std::atan2(t0.cosine[h0 % 3], t0.area4);
            cot_sum = t0.cosine[h0 % 3] / t0.area4;
            obtuse += margin < -tol;
        } else {
            ++nonmanifold;
            dual_term[e] = 0;
            continue;
        }
        cert.edge_margin[e] = margin;
        const double l = distance(P[edges.E(e, 1)], P[edges.E(e, 0)]);
        dual_term[e] = l * l * cot_sum / 8.0;
    }
    cert.interior_edges = interior;
    cert.boundary_edges = boundary;
    cert.nonmanifold_edges = nonmanifold;
    cert.non_delaunay_edges = non_delaunay;
    cert.boundary_obtuse_edges = obtuse;
    cert.negative_cotan_weights = non_delaunay + obtuse;
    cert.gabriel_violations = gabriel;

    // Serial passes: the smallest interior margin (first edge on ties) and the dual areas, summed
    // in edge order so that they are bit-identical for any thread count.
    cert.dual_area = detail::prefaulted_constant<Eigen::VectorXd>(num_vertices, 1, 0.0);
    auto dual_magnitude = detail::prefaulted_constant<Eigen::VectorXd>(num_vertices, 1, 0.0);
    for (int e = 0; e < num_edges; ++e) {
        if (edges.face_count[e] == 2 && cert.edge_margin[e] < cert.min_delaunay_margin) {
            cert.min_delaunay_margin = cert.edge_margin[e];
            cert.worst_edge = e;
        }
        for (int side = 0; side < 2; ++side) {
            cert.dual_area[edges.E(e, side)] += dual_term[e];
            dual_magnitude[edges.E(e, side)] += std::abs(dual_term[e]);
        }
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
